#include "sim/fracture/pane.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "sim/fracture/crack_tree.hpp"

namespace brisance::fracture {

namespace {

// Roark 7th ed. table 11.4, case 1a (simply supported, uniform load, nu = 0.3); the last row is
// a/b = infinity (a long strip), kept as the limit for any a/b beyond 5.
struct RoarkRow {
  double aspect;
  double beta;
  double alpha;
};
constexpr std::array kRoarkCase1a = {
    RoarkRow{1.0, 0.2874, 0.0444}, RoarkRow{1.2, 0.3762, 0.0616}, RoarkRow{1.4, 0.4530, 0.0770},
    RoarkRow{1.6, 0.5172, 0.0906}, RoarkRow{1.8, 0.5688, 0.1017}, RoarkRow{2.0, 0.6102, 0.1110},
    RoarkRow{3.0, 0.7134, 0.1335}, RoarkRow{4.0, 0.7410, 0.1400}, RoarkRow{5.0, 0.7476, 0.1417},
};
constexpr double kStripBeta = 0.7500;
constexpr double kStripAlpha = 0.1421;

template <typename Field>
double interpolate(double aspect_ratio, Field field, double strip) {
  assert(aspect_ratio >= 1.0);
  if (aspect_ratio >= kRoarkCase1a.back().aspect) {
    // Between a/b = 5 and infinity the coefficients move by under 0.5 %: approach the strip's.
    const RoarkRow& last = kRoarkCase1a.back();
    const double w = last.aspect / aspect_ratio;  // 1 at a/b = 5, 0 at infinity
    return w * field(last) + (1.0 - w) * strip;
  }
  for (std::size_t i = 1; i < kRoarkCase1a.size(); ++i) {
    const RoarkRow& hi = kRoarkCase1a[i];
    if (aspect_ratio <= hi.aspect) {
      const RoarkRow& lo = kRoarkCase1a[i - 1];
      const double s = (aspect_ratio - lo.aspect) / (hi.aspect - lo.aspect);
      return field(lo) + s * (field(hi) - field(lo));
    }
  }
  return field(kRoarkCase1a.back());
}

}  // namespace

double roark_beta(double aspect_ratio) {
  return interpolate(
      aspect_ratio, [](const RoarkRow& row) { return row.beta; }, kStripBeta);
}

double roark_alpha(double aspect_ratio) {
  return interpolate(
      aspect_ratio, [](const RoarkRow& row) { return row.alpha; }, kStripAlpha);
}

PlateResponse simply_supported_plate(double width_m, double height_m, double thickness_m,
                                     double pressure_pa, double youngs_modulus_pa) {
  assert(width_m > 0.0 && height_m > 0.0 && thickness_m > 0.0 && youngs_modulus_pa > 0.0);
  const double a = std::max(width_m, height_m);
  const double b = std::min(width_m, height_m);
  const double aspect = a / b;
  const double q = std::max(pressure_pa, 0.0);
  PlateResponse response;
  response.stress_pa = roark_beta(aspect) * q * b * b / (thickness_m * thickness_m);
  response.deflection_m = roark_alpha(aspect) * q * std::pow(b, 4) /
                          (youngs_modulus_pa * thickness_m * thickness_m * thickness_m);
  response.small_deflection = response.deflection_m <= 0.5 * thickness_m;
  return response;
}

PaneFracture pane_fracture(const PaneFractureInput& input) {
  return pane_fracture(input,
                       simply_supported_plate(input.width_m, input.height_m, input.thickness_m,
                                              input.pressure_pa, input.youngs_modulus_pa));
}

PaneFracture pane_fracture(const PaneFractureInput& input, const PlateResponse& plate) {
  PaneFracture result;
  result.plate = plate;
  result.breaks = result.plate.stress_pa > input.strength_pa;
  if (!result.breaks) return result;
  result.critical_crack_length_m =
      critical_crack_length_m(input.fracture_toughness_pa_sqrt_m, result.plate.stress_pa);
  const double scaled = input.pattern_scale * result.critical_crack_length_m;
  // std::clamp needs min <= max; a caller's min above its max gives way to the max.
  result.growth_length_m =
      std::clamp(scaled, std::min(input.min_growth_length_m, input.max_growth_length_m),
                 input.max_growth_length_m);
  result.clamped = result.growth_length_m != scaled;
  return result;
}

double empirical_fragment_area_m2(double peak_pressure_pa) {
  // Thesis eq. 2.45: 6.4516e-4 m^2 is one square inch, 5.8566e-5 per Pa is 0.4038 per psi.
  const double p = 5.8566e-5 * peak_pressure_pa;
  return 6.4516e-4 * std::exp(2.4 - std::sqrt(12.5 + p * p));
}

double empirical_fragment_velocity_m_s(double peak_pressure_pa, double thickness_m) {
  // Thesis eq. 2.46 as printed (h in m, P_e in Pa, v in m/s).
  return (0.2539 + 1.826e-4 * std::pow(thickness_m - 7.62e-4, -0.928)) *
         (0.3443 * std::pow(peak_pressure_pa, 0.547));
}

}  // namespace brisance::fracture
