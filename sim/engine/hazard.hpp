// sim/engine/hazard: how dangerous a window's glass is to the room behind it, rated from where
// its fragments go, after the GSA's glazing performance conditions (GSA P100, Facilities
// Standards for the Public Buildings Service, table 8-1 "Glazing protection levels based on
// fragment impact locations"; docs/fracture.md "Hazard rating").
//
// The test room of those conditions lies behind the pane: a floor, and a vertical witness panel
// 10 ft (3.048 m) behind the window. The rating follows the worst fragment:
//   1   safe       / hazard none      the glass does not break
//   2   very high  / none             it breaks, and no fragment enters the room
//   3a  high       / very low         fragments land on the floor no further than 3.3 ft (1 m)
//   3b  high       / low              ... no further than 10 ft (3.048 m)
//   4   medium     / medium           fragments hit the witness panel no higher than 2 ft
//                                     (0.61 m) above the floor
//   5   low        / high             fragments hit the witness panel higher than 2 ft
#pragma once

#include <cstdint>
#include <string>

#include "sim/engine/result.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

// GSA P100 table 8-1's distances, in m (its values are in feet).
inline constexpr double kFoot_m = 0.3048;
inline constexpr double kHazardVeryLowFloorDistance_m = 3.3 * kFoot_m;  // condition 3a
inline constexpr double kHazardWitnessDistance_m = 10.0 * kFoot_m;      // 3b, and the panel
inline constexpr double kHazardWitnessHeight_m = 2.0 * kFoot_m;         // 4 below, 5 above

// Fills PaneReport::hazard of every pane in `result.fracture` from the run's frames and final
// states: each released fragment is followed through the frames (and past the run's end on a
// ballistic path, without drag) until it lands on the room's floor behind the pane or reaches
// the witness panel. Needs the frames of a finished run.
void rate_pane_hazards(const scene::Scene& scene, Result& result);

}  // namespace brisance::engine
