// sim/blast/explosives: TNT equivalence of explosives (thesis table 2.1 and UFC 3-340-02).
// A charge of mass m of explosive X acts like W = m * factor kilograms of TNT (thesis §2.4.1).
// UFC 3-340-02 §2-13 gives some explosives two factors, one that matches the peak pressure and
// one that matches the impulse (its eqs. 2-4 and 2-5); where it does, both are kept.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace brisance::blast {

struct Explosive {
  std::string_view name;    // canonical name used in scenes and on the command line
  double tnt_factor;        // W / m
  std::string_view basis;   // what the factor equates: "energy", or "pressure" (peak overpressure)
  std::string_view source;  // where the factor is published
  // W / m for impulses (UFC 3-340-02 eq. 2-5); 0: the same as tnt_factor.
  double impulse_tnt_factor = 0.0;

  // The factor impulses are computed with.
  double impulse_factor() const {
    return impulse_tnt_factor > 0.0 ? impulse_tnt_factor : tnt_factor;
  }
};

// Every built-in explosive, TNT first.
std::span<const Explosive> known_explosives();

// Looks an explosive up by name: case, spaces, '-' and '_' are ignored ("comp-b" finds
// "Composition B"), and a few common aliases are accepted. Nothing found: nullopt.
std::optional<Explosive> find_explosive(std::string_view name);

// "TNT, RDX, ..." for error messages that must list the choices.
std::string known_explosive_names();

}  // namespace brisance::blast
