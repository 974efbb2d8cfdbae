#include "sim/io/blast_json.hpp"

namespace brisance::io {

nlohmann::ordered_json blast_report_json(const blast::BlastPoint& point,
                                         const blast::ObliqueReflection& reflection) {
  nlohmann::ordered_json out;
  out["scaled_distance_m_kg13"] = point.scaled_distance_m_kg13;
  out["tnt_equivalent_kg"] = point.tnt_equivalent_kg;
  out["incident_overpressure_kpa"] = point.incident_overpressure_pa * 1e-3;
  out["incident_impulse_kpa_ms"] = point.incident_impulse_pa_s;  // Pa*s == kPa*ms
  out["arrival_time_ms"] = point.arrival_time_s * 1e3;
  out["positive_duration_ms"] = point.positive_duration_s * 1e3;
  out["reflected_overpressure_kpa"] = reflection.overpressure_pa * 1e-3;
  out["reflected_impulse_kpa_ms"] = reflection.impulse_pa_s;
  out["shock_velocity_m_s"] = point.shock_velocity_m_s;
  out["dynamic_pressure_kpa"] = point.dynamic_pressure_pa * 1e-3;
  out["reflection_coefficient"] = reflection.coefficient;
  out["in_validity_range"] = point.in_validity_range && reflection.in_chart_range;
  return out;
}

blast::ObliqueReflection reflect(const blast::BlastPoint& point, double angle_rad) {
  return blast::oblique_reflection(point.incident_overpressure_pa, point.incident_impulse_pa_s,
                                   point.reflected_overpressure_pa, point.reflected_impulse_pa_s,
                                   angle_rad);
}

}  // namespace brisance::io
