// sim/response/limits: the table of response limits.
//
// Source: PDC-TR 06-08 (2008), table of flexural response limits for the B1..B4 boundaries
// (superficial / moderate / heavy / hazardous), as summarised in ASCE/SEI 59-11 for the same
// components. Flexure only: no shear or connection limits; masonry, wood and cold-formed steel
// are not in the table yet. The values were transcribed from the
// report's summary table; check them against the revision in force before a design use.
#include "sim/response/limits.hpp"

#include <array>

namespace brisance::response {
namespace {

constexpr std::string_view kPdc = "PDC-TR 06-08 (2008) flexural response limits";

constexpr std::array kLimits = {
    // Reinforced concrete slab or beam in flexure (no tension membrane).
    ResponseLimits{"rc_flexure", {1.0, {}}, {{}, 2.0}, {{}, 5.0}, {{}, 10.0}, kPdc},
    // Hot-rolled steel beam in flexure (compact section).
    ResponseLimits{"steel_beam_flexure", {1.0, {}}, {3.0, 3.0}, {12.0, 10.0}, {25.0, 20.0}, kPdc},
};

bool exceeds(const ResponseBound& b, double ductility, std::optional<double> rotation_deg) {
  if (b.ductility && ductility > *b.ductility) return true;
  return b.rotation_deg && rotation_deg && *rotation_deg > *b.rotation_deg;
}

}  // namespace

std::string_view to_string(DamageLevel level) {
  switch (level) {
    case DamageLevel::superficial:
      return "superficial";
    case DamageLevel::moderate:
      return "moderate";
    case DamageLevel::heavy:
      return "heavy";
    case DamageLevel::hazardous:
      return "hazardous";
    case DamageLevel::blowout:
      return "blowout";
  }
  return "unknown";
}

std::span<const ResponseLimits> limits_table() {
  return kLimits;
}

std::optional<ResponseLimits> find_limits(std::string_view element) {
  for (const ResponseLimits& l : kLimits) {
    if (l.element == element) return l;
  }
  return std::nullopt;
}

DamageLevel damage_level(const ResponseLimits& limits, double ductility,
                         std::optional<double> rotation_deg) {
  if (exceeds(limits.b4, ductility, rotation_deg)) return DamageLevel::blowout;
  if (exceeds(limits.b3, ductility, rotation_deg)) return DamageLevel::hazardous;
  if (exceeds(limits.b2, ductility, rotation_deg)) return DamageLevel::heavy;
  if (exceeds(limits.b1, ductility, rotation_deg)) return DamageLevel::moderate;
  return DamageLevel::superficial;
}

}  // namespace brisance::response
