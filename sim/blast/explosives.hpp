// sim/blast/explosives: TNT equivalence of explosives (thesis table 2.1 and UFC 3-340-02).
// A charge of mass m of explosive X acts like W = m * factor kilograms of TNT (thesis §2.4.1).
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
};

// Every built-in explosive, TNT first.
std::span<const Explosive> known_explosives();

// Looks an explosive up by name: case, spaces, '-' and '_' are ignored ("comp-b" finds
// "Composition B"), and a few common aliases are accepted. Nothing found: nullopt.
std::optional<Explosive> find_explosive(std::string_view name);

// "TNT, RDX, ..." for error messages that must list the choices.
std::string known_explosive_names();

}  // namespace brisance::blast
