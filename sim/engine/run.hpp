// sim/engine/run (private to the engine): the stepping of one prepared Model. Everything that
// changes while stepping lives in RunState (STYLE.md §1); Run reads the Model, writes the state,
// and fills the Result: init, a loop of steps, finish. A step is a short list of named phases;
// contacts between bodies are the last (collide.cpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/blast/panel_load.hpp"
#include "sim/dynamics/body_contact.hpp"
#include "sim/dynamics/convex.hpp"
#include "sim/dynamics/ground_contact.hpp"
#include "sim/dynamics/rigid_body.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/simulator.hpp"

namespace brisance::engine {

// A panel's wave while it acts on it.
struct ActiveLoad {
  std::uint32_t panel;
  double arrival_time_s;
  blast::PressureHistory history;  // net translatory pressure, Pa, time since arrival
};

// A contact's place in the solve: by island, then bottom up (collide.cpp); sorted on these
// packed keys, the comparisons read no contact.
struct ContactOrder {
  std::uint64_t height;  // of the point, as ordered bits (collide.cpp)
  std::uint64_t key;
  std::uint32_t index;
  std::uint32_t island;
};

// A body's world box grown by its margin, as the broadphase's sweep reads it (collide.cpp): in
// the sweep's order, so that the bodies a sweep passes over are read one after another.
struct SweptBox {
  Vec3 low, high;
  std::uint32_t body;
  bool awake;
};

// The narrowphase of a pair of bodies, kept while their relative pose barely changes
// (collide.cpp): the pose of b in a's frame it was found at, the margin it was found with, and
// its points (first, count) in RunState::cached_points.
struct PairCache {
  std::uint64_t key;             // contact_key(a, b, 0)
  Vec3 relative_position;        // b's centre of mass in a's frame, m
  dynamics::Quat relative_turn;  // b's orientation in a's frame
  double margin_m;
  std::uint32_t first, count;
};
// A cached contact point: where it lies on each body (each body's frame, from its centre of
// mass, m), the normal in a's frame, and the feature tag.
struct CachedPoint {
  Vec3 on_a, on_b, normal_a;
  std::uint32_t feature;
};

// `auto`: two pieces of a pane that touch at the start (collide.cpp, part_joined_pairs), and the
// pose of b in a's frame when their hulls were last found overlapping (at first, the start).
struct JoinedPair {
  std::uint64_t key;             // contact_key(a, b, 0)
  Vec3 relative_position;        // b's centre of mass in a's frame, m
  dynamics::Quat relative_turn;  // b's orientation in a's frame
};

// Everything that changes while stepping; per body in body order unless said otherwise.
struct RunState {
  std::vector<dynamics::BodyState> bodies;
  std::vector<Motion> motion;
  std::vector<double> rest_time_s;                // time at rest on the ground, s
  std::vector<dynamics::ContactMemory> contacts;  // for warm-started ground contact
  std::vector<std::uint8_t> moved;                // integrated at least once
  std::vector<std::uint8_t> panel_loaded;         // per panel: a wave has reached it
  std::vector<dynamics::StepLoads> loads;         // this step's, world frame
  std::vector<std::uint32_t> loaded_bodies;       // bodies with nonzero loads this step
  std::vector<std::uint8_t> is_loaded;
  // Per loaded body this step: the sum of its panels' force vectors at their largest (the start
  // of the step, or the wave's arrival within it: every pulse decays from its front), N, and
  // the time from which any load acted, s. The hold is judged on these, so whether a body is
  // released does not depend on the step size.
  std::vector<Vec3> peak_force_n;
  std::vector<double> loaded_from_s;
  // Fragments held in their pane: the loads taken while held, world frame, given to the
  // fragment when it breaks free (the pane bends and moves with them before it cracks through).
  std::vector<dynamics::StepLoads> deferred;
  // Held fragments: the largest load they have felt (N), and those whose load has beaten their
  // hold and who wait only for the crack front to free them (release_not_before_s).
  std::vector<double> held_peak_force_n;
  std::vector<std::uint32_t> pending_release;
  // Fragments: when each broke free and its speed once its blast load ended (launch), or -1.
  std::vector<double> release_time_s;
  std::vector<double> launch_speed_m_s;
  // The blast wind each body moves in (blast::BlastWind, body-major: [b * charges + c]), found
  // when the body first moves, and the time after which it is still air (-1: not yet found).
  std::vector<blast::BlastWind> wind;
  std::vector<double> wind_until_s;
  double step_start_s = 0.0;
  std::vector<ActiveLoad> active;         // waves acting on panels
  std::size_t next_event = 0;             // into Model::events
  std::vector<std::uint32_t> candidates;  // bodies that may move (all but anchored)
  std::vector<Pose> candidate_poses;      // frame-major over candidates
  std::size_t frame_count = 0;
  // Contacts between bodies (collide.cpp): shapes, their world placement, the sweep order
  // kept from step to step (nearly sorted: insertion sort), last step's impulses, and whether
  // each body touched another body last step (for sleeping).
  std::vector<dynamics::CollisionShape> shapes;
  // Each body's world box is found every step it moves; its pieces are placed only when a pair
  // reaches the narrowphase (most fragments never do).
  std::vector<std::vector<dynamics::PlacedPiece>> placed;
  std::vector<dynamics::BodyState> placed_state;  // the state each body's pieces were placed at
  std::vector<std::uint8_t> placed_valid;
  std::vector<dynamics::BodyState> box_state;  // the state each body's box was found at
  std::vector<std::uint8_t> box_valid;
  std::vector<Vec3> box_min, box_max;  // world boxes (each body's margin is added where used)
  // Each shape's box in its body's frame (centre and half sizes, from the centre of mass, m):
  // a fragment's world box is this box's, turned.
  std::vector<Vec3> shape_box_centre, shape_box_half;
  std::vector<std::uint32_t> sweep_order;
  std::vector<std::uint32_t> sweep_others, sweep_fragments;    // the step's order, split
  std::vector<SweptBox> swept_others, swept_fragments;         // and their boxes, alongside
  std::vector<std::pair<double, std::uint32_t>> sweep_flying;  // `on`: fragments in flight,
  std::vector<double> flying_margin;  // sorted by their boxes' low ends less their margins
                                      // relative to the flock (collide)
  int sweep_axis = 0;  // the axis the sweep order sorts along: the one of widest spread
  dynamics::ContactImpulses contact_impulses, next_contact_impulses;
  double contact_impulses_dt_s = 0.0;  // the step contact_impulses were solved in
  std::vector<std::uint8_t> touching_body;
  // The bodies integrated this step and whether each touched the ground: with contacts between
  // bodies, sleeping is judged after them (sleep_after_contacts).
  std::vector<std::uint32_t> stepped;
  std::vector<std::uint8_t> touching_ground;
  std::vector<std::uint8_t> ground_with_bodies;  // its ground contact is solved in collide
  // The step's buffers, kept to spare their allocations.
  std::vector<dynamics::PairContact> pair_contacts, sorted_contacts;
  std::vector<std::uint32_t> contact_held, sorted_held;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  std::vector<double> margin;                // per body: the step's motion plus kContactMargin_m, m
  std::vector<double> spin_margin;           // per body: how far its turning moves its surface, m
  std::vector<std::uint32_t> island_parent;  // union-find over the solve's bodies
  std::vector<std::int32_t> solver_index;    // per body: its solver body, or -1
  std::vector<dynamics::SolverBody> solver, solver_before;
  std::vector<std::uint32_t> solver_body;  // per solver body: the body
  std::vector<std::uint32_t> contact_island;
  std::vector<ContactOrder> contact_order;
  std::vector<std::uint32_t> island_start;  // per solve body: its island's first in contact_order
  std::vector<double> pushed;
  dynamics::PairSolveBuffers solve_buffers;
  // Last step's and this step's narrowphase by pair, sorted by key (pairs come sorted).
  std::vector<PairCache> pair_cache, next_pair_cache;
  std::vector<CachedPoint> cached_points, next_cached_points;
  // `auto`: pairs of pieces of a pane (two fragments, or a fragment and an anchored body: its
  // frame) whose boxes meet at the start and have not been apart since, sorted.
  std::vector<JoinedPair> joined_pairs;
  // Pairs pressed together (contact_key(a, b, 0)), sorted: last step's and this step's.
  std::vector<std::uint64_t> touching_pairs, next_touching_pairs;
  // Step-size limits gathered while integrating, used for the next step.
  double max_angular_speed_rad_s = 0.0;
  double min_contact_time_s = INFINITY;
  double min_active_duration_s = INFINITY;
};

class Run {
 public:
  // `result.bodies` must already hold one entry per body (their names go into final states).
  Run(const Model& model, Result& result, WarningLog& warnings)
      : model_(model), result_(result), warnings_(warnings) {}

  // False if cancelled (the result is then incomplete).
  bool execute(const RunHooks& hooks);
  const RunState& state() const { return state_; }

 private:
  void init();
  bool loop(const RunHooks& hooks);
  void finish();

  // The step and its phases, in order.
  void step(double t0, double t1);
  void activate_arrivals(double t1);  // waves that reach their panels before t1 start acting
  void apply_loads(double t0, double t1);
  void release_held(double t0, double t1);
  void integrate_awake(double dt);  // with ground contact and sleeping
  // The air's velocity at body b at time t: the blast wind of every charge (zero before its
  // arrival and after its positive phase), m/s, world frame.
  Vec3 air_velocity(std::uint32_t b, double t);
  void collide(double dt);  // contacts between bodies (collide.cpp)
  void init_collisions();
  void part_joined_pairs();
  // Awake and not on the ground (in this step's integration).
  bool in_flight(std::uint32_t b) const;
  // Whether the two bodies' boxes are farther apart than `gap` along some axis.
  bool boxes_apart(std::uint32_t a, std::uint32_t b, double gap) const;
  // How near two bodies in flight can come in a step: kContactMargin_m plus their motion
  // relative to each other (collide.cpp).
  double relative_margin(std::uint32_t a, std::uint32_t b, double dt) const;
  // The broadphase's test of a pair the sweep met: kept in state_.pairs if the boxes grown by
  // both margins meet, unless a fragment and a body both in flight (`a_flies`) lie farther
  // apart than their relative margin (then counted in `culled`).
  void form_pair(std::uint32_t a, std::uint32_t b, bool a_flies, double dt, std::uint64_t& culled);
  void sweep_flying_fragments(double dt, std::uint64_t& culled);
  void place_body(std::uint32_t b);
  void sleep_after_contacts(double dt);

  void activate(const PanelEvent& event);
  int contact_substeps(const dynamics::BodyModel& body, const dynamics::BodyState& state,
                       double dt) const;
  int ground_substeps(const dynamics::BodyModel& body, const dynamics::BodyState& state,
                      double dt) const;
  double next_step(double t, double until) const;
  bool quiet() const;
  void record_frame();

  const Model& model_;
  Result& result_;
  WarningLog& warnings_;
  RunState state_;
};

}  // namespace brisance::engine
