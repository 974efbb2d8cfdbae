#include "sim/blast/blast_point.hpp"

#include <cassert>
#include <cmath>

namespace brisance::blast {

namespace {
// Thesis §2.5.1: a surface burst acts like an air burst of 1.8 times the energy (2 for a perfect
// reflector, less the energy the ground absorbs).
constexpr double kSurfaceFactor = 1.8;
}  // namespace

BurstCurve curve_for(const Charge& charge) {
  return charge.burst == Burst::surface && charge.surface_model == SurfaceBurstModel::hemispherical
             ? BurstCurve::hemispherical_surface
             : BurstCurve::spherical_free_air;
}

double curve_charge_kg(const Charge& charge) {
  return charge.burst == Burst::surface && charge.surface_model == SurfaceBurstModel::factor_1_8
             ? kSurfaceFactor * charge.tnt_equivalent_kg
             : charge.tnt_equivalent_kg;
}

double curve_impulse_charge_kg(const Charge& charge) {
  if (!(charge.impulse_tnt_equivalent_kg > 0.0)) return curve_charge_kg(charge);
  return charge.burst == Burst::surface && charge.surface_model == SurfaceBurstModel::factor_1_8
             ? kSurfaceFactor * charge.impulse_tnt_equivalent_kg
             : charge.impulse_tnt_equivalent_kg;
}

BlastPoint blast_point(const Charge& charge, double distance_m, const Ambient& air) {
  assert(charge.tnt_equivalent_kg > 0.0 && distance_m > 0.0);
  const double w = curve_charge_kg(charge);
  const double cube_root_w = std::cbrt(w);
  const double z = distance_m / cube_root_w;
  const ScaledBlast scaled = kingery_bulmash(curve_for(charge), z);

  BlastPoint point;
  point.scaled_distance_m_kg13 = z;
  point.tnt_equivalent_kg = charge.tnt_equivalent_kg;
  point.incident_overpressure_pa = scaled.incident_overpressure_pa;
  point.incident_impulse_pa_s = scaled.incident_impulse_pa_s_kg13 * cube_root_w;
  point.arrival_time_s = scaled.arrival_time_s_kg13 * cube_root_w;
  point.positive_duration_s = scaled.positive_duration_s_kg13 * cube_root_w;
  point.reflected_overpressure_pa = scaled.reflected_overpressure_pa;
  point.reflected_impulse_pa_s = scaled.reflected_impulse_pa_s_kg13 * cube_root_w;
  point.shock_velocity_m_s = scaled.shock_velocity_m_s;
  point.dynamic_pressure_pa = rh_dynamic_pressure_pa(scaled.incident_overpressure_pa, air);
  point.in_validity_range = scaled.in_validity_range;
  point.impulse_tnt_equivalent_kg = charge.tnt_equivalent_kg;
  if (charge.impulse_tnt_equivalent_kg > 0.0 &&
      charge.impulse_tnt_equivalent_kg != charge.tnt_equivalent_kg) {
    const double cube_root_wi = std::cbrt(curve_impulse_charge_kg(charge));
    const ScaledBlast by_impulse = kingery_bulmash(curve_for(charge), distance_m / cube_root_wi);
    point.impulse_tnt_equivalent_kg = charge.impulse_tnt_equivalent_kg;
    point.incident_impulse_pa_s = by_impulse.incident_impulse_pa_s_kg13 * cube_root_wi;
    point.reflected_impulse_pa_s = by_impulse.reflected_impulse_pa_s_kg13 * cube_root_wi;
    point.in_validity_range = point.in_validity_range && by_impulse.in_validity_range;
  }
  return point;
}

double wave_reach_m(const Charge& charge, double time_s, const Ambient& air) {
  assert(time_s > 0.0);
  auto arrival = [&](double d) { return blast_point(charge, d, air).arrival_time_s; };
  double low = 1e-3, high = 1.0;
  while (arrival(high) < time_s && high < 1e12) {
    low = high;
    high *= 2.0;
  }
  while (high - low > 1e-6 * high) {
    const double middle = 0.5 * (low + high);
    (arrival(middle) < time_s ? low : high) = middle;
  }
  return high;
}

}  // namespace brisance::blast
