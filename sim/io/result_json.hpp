// sim/io/result_json: the result as JSON (the names of the issue and DESIGN.md).
//
// {
//   "bodies": [{"name", "mass", "mesh": {"vertices": [[x,y,z],...], "triangles": [[a,b,c],...]},
//               "animated": bool, "position": [x,y,z], "orientation": [x,y,z,w]}],
//   "frames": [{"index": f, "time": t, "poses": [{"body": i, "position": [..], "orientation":
//   [..]}]}], "final_state": [{"name", "position", "orientation", "linear_velocity",
//   "angular_velocity"}], "fracture": [{"name", "broken", "peak_pressure_pa", "stress_pa", ...,
//   "release_times_s"}], "stats": {...every Stats field...}, "warnings": [{"code", "message",
//   "count"}]
// }
// Static bodies appear once (their position/orientation in "bodies"); frames list only the
// animated ones by body index, in the one frame shape of sim/io/frames (the HTTP API's too).
#pragma once

#include <iosfwd>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sim/engine/result.hpp"

namespace brisance::io {

nlohmann::json result_to_json(const engine::Result& result);
nlohmann::json stats_to_json(const engine::Stats& stats);
nlohmann::json final_state_to_json(const engine::FinalState& state);
nlohmann::json warning_to_json(const engine::Warning& warning);
// The "final_state" and "warnings" arrays of a result, in its order.
nlohmann::json final_states_to_json(const std::vector<engine::FinalState>& states);
nlohmann::json warnings_to_json(const std::vector<engine::Warning>& warnings);
nlohmann::json distribution_to_json(const engine::Distribution& distribution);
nlohmann::json pane_to_json(const engine::PaneReport& pane);
// One entry per breakable pane (engine::Result::fracture); an empty array without panes.
nlohmann::json fracture_to_json(const std::vector<engine::PaneReport>& panes);
// The shielding report, one entry per charge whose pass ran: [{"charge", "bodies": [{"body",
// "name", "attenuation"}]}] (bodies at attenuation 1 left out); [] when none ran.
nlohmann::json shielding_to_json(const engine::Result& result);
// With `frame_velocities`, every pose of "frames" also has its velocities (io::with_velocities).
void write_result_json(const engine::Result& result, std::ostream& out,
                       bool frame_velocities = false);

}  // namespace brisance::io
