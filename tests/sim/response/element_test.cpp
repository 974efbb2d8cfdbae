// Tests of sim/response/element, factors and limits: parsing with field paths, the factor table
// against Biggs's K_LM column and against the integrals of the deflected shapes it comes from
// (the two-way plate's static shape solved independently by finite differences), and damage
// levels.
#include "sim/response/element.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/response/factors.hpp"
#include "sim/response/limits.hpp"

namespace brisance::response {
namespace {

nlohmann::json valid() {
  return nlohmann::json::parse(R"({
    "mass_kg": 500, "loaded_area_m2": 2,
    "resistance": {"type": "bilinear", "stiffness_n_per_m": 2e6, "yield_resistance_n": 1e5,
                   "hardening_stiffness_n_per_m": 1e5},
    "damping_ratio": 0.02, "factors": {"load": 0.64, "mass": 0.5}, "support": {"span_m": 3}})");
}

std::vector<std::string> errors_of(const nlohmann::json& j) {
  std::vector<std::string> out;
  for (const FieldError& e : parse_element(j).errors)
    out.push_back(e.text());
  return out;
}

bool has(const std::vector<std::string>& errors, const std::string& text) {
  return std::find(errors.begin(), errors.end(), text) != errors.end();
}

TEST(ParseElement, ReadsEveryField) {
  const ElementParse p = parse_element(valid());
  ASSERT_TRUE(p.errors.empty()) << p.errors.front().text();
  const Element& e = *p.element;
  EXPECT_EQ(e.mass_kg, 500.0);
  EXPECT_EQ(e.resistance.type, ResistanceType::bilinear);
  EXPECT_EQ(e.resistance.hardening_stiffness_n_per_m, 1e5);
  EXPECT_EQ(e.damping_ratio, 0.02);
  EXPECT_EQ(e.load_factor, 0.64);
  EXPECT_EQ(*e.span_m, 3.0);
}

TEST(ParseElement, DefaultsAreAnEquivalentUndampedSdof) {
  nlohmann::json j = valid();
  j.erase("factors");
  j.erase("damping_ratio");
  j.erase("support");
  const ElementParse p = parse_element(j);
  ASSERT_TRUE(p.element);
  EXPECT_EQ(p.element->load_factor, 1.0);
  EXPECT_EQ(p.element->mass_factor, 1.0);
  EXPECT_EQ(p.element->damping_ratio, 0.0);
  EXPECT_FALSE(p.element->span_m);
}

TEST(ParseElement, InvalidFieldsNameTheirPath) {
  nlohmann::json j = valid();
  j["resistance"]["stiffness_n_per_m"] = 0;
  EXPECT_TRUE(has(errors_of(j), "/resistance/stiffness_n_per_m must be > 0"));
  j = valid();
  j["colour"] = "red";
  EXPECT_TRUE(has(errors_of(j), "/colour is not a known field; remove it"));
  j = valid();
  j["resistance"]["hardening_stiffness_n_per_m"] = 3e6;
  EXPECT_TRUE(has(errors_of(j),
                  "/resistance/hardening_stiffness_n_per_m must be >= 0 and < stiffness_n_per_m"));
  j = valid();
  j.erase("mass_kg");
  j["damping_ratio"] = 1.5;
  j["factors"]["mass"] = "half";
  const auto errs = errors_of(j);
  EXPECT_TRUE(has(errs, "/mass_kg is required"));
  EXPECT_TRUE(has(errs, "/damping_ratio must be >= 0 and < 1"));
  EXPECT_TRUE(has(errs, "/factors/mass must be a finite number"));
  EXPECT_FALSE(parse_element(j).element);
  j = valid();
  j["resistance"]["type"] = "plastic";
  EXPECT_TRUE(
      has(errors_of(j), "/resistance/type must be elastic, elastic_plastic, bilinear or membrane"));
  j = valid();
  j["resistance"]["membrane_onset_m"] = 0.1;
  EXPECT_TRUE(has(errors_of(j),
                  "/resistance/membrane_onset_m applies to type membrane only; "
                  "remove it"));
  j = valid();
  j["resistance"] = {{"type", "membrane"},
                     {"stiffness_n_per_m", 1e6},
                     {"yield_resistance_n", 1e4},
                     {"membrane_onset_m", 0.001},
                     {"membrane_stiffness_n_per_m", 1e5}};
  EXPECT_TRUE(has(errors_of(j),
                  "/resistance/membrane_onset_m must be >= the yield displacement "
                  "yield_resistance_n / stiffness_n_per_m"));
  EXPECT_TRUE(has(errors_of(nlohmann::json::array()), "/ must be an object"));
}

TEST(ParseElement, LimitsNameATable) {
  nlohmann::json j = valid();
  j["limits"] = "steel_beam_flexure";
  const ElementParse p = parse_element(j);
  ASSERT_TRUE(p.element);
  EXPECT_EQ(*p.element->limits, "steel_beam_flexure");
  EXPECT_FALSE(parse_element(valid()).element->limits);
  j["limits"] = "glass";
  EXPECT_TRUE(has(errors_of(j),
                  "/limits must name a table of response limits: rc_flexure, steel_beam_flexure"));
  j["limits"] = 3;
  EXPECT_FALSE(parse_element(j).element);
}

TEST(Factors, LoadMassRatioMatchesBiggsColumn) {
  // Biggs 1964 tables 5.1-5.2 also print K_LM; the transcribed K_L, K_M must reproduce it.
  struct Row {
    const char* element;
    ResponseRange range;
    double klm;
  };
  for (const Row& r : {Row{"one_way_simply_supported", ResponseRange::elastic, 0.78},
                       Row{"one_way_simply_supported", ResponseRange::plastic, 0.66},
                       Row{"one_way_fixed", ResponseRange::elastic, 0.77},
                       Row{"one_way_fixed", ResponseRange::elasto_plastic, 0.78}}) {
    const auto f = find_factors(r.element, r.range);
    ASSERT_TRUE(f) << r.element;
    EXPECT_NEAR(f->load_mass(), r.klm, 0.01) << r.element;
  }
  EXPECT_FALSE(find_factors("cantilever", ResponseRange::elastic));
  for (const TransformationFactors& f : factor_table()) {
    EXPECT_GT(f.load, 0.0);
    EXPECT_LE(f.mass, f.load) << f.element;  // K_M <= K_L for every uniform-load case
    EXPECT_FALSE(f.source.empty());
  }
}

// ∫φ and ∫φ² over [0, 1] by Simpson's rule.
std::pair<double, double> shape_integrals(const std::function<double(double)>& phi) {
  const int n = 2000;
  double s1 = 0.0, s2 = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double v = phi(static_cast<double>(i) / n);
    s1 += w * v;
    s2 += w * v * v;
  }
  return {s1 / (3.0 * n), s2 / (3.0 * n)};
}

TEST(Factors, OneWayRowsAreTheIntegralsOfTheirShapes) {
  // Biggs's method (ch. 5): K_L = ∫φ, K_M = ∫φ² with φ the deflected shape, 1 at midspan. The
  // static shapes of a uniformly loaded beam (textbook elastic curves) and the plastic
  // mechanism reproduce the printed two decimals; this is what the two-way rows are built on.
  struct Row {
    const char* element;
    ResponseRange range;
    std::function<double(double)> phi;
  };
  const std::vector<Row> rows = {
      {"one_way_simply_supported", ResponseRange::elastic,
       [](double x) { return 16.0 / 5.0 * (x - 2 * x * x * x + x * x * x * x); }},
      {"one_way_simply_supported", ResponseRange::plastic,
       [](double x) { return 1.0 - std::abs(2.0 * x - 1.0); }},
      {"one_way_fixed", ResponseRange::elastic,
       [](double x) { return 16.0 * x * x * (1 - x) * (1 - x); }},
      {"one_way_fixed", ResponseRange::plastic,
       [](double x) { return 1.0 - std::abs(2.0 * x - 1.0); }},
  };
  for (const Row& r : rows) {
    const auto f = find_factors(r.element, r.range);
    ASSERT_TRUE(f);
    const auto [kl, km] = shape_integrals(r.phi);
    EXPECT_NEAR(f->load, kl, 0.005) << r.element;
    EXPECT_NEAR(f->mass, km, 0.005) << r.element;
  }
}

// The static deflection of a plate simply supported on four sides under uniform load, solved by
// finite differences independently of the Navier series: ∇²M = −q, ∇²w = −M/D with M = w = 0 on
// the edges (the moment sum vanishes on a straight simply supported edge), each Poisson problem
// by successive over-relaxation on an n × n grid. Returns (∫φ, ∫φ²) / area, φ = w / w(centre).
std::pair<double, double> plate_shape_by_finite_differences(double ratio, int n) {
  const double hx = ratio / n, hy = 1.0 / n;
  auto poisson = [&](const std::vector<double>& rhs) {
    std::vector<double> u((n + 1) * (n + 1), 0.0);
    const double cx = 1.0 / (hx * hx), cy = 1.0 / (hy * hy), diag = 2.0 * (cx + cy);
    const double omega = 2.0 / (1.0 + std::sin(std::acos(-1.0) / n));
    for (int sweep = 0; sweep < 20 * n; ++sweep) {
      for (int i = 1; i < n; ++i) {
        for (int j = 1; j < n; ++j) {
          const int k = i * (n + 1) + j;
          const double gs =
              (cx * (u[k - n - 1] + u[k + n + 1]) + cy * (u[k - 1] + u[k + 1]) + rhs[k]) / diag;
          u[k] += omega * (gs - u[k]);
        }
      }
    }
    return u;
  };
  const std::vector<double> moment = poisson(std::vector<double>((n + 1) * (n + 1), 1.0));
  const std::vector<double> w = poisson(moment);
  const double centre = w[(n / 2) * (n + 1) + n / 2];
  // Trapezoid rule over the grid (zero on the edges).
  double s1 = 0.0, s2 = 0.0;
  for (int i = 1; i < n; ++i) {
    for (int j = 1; j < n; ++j) {
      const double phi = w[i * (n + 1) + j] / centre;
      s1 += phi;
      s2 += phi * phi;
    }
  }
  const double cells = static_cast<double>(n) * n;
  return {s1 / cells, s2 / cells};
}

TEST(Factors, TwoWayElasticFactorsAreThePlatesStaticShape) {
  // The Navier series against an independent finite-difference solution of the same plate; the
  // grid's error is second order (h = 1/64: about 0.1 %).
  for (double ratio : {1.0, 0.8, 0.5}) {
    const ShapeFactors series = two_way_simply_supported_elastic(ratio);
    const auto [kl, km] = plate_shape_by_finite_differences(ratio, 64);
    EXPECT_NEAR(series.load / kl, 1.0, 0.003) << ratio;
    EXPECT_NEAR(series.mass / km, 1.0, 0.003) << ratio;
  }
  // A square plate: 0.419 and 0.262 (K_LM 0.626); a long plate tends to the one-way strip of
  // Biggs table 5.1 (0.64, 0.50), losing only its two ends.
  const ShapeFactors square = two_way_simply_supported_elastic(1.0);
  EXPECT_NEAR(square.load, 0.4191, 1e-4);
  EXPECT_NEAR(square.mass, 0.2623, 1e-4);
  const ShapeFactors strip = two_way_simply_supported_elastic(0.005);
  EXPECT_NEAR(strip.load, 0.64, 0.01);
  EXPECT_NEAR(strip.mass, 0.504, 0.01);
  // The table's two-way elastic rows are this function.
  const auto row = find_factors("two_way_simply_supported_0.7", ResponseRange::elastic);
  ASSERT_TRUE(row);
  EXPECT_DOUBLE_EQ(row->load, two_way_simply_supported_elastic(0.7).load);
}

TEST(Factors, TwoWayPlasticFactorsAreTheYieldLineMechanism) {
  // The closed form against a midpoint-rule integral of the hip roof (unit height, ridges a/2
  // from every edge), and against Biggs table 5.3's plastic rows as printed to two decimals
  // (a/b 1.0 ... 0.5: K_L 0.33 0.35 0.37 0.38 0.40 0.42, K_M 0.17 0.18 0.20 0.22 0.23 0.25).
  const std::vector<double> ratios = {1.0, 0.9, 0.8, 0.7, 0.6, 0.5};
  const std::vector<double> table_load = {0.33, 0.35, 0.37, 0.38, 0.40, 0.42};
  const std::vector<double> table_mass = {0.17, 0.18, 0.20, 0.22, 0.23, 0.25};
  for (std::size_t k = 0; k < ratios.size(); ++k) {
    const double a = ratios[k];
    const int n = 400;
    double s1 = 0.0, s2 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n * a;
      for (int j = 0; j < n; ++j) {
        const double y = (j + 0.5) / n;
        const double phi = std::min(std::min(x, a - x), std::min(y, 1.0 - y)) / (a / 2.0);
        s1 += phi;
        s2 += phi * phi;
      }
    }
    const ShapeFactors f = two_way_simply_supported_plastic(a);
    EXPECT_NEAR(f.load, s1 / (n * n), 1e-4) << a;
    EXPECT_NEAR(f.mass, s2 / (n * n), 1e-4) << a;
    EXPECT_NEAR(f.load, table_load[k], 0.005 + 1e-9) << a;
    EXPECT_NEAR(f.mass, table_mass[k], 0.005 + 1e-9) << a;
  }
}

TEST(Limits, DamageLevelsFollowTheBounds) {
  const auto rc = find_limits("rc_flexure");
  ASSERT_TRUE(rc);
  EXPECT_EQ(damage_level(*rc, 0.8, 0.1), DamageLevel::superficial);
  EXPECT_EQ(damage_level(*rc, 1.5, 1.0), DamageLevel::moderate);
  EXPECT_EQ(damage_level(*rc, 3.0, 3.0), DamageLevel::heavy);
  EXPECT_EQ(damage_level(*rc, 5.0, 7.0), DamageLevel::hazardous);
  EXPECT_EQ(damage_level(*rc, 9.0, 12.0), DamageLevel::blowout);
  const auto steel = find_limits("steel_beam_flexure");
  ASSERT_TRUE(steel);
  // Without a span only ductility counts.
  EXPECT_EQ(damage_level(*steel, 13.0, std::nullopt), DamageLevel::hazardous);
  EXPECT_EQ(to_string(DamageLevel::heavy), "heavy");
}

}  // namespace
}  // namespace brisance::response
