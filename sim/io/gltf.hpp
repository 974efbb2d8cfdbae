// sim/io/gltf: the result as binary glTF 2.0 (.glb): one mesh and one node per body, and one
// animation whose translation and rotation channels sample every animated body at the frame
// times (LINEAR interpolation; rotations as unit quaternions [x, y, z, w]). Static bodies are
// nodes with a fixed transform. Validates with zero errors in the Khronos glTF validator.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <vector>

#include "sim/engine/result.hpp"

namespace brisance::io {

std::vector<std::uint8_t> result_to_glb(const engine::Result& result);
void write_glb(const engine::Result& result, std::ostream& out);

}  // namespace brisance::io
