// sim/io/response_json: see response_json.hpp.
#include "sim/io/response_json.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

#include "sim/blast/pulse.hpp"
#include "sim/io/number_text.hpp"
#include "sim/response/limits.hpp"

namespace brisance::io {
namespace {

// The Friedlander decay coefficient used when a pulse is given without its impulse.
constexpr double kDefaultFriedlanderDecay = 1.0;
// Largest ductility ratio and support rotation a P–I request may ask for: beyond the PDC-TR 06-08
// B4 bounds (mu 25, theta 20 deg) with room to spare, and they keep each bisection's runs short.
constexpr double kMaxPiDuctility = 100.0;
constexpr double kMaxPiRotationDeg = 45.0;

nlohmann::ordered_json or_null(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

// A JSON object's members as the text a flag would carry: numbers as written, strings as they
// are, anything else as its JSON text (which then fails the number or name check).
std::function<std::optional<std::string>(std::string_view)> json_lookup(const nlohmann::json& j) {
  return [&j](std::string_view name) -> std::optional<std::string> {
    const auto it = j.find(std::string(name));
    if (it == j.end()) return std::nullopt;
    if (it->is_string()) return it->get<std::string>();
    return it->dump();
  };
}

// Members of `j` not in `known` are errors under `pointer`.
void unknown_members(const nlohmann::json& j, const std::string& pointer,
                     std::initializer_list<std::string_view> known,
                     std::vector<InputError>& errors) {
  for (const auto& [key, value] : j.items()) {
    bool found = false;
    for (std::string_view k : known)
      found = found || k == key;
    if (!found) errors.push_back({pointer + "/" + key, "is not a known field; remove it"});
  }
}

void element_errors(const nlohmann::json& body, response::Element& element,
                    std::vector<InputError>& errors) {
  if (!body.contains("element")) {
    errors.push_back({"/element", "is required: the element object (docs/response.md)"});
    return;
  }
  const response::ElementParse parsed = response::parse_element(body.at("element"));
  for (const response::FieldError& e : parsed.errors)
    errors.push_back({e.pointer == "/" ? "/element" : "/element" + e.pointer, e.message});
  if (parsed.element) element = *parsed.element;
}

}  // namespace

void parse_pulse_query(const std::function<std::optional<std::string>(std::string_view)>& lookup,
                       const std::function<std::string(std::string_view)>& spell, PulseQuery& pulse,
                       std::vector<BlastQueryError>& problems) {
  const auto fail = [&](std::string_view name, const std::string& message) {
    problems.push_back(BlastQueryError{std::string(name), spell(name) + " " + message});
  };
  const auto positive = [&](std::string_view name, bool required) -> std::optional<double> {
    const auto text = lookup(name);
    if (!text) {
      if (required) fail(name, "is required (> 0)");
      return std::nullopt;
    }
    const auto value = to_number(*text);
    if (!value) {
      fail(name, "must be a finite number, got '" + *text + "'");
      return std::nullopt;
    }
    if (!(*value > 0.0)) {
      fail(name, "must be greater than 0, got " + shown(*value));
      return std::nullopt;
    }
    return value;
  };
  pulse.peak_kpa = positive("peak_kpa", true).value_or(0.0);
  pulse.duration_ms = positive("duration_ms", true).value_or(0.0);
  if (const auto shape = lookup("shape")) {
    if (*shape == "triangular") {
      pulse.friedlander = false;
    } else if (*shape == "friedlander") {
      pulse.friedlander = true;
    } else {
      fail("shape", "must be 'triangular' or 'friedlander', got '" + *shape + "'");
    }
  }
  pulse.impulse_kpa_ms = positive("impulse_kpa_ms", false);
  if (pulse.impulse_kpa_ms && !pulse.friedlander && lookup("impulse_kpa_ms")) {
    fail("impulse_kpa_ms",
         "applies to the friedlander shape only (a triangle's impulse is peak x duration / 2)");
  }
}

LoadAnswer build_load(const LoadQuery& query) {
  LoadAnswer out;
  if (query.charge) {
    const BlastAnswer blast = calculate_blast(*query.charge);
    const blast::Pulse pulse =
        blast::make_pulse(blast::PulseShape::friedlander, blast.reflection.overpressure_pa,
                          blast.point.positive_duration_s, blast.reflection.impulse_pa_s);
    out.load.components.push_back(response::pulse_component(pulse, blast.point.arrival_time_s));
    out.peak_pressure_kpa = pulse.peak_pa * 1e-3;
    out.impulse_kpa_ms = pulse.total_impulse_pa_s();  // Pa*s == kPa*ms
    out.duration_ms = pulse.duration_s * 1e3;
    out.arrival_time_ms = blast.point.arrival_time_s * 1e3;
    out.shape = "friedlander";
    out.in_validity_range = blast.point.in_validity_range && blast.reflection.in_chart_range;
    return out;
  }
  const PulseQuery& p = *query.pulse;
  const double peak_pa = p.peak_kpa * 1e3;
  const double duration_s = p.duration_ms * 1e-3;
  blast::Pulse pulse;
  if (p.friedlander) {
    const double impulse_pa_s =
        p.impulse_kpa_ms
            ? *p.impulse_kpa_ms
            : peak_pa * duration_s * blast::friedlander_area_ratio(kDefaultFriedlanderDecay);
    pulse = blast::make_pulse(blast::PulseShape::friedlander, peak_pa, duration_s, impulse_pa_s);
  } else {
    pulse = blast::make_pulse(blast::PulseShape::triangle_same_period, peak_pa, duration_s,
                              0.5 * peak_pa * duration_s);
  }
  out.load.components.push_back(response::pulse_component(pulse, 0.0));
  out.peak_pressure_kpa = pulse.peak_pa * 1e-3;
  out.impulse_kpa_ms = pulse.total_impulse_pa_s();
  out.duration_ms = pulse.duration_s * 1e3;
  out.shape = p.friedlander ? "friedlander" : "triangular";
  return out;
}

std::optional<InputError> check_load_cost(const response::SdofSystem& system,
                                          const LoadAnswer& load, std::string_view pointer) {
  const double period_s = system.natural_period_s();
  const double end_s = load.load.end_s();
  if (!(end_s <= kMaxLoadPeriods * period_s)) {
    return InputError{std::string(pointer),
                      "gives a load that ends " + shown(end_s * 1e3) + " ms after detonation, " +
                          shown(std::round(end_s / period_s)) +
                          " natural periods of the element (" + shown(period_s * 1e3) +
                          " ms); at most " + shown(kMaxLoadPeriods) +
                          " are allowed: shorten the pulse, bring the charge closer, or check "
                          "the element's mass and stiffness"};
  }
  return std::nullopt;
}

nlohmann::ordered_json response_json(const response::Element& element, const LoadAnswer& load,
                                     bool history) {
  const response::SdofSystem system = response::equivalent_system(element);
  response::SolveOptions options;
  options.record_history = history;
  const response::SdofResult r = response::solve_sdof(system, load.load, options);

  nlohmann::ordered_json out;
  out["peak_displacement_m"] = r.peak_displacement_m;
  out["time_to_peak_ms"] = r.time_to_peak_s * 1e3;
  out["ductility"] = or_null(r.ductility);
  out["support_rotation_deg"] = or_null(r.support_rotation_deg);
  out["damage"] = nullptr;
  out["limits"] = nullptr;
  if (element.limits) {
    if (const auto limits = response::find_limits(*element.limits)) {
      // An elastic model has no yield: it is judged by its rotation alone.
      out["damage"] = std::string(response::to_string(
          response::damage_level(*limits, r.ductility.value_or(0.0), r.support_rotation_deg)));
      out["limits"] = *element.limits;
    }
  }
  out["permanent_set_m"] = r.permanent_set_m;
  out["min_displacement_m"] = r.min_displacement_m;
  out["natural_period_ms"] = system.natural_period_s() * 1e3;
  const double elastic_limit = system.elastic_limit_m();
  out["elastic_limit_m"] = std::isfinite(elastic_limit) ? nlohmann::ordered_json(elastic_limit)
                                                        : nlohmann::ordered_json(nullptr);
  out["load"] = {{"shape", load.shape},
                 {"peak_pressure_kpa", load.peak_pressure_kpa},
                 {"impulse_kpa_ms", load.impulse_kpa_ms},
                 {"duration_ms", load.duration_ms},
                 {"arrival_time_ms", load.arrival_time_ms},
                 {"in_validity_range", load.in_validity_range}};
  out["end_time_ms"] = r.end_time_s * 1e3;
  out["steps"] = r.steps;
  out["warnings"] = r.warnings;
  if (history) {
    const std::size_t n = r.history.size();
    const std::size_t stride =
        n > kMaxHistorySamples ? (n + kMaxHistorySamples - 1) / kMaxHistorySamples : 1;
    std::size_t peak = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (r.history[i].displacement_m > r.history[peak].displacement_m) peak = i;
    nlohmann::ordered_json time = nlohmann::ordered_json::array();
    nlohmann::ordered_json displacement = nlohmann::ordered_json::array();
    nlohmann::ordered_json velocity = nlohmann::ordered_json::array();
    nlohmann::ordered_json resistance = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < n; ++i) {
      if (i % stride != 0 && i != peak && i + 1 != n) continue;
      const response::HistorySample& s = r.history[i];
      time.push_back(s.time_s * 1e3);
      displacement.push_back(s.displacement_m);
      velocity.push_back(s.velocity_m_s);
      resistance.push_back(s.resistance_n * 1e-3);
    }
    out["history"] = {{"time_ms", time},
                      {"displacement_m", displacement},
                      {"velocity_m_s", velocity},
                      {"resistance_kn", resistance}};
  }
  return out;
}

std::optional<double> pi_displacement_limit(const response::Element& element, const PiLimit& limit,
                                            std::string_view ductility_name,
                                            std::string_view rotation_name,
                                            std::vector<InputError>& errors) {
  const response::SdofSystem system = response::equivalent_system(element);
  const bool elastic = element.resistance.type == response::ResistanceType::elastic;
  if (limit.ductility && limit.rotation_deg) {
    errors.push_back({std::string(rotation_name),
                      "and " + std::string(ductility_name) + " both set the limit: give one"});
    return std::nullopt;
  }
  if (limit.rotation_deg) {
    const double theta = *limit.rotation_deg;
    if (!(theta > 0.0 && theta <= kMaxPiRotationDeg)) {
      errors.push_back(
          {std::string(rotation_name),
           "must be > 0 and <= " + shown(kMaxPiRotationDeg) + " degrees, got " + shown(theta)});
      return std::nullopt;
    }
    if (!element.span_m) {
      errors.push_back({std::string(rotation_name),
                        "needs the element's support span (support.span_m) to turn a rotation "
                        "into a displacement"});
      return std::nullopt;
    }
    return response::displacement_for_rotation(system, theta);
  }
  if (elastic) {
    errors.push_back({std::string(limit.ductility ? ductility_name : rotation_name),
                      limit.ductility ? "does not apply to an elastic element (it never yields): "
                                        "give a support rotation instead"
                                      : "is required for an elastic element (it has no yield "
                                        "displacement for a ductility ratio)"});
    return std::nullopt;
  }
  const double mu = limit.ductility.value_or(1.0);
  if (!(mu > 0.0 && mu <= kMaxPiDuctility)) {
    errors.push_back({std::string(ductility_name),
                      "must be > 0 and <= " + shown(kMaxPiDuctility) + ", got " + shown(mu)});
    return std::nullopt;
  }
  return response::displacement_for_ductility(system, mu);
}

namespace {

// Ductility and rotation of a displacement limit, as the P–I and W–R answers give them.
void limit_fields(const response::Element& element, const response::SdofSystem& system,
                  double displacement_limit_m, nlohmann::ordered_json& out) {
  out["displacement_limit_m"] = displacement_limit_m;
  const double elastic_limit = system.elastic_limit_m();
  out["ductility"] = std::isfinite(elastic_limit)
                         ? nlohmann::ordered_json(displacement_limit_m / elastic_limit)
                         : nlohmann::ordered_json(nullptr);
  out["rotation_deg"] =
      element.span_m
          ? nlohmann::ordered_json(std::atan(displacement_limit_m / (0.5 * *element.span_m)) *
                                   180.0 / std::numbers::pi)
          : nlohmann::ordered_json(nullptr);
  out["natural_period_ms"] = system.natural_period_s() * 1e3;
}

}  // namespace

nlohmann::ordered_json pi_json(const response::Element& element, double displacement_limit_m,
                               std::size_t points) {
  const response::SdofSystem system = response::equivalent_system(element);
  response::PiOptions options;
  options.points = points;
  const response::PiCurve curve = response::pi_curve(system, displacement_limit_m, options);
  nlohmann::ordered_json out;
  limit_fields(element, system, displacement_limit_m, out);
  out["impulsive_asymptote_kpa_ms"] = curve.impulsive_asymptote_pa_s;  // Pa*s == kPa*ms
  out["quasi_static_asymptote_kpa"] = curve.quasi_static_asymptote_pa * 1e-3;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const response::PiPoint& p : curve.points) {
    list.push_back({{"duration_ms", p.duration_s * 1e3},
                    {"peak_pressure_kpa", p.peak_pressure_pa * 1e-3},
                    {"impulse_kpa_ms", p.impulse_pa_s}});
  }
  out["points"] = list;
  out["solves"] = curve.solves;
  out["warnings"] = curve.warnings;
  return out;
}

namespace {

blast::Charge wr_charge(const WrQuery& query, double mass_kg) {
  blast::Charge charge;
  charge.tnt_equivalent_kg = mass_kg;
  charge.burst = query.burst;
  return charge;
}

}  // namespace

std::optional<InputError> check_wr_cost(const response::SdofSystem& system, const WrQuery& query,
                                        std::string_view pointer) {
  const blast::BlastPoint far =
      blast::blast_point(wr_charge(query, kMaxWrChargeKg), query.max_distance_m);
  const double period_s = system.natural_period_s();
  const double end_s = far.arrival_time_s + far.positive_duration_s;
  if (!(end_s <= kMaxLoadPeriods * period_s)) {
    return InputError{std::string(pointer),
                      "reaches stand-offs where the largest charge searched (" +
                          shown(kMaxWrChargeKg) + " kg) gives a load ending " + shown(end_s * 1e3) +
                          " ms after detonation, more than " + shown(kMaxLoadPeriods) +
                          " natural periods of the element (" + shown(period_s * 1e3) +
                          " ms): bring the largest stand-off closer"};
  }
  return std::nullopt;
}

nlohmann::ordered_json wr_json(const response::Element& element, double displacement_limit_m,
                               std::size_t points, const WrQuery& query) {
  const response::SdofSystem system = response::equivalent_system(element);
  std::vector<double> distances(points);
  for (std::size_t k = 0; k < points; ++k) {
    const double s = points > 1 ? static_cast<double>(k) / static_cast<double>(points - 1) : 0.0;
    distances[k] = query.min_distance_m * std::pow(query.max_distance_m / query.min_distance_m, s);
  }
  response::WrOptions options;
  options.charge = wr_charge(query, 1.0);
  options.angle_rad = query.angle_deg * std::numbers::pi / 180.0;
  options.min_charge_kg = kMinWrChargeKg;
  options.max_charge_kg = kMaxWrChargeKg;
  const std::vector<response::WrPoint> curve =
      response::wr_curve(system, displacement_limit_m, distances, options);
  nlohmann::ordered_json out;
  out["diagram"] = "wr";
  limit_fields(element, system, displacement_limit_m, out);
  out["burst"] = query.burst == blast::Burst::surface ? "surface" : "air";
  out["angle_deg"] = query.angle_deg;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  std::size_t warnings = 0;
  for (const response::WrPoint& p : curve) {
    const bool found = p.charge_kg > 0.0;
    warnings += found ? 0 : 1;
    list.push_back(
        {{"distance_m", p.distance_m},
         {"charge_kg", found ? nlohmann::ordered_json(p.charge_kg) : nlohmann::ordered_json()},
         {"scaled_distance_m_kg13",
          found ? nlohmann::ordered_json(p.distance_m / std::cbrt(p.charge_kg))
                : nlohmann::ordered_json()},
         {"in_validity_range", p.in_validity_range}});
  }
  out["points"] = list;
  out["warnings"] = warnings;
  return out;
}

std::vector<InputError> parse_response_request(const nlohmann::json& body,
                                               ResponseRequest& request) {
  std::vector<InputError> errors;
  if (!body.is_object()) return {{"", "must be an object: {\"element\", \"charge\" | \"pulse\"}"}};
  unknown_members(body, "", {"element", "charge", "pulse", "history"}, errors);
  element_errors(body, request.element, errors);
  const bool charge = body.contains("charge");
  const bool pulse = body.contains("pulse");
  std::string load_pointer;
  if (charge && pulse) {
    errors.push_back({"/pulse", "and /charge both give the load: give one"});
  } else if (!charge && !pulse) {
    errors.push_back({"/charge",
                      "is required: give the load as a charge {charge_kg, distance_m, ...} or a "
                      "pulse {peak_kpa, duration_ms, ...}"});
  } else {
    const std::string name = charge ? "charge" : "pulse";
    const std::string base = "/" + name;
    const nlohmann::json& j = body.at(name);
    if (!j.is_object()) {
      errors.push_back({base, "must be an object"});
    } else {
      std::vector<BlastQueryError> problems;
      const auto spell = [](std::string_view n) { return std::string(n); };
      if (charge) {
        unknown_members(j, base,
                        {"charge_kg", "distance_m", "explosive", "tnt_factor", "impulse_tnt_factor",
                         "burst", "surface_model", "angle_deg"},
                        errors);
        BlastQuery query;
        problems = parse_blast_query(json_lookup(j), spell, query);
        request.load.charge = query;
        load_pointer = base + "/distance_m";
      } else {
        unknown_members(j, base, {"peak_kpa", "duration_ms", "shape", "impulse_kpa_ms"}, errors);
        PulseQuery query;
        parse_pulse_query(json_lookup(j), spell, query, problems);
        request.load.pulse = query;
        load_pointer = base + "/duration_ms";
      }
      for (const BlastQueryError& p : problems) {
        // The message starts with the parameter's name; the pointer names it instead.
        std::string message = p.message.substr(std::min(p.message.size(), p.parameter.size() + 1));
        errors.push_back({base + "/" + p.parameter, message});
      }
    }
  }
  if (body.contains("history")) {
    if (body.at("history").is_boolean()) {
      request.history = body.at("history").get<bool>();
    } else {
      errors.push_back({"/history", "must be true or false"});
    }
  }
  if (errors.empty()) {
    const LoadAnswer load = build_load(request.load);
    if (auto cost =
            check_load_cost(response::equivalent_system(request.element), load, load_pointer)) {
      errors.push_back(std::move(*cost));
    }
  }
  return errors;
}

std::vector<InputError> parse_pi_request(const nlohmann::json& body, PiRequest& request) {
  std::vector<InputError> errors;
  if (!body.is_object()) return {{"", "must be an object: {\"element\", \"ductility\" | ...}"}};
  unknown_members(body, "",
                  {"element", "ductility", "rotation_deg", "points", "diagram", "distances_m",
                   "burst", "angle_deg"},
                  errors);
  element_errors(body, request.element, errors);
  PiLimit limit;
  const auto number = [&](const char* key) -> std::optional<double> {
    if (!body.contains(key)) return std::nullopt;
    const nlohmann::json& v = body.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      errors.push_back({std::string("/") + key, "must be a finite number"});
      return std::nullopt;
    }
    return v.get<double>();
  };
  limit.ductility = number("ductility");
  limit.rotation_deg = number("rotation_deg");
  if (const auto points = number("points")) {
    if (!(*points >= kMinPiPoints && *points <= kMaxPiPoints && std::floor(*points) == *points)) {
      errors.push_back({"/points", "must be a whole number from " + std::to_string(kMinPiPoints) +
                                       " to " + std::to_string(kMaxPiPoints)});
    } else {
      request.points = static_cast<std::size_t>(*points);
    }
  }
  if (body.contains("diagram")) {
    const nlohmann::json& d = body.at("diagram");
    if (d == "wr") {
      request.wr = true;
    } else if (d != "pi") {
      errors.push_back({"/diagram",
                        "must be \"pi\" (pressure-impulse) or \"wr\" (charge "
                        "weight against stand-off)"});
    }
  }
  for (const char* key : {"distances_m", "burst", "angle_deg"}) {
    if (body.contains(key) && !request.wr)
      errors.push_back({std::string("/") + key, "is for \"diagram\": \"wr\" only"});
  }
  if (request.wr && body.contains("distances_m")) {
    const nlohmann::json& d = body.at("distances_m");
    if (!d.is_array() || d.size() != 2 || !d[0].is_number() || !d[1].is_number()) {
      errors.push_back({"/distances_m", "must be [min, max] in m"});
    } else {
      request.wr_query.min_distance_m = d[0].get<double>();
      request.wr_query.max_distance_m = d[1].get<double>();
      if (!(request.wr_query.min_distance_m >= kMinWrDistanceM &&
            request.wr_query.min_distance_m < request.wr_query.max_distance_m &&
            request.wr_query.max_distance_m <= kMaxWrDistanceM))
        errors.push_back({"/distances_m", "must be [min, max] with " + shown(kMinWrDistanceM) +
                                              " <= min < max <= " + shown(kMaxWrDistanceM) + " m"});
    }
  }
  if (request.wr && body.contains("burst")) {
    const nlohmann::json& b = body.at("burst");
    if (b == "surface") {
      request.wr_query.burst = blast::Burst::surface;
    } else if (b != "air") {
      errors.push_back({"/burst", "must be \"air\" or \"surface\""});
    }
  }
  if (request.wr) {
    if (const auto angle = number("angle_deg")) {
      if (!(*angle >= 0.0 && *angle < 90.0))
        errors.push_back({"/angle_deg", "must be in [0, 90) degrees"});
      else
        request.wr_query.angle_deg = *angle;
    }
  }
  if (errors.empty()) {
    if (const auto y =
            pi_displacement_limit(request.element, limit, "/ductility", "/rotation_deg", errors)) {
      request.displacement_limit_m = *y;
    }
  }
  if (errors.empty() && request.wr) {
    if (const auto cost = check_wr_cost(response::equivalent_system(request.element),
                                        request.wr_query, "/distances_m"))
      errors.push_back(*cost);
  }
  return errors;
}

}  // namespace brisance::io
