// sim/scene/reader (private to sim/scene): the small JSON reader the section parsers share —
// RFC 6901 pointers, the collected error list, number bounds with their message text, typed
// readers that report a problem at its exact pointer, the members of one JSON object with unknown
// ones reported, named choices (enums) and "did you mean" hints. It knows nothing of scenes.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/scene/scene.hpp"

namespace brisance::scene {

using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Pointers and message text

// RFC 6901: '~' becomes "~0" and '/' becomes "~1" inside a reference token.
std::string escape_token(std::string_view token);
std::string child(const std::string& pointer, std::string_view key);
std::string child(const std::string& pointer, std::size_t index);

std::string format_number(double value);  // 6 significant digits
std::string in_quotes(std::string_view text);
// What a JSON value is, for "got ..." in messages; long values are cut short.
std::string describe(const json& value);
std::string join(const std::vector<std::string>& names);  // "a, b, c"
std::string join(std::span<const std::string_view> names);
std::string join(std::initializer_list<std::string_view> names);

// Levenshtein distance, for "did you mean" hints on misspelt field and enum names.
std::size_t edit_distance(std::string_view a, std::string_view b);
// "did you mean 'x'? " for the closest choice within two edits, else "".
std::string did_you_mean(std::string_view given, std::span<const std::string_view> choices);
std::string did_you_mean(std::string_view given, std::initializer_list<std::string_view> choices);

// ---------------------------------------------------------------------------------------------
// The error list

// Every problem is counted; the first kMaxListed are kept, and take() closes a longer list with
// one more error (pointer "") saying how many were left out: a mesh of a million degenerate
// triangles must not become a million-entry answer.
class Errors {
 public:
  static constexpr std::size_t kMaxListed = 100;

  void add(std::string pointer, std::string message) {
    ++count_;
    if (list_.size() < kMaxListed) list_.push_back({std::move(pointer), std::move(message)});
  }
  std::size_t count() const { return count_; }
  std::vector<ValidationError> take() {
    if (count_ > list_.size()) {
      const std::size_t more = count_ - list_.size();
      list_.push_back({"", "and " + std::to_string(more) +
                               (more == 1 ? " more problem" : " more problems") +
                               "; only the first " + std::to_string(kMaxListed) + " are listed"});
    }
    count_ = 0;
    return std::move(list_);
  }

 private:
  std::vector<ValidationError> list_;
  std::size_t count_ = 0;
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
// Bounds

// Allowed range of a number and its unit, for the check and for the message.
struct Bound {
  double low = -std::numeric_limits<double>::infinity();
  bool low_open = false;
  double high = std::numeric_limits<double>::infinity();
  bool high_open = false;
  std::string_view unit;   // "kg", "m", ... or empty
  std::string limit_name;  // the Limits field behind `high`, if any

  bool contains(double value) const;
  // "a number in [0, 1] (m), the limit ...", as messages quote it.
  std::string text() const;
};

Bound range(double low, bool low_open, double high, bool high_open, std::string_view unit = {},
            std::string limit_name = {});
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
Bound any_number(std::string_view unit = {});
Bound positive(std::string_view unit = {});
Bound non_negative(std::string_view unit = {});

// ---------------------------------------------------------------------------------------------
// Typed readers. Each reports a problem at the exact pointer and returns nullopt.

// A finite number within `bound`; integers are numbers too, booleans are not.
std::optional<double> read_number(const json& value, const std::string& pointer,
                                  std::string_view name, const Bound& bound, Errors& errors);
// A whole number in [low, high]; 3.0 counts as 3 (JSON Schema's "integer"), 3.5 does not.
std::optional<std::int64_t> read_integer(const json& value, const std::string& pointer,
                                         std::string_view name, std::int64_t low, std::int64_t high,
                                         Errors& errors);
std::optional<bool> read_bool(const json& value, const std::string& pointer, std::string_view name,
                              Errors& errors);
// One of a fixed set of strings; returns its index in `choices`.
std::optional<std::size_t> read_choice(const json& value, const std::string& pointer,
                                       std::string_view name,
                                       std::span<const std::string_view> choices, Errors& errors);
std::optional<std::string> read_name(const json& value, const std::string& pointer,
                                     std::string_view name, Errors& errors);
// [x, y, z]; each element is checked against `bound` and reported at its own index.
std::optional<Vec3> read_vec3(const json& value, const std::string& pointer, std::string_view name,
                              const Bound& bound, Errors& errors);
// [x, y, z, w] (glTF order); a near-unit quaternion is normalised, anything else is an error.
std::optional<Quat> read_orientation(const json& value, const std::string& pointer, Errors& errors);

// A named value of an enum, as a JSON string names it. A table of them lists the choices in
// the order messages show them.
template <typename Enum>
struct Choice {
  std::string_view name;
  Enum value;
};

template <typename Enum, std::size_t N>
std::array<std::string_view, N> choice_names(const std::array<Choice<Enum>, N>& choices) {
  std::array<std::string_view, N> names;
  for (std::size_t i = 0; i < N; ++i)
    names[i] = choices[i].name;
  return names;
}

// The enum value `value` names, or nullopt after reporting it like read_choice.
template <typename Enum, std::size_t N>
std::optional<Enum> read_enum(const json& value, const std::string& pointer, std::string_view name,
                              const std::array<Choice<Enum>, N>& choices, Errors& errors) {
  const std::array<std::string_view, N> names = choice_names(choices);
  const auto index = read_choice(value, pointer, name, names, errors);
  if (!index) return std::nullopt;
  return choices[*index].value;
}

// ---------------------------------------------------------------------------------------------
// The members of one JSON object

// Unknown members are reported when the reader is made; the getters give the value of a known
// member or nullptr if it is absent.
class Fields {
 public:
  Fields(const json& object, std::string pointer, Errors& errors, std::string_view what,
         std::initializer_list<std::string_view> known);

  const json* get(std::string_view key) const {
    const auto found = object_.find(key);
    return found == object_.end() ? nullptr : &*found;
  }
  std::string at(std::string_view key) const { return child(pointer_, key); }
  const std::string& pointer() const { return pointer_; }
  Errors& errors() const { return errors_; }

  // "is required" at the member's would-be pointer; returns nullptr in that case.
  const json* require(std::string_view key, std::string_view what_it_is) const;

  // Optional members with defaults: an invalid value is reported and the default returned.
  double number(std::string_view key, double fallback, const Bound& bound) const;
  bool boolean(std::string_view key, bool fallback) const;
  Vec3 vec3(std::string_view key, const Vec3& fallback, const Bound& bound) const;
  Quat orientation(std::string_view key) const;
  template <typename Enum, std::size_t N>
  Enum choice(std::string_view key, Enum fallback,
              const std::array<Choice<Enum>, N>& choices) const {
    const json* value = get(key);
    if (!value) return fallback;
    return read_enum(*value, at(key), key, choices, errors_).value_or(fallback);
  }

  // Required members.
  std::optional<double> required_number(std::string_view key, const Bound& bound) const;
  std::optional<Vec3> required_vec3(std::string_view key, const Bound& bound) const;
  std::optional<std::int64_t> required_integer(std::string_view key, std::int64_t low,
                                               std::int64_t high) const;
  std::optional<std::string> required_name(std::string_view key) const;

 private:
  const json& object_;
  std::string pointer_;
  Errors& errors_;
};

// The member `key` of a JSON object, or nullptr.
const json* member(const json& object, std::string_view key);

// Reports a value that should have been a JSON object; true if it is one.
bool expect_object(const json& value, const std::string& pointer, std::string_view what,
                   Errors& errors);
// Reports a value that should have been a JSON array; true if it is one.
bool expect_array(const json& value, const std::string& pointer, std::string_view what,
                  Errors& errors);

}  // namespace brisance::scene
