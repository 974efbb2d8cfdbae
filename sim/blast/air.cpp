#include "sim/blast/air.hpp"

#include <cmath>

namespace brisance::blast {

namespace {
constexpr double kPaPerBar = 1e5;
}

// The equations below are written for gamma = 1.4 (the 6/7 and 5/2 coefficients), as in the
// thesis; `air.gamma` documents the assumption.

double rh_shock_velocity_m_s(double overpressure_pa, const Ambient& air) {
  const double p0 = air.pressure_pa;
  return air.sound_speed_m_s * std::sqrt((6.0 * overpressure_pa + 7.0 * p0) / (7.0 * p0));
}

double rh_density_behind_kg_m3(double overpressure_pa, const Ambient& air) {
  const double p0 = air.pressure_pa;
  return air.density_kg_m3 * (6.0 * overpressure_pa + 7.0 * p0) / (overpressure_pa + 7.0 * p0);
}

double rh_dynamic_pressure_pa(double overpressure_pa, const Ambient& air) {
  const double p = overpressure_pa;
  return 5.0 * p * p / (2.0 * (p + 7.0 * air.pressure_pa));
}

double rh_particle_velocity_m_s(double overpressure_pa, const Ambient& air) {
  // rho0 U = rho1 (U - u) (eq. 2.1) gives u = U (1 - rho0 / rho1).
  const double shock = rh_shock_velocity_m_s(overpressure_pa, air);
  return shock * (1.0 - air.density_kg_m3 / rh_density_behind_kg_m3(overpressure_pa, air));
}

double rh_reflected_overpressure_pa(double overpressure_pa, const Ambient& air) {
  const double p = overpressure_pa;
  const double p0 = air.pressure_pa;
  return 2.0 * p * (7.0 * p0 + 4.0 * p) / (7.0 * p0 + p);
}

EmpiricalOverpressure brode_overpressure(double z) {
  const double near_bar = 6.7 / (z * z * z) + 1.0;  // eq. 2.20
  if (near_bar > 10.0) return {near_bar * kPaPerBar, true};
  const double mid_bar = 0.975 / z + 1.455 / (z * z) + 5.85 / (z * z * z) - 0.019;  // eq. 2.21
  return {mid_bar * kPaPerBar, mid_bar >= 0.1 && mid_bar <= 10.0};
}

EmpiricalOverpressure henrych_overpressure(double z) {
  const double z2 = z * z;
  const double z3 = z2 * z;
  double bar;
  if (z < 0.3) {
    bar = 14.072 / z + 5.540 / z2 - 0.357 / z3 + 0.00625 / (z3 * z);  // eq. 2.22
  } else if (z < 1.0) {
    bar = 6.194 / z - 0.326 / z2 - 2.132 / z3;  // eq. 2.23
  } else {
    bar = 0.662 / z + 4.05 / z2 + 3.288 / z3;  // eq. 2.24
  }
  return {bar * kPaPerBar, z >= 0.05 && z <= 10.0};
}

}  // namespace brisance::blast
