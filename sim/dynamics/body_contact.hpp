// sim/dynamics/body_contact: contacts between bodies (and, for the bodies in them, the ground)
// solved together by warm-started sequential impulses with Coulomb friction and restitution,
// the scheme of ground_contact.hpp extended to pairs (issue 13). The engine finds the contact
// points (convex.hpp) and hands them here with the velocities of the bodies involved; static
// partners (the ground, anchored and held bodies) have zero inverse mass.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/dynamics/rigid_body.hpp"

namespace brisance::dynamics {

// A body in the solve: its velocities (world frame) and inverse mass and inertia (world frame;
// zero for a static partner).
struct SolverBody {
  Vec3 velocity = Vec3::Zero();
  Vec3 omega = Vec3::Zero();
  double inverse_mass = 0.0;
  Mat3 inverse_inertia = Mat3::Zero();
  Vec3 position_shift = Vec3::Zero();  // out of penetration, m (written by the solve)
  // Used by the solve: the farthest contact point from the centre of mass, m, and the
  // velocities at the end of the last sweep (for its convergence test).
  double reach_m = 0.0;
  bool listed = false;  // in the island's list of moving bodies
  Vec3 swept_velocity = Vec3::Zero(), swept_omega = Vec3::Zero();
};

struct PairContact {
  std::uint32_t a = 0, b = 0;   // solver bodies; the normal points from a to b
  Vec3 point = Vec3::Zero();    // world, m
  Vec3 normal = Vec3::UnitY();  // world, unit
  double depth_m = 0.0;         // penetration; negative: a gap (a speculative contact)
  double friction = 0.0;
  double restitution = 0.0;
  double gravity_speed_m_s = 0.0;  // the normal speed of b relative to a that gravity added
  std::uint64_t key = 0;           // stable id of the contact across steps, for warm starting
  Vec3 arm_a = Vec3::Zero(),
       arm_b = Vec3::Zero();  // from each centre of mass to the point, world, m (zero for static)
  // Filled by the solve.
  double approach_before = 0.0;  // normal speed of b relative to a before the solve, m/s
  double depth_after_m = 0.0;    // once the bodies move with the solved velocities
  double normal_impulse = 0.0;   // N s
};

// Impulses by contact key (world frame, N s): one step's, for the next step's warm start. A
// flat array and an open-addressed index over it, both reused from step to step (a hash map's
// node per contact and step cost more than the lookups: its allocations were 3 % of the brick
// wall's run; a binary search in the sorted array, 7 % of the contact phase).
class ContactImpulses {
 public:
  void clear() {
    entries_.clear();
    slots_.clear();
  }
  bool empty() const { return entries_.empty(); }
  std::size_t size() const { return entries_.size(); }
  // Any order while filling; of equal keys the last added is kept (seal).
  void add(std::uint64_t key, const Vec3& impulse) { entries_.push_back(Entry{key, impulse}); }
  // Indexes the keys once filled (of equal keys, the last added); required before find.
  void seal();
  // The impulse stored for `key`, or null.
  const Vec3* find(std::uint64_t key) const;

 private:
  struct Entry {
    std::uint64_t key;
    Vec3 impulse;
  };
  std::vector<Entry> entries_;
  std::vector<std::uint32_t> slots_;  // index + 1 into entries_, 0 empty; a power of two long
};

// One contact as the sweeps read it (packed: the sweeps touch nothing else). Per direction
// (normal, u, v): arm x direction for a and b, and the spin one unit of impulse gives each
// body (I^-1 (arm x direction)), so a sweep is dot products and adds.
struct ContactRow {
  std::uint32_t a, b;
  std::uint8_t moves;   // 1: a moves, 2: b moves, 3: both (a static partner's terms are zero)
  bool friction_ready;  // spin_*[1, 2], mass_u and mass_v are set (filled when first needed)
  double inverse_mass_a, inverse_mass_b;
  Vec3 normal, u, v;
  std::array<Vec3, 3> lever_a, lever_b, spin_a, spin_b;
  double mass_normal, mass_u, mass_v, target_speed, friction;
  double normal_impulse, friction_u, friction_v;
  // The normal impulse whose friction the contact may bear at most, N s, when a solve that ran
  // away is done again (solve_pair_contacts); unused otherwise.
  double friction_cap;
};

// The solve's buffers, kept by the caller from step to step to spare their allocations.
struct PairSolveBuffers {
  std::vector<std::uint32_t> island;  // the moving bodies
  std::vector<ContactRow> rows;
  // Per body of the island: its velocities before the solve and its world inertia (for the
  // island's kinetic energy).
  std::vector<Vec3> start_velocity, start_omega;
  std::vector<Mat3> inertia;
  // Per solver body: its place in the island's lists. Per body of the island: the turn it makes
  // when the step is redone with the solved velocities, rad, and whether it is large enough to
  // be taken exactly (then the rotation less the identity).
  std::vector<std::uint32_t> slot;
  std::vector<Vec3> turn;
  std::vector<Mat3> turn_minus_identity;
  std::vector<std::uint8_t> turned;
  std::uint64_t energy_limited = 0;  // islands whose solve was scaled back (passivity)
  std::uint64_t spin_limited = 0;    // bodies whose spin from the solve was limited
  std::uint64_t speed_limited = 0;   // bodies whose speed from the solve was limited
  std::uint64_t runaways = 0;        // islands solved again, their friction capped (runaway)
};

struct PairSolveSettings {
  double dt_s;
  double bounce_threshold_m_s = 0.5;  // slower impacts do not bounce, as on the ground
  int iterations = 60;
  // The sweeps stop once a sweep changes no body's velocity, at its farthest contact point, by
  // more than converged_m_s, or by more than converged_fraction of the speed of the island's
  // slowest body (at its farthest contact point): an island whose bodies all move (a wall
  // toppling as a block, debris in flight) is solved to a fraction of its motion, one with a
  // body at rest to 30 um/s. Both chosen on the ten-brick tower in 30 variants
  // (Stability.BrickTowerStandsWhateverTheDrop): 1e-4 m/s let 9 of them drift, 3e-5 none; a
  // fraction of 1e-2 let 4 drift, 3e-3 none.
  double converged_m_s = 3e-5;
  double converged_fraction = 3e-3;
  // Last step's impulses are scaled by this for the warm start: this step's length over last
  // step's (a steady contact force gives impulses in proportion to the step; the adaptive step
  // alternates between lengths, 9.5 and 4.9 ms as frames fall, which left every other warm
  // start twice or half what it needed).
  double warm_start_scale = 1.0;
  // The kinetic energy the solve may add to an island beyond its own 1 %, per kg of its
  // bodies: (g dt)^2, what one step's gravity and last step's impulses give a body at rest.
  double gravity_m_s2 = 9.81;
  double slop_m = 5e-4;              // penetration left alone (no jitter)
  double position_correction = 0.6;  // of the penetration beyond the slop, per step
};

// Solves the contacts of one island (no body other than static ones, of zero inverse mass, is
// in contacts outside it): velocities of `bodies` updated in place, each contact's impulses set,
// and added to `next` for the next step's warm start (`last` sealed; `next` is sealed by the
// caller once every island is solved).
//
// The contacts are found at the end of a step whose positions were advanced with the velocities
// handed in (x1 = x0 + v dt); the caller moves each body again by (v' - v) dt with the solved
// velocities v', so that x1' = x0 + v' dt: the solve acts on this step's motion, not the next
// one's. Each contact's depth at the start of the step is its depth minus the approach it made
// within the step; a gap there may close within the step, no more, and a penetration there is
// not pushed out by velocity (which would add energy) but by the position shifts.
// Returns the number of sweeps it took.
int solve_pair_contacts(std::vector<SolverBody>& bodies, std::span<PairContact> contacts,
                        const ContactImpulses& last, ContactImpulses& next,
                        const PairSolveSettings& settings, PairSolveBuffers& buffers);

}  // namespace brisance::dynamics
