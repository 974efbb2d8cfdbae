// sim/scene/reader: pointers, message text, bounds, typed readers and object members for the
// scene parsers (see reader.hpp). Every message the scene validator gives about a single value is
// worded here.
#include "sim/scene/reader.hpp"

#include <algorithm>
#include <sstream>

namespace brisance::scene {

// ---------------------------------------------------------------------------------------------
// Pointers and message text

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

std::string join(std::span<const std::string_view> names) {
  std::string text;
  for (std::string_view name : names) {
    if (!text.empty()) text += ", ";
    text += name;
  }
  return text;
}

std::string join(std::initializer_list<std::string_view> names) {
  return join(std::span<const std::string_view>(names.begin(), names.size()));
}

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

std::string did_you_mean(std::string_view given, std::span<const std::string_view> choices) {
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

std::string did_you_mean(std::string_view given, std::initializer_list<std::string_view> choices) {
  return did_you_mean(given, std::span<const std::string_view>(choices.begin(), choices.size()));
}

// ---------------------------------------------------------------------------------------------
// Bounds

bool Bound::contains(double value) const {
  if (low_open ? !(value > low) : !(value >= low)) return false;
  if (high_open ? !(value < high) : !(value <= high)) return false;
  return true;
}

std::string Bound::text() const {
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

Bound range(double low, bool low_open, double high, bool high_open, std::string_view unit,
            std::string limit_name) {
  Bound bound;
  bound.low = low;
  bound.low_open = low_open;
  bound.high = high;
  bound.high_open = high_open;
  bound.unit = unit;
  bound.limit_name = std::move(limit_name);
  return bound;
}
Bound any_number(std::string_view unit) {
  return range(-kInfinity, false, kInfinity, false, unit);
}
Bound positive(std::string_view unit) {
  return range(0.0, true, kInfinity, false, unit);
}
Bound non_negative(std::string_view unit) {
  return range(0.0, false, kInfinity, false, unit);
}

// ---------------------------------------------------------------------------------------------
// Typed readers

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

std::optional<std::size_t> read_choice(const json& value, const std::string& pointer,
                                       std::string_view name,
                                       std::span<const std::string_view> choices, Errors& errors) {
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

// ---------------------------------------------------------------------------------------------
// The members of one JSON object

Fields::Fields(const json& object, std::string pointer, Errors& errors, std::string_view what,
               std::initializer_list<std::string_view> known)
    : object_(object), pointer_(std::move(pointer)), errors_(errors) {
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    errors.add(child(pointer_, key), "unknown field " + in_quotes(key) + " in " +
                                         std::string(what) + "; " + did_you_mean(key, known) +
                                         "known fields: " + join(known));
  }
}

const json* Fields::require(std::string_view key, std::string_view what_it_is) const {
  const json* value = get(key);
  if (!value) errors_.add(at(key), in_quotes(key) + " is required: " + std::string(what_it_is));
  return value;
}

double Fields::number(std::string_view key, double fallback, const Bound& bound) const {
  const json* value = get(key);
  if (!value) return fallback;
  return read_number(*value, at(key), key, bound, errors_).value_or(fallback);
}

bool Fields::boolean(std::string_view key, bool fallback) const {
  const json* value = get(key);
  if (!value) return fallback;
  return read_bool(*value, at(key), key, errors_).value_or(fallback);
}

Vec3 Fields::vec3(std::string_view key, const Vec3& fallback, const Bound& bound) const {
  const json* value = get(key);
  if (!value) return fallback;
  return read_vec3(*value, at(key), key, bound, errors_).value_or(fallback);
}

Quat Fields::orientation(std::string_view key) const {
  const json* value = get(key);
  if (!value) return Quat::Identity();
  return read_orientation(*value, at(key), errors_).value_or(Quat::Identity());
}

std::optional<double> Fields::required_number(std::string_view key, const Bound& bound) const {
  const json* value = require(key, bound.text());
  return value ? read_number(*value, at(key), key, bound, errors_) : std::nullopt;
}

std::optional<Vec3> Fields::required_vec3(std::string_view key, const Bound& bound) const {
  const json* value = require(key, "an array of 3 numbers [x, y, z], each " + bound.text());
  return value ? read_vec3(*value, at(key), key, bound, errors_) : std::nullopt;
}

std::optional<std::int64_t> Fields::required_integer(std::string_view key, std::int64_t low,
                                                     std::int64_t high) const {
  const json* value = require(key, "an integer >= " + std::to_string(low));
  return value ? read_integer(*value, at(key), key, low, high, errors_) : std::nullopt;
}

std::optional<std::string> Fields::required_name(std::string_view key) const {
  const json* value = require(key, "a non-empty string");
  return value ? read_name(*value, at(key), key, errors_) : std::nullopt;
}

const json* member(const json& object, std::string_view key) {
  const auto found = object.find(key);
  return found == object.end() ? nullptr : &*found;
}

bool expect_object(const json& value, const std::string& pointer, std::string_view what,
                   Errors& errors) {
  if (value.is_object()) return true;
  errors.add(pointer, std::string(what) + " must be a JSON object {...}; got " + describe(value));
  return false;
}

bool expect_array(const json& value, const std::string& pointer, std::string_view what,
                  Errors& errors) {
  if (value.is_array()) return true;
  errors.add(pointer, std::string(what) + " must be a JSON array [...]; got " + describe(value));
  return false;
}

}  // namespace brisance::scene
