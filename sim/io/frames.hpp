// sim/io/frames: the one shape of result frames, and its encoders. A FrameSet is the poses of
// some bodies over a run of consecutive frames; the CLI builds it from an engine::Result, the
// server from its stored float32 rows, and both encode it here, so `brisance run -o OUT.json`,
// `-o OUT.brf` and `GET /v1/jobs/{id}/frames` give the same shape (docs/pipelines.md):
//
//   frame (JSON):  {"index": i, "poses": [{"body": b, "orientation": [x,y,z,w],
//                   "position": [x,y,z]}, ...], "time": t}
//                  with velocities asked for, each pose also has "linear_velocity" [m/s] and
//                  "angular_velocity" [rad/s] (world frame; see with_velocities)
//   BRF1 (binary): "BRF1", u32 first frame, u32 F, u32 B, B x u32 body indices, then per frame
//                  f64 time and per body 7 x f32 (position x y z, orientation x y z w);
//                  little-endian, packed (api/openapi.yaml, getJobFrames).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sim/engine/result.hpp"

namespace brisance::io {

// How a pose moves at a frame: the velocity of its position and the body's angular velocity,
// world frame.
struct Twist {
  std::array<double, 3> linear_m_s{};
  std::array<double, 3> angular_rad_s{};
};

struct FrameSet {
  std::uint64_t first_frame = 0;      // index of the first frame here in the whole result
  std::vector<std::uint32_t> bodies;  // the body index of each pose slot
  std::vector<double> times_s;        // one per frame
  std::vector<engine::Pose> poses;    // frame-major: poses[f * bodies.size() + k]
  std::vector<Twist> velocities;      // empty, or one per pose (with_velocities)

  std::size_t frame_count() const { return times_s.size(); }
  const engine::Pose& pose(std::size_t frame, std::size_t slot) const {
    return poses[frame * bodies.size() + slot];
  }
};

// Every frame of the result, one slot per animated body in `result.animated` order.
FrameSet frames_of(const engine::Result& result);

// `frames` with a velocity per pose, for motion blur: central differences of the poses over the
// neighbouring frames, (p[f+1] - p[f-1]) / (t[f+1] - t[f-1]) and the rotation q[f+1] q[f-1]^-1 as
// an angle about its axis over the same time (one-sided at the set's ends): the mean motion
// across the two frame intervals around the frame, which is what a shutter spanning them sees.
// The first `margin_before` and last `margin_after` frames only serve as neighbours and are
// dropped from the set returned (a page of frames takes one frame on each side it has).
FrameSet with_velocities(FrameSet frames, std::size_t margin_before = 0,
                         std::size_t margin_after = 0);

// Frame `frame` of the set as a JSON object (the reference the streamed writers must equal).
nlohmann::json frame_to_json(const FrameSet& frames, std::size_t frame);

// frame_to_json(frames, frame).dump() without building the DOM: frames are nearly all of a large
// result, and one small object per pose costs several allocations.
void write_frame_json(std::ostream& out, const FrameSet& frames, std::size_t frame);

// All frames as a JSON array, `[frame, frame, ...]`, streamed.
void write_frames_array(std::ostream& out, const FrameSet& frames);

// The document of `GET /v1/jobs/{id}/frames` in JSON: {"bodies": [...], "frame_count": N,
// "frames": [...], "from": first, "to": first + F}. `total_frame_count` is the result's.
std::string frames_document_json(const FrameSet& frames, std::uint64_t total_frame_count);

// The same frames as BRF1 bytes (`Accept: application/octet-stream`). Poses are written as
// float32, times as float64.
std::string frames_to_brf1(const FrameSet& frames);
// The BRF1 bytes in parts, for a writer that streams a page in blocks of frames: the header of a
// page of `frame_count` frames from `first_frame`, then each block's frame records.
std::string brf1_header(std::uint64_t first_frame, std::uint64_t frame_count,
                        const std::vector<std::uint32_t>& bodies);
void append_brf1_frames(std::string& out, const FrameSet& frames);
void write_brf1(const FrameSet& frames, std::ostream& out);

}  // namespace brisance::io
