// Parsing and validation of the scene JSON (DESIGN.md "Contracts"). Every check lives here, so
// the simulator can trust a Scene. The parser never stops at the first problem: each value is
// checked where it is, and an invalid value is reported and skipped (its object or charge drops
// out of the cross-checks) so one run lists everything the user has to fix.
#include "sim/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <unordered_map>
#include <utility>

#include <nlohmann/json.hpp>

#include "sim/blast/explosives.hpp"
#include "sim/scene/generators.hpp"

namespace brisance::scene {

namespace {

using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Pointers, messages and the error list

// RFC 6901: '~' becomes "~0" and '/' becomes "~1" inside a reference token.
std::string escape_token(std::string_view token) {
  std::string escaped;
  for (char c : token) {
    if (c == '~') {
      escaped += "~0";
    } else if (c == '/') {
      escaped += "~1";
    } else {
      escaped += c;
    }
  }
  return escaped;
}

std::string child(const std::string& pointer, std::string_view key) {
  return pointer + "/" + escape_token(key);
}

std::string child(const std::string& pointer, std::size_t index) {
  return pointer + "/" + std::to_string(index);
}

std::string format_number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

std::string in_quotes(std::string_view text) {
  return "'" + std::string(text) + "'";
}

// What a JSON value is, for "got ..." in messages; long values are cut short.
std::string describe(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return value.get<bool>() ? "true" : "false";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array of " + std::to_string(value.size());
    case json::value_t::string: {
      std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
      if (text.size() > 42) text = text.substr(0, 40) + "...\"";
      return "the string " + text;
    }
    default: {
      std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
      if (text.size() > 42) text = text.substr(0, 40) + "...";
      return text;
    }
  }
}

std::string join(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) {
    if (!text.empty()) text += ", ";
    text += name;
  }
  return text;
}

std::string join(std::initializer_list<std::string_view> names) {
  std::string text;
  for (std::string_view name : names) {
    if (!text.empty()) text += ", ";
    text += name;
  }
  return text;
}

// Levenshtein distance, for "did you mean" hints on misspelt field and enum names.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitution});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string did_you_mean(std::string_view given, std::initializer_list<std::string_view> choices) {
  std::string_view best;
  std::size_t best_distance = 3;  // only close matches are worth suggesting
  for (std::string_view choice : choices) {
    const std::size_t distance = edit_distance(given, choice);
    if (distance < best_distance) {
      best_distance = distance;
      best = choice;
    }
  }
  return best.empty() ? std::string() : "did you mean " + in_quotes(best) + "? ";
}

class Errors {
 public:
  void add(std::string pointer, std::string message) {
    list_.push_back({std::move(pointer), std::move(message)});
  }
  std::size_t count() const { return list_.size(); }
  std::vector<ValidationError> take() { return std::move(list_); }

 private:
  std::vector<ValidationError> list_;
};

// Counts the errors added while it lives: ok() is true if there were none.
class ErrorScope {
 public:
  explicit ErrorScope(const Errors& errors) : errors_(errors), start_(errors.count()) {}
  bool ok() const { return errors_.count() == start_; }

 private:
  const Errors& errors_;
  std::size_t start_;
};

// ---------------------------------------------------------------------------------------------
// Typed readers. Each reports a problem at the exact pointer and returns nullopt.

// Allowed range of a number and its unit, for the check and for the message.
struct Bound {
  double low = -std::numeric_limits<double>::infinity();
  bool low_open = false;
  double high = std::numeric_limits<double>::infinity();
  bool high_open = false;
  std::string_view unit;   // "kg", "m", ... or empty
  std::string limit_name;  // the Limits field behind `high`, if any

  bool contains(double value) const {
    if (low_open ? !(value > low) : !(value >= low)) return false;
    if (high_open ? !(value < high) : !(value <= high)) return false;
    return true;
  }

  std::string text() const {
    const bool has_low = std::isfinite(low);
    const bool has_high = std::isfinite(high);
    std::string range;
    if (has_low && has_high) {
      range = std::string(" in ") + (low_open ? "(" : "[") + format_number(low) + ", " +
              format_number(high) + (high_open ? ")" : "]");
    } else if (has_low) {
      range = std::string(low_open ? " > " : " >= ") + format_number(low);
    } else if (has_high) {
      range = std::string(high_open ? " < " : " <= ") + format_number(high);
    }
    std::string text = "a number" + range;
    if (!unit.empty()) text += " (" + std::string(unit) + ")";
    if (!limit_name.empty()) text += ", the limit " + limit_name;
    return text;
  }
};

Bound range(double low, bool low_open, double high, bool high_open, std::string_view unit = {},
            std::string limit_name = {}) {
  Bound bound;
  bound.low = low;
  bound.low_open = low_open;
  bound.high = high;
  bound.high_open = high_open;
  bound.unit = unit;
  bound.limit_name = std::move(limit_name);
  return bound;
}
constexpr double kInfinity = std::numeric_limits<double>::infinity();
Bound any_number(std::string_view unit = {}) {
  return range(-kInfinity, false, kInfinity, false, unit);
}
Bound positive(std::string_view unit = {}) {
  return range(0.0, true, kInfinity, false, unit);
}
Bound non_negative(std::string_view unit = {}) {
  return range(0.0, false, kInfinity, false, unit);
}

// A finite number within `bound`; integers are numbers too, booleans are not.
std::optional<double> read_number(const json& value, const std::string& pointer,
                                  std::string_view name, const Bound& bound, Errors& errors) {
  if (!value.is_number() || !std::isfinite(value.get<double>())) {
    errors.add(pointer, in_quotes(name) + " must be " + bound.text() + "; got " + describe(value));
    return std::nullopt;
  }
  const double number = value.get<double>();
  if (!bound.contains(number)) {
    errors.add(pointer, in_quotes(name) + " must be " + bound.text() + "; got " + describe(value));
    return std::nullopt;
  }
  return number;
}

// A whole number in [low, high]; 3.0 counts as 3 (JSON Schema's "integer"), 3.5 does not.
std::optional<std::int64_t> read_integer(const json& value, const std::string& pointer,
                                         std::string_view name, std::int64_t low, std::int64_t high,
                                         Errors& errors) {
  const std::string expected =
      "an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
  std::optional<std::int64_t> integer;
  if (value.is_number_unsigned()) {
    const auto u = value.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      integer = static_cast<std::int64_t>(u);
  } else if (value.is_number_integer()) {
    integer = value.get<std::int64_t>();
  } else if (value.is_number_float()) {
    const double d = value.get<double>();
    // 2^63 is the first double outside int64.
    if (std::isfinite(d) && d == std::floor(d) && d >= -9.2233720368547758e18 &&
        d < 9.2233720368547758e18)
      integer = static_cast<std::int64_t>(d);
  }
  if (!integer || *integer < low || *integer > high) {
    errors.add(pointer, in_quotes(name) + " must be " + expected + "; got " + describe(value));
    return std::nullopt;
  }
  return integer;
}

std::optional<bool> read_bool(const json& value, const std::string& pointer, std::string_view name,
                              Errors& errors) {
  if (!value.is_boolean()) {
    errors.add(pointer, in_quotes(name) + " must be true or false; got " + describe(value));
    return std::nullopt;
  }
  return value.get<bool>();
}

// One of a fixed set of strings; returns its index in `choices`.
std::optional<std::size_t> read_choice(const json& value, const std::string& pointer,
                                       std::string_view name,
                                       std::initializer_list<std::string_view> choices,
                                       Errors& errors) {
  if (value.is_string()) {
    const auto& text = value.get_ref<const std::string&>();
    std::size_t index = 0;
    for (std::string_view choice : choices) {
      if (text == choice) return index;
      ++index;
    }
    errors.add(pointer, in_quotes(name) + " must be one of " + join(choices) + "; " +
                            did_you_mean(text, choices) + "got " + describe(value));
    return std::nullopt;
  }
  errors.add(pointer, in_quotes(name) + " must be one of the strings " + join(choices) + "; got " +
                          describe(value));
  return std::nullopt;
}

std::optional<std::string> read_name(const json& value, const std::string& pointer,
                                     std::string_view name, Errors& errors) {
  if (!value.is_string() || value.get_ref<const std::string&>().empty()) {
    errors.add(pointer, in_quotes(name) + " must be a non-empty string; got " + describe(value));
    return std::nullopt;
  }
  return value.get<std::string>();
}

// [x, y, z]; each element is checked against `bound` and reported at its own index.
std::optional<Vec3> read_vec3(const json& value, const std::string& pointer, std::string_view name,
                              const Bound& bound, Errors& errors) {
  if (!value.is_array() || value.size() != 3) {
    errors.add(pointer, in_quotes(name) + " must be an array of 3 numbers [x, y, z], each " +
                            bound.text() + "; got " + describe(value));
    return std::nullopt;
  }
  Vec3 vector;
  bool ok = true;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const std::string element_name = std::string(name) + "[" + std::to_string(axis) + "]";
    const auto element =
        read_number(value[axis], child(pointer, axis), element_name, bound, errors);
    if (element) {
      vector[static_cast<Eigen::Index>(axis)] = *element;
    } else {
      ok = false;
    }
  }
  return ok ? std::optional<Vec3>(vector) : std::nullopt;
}

// [x, y, z, w] (glTF order); a near-unit quaternion is normalised, anything else is an error.
std::optional<Quat> read_orientation(const json& value, const std::string& pointer,
                                     Errors& errors) {
  static constexpr std::string_view kMessage =
      "orientation must be a unit quaternion [x, y, z, w] (identity: [0, 0, 0, 1])";
  if (!value.is_array() || value.size() != 4) {
    errors.add(pointer, std::string(kMessage) + "; got " + describe(value));
    return std::nullopt;
  }
  std::array<double, 4> xyzw{};
  bool ok = true;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::string element_name = "orientation[" + std::to_string(k) + "]";
    const auto element =
        read_number(value[k], child(pointer, k), element_name, any_number(), errors);
    if (element) {
      xyzw[k] = *element;
    } else {
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  Quat q(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
  const double norm = q.norm();
  // A quaternion typed with a few decimals is within 1e-3 of unit length; further off is more
  // likely a mistake (Euler angles, a missing component) than rounding.
  if (!(norm > 0.0) || std::abs(norm - 1.0) > 1e-3) {
    errors.add(pointer, std::string(kMessage) + "; its length is " + format_number(norm));
    return std::nullopt;
  }
  q.normalize();
  return q;
}

// The members of one JSON object. Unknown members are reported when the reader is made; the
// getters give the value of a known member or nullptr if it is absent.
class Fields {
 public:
  Fields(const json& object, std::string pointer, Errors& errors, std::string_view what,
         std::initializer_list<std::string_view> known)
      : object_(object), pointer_(std::move(pointer)), errors_(errors) {
    for (const auto& [key, value] : object.items()) {
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      errors.add(child(pointer_, key), "unknown field " + in_quotes(key) + " in " +
                                           std::string(what) + "; " + did_you_mean(key, known) +
                                           "known fields: " + join(known));
    }
  }

  const json* get(std::string_view key) const {
    const auto found = object_.find(key);
    return found == object_.end() ? nullptr : &*found;
  }
  std::string at(std::string_view key) const { return child(pointer_, key); }
  const std::string& pointer() const { return pointer_; }
  Errors& errors() const { return errors_; }

  // "is required" at the member's would-be pointer; returns nullptr in that case.
  const json* require(std::string_view key, std::string_view what_it_is) const {
    const json* value = get(key);
    if (!value) errors_.add(at(key), in_quotes(key) + " is required: " + std::string(what_it_is));
    return value;
  }

  // Optional members with defaults: an invalid value is reported and the default returned.
  double number(std::string_view key, double fallback, const Bound& bound) const {
    const json* value = get(key);
    if (!value) return fallback;
    return read_number(*value, at(key), key, bound, errors_).value_or(fallback);
  }
  bool boolean(std::string_view key, bool fallback) const {
    const json* value = get(key);
    if (!value) return fallback;
    return read_bool(*value, at(key), key, errors_).value_or(fallback);
  }
  Vec3 vec3(std::string_view key, const Vec3& fallback, const Bound& bound) const {
    const json* value = get(key);
    if (!value) return fallback;
    return read_vec3(*value, at(key), key, bound, errors_).value_or(fallback);
  }
  Quat orientation(std::string_view key) const {
    const json* value = get(key);
    if (!value) return Quat::Identity();
    return read_orientation(*value, at(key), errors_).value_or(Quat::Identity());
  }
  std::size_t choice(std::string_view key, std::size_t fallback,
                     std::initializer_list<std::string_view> choices) const {
    const json* value = get(key);
    if (!value) return fallback;
    return read_choice(*value, at(key), key, choices, errors_).value_or(fallback);
  }

  // Required members.
  std::optional<double> required_number(std::string_view key, const Bound& bound) const {
    const json* value = require(key, bound.text());
    return value ? read_number(*value, at(key), key, bound, errors_) : std::nullopt;
  }
  std::optional<Vec3> required_vec3(std::string_view key, const Bound& bound) const {
    const json* value = require(key, "an array of 3 numbers [x, y, z], each " + bound.text());
    return value ? read_vec3(*value, at(key), key, bound, errors_) : std::nullopt;
  }
  std::optional<std::int64_t> required_integer(std::string_view key, std::int64_t low,
                                               std::int64_t high) const {
    const json* value = require(key, "an integer >= " + std::to_string(low));
    return value ? read_integer(*value, at(key), key, low, high, errors_) : std::nullopt;
  }
  std::optional<std::string> required_name(std::string_view key) const {
    const json* value = require(key, "a non-empty string");
    return value ? read_name(*value, at(key), key, errors_) : std::nullopt;
  }

 private:
  const json& object_;
  std::string pointer_;
  Errors& errors_;
};

// The member `key` of a JSON object, or nullptr.
const json* member(const json& object, std::string_view key) {
  const auto found = object.find(key);
  return found == object.end() ? nullptr : &*found;
}

// Reports a value that should have been a JSON object; true if it is one.
bool expect_object(const json& value, const std::string& pointer, std::string_view what,
                   Errors& errors) {
  if (value.is_object()) return true;
  errors.add(pointer, std::string(what) + " must be a JSON object {...}; got " + describe(value));
  return false;
}

// Reports a value that should have been a JSON array; true if it is one.
bool expect_array(const json& value, const std::string& pointer, std::string_view what,
                  Errors& errors) {
  if (value.is_array()) return true;
  errors.add(pointer, std::string(what) + " must be a JSON array [...]; got " + describe(value));
  return false;
}

// ---------------------------------------------------------------------------------------------
// Materials

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return lower;
}

std::string material_names() {
  std::vector<std::string> names;
  for (const Material& material : known_materials())
    names.emplace_back(material.name);
  return join(names);
}

// Case-insensitive lookup of a material name.
std::optional<Material> find_material(std::string_view name) {
  const std::string key = lower_case(name);
  for (const Material& material : known_materials()) {
    if (material.name == key) return material;
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// Sections of the scene

constexpr double kMaxTimeStep_s = 0.1;
// How far below the ground plane a vertex or charge may sit before it counts as buried, m: room
// for objects placed by hand at y = half their height with rounded numbers.
constexpr double kGroundTolerance_m = 1e-3;

std::optional<ChargeSpec> parse_charge(const json& value, const std::string& pointer,
                                       Errors& errors) {
  if (!expect_object(value, pointer, "a charge", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a charge",
                      {"position", "mass", "explosive", "burst", "burst_model"});
  ChargeSpec charge;
  if (auto position = fields.required_vec3("position", any_number("m")))
    charge.position = *position;
  if (auto mass = fields.required_number("mass", positive("kg"))) charge.mass_kg = *mass;

  if (const json* explosive = fields.get("explosive")) {
    const std::string at = fields.at("explosive");
    if (explosive->is_string()) {
      const auto& name = explosive->get_ref<const std::string&>();
      if (const auto found = blast::find_explosive(name)) {
        charge.explosive = std::string(found->name);
        charge.tnt_factor = found->tnt_factor;
      } else {
        errors.add(at, "unknown explosive " + in_quotes(name) + "; use one of " +
                           blast::known_explosive_names() +
                           ", or {\"tnt_factor\": F} for a custom TNT equivalence");
      }
    } else if (explosive->is_object()) {
      const Fields custom(*explosive, at, errors, "a custom explosive", {"tnt_factor"});
      if (auto factor = custom.required_number("tnt_factor", positive("kg TNT per kg"))) {
        charge.explosive = "custom";
        charge.tnt_factor = *factor;
      }
    } else {
      errors.add(at, "'explosive' must be an explosive's name (" + blast::known_explosive_names() +
                         ") or an object {\"tnt_factor\": F}; got " + describe(*explosive));
    }
  }
  charge.burst = fields.choice("burst", 0, {"air", "surface"}) == 0 ? blast::Burst::air
                                                                    : blast::Burst::surface;
  charge.surface_model = fields.choice("burst_model", 0, {"hemispherical", "factor_1_8"}) == 0
                             ? blast::SurfaceBurstModel::hemispherical
                             : blast::SurfaceBurstModel::factor_1_8;
  if (!scope.ok()) return std::nullopt;
  return charge;
}

EnvironmentSpec parse_environment(const json& value, const std::string& pointer, Errors& errors) {
  EnvironmentSpec environment;
  if (!expect_object(value, pointer, "'environment'", errors)) return environment;
  const Fields fields(value, pointer, errors, "'environment'",
                      {"gravity", "air_density", "ambient_pressure", "ground"});
  environment.gravity_m_s2 = fields.vec3("gravity", environment.gravity_m_s2, any_number("m/s^2"));
  environment.air_density_kg_m3 =
      fields.number("air_density", environment.air_density_kg_m3, non_negative("kg/m^3"));
  environment.ambient_pressure_pa =
      fields.number("ambient_pressure", environment.ambient_pressure_pa, positive("Pa"));
  if (const json* ground = fields.get("ground")) {
    if (ground->is_null()) {
      environment.ground.reset();
    } else if (ground->is_object()) {
      const Fields ground_fields(*ground, fields.at("ground"), errors, "'ground'",
                                 {"height", "friction", "restitution"});
      GroundSpec spec;
      spec.height_m = ground_fields.number("height", spec.height_m, any_number("m"));
      spec.friction = ground_fields.number("friction", spec.friction, non_negative());
      spec.restitution =
          ground_fields.number("restitution", spec.restitution, range(0.0, false, 1.0, false));
      environment.ground = spec;
    } else {
      errors.add(fields.at("ground"),
                 "'ground' must be an object {\"height\", \"friction\", \"restitution\"} or null "
                 "for no ground; got " +
                     describe(*ground));
    }
  }
  return environment;
}

SimulationSpec parse_simulation(const json& value, const std::string& pointer, const Limits& limits,
                                Errors& errors) {
  SimulationSpec simulation;
  if (!expect_object(value, pointer, "'simulation'", errors)) return simulation;
  const Fields fields(value, pointer, errors, "'simulation'",
                      {"duration", "frame_rate", "time_step", "tolerance", "seed", "clearing",
                       "occlusion", "integrator", "pulse", "max_panel_area", "linear_damping",
                       "angular_damping", "rotation_factor", "sleep"});
  simulation.duration_s =
      fields.number("duration", simulation.duration_s,
                    range(0.0, true, limits.max_duration_s, false, "s", "max_duration_s"));
  simulation.frame_rate_hz = fields.number(
      "frame_rate", simulation.frame_rate_hz,
      range(0.0, true, limits.max_frame_rate_hz, false, "frames per s", "max_frame_rate_hz"));
  if (const json* step = fields.get("time_step")) {
    simulation.time_step_s = read_number(*step, fields.at("time_step"), "time_step",
                                         range(0.0, true, kMaxTimeStep_s, false, "s"), errors);
  }
  simulation.tolerance =
      fields.number("tolerance", simulation.tolerance, range(0.0, true, 1.0, true));
  if (fields.get("time_step") && fields.get("tolerance")) {
    errors.add(fields.at("tolerance"),
               "give either 'time_step' (a fixed step) or 'tolerance' (an adaptive step), not "
               "both; remove one of them");
  }
  if (const json* seed = fields.get("seed")) {
    const std::string at = fields.at("seed");
    if (seed->is_number_unsigned()) {
      simulation.seed = seed->get<std::uint64_t>();
    } else if (seed->is_number_integer() && seed->get<std::int64_t>() >= 0) {
      simulation.seed = static_cast<std::uint64_t>(seed->get<std::int64_t>());
    } else if (seed->is_number_float() && seed->get<double>() >= 0.0 &&
               seed->get<double>() < 1.8446744073709552e19 &&
               seed->get<double>() == std::floor(seed->get<double>())) {
      simulation.seed = static_cast<std::uint64_t>(seed->get<double>());
    } else {
      errors.add(at, "'seed' must be an integer in [0, 2^64 - 1]; got " + describe(*seed));
    }
  }
  simulation.clearing = fields.boolean("clearing", simulation.clearing);
  simulation.occlusion = static_cast<OcclusionMode>(fields.choice(
      "occlusion", static_cast<std::size_t>(OcclusionMode::automatic), {"auto", "on", "off"}));
  simulation.integrator = static_cast<Integrator>(
      fields.choice("integrator", static_cast<std::size_t>(Integrator::semi_implicit_euler),
                    {"explicit_euler", "semi_implicit_euler", "rk4"}));
  simulation.pulse_shape = static_cast<blast::PulseShape>(
      fields.choice("pulse", static_cast<std::size_t>(blast::PulseShape::friedlander),
                    {"friedlander", "triangle_same_impulse", "triangle_same_period"}));
  simulation.max_panel_area_m2 =
      fields.number("max_panel_area", simulation.max_panel_area_m2, positive("m^2"));
  simulation.linear_damping =
      fields.number("linear_damping", simulation.linear_damping, non_negative("1/s"));
  simulation.angular_damping =
      fields.number("angular_damping", simulation.angular_damping, non_negative("1/s"));
  simulation.rotation_factor =
      fields.number("rotation_factor", simulation.rotation_factor, non_negative());
  simulation.sleep = fields.boolean("sleep", simulation.sleep);
  return simulation;
}

// The enums above are read by position in their choice lists; keep the lists in enum order.
static_assert(static_cast<int>(OcclusionMode::automatic) == 0 &&
              static_cast<int>(OcclusionMode::on) == 1 &&
              static_cast<int>(OcclusionMode::off) == 2);
static_assert(static_cast<int>(Integrator::explicit_euler) == 0 &&
              static_cast<int>(Integrator::semi_implicit_euler) == 1 &&
              static_cast<int>(Integrator::rk4) == 2);
static_assert(static_cast<int>(blast::PulseShape::friedlander) == 0 &&
              static_cast<int>(blast::PulseShape::triangle_same_impulse) == 1 &&
              static_cast<int>(blast::PulseShape::triangle_same_period) == 2);

// The mesh of a {"type": "mesh"} shape; its closedness is checked by the caller.
std::optional<geometry::TriangleMesh> parse_mesh(const Fields& shape, const Limits& limits,
                                                 Errors& errors) {
  const ErrorScope scope(errors);
  geometry::TriangleMesh mesh;
  if (const json* vertices =
          shape.require("vertices", "an array of vertices [[x, y, z], ...] in metres")) {
    const std::string at = shape.at("vertices");
    if (expect_array(*vertices, at, "'vertices'", errors)) {
      if (vertices->size() > limits.max_mesh_vertices) {
        errors.add(at, "the mesh has " + std::to_string(vertices->size()) +
                           " vertices, more than the limit max_mesh_vertices = " +
                           std::to_string(limits.max_mesh_vertices) + "; simplify the mesh");
      } else {
        mesh.vertices.reserve(vertices->size());
        for (std::size_t i = 0; i < vertices->size(); ++i) {
          const std::string name = "vertices[" + std::to_string(i) + "]";
          if (auto vertex = read_vec3((*vertices)[i], child(at, i), name, any_number("m"), errors))
            mesh.vertices.push_back(*vertex);
        }
      }
    }
  }
  if (const json* triangles =
          shape.require("triangles",
                        "an array of triangles [[i, j, k], ...] indexing 'vertices', "
                        "counter-clockwise seen from outside")) {
    const std::string at = shape.at("triangles");
    if (expect_array(*triangles, at, "'triangles'", errors)) {
      mesh.triangles.reserve(triangles->size());
      for (std::size_t t = 0; t < triangles->size(); ++t) {
        const json& triangle = (*triangles)[t];
        const std::string triangle_at = child(at, t);
        if (!triangle.is_array() || triangle.size() != 3) {
          errors.add(triangle_at, "triangles[" + std::to_string(t) +
                                      "] must be an array of 3 vertex indices [i, j, k]; got " +
                                      describe(triangle));
          continue;
        }
        std::array<std::uint32_t, 3> indices{};
        bool ok = true;
        for (std::size_t k = 0; k < 3; ++k) {
          const std::string name =
              "triangles[" + std::to_string(t) + "][" + std::to_string(k) + "]";
          const auto index = read_integer(triangle[k], child(triangle_at, k), name, 0,
                                          std::numeric_limits<std::uint32_t>::max(), errors);
          if (index) {
            indices[k] = static_cast<std::uint32_t>(*index);
          } else {
            ok = false;
          }
        }
        if (ok) mesh.triangles.push_back(indices);
      }
      if (triangles->size() < 4 && scope.ok()) {
        errors.add(at, "a closed mesh needs at least 4 triangles; got " +
                           std::to_string(triangles->size()));
      }
    }
  }
  if (!scope.ok()) return std::nullopt;
  return mesh;
}

std::string breakable_material_names() {
  std::vector<std::string> names;
  for (const Material& material : known_materials())
    if (material.strength_pa > 0.0) names.emplace_back(material.name);
  return join(names);
}

// The `fracture` member of an object or a window generator. `material` is the object's, if any:
// a breakable one supplies Young's modulus, K_c and the strength, which the fields may
// override. `allow_framed`: objects say whether an anchored frame holds them; a window's
// `frame` says it for its pane.
std::optional<FractureSpec> parse_fracture(const json& value, const std::string& pointer,
                                           const std::optional<Material>& material,
                                           bool allow_framed, Errors& errors) {
  if (!expect_object(value, pointer, "'fracture'", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  std::initializer_list<std::string_view> known = {
      "break",           "growth_length",  "pattern_scale",
      "branch_angle",    "angle_variance", "wiggle_probability",
      "wiggle_variance", "grid",           "seed",
      "framed",          "bond_strength",  "frame_strength",
      "frame_bite",      "clearing",       "strength",
      "toughness",       "youngs_modulus"};
  const Fields fields(value, pointer, errors, "'fracture'", known);
  FractureSpec spec;
  spec.trigger = fields.choice("break", 0, {"auto", "always"}) == 0
                     ? FractureSpec::Trigger::automatic
                     : FractureSpec::Trigger::always;
  if (const json* growth = fields.get("growth_length"))
    spec.growth_length_m = read_number(*growth, fields.at("growth_length"), "growth_length",
                                       range(0.0, true, 10.0, false, "m"), errors);
  spec.pattern_scale = fields.number("pattern_scale", spec.pattern_scale, positive());
  spec.branch_angle_deg =
      fields.number("branch_angle", spec.branch_angle_deg, range(5.0, false, 90.0, false, "deg"));
  spec.angle_variance_deg = fields.number("angle_variance", spec.angle_variance_deg,
                                          range(0.0, false, 90.0, false, "deg"));
  spec.wiggle_probability =
      fields.number("wiggle_probability", spec.wiggle_probability, range(0.0, false, 1.0, false));
  spec.wiggle_variance_deg = fields.number("wiggle_variance", spec.wiggle_variance_deg,
                                           range(0.0, false, 90.0, false, "deg"));
  if (const json* grid = fields.get("grid")) {
    if (auto cells = read_integer(*grid, fields.at("grid"), "grid", 16, 4096, errors))
      spec.grid = static_cast<int>(*cells);
  }
  if (const json* seed = fields.get("seed")) {
    if (auto seed_value = read_integer(*seed, fields.at("seed"), "seed", 0,
                                       std::numeric_limits<std::int64_t>::max(), errors))
      spec.seed = static_cast<std::uint64_t>(*seed_value);
  }
  if (const json* framed = fields.get("framed")) {
    if (allow_framed) {
      spec.framed = read_bool(*framed, fields.at("framed"), "framed", errors).value_or(false);
    } else {
      errors.add(fields.at("framed"),
                 "a window's pane is framed by the generator's 'frame'; remove 'framed' here");
    }
  }
  spec.bond_strength_pa = fields.number("bond_strength", spec.bond_strength_pa, non_negative("Pa"));
  spec.frame_strength_pa =
      fields.number("frame_strength", spec.frame_strength_pa, non_negative("Pa"));
  spec.frame_bite_m = fields.number("frame_bite", spec.frame_bite_m, positive("m"));
  spec.clearing = fields.choice("clearing", 0, {"fragment", "pane"}) == 0
                      ? FractureSpec::Clearing::fragment
                      : FractureSpec::Clearing::pane;
  // The material's values, then the explicit ones.
  const bool breakable = material && material->strength_pa > 0.0;
  if (breakable) {
    spec.youngs_modulus_pa = material->youngs_modulus_pa;
    spec.fracture_toughness_pa_sqrt_m = material->fracture_toughness_pa_sqrt_m;
    spec.strength_pa = material->strength_pa;
  }
  const bool all_given =
      fields.get("strength") && fields.get("toughness") && fields.get("youngs_modulus");
  if (!breakable && !all_given) {
    errors.add(pointer, "a breakable object needs a breakable 'material' (" +
                            breakable_material_names() +
                            ") or all of 'strength' (Pa), 'toughness' (Pa m^0.5) and "
                            "'youngs_modulus' (Pa) in 'fracture'");
  }
  spec.strength_pa = fields.number("strength", spec.strength_pa, positive("Pa"));
  spec.fracture_toughness_pa_sqrt_m =
      fields.number("toughness", spec.fracture_toughness_pa_sqrt_m, positive("Pa m^0.5"));
  spec.youngs_modulus_pa = fields.number("youngs_modulus", spec.youngs_modulus_pa, positive("Pa"));
  if (!scope.ok()) return std::nullopt;
  return spec;
}

// One entry of `objects` or a generated object, with where it came from for error pointers.
struct SceneObject {
  ObjectSpec spec;
  std::string name_pointer;              // where its name was given
  std::string position_pointer;          // where its placement was given
  std::optional<std::size_t> generator;  // index into `generators`, if generated
};

std::optional<SceneObject> parse_object(const json& value, const std::string& pointer,
                                        const Limits& limits, Errors& errors) {
  if (!expect_object(value, pointer, "an object", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  const Fields fields(
      value, pointer, errors, "an object",
      {"name", "shape", "position", "orientation", "mass", "density", "friction",
       "drag_coefficient", "anchored", "blocks", "rotates", "material", "fracture"});
  ObjectSpec object;
  if (auto name = fields.required_name("name")) object.name = *name;

  std::optional<Material> material;
  if (const json* material_value = fields.get("material")) {
    const std::string at = fields.at("material");
    if (!material_value->is_string()) {
      errors.add(at, "'material' must be one of the strings " + material_names() + "; got " +
                         describe(*material_value));
    } else if ((material = find_material(material_value->get_ref<const std::string&>()))) {
      object.material = std::string(material->name);
    } else {
      errors.add(at, "unknown material " +
                         in_quotes(material_value->get_ref<const std::string&>()) +
                         "; use one of " + material_names() +
                         ", or give 'mass' or 'density' and 'friction' instead");
    }
  }

  bool shape_ok = false;
  if (const json* shape =
          fields.require("shape",
                         "{\"type\": \"box\", \"size\": [x, y, z]} or {\"type\": \"mesh\", "
                         "\"vertices\": [...], \"triangles\": [...]}")) {
    const std::string at = fields.at("shape");
    if (expect_object(*shape, at, "'shape'", errors)) {
      const ErrorScope shape_scope(errors);
      const json* type = member(*shape, "type");
      std::optional<std::size_t> kind;
      if (!type) {
        errors.add(child(at, "type"), "'type' is required: one of box, mesh");
      } else {
        kind = read_choice(*type, child(at, "type"), "type", {"box", "mesh"}, errors);
      }
      if (kind == 0u) {
        const Fields box(*shape, at, errors, "a box shape", {"type", "size"});
        if (auto size = box.required_vec3("size", positive("m"))) {
          object.shape = ShapeType::box;
          object.box_size_m = *size;
          object.mesh = geometry::make_box(*size);
        }
      } else if (kind == 1u) {
        const Fields mesh_fields(*shape, at, errors, "a mesh shape",
                                 {"type", "vertices", "triangles"});
        if (auto mesh = parse_mesh(mesh_fields, limits, errors)) {
          if (auto problem = geometry::check_closed_mesh(*mesh)) {
            errors.add(at, "the mesh cannot be simulated: " + *problem +
                               "; give a closed mesh with triangles wound counter-clockwise seen "
                               "from outside");
          } else {
            object.shape = ShapeType::mesh;
            object.mesh = std::move(*mesh);
          }
        }
      }
      shape_ok = shape_scope.ok() && kind.has_value();
    }
  }

  object.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
  object.orientation = fields.orientation("orientation");

  // Mass: given, or density (given or the material's) times the mesh's volume.
  const json* mass = fields.get("mass");
  const json* density = fields.get("density");
  std::optional<double> density_kg_m3;
  if (mass && density) {
    errors.add(fields.at("density"),
               "give either 'mass' or 'density', not both; remove one of them");
  } else if (mass) {
    if (auto kg = read_number(*mass, fields.at("mass"), "mass", positive("kg"), errors))
      object.mass_kg = *kg;
  } else if (density) {
    density_kg_m3 =
        read_number(*density, fields.at("density"), "density", positive("kg/m^3"), errors);
  } else if (material) {
    density_kg_m3 = material->density_kg_m3;
  } else if (!fields.get("material")) {
    errors.add(fields.at("mass"),
               "'mass' is required: give 'mass' (kg), 'density' (kg/m^3) or a 'material' (" +
                   material_names() + ")");
  }
  if (density_kg_m3 && shape_ok) {
    object.mass_kg = geometry::mass_properties(object.mesh, *density_kg_m3).mass_kg;
    if (!(object.mass_kg > 0.0)) {
      errors.add(fields.at("shape"),
                 "the shape has no volume, so it has no mass; give it a "
                 "positive volume");
    }
  }

  object.friction = fields.number("friction", material ? material->friction : 0.5, non_negative());
  object.drag_coefficient = fields.number("drag_coefficient", 1.0, positive());
  object.anchored = fields.boolean("anchored", false);
  object.blocks = fields.boolean("blocks", true);
  object.rotates = fields.boolean("rotates", true);
  if (const json* fracture = fields.get("fracture")) {
    object.fracture = parse_fracture(*fracture, fields.at("fracture"), material, true, errors);
    if (object.fracture && shape_ok) {
      const Vec3& size = object.box_size_m;
      if (object.shape != ShapeType::box) {
        errors.add(fields.at("shape"),
                   "a breakable object (with 'fracture') must be a box pane {\"type\": \"box\", "
                   "\"size\": [width, height, thickness]}; use a box shape");
      } else if (size.z() > size.x() || size.z() > size.y()) {
        errors.add(child(child(fields.at("shape"), "size"), 2),
                   "a breakable pane's thickness is size[2] and must be its smallest edge; got "
                   "size [" +
                       format_number(size.x()) + ", " + format_number(size.y()) + ", " +
                       format_number(size.z()) +
                       "]; give [width, height, thickness] and turn the pane with 'orientation'");
      }
    }
    if (object.fracture && object.anchored) {
      errors.add(fields.at("anchored"),
                 "a breakable pane cannot be anchored (its fragments must fly); remove "
                 "'anchored' and set 'fracture.framed' to hold its edges in a frame");
    }
  }
  if (!scope.ok()) return std::nullopt;
  return SceneObject{std::move(object), fields.at("name"), fields.at("position"), std::nullopt};
}

// ---------------------------------------------------------------------------------------------
// Generators

// `generated_before`: objects already in the scene, for the max_objects check before anything
// is generated (a generator asking for millions of bricks must not allocate them).
std::vector<SceneObject> parse_generator(const json& value, const std::string& pointer,
                                         std::size_t generator_index, std::size_t objects_before,
                                         const Limits& limits, Errors& errors) {
  if (!expect_object(value, pointer, "a generator", errors)) return {};
  const ErrorScope scope(errors);
  const json* type = member(value, "type");
  if (!type) {
    errors.add(child(pointer, "type"), "'type' is required: one of brick_wall, blocks, window");
    return {};
  }
  const auto kind = read_choice(*type, child(pointer, "type"), "type",
                                {"brick_wall", "blocks", "window"}, errors);
  if (!kind) return {};

  const auto check_count = [&](std::uint64_t count) {
    const std::uint64_t room =
        limits.max_objects > objects_before ? limits.max_objects - objects_before : 0;
    if (count <= room) return true;
    errors.add(pointer, "this generator would make " + std::to_string(count) + " objects and " +
                            std::to_string(objects_before) +
                            " come before it, more than the limit max_objects = " +
                            std::to_string(limits.max_objects) + "; make it smaller");
    return false;
  };
  constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max();

  std::vector<ObjectSpec> objects;
  if (*kind == 0) {
    const Fields fields(value, pointer, errors, "a brick_wall generator",
                        {"type", "name", "position", "orientation", "rows", "columns", "brick_size",
                         "brick_mass", "friction", "mortar_gap"});
    BrickWallParams wall;
    if (auto name = fields.required_name("name")) wall.name = *name;
    wall.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
    wall.orientation = fields.orientation("orientation");
    if (auto rows = fields.required_integer("rows", 1, kMaxCount)) wall.rows = *rows;
    if (auto columns = fields.required_integer("columns", 1, kMaxCount)) wall.columns = *columns;
    const auto size = fields.required_vec3("brick_size", positive("m"));
    if (size) wall.brick_size_m = *size;
    if (auto mass = fields.required_number("brick_mass", positive("kg")))
      wall.brick_mass_kg = *mass;
    wall.friction = fields.number("friction", 0.6, non_negative());
    wall.mortar_gap_m = fields.number("mortar_gap", 0.0, non_negative("m"));
    if (size && wall.mortar_gap_m >= size->x()) {
      errors.add(fields.at("mortar_gap"),
                 "'mortar_gap' must be smaller than the brick length brick_size[0] = " +
                     format_number(size->x()) + " m, or the half bricks have no length");
    }
    if (!scope.ok() || !check_count(brick_wall_count(wall.rows, wall.columns))) return {};
    objects = brick_wall(wall);
  } else if (*kind == 2) {
    const Fields fields(value, pointer, errors, "a window generator",
                        {"type", "name", "position", "orientation", "size", "thickness", "material",
                         "frame", "frame_width", "frame_depth", "fracture"});
    WindowParams window_params;
    if (auto name = fields.required_name("name")) window_params.name = *name;
    window_params.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
    window_params.orientation = fields.orientation("orientation");
    if (const json* size = fields.require("size", "an array [width, height] of the pane, m")) {
      const std::string at = fields.at("size");
      if (!size->is_array() || size->size() != 2) {
        errors.add(at, "'size' must be an array of 2 numbers [width, height], m, each > 0; got " +
                           describe(*size));
      } else {
        const auto width = read_number((*size)[0], child(at, 0), "size[0]", positive("m"), errors);
        const auto height = read_number((*size)[1], child(at, 1), "size[1]", positive("m"), errors);
        if (width) window_params.width_m = *width;
        if (height) window_params.height_m = *height;
      }
    }
    window_params.thickness_m =
        fields.number("thickness", window_params.thickness_m, range(0.0, true, 0.1, false, "m"));
    if (window_params.thickness_m > std::min(window_params.width_m, window_params.height_m)) {
      errors.add(fields.at("thickness"),
                 "'thickness' must not exceed the pane's width and height; make it thinner");
    }
    std::optional<Material> material = find_material(window_params.material);
    if (const json* name = fields.get("material")) {
      const std::string at = fields.at("material");
      std::optional<Material> found;
      if (name->is_string()) found = find_material(name->get_ref<const std::string&>());
      if (found && found->strength_pa > 0.0) {
        material = found;
      } else {
        errors.add(at, "a window's 'material' must be a breakable material (" +
                           breakable_material_names() + "); got " + describe(*name));
      }
    }
    if (material) {
      window_params.material = std::string(material->name);
      window_params.density_kg_m3 = material->density_kg_m3;
      window_params.friction = material->friction;
    }
    window_params.frame = fields.boolean("frame", true);
    window_params.frame_width_m =
        fields.number("frame_width", window_params.frame_width_m, positive("m"));
    window_params.frame_depth_m =
        fields.number("frame_depth", window_params.frame_depth_m, positive("m"));
    if (window_params.frame_depth_m < window_params.thickness_m) {
      errors.add(fields.at("frame_depth"), "'frame_depth' must be at least the pane's thickness " +
                                               format_number(window_params.thickness_m) +
                                               " m; make the frame deeper");
    }
    if (const json* fracture = fields.get("fracture")) {
      if (auto spec = parse_fracture(*fracture, fields.at("fracture"), material, false, errors))
        window_params.fracture = *spec;
    } else if (material) {
      window_params.fracture.youngs_modulus_pa = material->youngs_modulus_pa;
      window_params.fracture.fracture_toughness_pa_sqrt_m = material->fracture_toughness_pa_sqrt_m;
      window_params.fracture.strength_pa = material->strength_pa;
    }
    if (!scope.ok() || !check_count(window_params.frame ? 5 : 1)) return {};
    objects = window(window_params);
  } else {
    const Fields fields(value, pointer, errors, "a blocks generator",
                        {"type", "name", "position", "orientation", "counts", "size", "spacing",
                         "mass", "density", "friction"});
    BlocksParams grid;
    if (auto name = fields.required_name("name")) grid.name = *name;
    grid.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
    grid.orientation = fields.orientation("orientation");
    if (const json* counts = fields.require("counts", "an array of 3 integers [nx, ny, nz] >= 1")) {
      const std::string at = fields.at("counts");
      if (!counts->is_array() || counts->size() != 3) {
        errors.add(at, "'counts' must be an array of 3 integers [nx, ny, nz], each >= 1; got " +
                           describe(*counts));
      } else {
        for (std::size_t axis = 0; axis < 3; ++axis) {
          if (auto n = read_integer((*counts)[axis], child(at, axis),
                                    "counts[" + std::to_string(axis) + "]", 1, kMaxCount, errors))
            grid.counts[axis] = *n;
        }
      }
    }
    const auto size = fields.required_vec3("size", positive("m"));
    if (size) grid.size_m = *size;
    grid.spacing_m = fields.vec3("spacing", Vec3::Zero(), non_negative("m"));
    const json* mass = fields.get("mass");
    const json* density = fields.get("density");
    if (mass && density) {
      errors.add(fields.at("density"),
                 "give either 'mass' or 'density', not both; remove one of them");
    } else if (mass) {
      if (auto kg = read_number(*mass, fields.at("mass"), "mass", positive("kg"), errors))
        grid.mass_kg = *kg;
    } else if (density) {
      if (auto rho =
              read_number(*density, fields.at("density"), "density", positive("kg/m^3"), errors);
          rho && size) {
        grid.mass_kg = *rho * size->prod();
      }
    } else {
      errors.add(fields.at("mass"),
                 "'mass' is required: give 'mass' (kg, of one block) or 'density' (kg/m^3)");
    }
    grid.friction = fields.number("friction", 0.5, non_negative());
    if (!scope.ok() || !check_count(blocks_count(grid.counts))) return {};
    objects = blocks(grid);
  }

  std::vector<SceneObject> generated;
  generated.reserve(objects.size());
  for (ObjectSpec& object : objects) {
    generated.push_back(SceneObject{std::move(object), child(pointer, "name"),
                                    child(pointer, "position"), generator_index});
  }
  return generated;
}

// ---------------------------------------------------------------------------------------------
// Cross-checks on the whole scene

// Solid angle of triangle (a, b, c) seen from the origin, signed by its winding (Van Oosterom &
// Strackee 1983, IEEE Trans. Biomed. Eng. 30(2)).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm();
  const double lb = b.norm();
  const double lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(numerator, denominator);
}

// The winding number of a closed, outward-wound mesh about a point: 1 inside, 0 outside. Unlike
// ray casting it needs no care for rays through edges or vertices. On the surface it is not
// well defined (a triangle seen edge-on subtends +-2 pi or 0); see distance_to_surface.
double winding_number(const geometry::TriangleMesh& mesh, const Vec3& point) {
  double total = 0.0;
  for (const auto& triangle : mesh.triangles) {
    total += solid_angle(mesh.vertices[triangle[0]] - point, mesh.vertices[triangle[1]] - point,
                         mesh.vertices[triangle[2]] - point);
  }
  return total / (4.0 * std::numbers::pi);
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double t =
      length_squared > 0.0 ? std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Distance from p to the triangle (a, b, c): to its plane if p projects inside it, else to the
// nearest edge.
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a);
  const double twice_area = normal.norm();
  if (twice_area > 0.0) {
    const Vec3 n = normal / twice_area;
    const double height = (p - a).dot(n);
    const Vec3 q = p - height * n;
    // q is inside if it is on the inner side of all three edges.
    if ((b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
        (a - c).cross(q - c).dot(n) >= 0.0)
      return std::abs(height);
  }
  return std::min(
      {distance_to_segment(p, a, b), distance_to_segment(p, b, c), distance_to_segment(p, c, a)});
}

double distance_to_surface(const geometry::TriangleMesh& mesh, const Vec3& point) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& triangle : mesh.triangles) {
    nearest = std::min(
        nearest, distance_to_triangle(point, mesh.vertices[triangle[0]], mesh.vertices[triangle[1]],
                                      mesh.vertices[triangle[2]]));
  }
  return nearest;
}

// A sphere around a mesh in its own frame, for a quick "certainly outside".
struct BoundingSphere {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
};

BoundingSphere bounding_sphere(const geometry::TriangleMesh& mesh) {
  BoundingSphere sphere;
  if (mesh.vertices.empty()) return sphere;
  Vec3 low = mesh.vertices.front();
  Vec3 high = low;
  for (const Vec3& vertex : mesh.vertices) {
    low = low.cwiseMin(vertex);
    high = high.cwiseMax(vertex);
  }
  sphere.centre = 0.5 * (low + high);
  for (const Vec3& vertex : mesh.vertices)
    sphere.radius = std::max(sphere.radius, (vertex - sphere.centre).norm());
  return sphere;
}

// A charge strictly inside an object is an error; on its surface is allowed (a contact charge).
void check_charges_outside_objects(const std::vector<std::optional<ChargeSpec>>& charges,
                                   const std::vector<SceneObject>& objects, Errors& errors) {
  std::vector<BoundingSphere> spheres;
  spheres.reserve(objects.size());
  for (const SceneObject& object : objects)
    spheres.push_back(bounding_sphere(object.spec.mesh));
  for (std::size_t c = 0; c < charges.size(); ++c) {
    if (!charges[c]) continue;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      const ObjectSpec& object = objects[o].spec;
      // The charge in the object's own frame.
      const Vec3 local = object.orientation.conjugate() * (charges[c]->position - object.position);
      // Within a nanometre per metre of size counts as on the surface, whatever rounding did.
      const double margin = 1e-9 * std::max(1.0, spheres[o].radius);
      if ((local - spheres[o].centre).norm() > spheres[o].radius + margin) continue;
      if (winding_number(object.mesh, local) <= 0.5) continue;
      if (distance_to_surface(object.mesh, local) <= margin) continue;
      errors.add(child(child("", "charges"), c) + "/position",
                 "the charge is inside object " + in_quotes(object.name) +
                     "; move the charge out of the object (or the object away from it)");
    }
  }
}

// Objects sunk into the ground: one error per explicit object, one per generator.
void check_objects_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<SceneObject>& objects, Errors& errors) {
  if (!ground) return;
  std::map<std::size_t, std::pair<std::size_t, double>> per_generator;  // count, deepest
  std::map<std::size_t, std::string> first_name;
  for (const SceneObject& object : objects) {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& vertex : object.spec.mesh.vertices)
      lowest = std::min(lowest, (object.spec.position + object.spec.orientation * vertex).y());
    if (lowest >= ground->height_m - kGroundTolerance_m) continue;
    const double depth = ground->height_m - lowest;
    if (object.generator) {
      auto& [count, deepest] = per_generator[*object.generator];
      if (count == 0) first_name[*object.generator] = object.spec.name;
      ++count;
      deepest = std::max(deepest, depth);
      continue;
    }
    errors.add(object.position_pointer,
               "object " + in_quotes(object.spec.name) + " reaches " + format_number(depth) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   "; raise it by at least that much (or lower environment.ground.height)");
  }
  for (const auto& [generator, entry] : per_generator) {
    const auto& [count, deepest] = entry;
    errors.add(child(child(child("", "generators"), generator), "position"),
               std::to_string(count) + " generated objects (the first " +
                   in_quotes(first_name[generator]) + ") reach up to " + format_number(deepest) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   "; raise the generator's position by at least that much");
  }
}

void check_charges_above_ground(const std::optional<GroundSpec>& ground,
                                const std::vector<std::optional<ChargeSpec>>& charges,
                                Errors& errors) {
  if (!ground) return;
  for (std::size_t c = 0; c < charges.size(); ++c) {
    if (!charges[c]) continue;
    const double y = charges[c]->position.y();
    if (y >= ground->height_m - kGroundTolerance_m) continue;
    errors.add(child(child("", "charges"), c) + "/position",
               "the charge is " + format_number(ground->height_m - y) +
                   " m below the ground plane y = " + format_number(ground->height_m) +
                   " (buried charges are not modelled); raise it to at least the ground (a "
                   "charge on the ground is a surface burst)");
  }
}

// Unique names; the second of a pair is the error. A generator reports only its first clash.
void check_unique_names(const std::vector<SceneObject>& objects, Errors& errors) {
  std::unordered_map<std::string_view, const SceneObject*> seen;
  seen.reserve(objects.size());
  std::vector<bool> generator_reported;
  for (const SceneObject& object : objects) {
    const auto [it, inserted] = seen.emplace(object.spec.name, &object);
    if (inserted) continue;
    if (object.generator) {
      if (generator_reported.size() <= *object.generator)
        generator_reported.resize(*object.generator + 1, false);
      if (generator_reported[*object.generator]) continue;
      generator_reported[*object.generator] = true;
    }
    const SceneObject& first = *it->second;
    std::string message = "the object name " + in_quotes(object.spec.name) +
                          " is already used (at " + first.name_pointer + "); ";
    message += object.generator ? "choose another name prefix for this generator"
                                : "object names must be unique, rename one of them";
    errors.add(object.name_pointer, message);
  }
}

void check_limits(const std::vector<SceneObject>& objects, const SimulationSpec& simulation,
                  bool simulation_ok, const Limits& limits, Errors& errors) {
  // Panels: counted with geometry::make_panels itself, so the count is the engine's. It caps the
  // subdivision per face, so one call stays bounded; equal boxes (a wall has two sizes) are
  // counted once, and counting stops as soon as the limit is passed.
  if (simulation_ok) {
    std::map<std::array<double, 3>, std::uint64_t> box_panels;
    std::uint64_t total = 0;
    for (const SceneObject& object : objects) {
      const ObjectSpec& spec = object.spec;
      const auto count_panels = [&] {
        return static_cast<std::uint64_t>(
            geometry::make_panels(spec.mesh, simulation.max_panel_area_m2).size());
      };
      if (spec.shape == ShapeType::box) {
        const std::array<double, 3> size = {spec.box_size_m.x(), spec.box_size_m.y(),
                                            spec.box_size_m.z()};
        auto [it, inserted] = box_panels.try_emplace(size, 0);
        if (inserted) it->second = count_panels();
        total += it->second;
      } else {
        total += count_panels();
      }
      if (total > limits.max_panels) break;
    }
    if (total > limits.max_panels) {
      errors.add("", "the scene's objects make more than " + std::to_string(limits.max_panels) +
                         " load panels (the limit max_panels); raise simulation.max_panel_area "
                         "(now " +
                         format_number(simulation.max_panel_area_m2) +
                         " m^2) or use fewer or smaller objects");
    }
  }
  // Frames x bodies: what the recorder may have to store.
  if (simulation_ok && !objects.empty()) {
    const double frames = std::ceil(simulation.duration_s * simulation.frame_rate_hz) + 1.0;
    const double samples = frames * static_cast<double>(objects.size());
    if (samples > static_cast<double>(limits.max_frame_samples)) {
      errors.add("/simulation",
                 format_number(frames) + " frames x " + std::to_string(objects.size()) +
                     " objects = " + format_number(samples) +
                     " frame samples, more than the limit max_frame_samples = " +
                     std::to_string(limits.max_frame_samples) +
                     "; shorten simulation.duration, lower simulation.frame_rate or use fewer "
                     "objects");
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

ParseResult parse_scene(const json& document, const Limits& limits) {
  Errors errors;
  ParseResult result;
  if (!document.is_object()) {
    errors.add("",
               "a scene must be a JSON object {\"charges\": [...], \"objects\": [...], ...}; "
               "got " +
                   describe(document));
    result.errors = errors.take();
    return result;
  }
  const Fields top(document, "", errors, "the scene",
                   {"charges", "environment", "objects", "generators", "simulation"});
  Scene scene;

  // Charges (invalid ones stay as nullopt so their indices still match for later checks).
  std::vector<std::optional<ChargeSpec>> charges;
  if (const json* list = top.require("charges",
                                     "an array of at least one charge {\"position\": "
                                     "[x, y, z], \"mass\": kg}")) {
    const std::string at = top.at("charges");
    if (expect_array(*list, at, "'charges'", errors)) {
      if (list->empty()) {
        errors.add(at,
                   "the scene needs at least one charge; add {\"position\": [x, y, z], "
                   "\"mass\": kg}");
      } else if (list->size() > limits.max_charges) {
        errors.add(at, "the scene has " + std::to_string(list->size()) +
                           " charges, more than the limit max_charges = " +
                           std::to_string(limits.max_charges));
      } else {
        for (std::size_t i = 0; i < list->size(); ++i)
          charges.push_back(parse_charge((*list)[i], child(at, i), errors));
      }
    }
  }

  if (const json* environment = top.get("environment"))
    scene.environment = parse_environment(*environment, top.at("environment"), errors);

  std::vector<SceneObject> objects;
  if (const json* list = top.get("objects")) {
    const std::string at = top.at("objects");
    if (expect_array(*list, at, "'objects'", errors)) {
      if (list->size() > limits.max_objects) {
        errors.add(at, "the scene has " + std::to_string(list->size()) +
                           " objects, more than the limit max_objects = " +
                           std::to_string(limits.max_objects));
      } else {
        for (std::size_t i = 0; i < list->size(); ++i) {
          if (auto object = parse_object((*list)[i], child(at, i), limits, errors))
            objects.push_back(std::move(*object));
        }
      }
    }
  }
  const json* explicit_objects = top.get("objects");
  const std::size_t explicit_count =
      explicit_objects && explicit_objects->is_array() ? explicit_objects->size() : 0;

  bool generators_ok = true;
  if (const json* list = top.get("generators")) {
    const std::string at = top.at("generators");
    if (expect_array(*list, at, "'generators'", errors)) {
      std::size_t before = explicit_count;
      for (std::size_t i = 0; i < list->size(); ++i) {
        const ErrorScope scope(errors);
        auto generated = parse_generator((*list)[i], child(at, i), i, before, limits, errors);
        generators_ok = generators_ok && scope.ok();
        before += generated.size();
        for (SceneObject& object : generated)
          objects.push_back(std::move(object));
      }
    } else {
      generators_ok = false;
    }
  }

  bool simulation_ok = true;
  if (const json* simulation = top.get("simulation")) {
    const ErrorScope scope(errors);
    scene.simulation = parse_simulation(*simulation, top.at("simulation"), limits, errors);
    simulation_ok = scope.ok();
  }

  // The scene as a whole. An empty scene is only reported when nothing else explains it.
  if (objects.empty() && explicit_count == 0 && generators_ok &&
      (!explicit_objects || explicit_objects->is_array())) {
    errors.add("/objects",
               "the scene needs at least one object: add one to 'objects' or add a "
               "generator to 'generators'");
  }
  check_unique_names(objects, errors);
  check_charges_above_ground(scene.environment.ground, charges, errors);
  check_objects_above_ground(scene.environment.ground, objects, errors);
  check_charges_outside_objects(charges, objects, errors);
  check_limits(objects, scene.simulation, simulation_ok, limits, errors);

  result.errors = errors.take();
  if (!result.errors.empty()) return result;
  for (auto& charge : charges)
    scene.charges.push_back(std::move(*charge));
  scene.objects.reserve(objects.size());
  for (SceneObject& object : objects)
    scene.objects.push_back(std::move(object.spec));
  result.scene = std::move(scene);
  return result;
}

ParseResult parse_scene_text(std::string_view text, const Limits& limits) {
  json document;
  try {
    document = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& error) {
    // what() reads "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string detail = error.what();
    if (const auto bracket = detail.find("] ");
        detail.starts_with("[json.exception") && bracket != std::string::npos)
      detail = detail.substr(bracket + 2);
    ParseResult result;
    result.errors.push_back({"", "malformed JSON at byte " + std::to_string(error.byte) + ": " +
                                     detail + "; fix the JSON syntax"});
    return result;
  }
  return parse_scene(document, limits);
}

}  // namespace brisance::scene
