// sim/response/element: parsing and validation of an element.
#include "sim/response/element.hpp"

#include <cmath>
#include <initializer_list>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sim/response/limits.hpp"

namespace brisance::response {
namespace {

// Collects every error of one document, so a client sees them all at once.
class Reader {
 public:
  explicit Reader(std::vector<FieldError>& errors) : errors_(errors) {}

  void fail(std::string pointer, std::string message) {
    errors_.push_back({std::move(pointer), std::move(message)});
  }

  bool object(const nlohmann::json& j, const std::string& pointer,
              std::initializer_list<std::string_view> known) {
    if (!j.is_object()) {
      fail(pointer.empty() ? "/" : pointer, "must be an object");
      return false;
    }
    for (const auto& [key, value] : j.items()) {
      bool found = false;
      for (std::string_view k : known)
        found = found || k == key;
      if (!found) fail(pointer + "/" + key, "is not a known field; remove it");
    }
    return true;
  }

  // A finite number, or the default when absent (required: an error when absent).
  std::optional<double> number(const nlohmann::json& j, const std::string& pointer, const char* key,
                               std::optional<double> fallback) {
    const std::string path = pointer + "/" + key;
    if (!j.contains(key)) {
      if (!fallback) fail(path, "is required");
      return fallback;
    }
    const nlohmann::json& v = j.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      fail(path, "must be a finite number");
      return std::nullopt;
    }
    return v.get<double>();
  }

  void positive(std::optional<double> v, const std::string& path) {
    if (v && !(*v > 0.0)) fail(path, "must be > 0");
  }

 private:
  std::vector<FieldError>& errors_;
};

void parse_resistance(Reader& r, const nlohmann::json& j, Element& e) {
  const std::string p = "/resistance";
  if (!r.object(j, p,
                {"type", "stiffness_n_per_m", "yield_resistance_n", "hardening_stiffness_n_per_m",
                 "membrane_onset_m", "membrane_stiffness_n_per_m"})) {
    return;
  }
  ResistanceSpec& s = e.resistance;
  if (!j.contains("type") || !j.at("type").is_string()) {
    r.fail(p + "/type", "is required: elastic, elastic_plastic, bilinear or membrane");
    return;
  }
  const std::string type = j.at("type").get<std::string>();
  if (type == "elastic") {
    s.type = ResistanceType::elastic;
  } else if (type == "elastic_plastic") {
    s.type = ResistanceType::elastic_plastic;
  } else if (type == "bilinear") {
    s.type = ResistanceType::bilinear;
  } else if (type == "membrane") {
    s.type = ResistanceType::membrane;
  } else {
    r.fail(p + "/type", "must be elastic, elastic_plastic, bilinear or membrane");
    return;
  }
  const auto k = r.number(j, p, "stiffness_n_per_m", std::nullopt);
  r.positive(k, p + "/stiffness_n_per_m");
  s.stiffness_n_per_m = k.value_or(0.0);
  const bool plastic = s.type != ResistanceType::elastic;
  const auto yield =
      r.number(j, p, "yield_resistance_n", plastic ? std::nullopt : std::optional(0.0));
  if (plastic) r.positive(yield, p + "/yield_resistance_n");
  s.yield_resistance_n = yield.value_or(0.0);
  // Fields that belong to another type are errors, not silently ignored.
  auto only_for = [&](const char* key, ResistanceType owner, const char* owner_name) {
    if (j.contains(key) && s.type != owner) {
      r.fail(p + "/" + key, std::string("applies to type ") + owner_name + " only; remove it");
    }
  };
  only_for("hardening_stiffness_n_per_m", ResistanceType::bilinear, "bilinear");
  only_for("membrane_onset_m", ResistanceType::membrane, "membrane");
  only_for("membrane_stiffness_n_per_m", ResistanceType::membrane, "membrane");
  if (type == "elastic" && j.contains("yield_resistance_n")) {
    r.fail(p + "/yield_resistance_n", "does not apply to type elastic; remove it");
  }
  if (s.type == ResistanceType::bilinear) {
    const auto k2 = r.number(j, p, "hardening_stiffness_n_per_m", std::nullopt);
    if (k2 && k && !(*k2 >= 0.0 && *k2 < *k)) {
      r.fail(p + "/hardening_stiffness_n_per_m", "must be >= 0 and < stiffness_n_per_m");
    }
    s.hardening_stiffness_n_per_m = k2.value_or(0.0);
  }
  if (s.type == ResistanceType::membrane) {
    const auto onset = r.number(j, p, "membrane_onset_m", std::nullopt);
    const auto km = r.number(j, p, "membrane_stiffness_n_per_m", std::nullopt);
    if (onset && k && yield && *k > 0.0 && !(*onset >= *yield / *k)) {
      r.fail(p + "/membrane_onset_m",
             "must be >= the yield displacement yield_resistance_n / stiffness_n_per_m");
    }
    if (km && k && !(*km > 0.0 && *km < *k)) {
      r.fail(p + "/membrane_stiffness_n_per_m", "must be > 0 and < stiffness_n_per_m");
    }
    s.membrane_onset_m = onset.value_or(0.0);
    s.membrane_stiffness_n_per_m = km.value_or(0.0);
  }
}

}  // namespace

ElementParse parse_element(const nlohmann::json& json) {
  ElementParse out;
  Reader r(out.errors);
  if (!r.object(json, "",
                {"mass_kg", "loaded_area_m2", "resistance", "damping_ratio", "factors", "support",
                 "limits"})) {
    return out;
  }
  Element e;
  const auto mass = r.number(json, "", "mass_kg", std::nullopt);
  r.positive(mass, "/mass_kg");
  e.mass_kg = mass.value_or(0.0);
  const auto area = r.number(json, "", "loaded_area_m2", std::nullopt);
  r.positive(area, "/loaded_area_m2");
  e.loaded_area_m2 = area.value_or(0.0);
  if (json.contains("resistance")) {
    parse_resistance(r, json.at("resistance"), e);
  } else {
    r.fail("/resistance", "is required");
  }
  const auto zeta = r.number(json, "", "damping_ratio", 0.0);
  if (zeta && !(*zeta >= 0.0 && *zeta < 1.0)) r.fail("/damping_ratio", "must be >= 0 and < 1");
  e.damping_ratio = zeta.value_or(0.0);
  if (json.contains("factors")) {
    const nlohmann::json& f = json.at("factors");
    if (r.object(f, "/factors", {"load", "mass"})) {
      const auto kl = r.number(f, "/factors", "load", 1.0);
      const auto km = r.number(f, "/factors", "mass", 1.0);
      r.positive(kl, "/factors/load");
      r.positive(km, "/factors/mass");
      e.load_factor = kl.value_or(1.0);
      e.mass_factor = km.value_or(1.0);
    }
  }
  if (json.contains("support")) {
    const nlohmann::json& s = json.at("support");
    if (r.object(s, "/support", {"span_m"})) {
      const auto span = r.number(s, "/support", "span_m", std::nullopt);
      r.positive(span, "/support/span_m");
      if (span && *span > 0.0) e.span_m = *span;
    }
  }
  if (json.contains("limits")) {
    const nlohmann::json& l = json.at("limits");
    if (l.is_string() && find_limits(l.get<std::string>())) {
      e.limits = l.get<std::string>();
    } else {
      std::string names;
      for (const ResponseLimits& known : limits_table())
        names += (names.empty() ? "" : ", ") + std::string(known.element);
      r.fail("/limits", "must name a table of response limits: " + names);
    }
  }
  if (out.errors.empty()) out.element = e;
  return out;
}

}  // namespace brisance::response
