// sim/io/blast_json: see blast_json.hpp.
#include "sim/io/blast_json.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "sim/blast/explosives.hpp"
#include "sim/io/number_text.hpp"

namespace brisance::io {
namespace {}  // namespace

std::vector<BlastQueryError> parse_blast_query(
    const std::function<std::optional<std::string>(std::string_view name)>& lookup,
    const std::function<std::string(std::string_view name)>& spell, BlastQuery& query) {
  // Every parameter is checked on its own, so a caller sees all its mistakes in one answer.
  std::vector<BlastQueryError> problems;
  const auto fail = [&](std::string_view name, const std::string& message) {
    problems.push_back(BlastQueryError{std::string(name), spell(name) + " " + message});
  };
  // A number parameter: nullopt if absent or not a finite number (then reported).
  const auto number = [&](std::string_view name) -> std::optional<double> {
    const auto text = lookup(name);
    if (!text) return std::nullopt;
    const auto value = to_number(*text);
    if (!value) fail(name, "must be a finite number, got '" + *text + "'");
    return value;
  };
  // A required positive number; 0 when absent or bad (then reported).
  const auto positive = [&](std::string_view name, std::string_view what) -> double {
    if (!lookup(name)) {
      fail(name, "is required: " + std::string(what) + " (> 0)");
      return 0.0;
    }
    const auto value = number(name);
    if (!value) return 0.0;
    if (!(*value > 0.0)) fail(name, "must be greater than 0, got " + shown(*value));
    return *value;
  };

  query.charge_kg = positive("charge_kg", "the charge mass in kg");
  query.distance_m = positive("distance_m", "the distance from the charge centre in m");

  const auto explosive = lookup("explosive");
  if (explosive && lookup("tnt_factor")) {
    fail("tnt_factor",
         "and " + spell("explosive") + " name the explosive twice: give one, not both");
  } else if (lookup("tnt_factor")) {
    query.tnt_factor = positive("tnt_factor", "kg TNT per kg of explosive");
    query.impulse_tnt_factor = query.tnt_factor;
    query.explosive_name = "custom";
  } else if (explosive) {
    if (const auto found = blast::find_explosive(*explosive)) {
      query.explosive_name = found->name;
      query.tnt_factor = found->tnt_factor;
      query.impulse_tnt_factor = found->impulse_factor();
    } else {
      fail("explosive", "names no known explosive ('" + *explosive +
                            "'); known: " + blast::known_explosive_names() + " (or give " +
                            spell("tnt_factor") + ")");
    }
  }

  if (lookup("impulse_tnt_factor")) {
    if (!lookup("tnt_factor")) {
      fail("impulse_tnt_factor", "goes with " + spell("tnt_factor") +
                                     " (a custom explosive); a named explosive brings its own");
    } else {
      query.impulse_tnt_factor =
          positive("impulse_tnt_factor", "kg TNT per kg of explosive, for impulses");
    }
  }

  if (const auto burst = lookup("burst")) {
    if (*burst == "air") {
      query.charge.burst = blast::Burst::air;
    } else if (*burst == "surface") {
      query.charge.burst = blast::Burst::surface;
    } else {
      fail("burst", "must be 'air' or 'surface', got '" + *burst + "'");
    }
  }
  if (const auto model = lookup("surface_model")) {
    if (*model == "hemispherical") {
      query.charge.surface_model = blast::SurfaceBurstModel::hemispherical;
    } else if (*model == "factor_1_8") {
      query.charge.surface_model = blast::SurfaceBurstModel::factor_1_8;
    } else {
      fail("surface_model", "must be 'hemispherical' or 'factor_1_8', got '" + *model + "'");
    }
  }
  if (const auto angle = number("angle_deg")) {
    if (*angle < 0.0 || *angle > 90.0) {
      fail("angle_deg", "must be between 0 and 90, got " + shown(*angle));
    } else {
      query.angle_deg = *angle;
    }
  }
  query.charge.tnt_equivalent_kg = query.charge_kg * query.tnt_factor;
  query.charge.impulse_tnt_equivalent_kg = query.charge_kg * query.impulse_tnt_factor;
  // Beyond the fits' range (Z up to 40 m/kg^(1/3)) the result is flagged, not refused; but far
  // beyond it their extrapolation underflows to an overpressure of 0 Pa, which the reflection
  // cannot take (distance_m=5.8e89 tripped its assert; found by fuzz_http).
  constexpr double kMaxScaledDistance = 1e6;  // m/kg^(1/3)
  // A TNT equivalent that overflows (1e200 kg times a factor of 1e200) would give a scaled
  // distance of 0, which the curves cannot take; the impulse equivalent is checked alike.
  if (problems.empty()) {
    for (const double w :
         {query.charge.tnt_equivalent_kg, query.charge.impulse_tnt_equivalent_kg}) {
      if (!std::isfinite(w)) {
        fail("charge_kg", "times the TNT factor is not a finite mass (" + shown(w) +
                              " kg of TNT); use a smaller charge or factor");
        break;
      }
      const double scaled = query.distance_m / std::cbrt(w);
      if (!(scaled > 0.0)) {
        fail("distance_m", "is too small for the charge: its scaled distance underflows to 0");
        break;
      }
      if (!(scaled <= kMaxScaledDistance)) {
        fail("distance_m", "gives a scaled distance of " + shown(scaled) +
                               " m/kg^(1/3), beyond the 1e+06 this calculator extrapolates to "
                               "(its fits hold up to 40); move the point closer or use a larger "
                               "charge");
        break;
      }
    }
  }
  return problems;
}

BlastAnswer calculate_blast(const BlastQuery& query) {
  BlastAnswer answer;
  answer.point = blast::blast_point(query.charge, query.distance_m);
  answer.reflection = reflect(answer.point, query.angle_deg * std::numbers::pi / 180.0);
  answer.incident_pulse =
      blast::make_pulse(blast::PulseShape::friedlander, answer.point.incident_overpressure_pa,
                        answer.point.positive_duration_s, answer.point.incident_impulse_pa_s);
  answer.reflected_pulse =
      blast::make_pulse(blast::PulseShape::friedlander, answer.reflection.overpressure_pa,
                        answer.point.positive_duration_s, answer.reflection.impulse_pa_s);
  answer.negative_phase = blast::negative_phase(query.charge, query.distance_m);
  return answer;
}

nlohmann::ordered_json blast_report_json(const blast::BlastPoint& point,
                                         const blast::ObliqueReflection& reflection) {
  nlohmann::ordered_json out;
  out["scaled_distance_m_kg13"] = point.scaled_distance_m_kg13;
  out["tnt_equivalent_kg"] = point.tnt_equivalent_kg;
  out["impulse_tnt_equivalent_kg"] = point.impulse_tnt_equivalent_kg;
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

nlohmann::ordered_json blast_inputs_json(const BlastQuery& query) {
  nlohmann::ordered_json out;
  out["charge_kg"] = query.charge_kg;
  out["distance_m"] = query.distance_m;
  out["explosive"] = query.explosive_name;
  out["tnt_factor"] = query.tnt_factor;
  out["impulse_tnt_factor"] = query.impulse_tnt_factor;
  out["burst"] = query.charge.burst == blast::Burst::air ? "air" : "surface";
  out["surface_model"] = query.charge.surface_model == blast::SurfaceBurstModel::hemispherical
                             ? "hemispherical"
                             : "factor_1_8";
  out["angle_deg"] = query.angle_deg;
  return out;
}

namespace {

nlohmann::ordered_json pulse_json(const blast::Pulse& pulse) {
  nlohmann::ordered_json out;
  out["peak_kpa"] = pulse.peak_pa * 1e-3;
  out["duration_ms"] = pulse.duration_s * 1e3;
  out["impulse_kpa_ms"] = pulse.total_impulse_pa_s();  // Pa*s == kPa*ms
  out["decay"] = pulse.decay;
  return out;
}

}  // namespace

nlohmann::ordered_json blast_answer_json(const BlastQuery& query, const BlastAnswer& answer) {
  nlohmann::ordered_json out = blast_report_json(answer.point, answer.reflection);
  out["incident_pulse"] = pulse_json(answer.incident_pulse);
  out["reflected_pulse"] = pulse_json(answer.reflected_pulse);
  const blast::NegativePhase& negative = answer.negative_phase;
  nlohmann::ordered_json suction;
  suction["underpressure_kpa"] = negative.underpressure_pa * 1e-3;
  suction["impulse_kpa_ms"] = negative.impulse_pa_s;  // Pa*s == kPa*ms
  suction["duration_ms"] = negative.duration_s * 1e3;
  suction["chart_duration_ms"] = negative.chart_duration_s * 1e3;
  suction["in_validity_range"] = negative.in_validity_range;
  out["negative_phase"] = std::move(suction);
  out["inputs"] = blast_inputs_json(query);
  return out;
}

std::string blast_pulse_csv(const BlastAnswer& answer, std::size_t samples) {
  const double arrival_s = answer.point.arrival_time_s;
  const double positive_s = answer.incident_pulse.duration_s;
  const double end_s =
      std::max(positive_s + answer.negative_phase.duration_s, answer.reflected_pulse.duration_s);
  std::string out = "time_ms,incident_kpa,reflected_kpa\n";
  char line[96];
  for (std::size_t i = 0; i < samples; ++i) {
    const double t_s = end_s * static_cast<double>(i) / static_cast<double>(samples - 1);
    const double incident_pa = t_s < positive_s
                                   ? answer.incident_pulse.pressure_pa(t_s)
                                   : answer.negative_phase.pressure_pa(t_s - positive_s);
    std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g\n", (arrival_s + t_s) * 1e3,
                  incident_pa * 1e-3, answer.reflected_pulse.pressure_pa(t_s) * 1e-3);
    out += line;
  }
  return out;
}

blast::ObliqueReflection reflect(const blast::BlastPoint& point, double angle_rad) {
  return blast::oblique_reflection(point.incident_overpressure_pa, point.incident_impulse_pa_s,
                                   point.reflected_overpressure_pa, point.reflected_impulse_pa_s,
                                   angle_rad);
}

}  // namespace brisance::io
