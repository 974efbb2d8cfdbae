// sim/engine/pane_pattern: how a breakable pane of a scene becomes a crack pattern — its bending
// stress under the peak pressure, whether it breaks, the growth length (thesis eq. 5.5, or the
// one given) and the crack-tree parameters. One function, so that `brisance fracture` previews
// exactly the pattern a job grows for the same pane, pressure and seed.
#pragma once

#include <cstdint>

#include "sim/fracture/crack_tree.hpp"
#include "sim/fracture/pane.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

struct PanePattern {
  fracture::PaneFracture response;  // plate stress, breaks, a_c, eq. 5.5's growth length
  bool forced = false;              // trigger "always" broke a pane its stress does not
  double growth_length_m = 0.0;     // what the pattern is grown with
  bool growth_length_given = false;
  bool growth_length_clamped = false;
  fracture::FractureParams params;  // valid when the pane breaks (or is forced)
};

// The pane `spec` of width x height x thickness m under `peak_pressure_pa` on its face, its
// pattern grown from `seed`. The parameters are not validated here: a scene's spec was, and the
// CLI checks fracture::validate(params) with the flags it took.
PanePattern pane_pattern(const scene::FractureSpec& spec, double width_m, double height_m,
                         double thickness_m, double peak_pressure_pa, std::uint64_t seed);

// The lowest peak pressure that breaks the pane by its stress (bisection on pane_pattern's
// stress test, to 0.1 %), Pa.
double breaking_pressure_pa(const scene::FractureSpec& spec, double width_m, double height_m,
                            double thickness_m);

}  // namespace brisance::engine
