// sim/response/element: a structural element as the SDOF solver sees it, and its parser from
// JSON with validation at the boundary (errors carry a JSON-pointer-like path and say the fix).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sim/response/resistance.hpp"

namespace brisance::response {

struct Element {
  double mass_kg = 0.0;          // mass of the real element, > 0
  double loaded_area_m2 = 0.0;   // area the pressure acts on, > 0
  ResistanceSpec resistance;     // of the real element, referred to the peak displacement
  double damping_ratio = 0.0;    // viscous, fraction of critical at the initial stiffness, [0, 1)
  double load_factor = 1.0;      // K_L (1, 1: already an equivalent SDOF)
  double mass_factor = 1.0;      // K_M
  std::optional<double> span_m;  // support span; gives the support rotation
  // Name of the response limits the damage level is judged against (limits.hpp), e.g.
  // "rc_flexure"; none: no damage level.
  std::optional<std::string> limits;
};

struct FieldError {
  std::string pointer;  // e.g. "/resistance/stiffness_n_per_m"
  std::string message;  // e.g. "must be > 0"
  std::string text() const { return pointer + " " + message; }
};

struct ElementParse {
  std::optional<Element> element;  // set when errors is empty
  std::vector<FieldError> errors;
};

// Reads {"mass_kg", "loaded_area_m2", "resistance": {"type", "stiffness_n_per_m",
// "yield_resistance_n", "hardening_stiffness_n_per_m", "membrane_onset_m",
// "membrane_stiffness_n_per_m"}, "damping_ratio", "factors": {"load", "mass"},
// "support": {"span_m"}, "limits"}. Unknown fields are errors.
ElementParse parse_element(const nlohmann::json& json);

}  // namespace brisance::response
