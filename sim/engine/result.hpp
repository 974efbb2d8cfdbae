// sim/engine/result: what a simulation run produces — bodies, sampled frames, final states,
// statistics and warnings. Plain data, no Eigen, so writers and storage need nothing else.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/geometry/mesh.hpp"

namespace brisance::engine {

// The pose of a body's shape origin in the world (the same frame as the scene's `position` and
// `orientation`): position in m, unit quaternion [x, y, z, w].
struct Pose {
  std::array<double, 3> position{};
  std::array<double, 4> orientation{0.0, 0.0, 0.0, 1.0};
};

struct BodyInfo {
  std::string name;
  double mass_kg = 0.0;
  geometry::TriangleMesh mesh;  // in the shape's own frame
  Pose initial_pose;            // also the pose for every frame if the body never moves
};

struct FinalState {
  std::string name;
  Pose pose;
  std::array<double, 3> linear_velocity_m_s{};     // world frame, of the centre of mass
  std::array<double, 3> angular_velocity_rad_s{};  // world frame
};

// What the run skipped or did, for the `stats` object of the result (DESIGN.md decision 10).
struct Stats {
  std::uint64_t steps = 0;
  double simulated_time_s = 0.0;
  double wall_time_s = 0.0;
  bool ended_early = false;  // everything at rest or gone before `duration`
  std::uint64_t bodies = 0;
  std::uint64_t bodies_anchored = 0;
  std::uint64_t bodies_never_released = 0;    // held by friction throughout: never integrated
  std::uint64_t bodies_slept = 0;             // came to rest and stopped being integrated
  std::uint64_t bodies_static_in_frames = 0;  // stored once instead of per frame
  std::uint64_t panels = 0;
  std::uint64_t panels_loaded = 0;
  std::uint64_t panels_back_facing = 0;  // facing away from every charge: never loaded
  std::uint64_t panels_not_reached = 0;  // the wave arrived after the run ended
  std::uint64_t body_steps = 0;          // bodies integrated, summed over steps
  bool occlusion_skipped = true;         // no occlusion pass ran
};

// A counted warning: numerical trouble or input at the edge of the model, never silent.
struct Warning {
  std::string code;     // stable identifier, e.g. "blast_out_of_range"
  std::string message;  // what happened and what it means for the result
  std::uint64_t count = 1;
};

struct Result {
  std::vector<BodyInfo> bodies;
  // Indices into `bodies` of the bodies that move; frames store poses only for these.
  std::vector<std::uint32_t> animated;
  std::vector<double> frame_times_s;  // exact multiples of 1 / frame_rate, from 0
  // Frame-major: poses[frame * animated.size() + k] is the pose of bodies[animated[k]].
  std::vector<Pose> poses;
  std::vector<FinalState> final_state;  // one per body, in body order
  Stats stats;
  std::vector<Warning> warnings;

  const Pose& pose(std::size_t frame, std::size_t animated_index) const {
    return poses[frame * animated.size() + animated_index];
  }
};

}  // namespace brisance::engine
