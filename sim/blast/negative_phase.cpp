// sim/blast/negative_phase: see negative_phase.hpp.
#include "sim/blast/negative_phase.hpp"

#include <cassert>
#include <cmath>
#include <span>

namespace brisance::blast {

namespace {

// One piece of Rigby et al.'s fits: A Z^B + C Z + D for Z up to z_max (B = 2 gives their
// quadratics), in MPa, MPa·ms/kg^(1/3) or ms/kg^(1/3).
struct FitPiece {
  double z_max;
  double a, b, c, d;
};

// The last piece runs to infinity, so one always applies.
double evaluate(std::span<const FitPiece> pieces, double z) {
  for (const FitPiece& piece : pieces) {
    if (z <= piece.z_max) return piece.a * std::pow(z, piece.b) + piece.c * z + piece.d;
  }
  return 0.0;  // unreachable for finite z; NaN z reaches here
}

// Spherical free-air burst (UFC 3-340-02 fig. 2-16's negative phase).
constexpr FitPiece kAirPressure[] = {{0.7, 0.0, 0.0, 0.0, 0.100},
                                     {1.469, -29.078e-3, 2.0, 0.0352e-3, 114e-3},
                                     {2.754, 84.132e-3, -1.286, 0.0, 0.0},
                                     {INFINITY, 59.559e-3, -0.945, 0.0, 0.0}};
constexpr FitPiece kAirImpulse[] = {{0.304, 0.0, 0.0, 0.0, 496e-3},
                                    {1.44, 36.919e-3, 2.0, -298.72e-3, 583e-3},
                                    {INFINITY, 316.36e-3, -0.879, 0.0, 0.0}};
constexpr FitPiece kAirDuration[] = {{0.537, 0.382, 2.0, 2.952, 7.917},
                                     {2.83, -0.309, 2.0, 1.6443, 8.818},
                                     {INFINITY, 0.0, 0.0, 0.0, 11.0}};
// Hemispherical surface burst.
constexpr FitPiece kSurfacePressure[] = {{0.669, 0.0, 0.0, 0.0, 0.100},
                                         {1.27, -32.91e-3, 2.0, 13e-3, 106e-3},
                                         {2.78, 93e-3, -1.215, 0.0, 0.0},
                                         {INFINITY, 72.99e-3, -0.978, 0.0, 0.0}};
constexpr FitPiece kSurfaceImpulse[] = {{0.58, -724.37e-3, 2.0, 445.34e-3, 553e-3},
                                        {1.19, 11.356e-3, 2.0, -314.76e-3, 752e-3},
                                        {5.25, 461.8e-3, -0.88, 0.0, 0.0},
                                        {INFINITY, 433.6e-3, -0.842, 0.0, 0.0}};
constexpr FitPiece kSurfaceDuration[] = {{0.267, 0.0, 0.0, 0.0, 10.57},
                                         {2.9, -0.474, 2.0, 2.745, 9.87},
                                         {INFINITY, 0.0, 0.0, 0.0, 13.9}};

// The charts end at Z = 40 m/kg^(1/3), as the Kingery–Bulmash curves do.
constexpr double kMaxChartZ = 40.0;

}  // namespace

double NegativePhase::pressure_pa(double t_s) const {
  if (!(t_s > 0.0) || !(t_s < duration_s)) return 0.0;
  const double u = t_s / duration_s;
  return -underpressure_pa * 6.75 * u * (1.0 - u) * (1.0 - u);
}

NegativePhase negative_phase(const Charge& charge, double distance_m) {
  assert(charge.tnt_equivalent_kg > 0.0 && distance_m > 0.0);
  const bool air = curve_for(charge) == BurstCurve::spherical_free_air;
  const double w_pressure = curve_charge_kg(charge);
  const double w_impulse = curve_impulse_charge_kg(charge);
  const double z_pressure = distance_m / std::cbrt(w_pressure);
  const double z_impulse = distance_m / std::cbrt(w_impulse);

  NegativePhase phase;
  phase.underpressure_pa =
      1e6 * evaluate(air ? std::span<const FitPiece>(kAirPressure) : kSurfacePressure, z_pressure);
  // MPa·ms/kg^(1/3) times W^(1/3) is kPa·s; Pa·s needs 1e3.
  phase.impulse_pa_s =
      1e3 * evaluate(air ? std::span<const FitPiece>(kAirImpulse) : kSurfaceImpulse, z_impulse) *
      std::cbrt(w_impulse);
  phase.duration_s = 16.0 / 9.0 * phase.impulse_pa_s / phase.underpressure_pa;
  phase.chart_duration_s =
      1e-3 *
      evaluate(air ? std::span<const FitPiece>(kAirDuration) : kSurfaceDuration, z_pressure) *
      std::cbrt(w_pressure);
  phase.in_validity_range = z_pressure <= kMaxChartZ && z_impulse <= kMaxChartZ;
  return phase;
}

}  // namespace brisance::blast
