// Tests of sim/response/element, factors and limits: parsing with field paths, the factor table
// against Biggs's K_LM column, and damage levels.
#include "sim/response/element.hpp"

#include <algorithm>

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
  // Biggs 1964 tables 5.1-5.3 also print K_LM; the transcribed K_L, K_M must reproduce it.
  struct Row {
    const char* element;
    ResponseRange range;
    double klm;
  };
  for (const Row& r : {Row{"one_way_simply_supported", ResponseRange::elastic, 0.78},
                       Row{"one_way_simply_supported", ResponseRange::plastic, 0.66},
                       Row{"one_way_fixed", ResponseRange::elastic, 0.77},
                       Row{"one_way_fixed", ResponseRange::elasto_plastic, 0.78},
                       Row{"two_way_simply_supported_1.0", ResponseRange::elastic, 0.68},
                       Row{"two_way_simply_supported_1.0", ResponseRange::plastic, 0.51}}) {
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
