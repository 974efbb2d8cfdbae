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
  std::string material;   // the materials table's name, or "" (a density or mass was given)
  bool fragment = false;  // a piece of a broken pane: its side walls are crack faces
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
  std::uint64_t bodies_never_released =
      0;  // held throughout (friction or a frame): never integrated
  std::uint64_t fragments_held_by_frame = 0;  // of those, glass fragments its frame kept
  std::uint64_t bodies_slept = 0;             // came to rest and stopped being integrated
  std::uint64_t bodies_static_in_frames = 0;  // stored once instead of per frame
  std::uint64_t panels = 0;
  std::uint64_t panels_loaded = 0;
  std::uint64_t panels_back_facing = 0;  // sheltered and facing away from every charge
  std::uint64_t panels_not_reached = 0;  // the wave arrived after the run ended
  std::uint64_t body_steps = 0;          // bodies integrated, summed over steps
  bool occlusion_skipped = true;         // no occlusion pass ran
  std::uint64_t panels_shielded = 0;     // (panel, charge) pairs wholly shielded: no load
  std::uint64_t panes_broken = 0;        // breakable panes cut into fragments
  std::uint64_t panes_not_broken = 0;    // stress below strength: no fracture work at all
  std::uint64_t fragments = 0;           // fragment bodies made
  // Load panels not made: a fragment under 2 cm, or one every wave crosses within 2 cm of path,
  // takes one panel a face instead of 5-16, which carry nearly the same pressure on it
  // (docs/fracture.md, "Performance").
  std::uint64_t panels_merged = 0;
  // Contacts between bodies (issue 13), summed over steps: pairs whose boxes met (broadphase),
  // pairs skipped by `collisions: "auto"` (moving apart, not touching last step), and contact
  // points solved.
  std::uint64_t collision_pairs = 0;
  std::uint64_t collision_pairs_skipped = 0;
  std::uint64_t contact_points = 0;
};

// Mean and percentiles of a per-fragment quantity (nearest-rank percentiles); all zero when
// there is nothing to summarise.
struct Distribution {
  std::uint64_t count = 0;
  double mean = 0.0;
  double min = 0.0;
  double p10 = 0.0;
  double p50 = 0.0;
  double p90 = 0.0;
  double max = 0.0;
};

// Where a pane's glass went in the test room behind it, and the glazing performance condition
// that follows (GSA P100 table 8-1; sim/engine/hazard.hpp). The room's floor is the ground, or
// y = 0 without one, but never above the pane's lowest corner; its witness panel stands 10 ft
// (3.048 m) behind the pane's inner face.
struct PaneHazard {
  std::string condition = "1";            // "1", "2", "3a", "3b", "4" or "5"
  std::string protection_level = "safe";  // safe, very_high, high, medium, low
  std::string hazard_level = "none";      // none, very_low, low, medium, high
  double floor_height_m = 0.0;            // the room's floor, world y
  std::uint64_t fragments_in_room = 0;    // released fragments that went in behind the pane
  std::uint64_t fragments_outside = 0;    // released fragments thrown out toward the blast
  std::uint64_t fragments_on_floor = 0;   // of those in the room, landed before the panel
  std::uint64_t witness_impacts = 0;      // of those in the room, reached the witness panel
  // Followed past the run's end on a ballistic path (still in flight when it ended).
  std::uint64_t fragments_extrapolated = 0;
  double max_floor_distance_m = 0.0;  // furthest landing behind the pane's inner face
  double max_witness_height_m = 0.0;  // highest witness impact above the floor
};

// One breakable pane: the blast coupling (DESIGN.md decision 9) and its fragments.
struct PaneReport {
  std::string name;  // the pane object's name; its fragments are "<name>/f<k>"
  bool broken = false;
  bool forced = false;            // fracture.break = always: broken whatever the stress
  double peak_pressure_pa = 0.0;  // peak reflected overpressure at the pane's centre
  double stress_pa = 0.0;         // peak centre stress by fracture.breakage (docs/fracture.md)
  double strength_pa = 0.0;
  double deflection_m = 0.0;             // the same model's (peak) centre deflection
  bool small_deflection = true;          // deflection <= thickness / 2
  double critical_crack_length_m = 0.0;  // a_c of thesis eq. 5.5 at that stress (0: unbroken)
  double growth_length_m = 0.0;          // the crack pattern's a_c (0: unbroken)
  bool growth_length_given = false;      // set by fracture.growth_length
  bool growth_length_clamped = false;    // eq. 5.5's scale hit the bit bucket's or pane's size
  std::uint32_t first_body = 0;          // its fragments are bodies first_body ...
  std::uint64_t fragment_count = 0;      //  ... first_body + fragment_count - 1
  Distribution frontal_area_m2;          // of the fragments
  // Speed of each released fragment right after its blast load ended (launch), m/s.
  Distribution launch_speed_m_s;
  // Mean launch speed of the larger and the smaller half of the released fragments by area
  // (thesis §6.5: larger fragments fly faster when each clears from its own edges), m/s.
  double launch_speed_larger_half_m_s = 0.0;
  double launch_speed_smaller_half_m_s = 0.0;
  // Mean launch speed weighted by mass (the released fragments' momentum over their mass), m/s:
  // what the wave's impulse bounds (i_r / (rho h) for a pane with a sheltered back).
  double launch_speed_mass_weighted_m_s = 0.0;
  // When the pane's cracks start, s after detonation (its stress first reaches its strength; the
  // first arrival for the static model or a forced break); -1 if unbroken. They run out from the
  // pane's centre at fracture::kTerminalCrackSpeed_m_s, and no fragment is free before the front
  // has passed all of its outline.
  double cracks_start_s = -1.0;
  // Where they start, m, in the pane's own x and y from its lower-left corner: the largest
  // bending stress of the simply supported plate under the peak pressures over its face
  // (sim/fracture/nucleation); the centre for a uniform load. [0, 0] if unbroken.
  std::array<double, 2> crack_origin_m{};
  std::uint64_t released = 0;
  // Per fragment, in body order: when it broke free (s), or a negative value if it never did
  // (held by the frame or the crack interlock; such fragments stay in place, static).
  std::vector<double> release_times_s;
  Distribution release_time_s;  // of the released ones
  // Empirical window-glass fragments at the same peak pressure (thesis eqs. 2.45, 2.46).
  double empirical_mean_area_m2 = 0.0;
  double empirical_mean_speed_m_s = 0.0;
  PaneHazard hazard;  // filled once the run is over
};

// A counted warning: numerical trouble or input at the edge of the model, never silent.
struct Warning {
  std::string code;     // stable identifier, e.g. "blast_out_of_range"
  std::string message;  // what happened and what it means for the result
  std::uint64_t count = 1;
};

// What shielded bodies from one charge (thesis ch. 4): each body whose loads the charge's
// shielding pass scaled down, with its area-weighted mean attenuation over its panels.
struct ShieldedBody {
  std::uint32_t body = 0;    // index into Result::bodies
  double attenuation = 1.0;  // in [0, 1): 0 wholly shielded
};
struct ChargeShielding {
  std::uint32_t charge = 0;          // index into the scene's charges
  std::vector<ShieldedBody> bodies;  // ascending body index; bodies at 1 are left out
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
  std::vector<PaneReport> fracture;        // one per breakable pane, in scene order
  std::vector<ChargeShielding> shielding;  // one per charge, when a shielding pass ran

  const Pose& pose(std::size_t frame, std::size_t animated_index) const {
    return poses[frame * animated.size() + animated_index];
  }
};

}  // namespace brisance::engine
