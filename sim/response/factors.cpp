// sim/response/factors: the table of transformation factors.
//
// Sources:
// - One-way rows: J. M. Biggs (1964) "Introduction to Structural Dynamics", McGraw-Hill, table 5.1
//   (simply supported beams and one-way slabs) and table 5.2 (fixed ends), reprinted in
//   UFC 3-340-02 (2008) table 3-12; cross-checked against the copy Ingeania publishes
//   (ingeania.com/Reference/SDOF_Transformation_Factors) and against the integrals of their
//   shapes (tests).
// - Two-way slabs simply supported on four sides (Biggs table 5.3, UFC 3-340-02 table 3-13): no
//   printed copy was reachable, so both ranges are computed here by Biggs's own method (K_L and
//   K_M from the deflected shape, ch. 5): elastic from the plate's static shape (Navier series),
//   plastic from the 45° yield-line mechanism. The plastic values equal the table's as we
//   remember it to its two decimals; the elastic ones are 7–26 % below the remembered values
//   (0.45 … 0.55), which do not follow from the static shape (docs/response.md).
// Uniformly distributed load only. K_LM = K_M / K_L.
// Not in the table (missing): concentrated and third-point loads, cantilevers, the fixed-edge
// two-way slabs of Biggs table 5.4 / UFC table 3-13's fixed cases.
#include "sim/response/factors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace brisance::response {
namespace {

constexpr std::string_view kTable51 = "Biggs 1964 table 5.1; UFC 3-340-02 table 3-12";
constexpr std::string_view kTable52 = "Biggs 1964 table 5.2; UFC 3-340-02 table 3-12";
constexpr std::string_view kNavier =
    "static shape, Navier series (Timoshenko & Woinowsky-Krieger 1959 §30); Biggs 1964 ch. 5 "
    "method";
constexpr std::string_view kYieldLines =
    "45° yield-line mechanism; Biggs 1964 table 5.3, UFC 3-340-02 table 3-13";

// Smallest side ratio the series is summed for; thinner plates are one-way strips in all but
// their ends.
constexpr double kMinRatio = 1e-3;

std::vector<TransformationFactors> build_table() {
  using R = ResponseRange;
  std::vector<TransformationFactors> t = {
      // One-way, simply supported, uniform load.
      {"one_way_simply_supported", R::elastic, 0.64, 0.50, kTable51},
      {"one_way_simply_supported", R::plastic, 0.50, 0.33, kTable51},
      // One-way, fixed both ends, uniform load (elasto-plastic: ends hinged, midspan elastic).
      {"one_way_fixed", R::elastic, 0.53, 0.41, kTable52},
      {"one_way_fixed", R::elasto_plastic, 0.64, 0.50, kTable52},
      {"one_way_fixed", R::plastic, 0.50, 0.33, kTable52},
  };
  // Two-way slab simply supported on four sides, uniform load; the suffix is the side ratio
  // a/b (short/long), the rows of Biggs table 5.3.
  constexpr std::array<std::pair<std::string_view, double>, 6> kRatios = {{
      {"two_way_simply_supported_1.0", 1.0},
      {"two_way_simply_supported_0.9", 0.9},
      {"two_way_simply_supported_0.8", 0.8},
      {"two_way_simply_supported_0.7", 0.7},
      {"two_way_simply_supported_0.6", 0.6},
      {"two_way_simply_supported_0.5", 0.5},
  }};
  for (const auto& [name, ratio] : kRatios) {
    const ShapeFactors e = two_way_simply_supported_elastic(ratio);
    const ShapeFactors p = two_way_simply_supported_plastic(ratio);
    t.push_back({name, R::elastic, e.load, e.mass, kNavier});
    t.push_back({name, R::plastic, p.load, p.mass, kYieldLines});
  }
  return t;
}

const std::vector<TransformationFactors>& table() {
  static const std::vector<TransformationFactors> t = build_table();
  return t;
}

}  // namespace

ShapeFactors two_way_simply_supported_elastic(double short_over_long) {
  // w(x, y) ∝ Σ_{m,n odd} sin(mπx/a) sin(nπy/b) / (m n (m²/a² + n²/b²)²), with b = 1 and
  // a = r. Over the plate the mean of sin(mπx/a) is 2/(mπ) and the sines are orthogonal with
  // mean square 1/2, so ∫φ and ∫φ² are sums of the coefficients; the centre value
  // alternates in sign. The coefficients fall as (m n)⁻¹ (m²/r² + n²)⁻²: 81 terms in m, and in
  // n enough to pass m/r, give 1e-6.
  const double r = std::clamp(short_over_long, kMinRatio, 1.0);
  const int m_max = 81;
  const int n_max = 81 + 2 * static_cast<int>(std::ceil(4.0 / r));
  double centre = 0.0;
  double mean = 0.0;
  double mean_square = 0.0;
  for (int m = 1; m <= m_max; m += 2) {
    const double sm = ((m - 1) / 2) % 2 == 0 ? 1.0 : -1.0;
    const double mr = m / r;
    for (int n = 1; n <= n_max; n += 2) {
      const double sn = ((n - 1) / 2) % 2 == 0 ? 1.0 : -1.0;
      const double q = mr * mr + static_cast<double>(n) * n;
      const double c = 1.0 / (static_cast<double>(m) * n * q * q);
      centre += sm * sn * c;
      mean += c * 4.0 / (std::numbers::pi * std::numbers::pi * m * n);
      mean_square += c * c / 4.0;
    }
  }
  return {mean / centre, mean_square / (centre * centre)};
}

ShapeFactors two_way_simply_supported_plastic(double short_over_long) {
  // Hip roof of unit height over an a × b plate (a = r b): ridges at a/2 from every edge. Its
  // volume is a b (1/2 − r/6) and the mean of its square a b (1/3 − r/6): the two long-side
  // trapezoids and the two short-side triangles are integrated in closed form.
  const double r = std::clamp(short_over_long, kMinRatio, 1.0);
  return {0.5 - r / 6.0, 1.0 / 3.0 - r / 6.0};
}

std::span<const TransformationFactors> factor_table() {
  return table();
}

std::optional<TransformationFactors> find_factors(std::string_view element, ResponseRange range) {
  for (const TransformationFactors& f : table()) {
    if (f.element == element && f.range == range) return f;
  }
  return std::nullopt;
}

}  // namespace brisance::response
