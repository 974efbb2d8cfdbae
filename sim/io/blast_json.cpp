// sim/io/blast_json: see blast_json.hpp.
#include "sim/io/blast_json.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "sim/blast/explosives.hpp"

namespace brisance::io {
namespace {

// A finite number, or nullopt (the caller reports it).
std::optional<double> to_number(std::string_view text) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::string shown(double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("?");
}

}  // namespace

std::optional<BlastQueryError> parse_blast_query(
    const std::function<std::optional<std::string>(std::string_view name)>& lookup,
    const std::function<std::string(std::string_view name)>& spell, BlastQuery& query) {
  const auto error = [&](std::string_view name, const std::string& message) {
    return BlastQueryError{std::string(name), spell(name) + " " + message};
  };
  // A number parameter: nullopt if absent, an error if not a finite number.
  std::optional<BlastQueryError> problem;
  const auto number = [&](std::string_view name) -> std::optional<double> {
    const auto text = lookup(name);
    if (!text) return std::nullopt;
    const auto value = to_number(*text);
    if (!value) problem = error(name, "must be a finite number, got '" + *text + "'");
    return value;
  };
  const auto positive = [&](std::string_view name, std::string_view what) -> double {
    const auto value = number(name);
    if (problem) return 0.0;
    if (!value) {
      problem = error(name, "is required: " + std::string(what) + " (> 0)");
      return 0.0;
    }
    if (!(*value > 0.0)) problem = error(name, "must be greater than 0, got " + shown(*value));
    return *value;
  };

  query.charge_kg = positive("charge_kg", "the charge mass in kg");
  if (problem) return problem;
  query.distance_m = positive("distance_m", "the distance from the charge centre in m");
  if (problem) return problem;

  const auto explosive = lookup("explosive");
  if (explosive && lookup("tnt_factor"))
    return error("tnt_factor",
                 "and " + spell("explosive") + " name the explosive twice: give one, not both");
  if (lookup("tnt_factor")) {
    query.tnt_factor = positive("tnt_factor", "kg TNT per kg of explosive");
    if (problem) return problem;
    query.explosive_name = "custom";
  } else if (explosive) {
    const auto found = blast::find_explosive(*explosive);
    if (!found)
      return error("explosive", "names no known explosive ('" + *explosive +
                                    "'); known: " + blast::known_explosive_names() + " (or give " +
                                    spell("tnt_factor") + ")");
    query.explosive_name = found->name;
    query.tnt_factor = found->tnt_factor;
  }

  if (const auto burst = lookup("burst")) {
    if (*burst == "air") {
      query.charge.burst = blast::Burst::air;
    } else if (*burst == "surface") {
      query.charge.burst = blast::Burst::surface;
    } else {
      return error("burst", "must be 'air' or 'surface', got '" + *burst + "'");
    }
  }
  if (const auto model = lookup("surface_model")) {
    if (*model == "hemispherical") {
      query.charge.surface_model = blast::SurfaceBurstModel::hemispherical;
    } else if (*model == "factor_1_8") {
      query.charge.surface_model = blast::SurfaceBurstModel::factor_1_8;
    } else {
      return error("surface_model",
                   "must be 'hemispherical' or 'factor_1_8', got '" + *model + "'");
    }
  }
  if (const auto angle = number("angle_deg")) {
    if (*angle < 0.0 || *angle > 90.0)
      return error("angle_deg", "must be between 0 and 90, got " + shown(*angle));
    query.angle_deg = *angle;
  }
  if (problem) return problem;
  query.charge.tnt_equivalent_kg = query.charge_kg * query.tnt_factor;
  return std::nullopt;
}

BlastAnswer calculate_blast(const BlastQuery& query) {
  BlastAnswer answer;
  answer.point = blast::blast_point(query.charge, query.distance_m);
  answer.reflection = reflect(answer.point, query.angle_deg * std::numbers::pi / 180.0);
  return answer;
}

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
