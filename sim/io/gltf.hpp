// sim/io/gltf: the result as binary glTF 2.0 (.glb): one mesh and one node per body, and one
// animation whose translation and rotation channels sample every animated body at the frame
// times (LINEAR interpolation; rotations as unit quaternions [x, y, z, w]). Static bodies are
// nodes with a fixed transform. Validates with zero errors in the Khronos glTF validator.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <span>
#include <vector>

#include "sim/engine/result.hpp"
#include "sim/io/frames.hpp"

namespace brisance::io {

// The glb of `bodies` (node i for body i) animated by `frames` (a channel pair per slot, in slot
// order). The CLI passes frames_of(result); the service its stored bodies and float32 frames.
std::vector<std::uint8_t> to_glb(std::span<const engine::BodyInfo> bodies, const FrameSet& frames);
// to_glb(result.bodies, frames_of(result)).
std::vector<std::uint8_t> result_to_glb(const engine::Result& result);
void write_glb(const engine::Result& result, std::ostream& out);

}  // namespace brisance::io
