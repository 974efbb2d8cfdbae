// sim/response/limits: named response limits (ductility ratio mu and support rotation theta) for
// common element types, and the damage level a response reaches against them.
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace brisance::response {

// The component damage levels of PDC-TR 06-08 (US Army Corps of Engineers Protective Design
// Center, "Single degree of freedom structural response limits for antiterrorism design", 2008).
enum class DamageLevel {
  superficial,  // below B1: no visible permanent damage
  moderate,     // B1..B2: some permanent deflection, generally repairable
  heavy,        // B2..B3: significant permanent deflection, not repairable economically
  hazardous,    // B3..B4: failure likely, debris with low velocity
  blowout,      // beyond B4: element fails, debris with significant velocity
};

std::string_view to_string(DamageLevel level);

// One boundary: exceeded when mu > ductility OR theta > rotation (a missing value never governs).
struct ResponseBound {
  std::optional<double> ductility;
  std::optional<double> rotation_deg;
};

struct ResponseLimits {
  std::string_view element;  // e.g. "rc_slab_flexure"
  ResponseBound b1, b2, b3, b4;
  std::string_view source;
};

std::span<const ResponseLimits> limits_table();
std::optional<ResponseLimits> find_limits(std::string_view element);

// The damage level of a response with ductility mu and support rotation theta (nullopt when no
// span is given, then only ductility bounds count).
DamageLevel damage_level(const ResponseLimits& limits, double ductility,
                         std::optional<double> rotation_deg);

}  // namespace brisance::response
