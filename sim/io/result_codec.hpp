// sim/io/result_codec: the result's stored and served forms other than frames (sim/io/frames)
// and glb (sim/io/gltf): the summary the service stores and serves at GET /v1/jobs/{id}/result,
// and the meshes document of GET /v1/jobs/{id}/meshes. The service builds the same inputs from
// its stored rows (float32 meshes widened to double), so the bytes depend only on the values.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sim/engine/result.hpp"

namespace brisance::io {

// The stored summary: {"animated", "bodies": [{"index", "name", "mass", "animated", "position",
// "orientation"}] (no meshes), "duration", "final_state", "fracture", "frame_count",
// "frame_times", "stats", "warnings"}. Its "stats" member is also what a job's `stats` shows.
nlohmann::json result_summary(const engine::Result& result);

// animated_flags(bodies, animated)[i] is true when body i is in `animated`.
std::vector<bool> animated_flags(std::size_t body_count, std::span<const std::uint32_t> animated);

// {"bodies": [{"index", "name", "mass", "animated", "position", "orientation",
// "mesh": {"vertices", "triangles"}}]}, one entry per body in order; `animated[i]` says whether
// body i moves.
std::string meshes_document_json(std::span<const engine::BodyInfo> bodies,
                                 const std::vector<bool>& animated);

}  // namespace brisance::io
