// sim/engine/run: the stepping loop (DESIGN.md decision 6) — init from the model, a loop of
// steps made of named phases (arrivals, loads, holds, integration with ground contact and
// sleeping), frames at exact multiples of 1 / frame_rate, and finish into the Result.
#include "sim/engine/run.hpp"

#include <algorithm>
#include <cmath>

#include "sim/blast/reflection.hpp"
#include "sim/engine/sleeping.hpp"

namespace brisance::engine {

namespace {

// A sum of finite numbers is finite unless it overflows (beyond 1e308: no state of a body),
// and a NaN or an infinity in any term makes it NaN or infinite: one test instead of thirteen.
// How far every body an anchored body was set into must have moved for it to be left alone, m.
constexpr double kAnchorLeftAlone_m = 0.05;

bool finite(const dynamics::BodyState& s) {
  return std::isfinite(s.position.sum() + s.velocity.sum() + s.orientation.coeffs().sum() +
                       s.angular_momentum.sum());
}

}  // namespace

void Run::activate(const PanelEvent& event) {
  const PanelModel& panel = model_.panels[event.panel];
  const dynamics::BodyState& state = state_.bodies[panel.body];
  const ChargeModel& charge = model_.charges[event.charge];
  const Vec3 centre = state.position + state.orientation * panel.centre;
  const Vec3 normal = state.orientation * panel.normal;
  const Vec3 d = centre - charge.position;
  const double distance = std::max(d.norm(), 1e-3);
  const double cos_incidence = -normal.dot(d) / distance;
  const blast::FaceKind kind = blast::face_kind(cos_incidence);
  // A sheltered face (a room behind a window) is loaded only by a wave that strikes it.
  if (panel.sheltered && kind != blast::FaceKind::front) return;
  const blast::BlastPoint point = blast::blast_point(charge.charge, distance);
  if (!point.in_validity_range) warnings_.add("blast_out_of_range", kBlastOutOfRangeMessage);
  blast::PanelWave wave = blast::panel_wave(point, cos_incidence);
  if (kind == blast::FaceKind::front) {
    const blast::ObliqueReflection reflection =
        blast::oblique_reflection(point.incident_overpressure_pa, point.incident_impulse_pa_s,
                                  point.reflected_overpressure_pa, point.reflected_impulse_pa_s,
                                  std::acos(std::min(1.0, cos_incidence)));
    if (!reflection.in_chart_range)
      warnings_.add("reflection_out_of_chart",
                    "a panel's incident overpressure lies outside the reflection chart "
                    "(1.4 kPa - 34.5 MPa); the nearest chart curve was used");
    wave.reflected_overpressure_pa = reflection.overpressure_pa;
    wave.reflected_impulse_pa_s = reflection.impulse_pa_s;
  }
  blast::PanelLoadOptions options = model_.load_options;
  options.clearing_distance_m = panel.clearing_distance_m;
  if (kind == blast::FaceKind::front && options.clearing)
    options.clearing_delay_s =
        blast::clearing_delay_s(charge.charge, std::abs(normal.dot(d)),
                                (d - normal.dot(d) * normal).norm(), panel.clearing_distance_m);
  options.panel_extent_m = panel.extent_m;
  options.drag_coefficient = model_.bodies[panel.body].drag_coefficient;
  blast::PressureHistory history = blast::face_history(kind, wave, options);
  // What stands between the charge and the panel takes its share (thesis eq. 4.1).
  if (!model_.shielding.empty())
    history.scale(kind == blast::FaceKind::front
                      ? model_.shielding[event.charge * model_.panels.size() + event.panel]
                      : model_.body_shielding[event.charge * model_.bodies.size() + panel.body]);
  state_.active.push_back(ActiveLoad{event.panel, event.arrival_time_s, history});
  state_.panel_loaded[event.panel] = 1;
}

void Run::apply_loads(double t0, double t1) {
  const bool moments = model_.world.integrator == dynamics::Integrator::rk4;
  std::size_t kept = 0;
  state_.min_active_duration_s = INFINITY;
  for (std::size_t i = 0; i < state_.active.size(); ++i) {
    const ActiveLoad& load = state_.active[i];
    const PanelModel& panel = model_.panels[load.panel];
    const double a = t0 - load.arrival_time_s;
    const double b = t1 - load.arrival_time_s;
    const double impulse = load.history.impulse_pa_s(a, b) * panel.area_m2;
    if (impulse != 0.0 && state_.motion[panel.body] != Motion::anchored) {
      const dynamics::BodyState& state = state_.bodies[panel.body];
      const Vec3 push = -(state.orientation * panel.normal);  // pressure acts inward
      const Vec3 arm = state.orientation * panel.centre;
      dynamics::StepLoads& body = state_.loads[panel.body];
      body.impulse += impulse * push;
      body.angular_impulse += model_.rotation_factor * arm.cross(impulse * push);
      if (moments) body.impulse_moment += load.history.moment_pa_s2(a, b) * panel.area_m2 * push;
      const double from = std::max(a, 0.0);
      if (!state_.is_loaded[panel.body]) {
        state_.is_loaded[panel.body] = 1;
        state_.loaded_bodies.push_back(panel.body);
        state_.peak_force_n[panel.body].setZero();
        state_.loaded_from_s[panel.body] = t1;
      }
      state_.peak_force_n[panel.body] += load.history.pressure_pa(from) * panel.area_m2 * push;
      state_.loaded_from_s[panel.body] =
          std::min(state_.loaded_from_s[panel.body], load.arrival_time_s + from);
    }
    if (b < load.history.end_s()) {
      state_.min_active_duration_s = std::min(state_.min_active_duration_s, load.history.end_s());
      state_.active[kept++] = std::move(state_.active[i]);
    }
  }
  state_.active.resize(kept);
}

void Run::release_held(double t0, double t1) {
  // Fragments whose load beat their hold while their cracks were still closing go once the
  // crack front has passed them, loaded this step or not (the wave may have passed by then).
  std::size_t waiting = 0;
  for (std::uint32_t body : state_.pending_release) {
    if (state_.motion[body] != Motion::held) continue;
    if (t1 < model_.release_not_before_s[body]) {
      state_.pending_release[waiting++] = body;
    } else if (!state_.is_loaded[body]) {
      state_.is_loaded[body] = 1;
      state_.loaded_bodies.push_back(body);
      state_.peak_force_n[body].setZero();
      state_.loaded_from_s[body] = t1;
    }
  }
  state_.pending_release.resize(waiting);
  for (std::uint32_t body : state_.loaded_bodies) {
    if (state_.motion[body] == Motion::asleep) {
      state_.motion[body] = Motion::awake;  // a later wave wakes a resting body
      state_.rest_time_s[body] = 0.0;
    }
    const double hold = model_.hold_force_n[body];  // mu N, N
    dynamics::StepLoads& loads = state_.loads[body];
    if (state_.motion[body] == Motion::held) {
      // A fragment breaks free once its load has beaten its hold (thesis §6.7) and the wave has
      // reached its centroid and the crack front has passed all of its outline (its cracks have
      // closed around it); the loads of its panels reached earlier are taken by the hold.
      const double not_before = model_.release_not_before_s[body];
      const bool fragment = model_.fragment[body] != 0;
      double judged = state_.peak_force_n[body].norm();
      bool beaten_now = false;  // its load beats its hold for the first time
      if (fragment) {
        const double before = state_.held_peak_force_n[body];
        state_.held_peak_force_n[body] = std::max(before, judged);
        judged = state_.held_peak_force_n[body];
        beaten_now = before <= hold && judged > hold;
      }
      if (t1 < not_before || judged <= hold) {
        if (beaten_now) state_.pending_release.push_back(body);
        // A fragment's load moves its pane until it breaks free; a resting body's is taken by
        // static friction.
        if (fragment) {
          dynamics::StepLoads& deferred = state_.deferred[body];
          deferred.impulse += loads.impulse;
          deferred.angular_impulse += loads.angular_impulse;
        }
        loads = dynamics::StepLoads{};
        continue;
      }
      state_.motion[body] = Motion::awake;
      if (fragment) {
        state_.release_time_s[body] = std::max(t0, not_before);
        // What it took while held acts at the start of this step, shared out as the plate's
        // velocity was when its pane broke (model.hpp, release_velocity_m_s).
        const dynamics::StepLoads& deferred = state_.deferred[body];
        loads.impulse += model_.bodies[body].mass_kg * model_.release_velocity_m_s[body];
        loads.impulse += deferred.impulse;
        loads.angular_impulse += deferred.angular_impulse;
        loads.impulse_moment += (t1 - t0) * deferred.impulse;
        state_.deferred[body] = dynamics::StepLoads{};
      }
    }
    // Thesis eq. 2.40, M x'' + R = F(t) with R = mu N: while the wave pushes a body off its
    // support, friction takes mu N of the push from the load's arrival on, so the body gains the
    // integral of (F - mu N). The push keeps its lever arm, so torque scales the same way.
    const double magnitude = loads.impulse.norm();
    if (model_.supported[body] && magnitude > 0.0) {
      const double resistance = hold * (t1 - state_.loaded_from_s[body]);
      const double keep = std::max(0.0, magnitude - resistance) / magnitude;
      loads.impulse *= keep;
      loads.angular_impulse *= keep;
      loads.impulse_moment *= keep;
    }
  }
}

Vec3 Run::air_velocity(std::uint32_t b, double t) {
  const std::size_t charges = model_.charges.size();
  if (charges == 0 || model_.world.air_density_kg_m3 <= 0.0) return Vec3::Zero();
  const dynamics::BodyState& state = state_.bodies[b];
  if (state_.wind_until_s[b] < 0.0) {
    // Found once, where the body is when it first moves: it moves little while the wave passes.
    double until = 0.0;
    for (std::size_t c = 0; c < charges; ++c) {
      const double distance = std::max((state.position - model_.charges[c].position).norm(), 1e-3);
      blast::BlastWind& wind = state_.wind[b * charges + c];
      wind = blast::blast_wind(blast::blast_point(model_.charges[c].charge, distance),
                               model_.load_options.shape);
      until = std::max(until, wind.end_s());
    }
    state_.wind_until_s[b] = until;
  }
  if (t >= state_.wind_until_s[b]) return Vec3::Zero();
  Vec3 air = Vec3::Zero();
  for (std::size_t c = 0; c < charges; ++c) {
    double speed = state_.wind[b * charges + c].velocity_m_s(t);
    if (speed <= 0.0) continue;
    // What shields the body from the charge takes its share of the dynamic pressure (thesis
    // eq. 4.1), so of the wind its square root.
    if (!model_.body_shielding.empty())
      speed *= std::sqrt(std::max(0.0f, model_.body_shielding[c * model_.bodies.size() + b]));
    const Vec3 away = state.position - model_.charges[c].position;
    const double length = away.norm();
    if (length > 0.0) air += speed / length * away;
  }
  return air;
}

void Run::integrate_awake(double dt) {
  const bool may_sleep = model_.timing.sleep && model_.ground.has_value();
  double max_angular_squared = 0.0;
  std::uint64_t body_steps = 0;
  state_.min_contact_time_s = INFINITY;
  for (std::uint32_t b = 0; b < state_.bodies.size(); ++b) {
    if (state_.motion[b] != Motion::awake) continue;
    const dynamics::BodyModel& body = model_.bodies[b];
    dynamics::BodyState& state = state_.bodies[b];
    const dynamics::BodyState before = state;
    // Most bodies carry no load: their step does not read state_.loads (72 bytes a body).
    static const dynamics::StepLoads kNoLoads{};
    const dynamics::StepLoads* step_loads = state_.is_loaded[b] ? &state_.loads[b] : &kNoLoads;
    // The blast wind over the step (at its middle): flight drag acts on the velocity relative
    // to it (docs/simulator.md). A body its panels load already takes the drag of the wind on a
    // body at rest from them (the faces' C_D q): that much is taken off again, so only the
    // change the body's own motion makes is added.
    const Vec3 air = air_velocity(b, state_.step_start_s + 0.5 * dt);
    dynamics::StepLoads with_wind;
    if (state_.is_loaded[b] && !air.isZero(0.0)) {
      const double wind = air.norm();
      const Vec3 direction_body = state.orientation.conjugate() * (air * (1.0 / wind));
      const double drag_at_rest = 0.5 * model_.world.air_density_kg_m3 * body.drag_coefficient *
                                  body.drag_shape.projected_area_m2(direction_body) * wind * wind;
      with_wind = *step_loads;
      with_wind.impulse -= drag_at_rest * dt * (air * (1.0 / wind));
      step_loads = &with_wind;
    }
    const dynamics::StepLoads& loads = *step_loads;
    // A body that touched another last step meets the ground in the solve of the contacts
    // between bodies (collide.cpp), with the bodies on it: solved here first, apart from
    // them, its ground contact stopped it alone and the weight above it then tipped it.
    const bool ground_with_bodies = !state_.touching_body.empty() && state_.touching_body[b];
    if (!state_.touching_body.empty()) state_.ground_with_bodies[b] = ground_with_bodies;
    const int substeps =
        ground_with_bodies
            ? 1
            : std::max(model_.timing.body_substeps ? ground_substeps(body, state, dt) : 1,
                       contact_substeps(body, state, dt));
    Vec3 omega = Vec3::Zero();
    bool touching = false;
    if (substeps == 1) {
      omega = dynamics::integrate(body, state, loads, model_.world, dt, air);
      if (model_.ground && !ground_with_bodies)
        touching =
            dynamics::resolve_ground_contact(body, state, *model_.ground, &state_.contacts[b]);
    } else {
      // The step's impulse acts in the first substep, as it acts at the start of a step.
      const double h = dt / static_cast<double>(substeps);
      for (int k = 0; k < substeps; ++k) {
        omega = dynamics::integrate(body, state, k == 0 ? loads : kNoLoads, model_.world, h, air);
        touching =
            dynamics::resolve_ground_contact(body, state, *model_.ground, &state_.contacts[b]);
      }
    }
    if (!finite(state)) {
      state = before;
      state_.motion[b] = Motion::asleep;
      warnings_.add("non_finite_state",
                    "a body's state became non-finite (NaN or infinity); it was frozen at its last "
                    "finite state");
      continue;
    }
    state_.moved[b] = 1;
    ++body_steps;
    if (!state_.is_loaded[b] && state_.launch_speed_m_s[b] < 0.0 && model_.fragment[b])
      state_.launch_speed_m_s[b] = state.velocity.norm();
    // Squared speeds, roots only where needed: the largest root is the root of the largest.
    const double angular_squared = omega.squaredNorm();
    if (!model_.ground) {
      max_angular_squared = std::max(max_angular_squared, angular_squared);
      continue;
    }
    const double speed = state.velocity.norm();
    const bool contacts_follow = !state_.touching_body.empty();
    if (contacts_follow) {
      state_.stepped.push_back(b);
      state_.touching_ground[b] = touching ? 1 : 0;
    } else if (falls_asleep(may_sleep && touching, speed, angular_squared, dt,
                            state_.rest_time_s[b])) {
      state_.motion[b] = Motion::asleep;
      state.velocity.setZero();
      state.angular_momentum.setZero();
      ++result_.stats.bodies_slept;
      continue;
    }
    max_angular_squared = std::max(max_angular_squared, angular_squared);
    // A body that can reach the ground within a coarse step must take steps of a fraction of
    // its size, so contact is found before it sinks far in.
    if (speed > 0.0) {
      const double clearance =
          state.position.y() - body.bounding_radius_m - model_.ground->height_m;
      if (clearance < speed * 0.01)
        state_.min_contact_time_s =
            std::min(state_.min_contact_time_s, body.bounding_radius_m / speed);
    }
  }
  result_.stats.body_steps += body_steps;
  state_.max_angular_speed_rad_s = std::sqrt(max_angular_squared);
  for (std::uint32_t b : state_.loaded_bodies) {
    state_.loads[b] = dynamics::StepLoads{};
    state_.is_loaded[b] = 0;
  }
  state_.loaded_bodies.clear();
}

// With body_substeps: the substeps a body near the ground takes over dt, so that each lasts at
// most the fraction of its ground-crossing time the global step keeps to without them.
int Run::ground_substeps(const dynamics::BodyModel& body, const dynamics::BodyState& state,
                         double dt) const {
  if (!model_.ground) return 1;
  const double speed = state.velocity.norm();
  if (!(speed > 0.0)) return 1;
  const double clearance = state.position.y() - body.bounding_radius_m - model_.ground->height_m;
  if (clearance >= speed * 0.01) return 1;
  const double longest = 10.0 * std::sqrt(model_.timing.tolerance) * body.bounding_radius_m / speed;
  // At most 10 000 substeps (a body crossing its own size 30 000 times a step).
  return static_cast<int>(std::clamp(std::ceil(dt / longest), 1.0, 1e4));
}

// With a fixed time_step longer than the adaptive step's longest (0.3 sqrt(tolerance), 9.5 ms
// at 1e-3): the substeps a body that may reach the ground within dt takes, so that its ground
// contact is resolved at most that far apart. A body resting on the ground sank g dt^2 into it
// every step (98 mm at 0.1 s) and rocked on its corners for ever, its energy never falling.
int Run::contact_substeps(const dynamics::BodyModel& body, const dynamics::BodyState& state,
                          double dt) const {
  if (!model_.ground || !model_.timing.time_step_s) return 1;
  const double longest = 0.3 * std::sqrt(model_.timing.tolerance);
  if (dt <= longest) return 1;
  const double clearance = state.position.y() - body.bounding_radius_m - model_.ground->height_m;
  const double fall = std::max(0.0, -model_.world.gravity_m_s2.y()) * dt * dt;
  if (clearance > state.velocity.norm() * dt + fall) return 1;
  return static_cast<int>(std::clamp(std::ceil(dt / longest), 1.0, 1e4));
}

double Run::next_step(double t, double until) const {
  const Timing& sim = model_.timing;
  if (sim.time_step_s) return std::min(*sim.time_step_s, until - t);
  const bool busy = !state_.active.empty() || std::find(state_.motion.begin(), state_.motion.end(),
                                                        Motion::awake) != state_.motion.end();
  if (!busy) {
    // Nothing moves: jump to the next frame or the next arrival.
    double next = until;
    if (state_.next_event < model_.events.size())
      next = std::min(next, std::max(model_.events[state_.next_event].arrival_time_s, t + 1e-9));
    return next - t;
  }
  // The adaptive step: a fraction sqrt(tolerance) of every time scale in play — at tolerance
  // 1e-3, 3 % of the shortest active pulse, 0.06 rad of turn, a third of the time a body near
  // the ground takes to cross its own size, and 9.5 ms at most.
  const double fraction = std::sqrt(sim.tolerance);
  double dt = std::min(1.0 / sim.frame_rate_hz, 0.3 * fraction);
  if (state_.min_active_duration_s < INFINITY)
    dt = std::min(dt, fraction * state_.min_active_duration_s);
  if (state_.max_angular_speed_rad_s > 0.0 && !sim.turn_substeps)
    dt = std::min(dt, 2.0 * fraction / state_.max_angular_speed_rad_s);
  if (state_.min_contact_time_s < INFINITY && !sim.body_substeps)
    dt = std::min(dt, 10.0 * fraction * state_.min_contact_time_s);
  if (state_.next_event < model_.events.size() && state_.active.empty()) {
    // Land the first step of a wave on its arrival.
    const double arrival = model_.events[state_.next_event].arrival_time_s;
    if (arrival > t) dt = std::min(dt, arrival - t);
  }
  return std::clamp(dt, std::min(1e-6, until - t), until - t);
}

void Run::record_frame() {
  for (std::uint32_t body : state_.candidates)
    state_.candidate_poses.push_back(origin_pose(model_, body, state_.bodies[body]));
}

void Run::init() {
  const std::size_t bodies = model_.bodies.size();
  state_.bodies = model_.initial_states;
  state_.motion = model_.initial_motion;
  state_.rest_time_s.assign(bodies, 0.0);
  state_.contacts.assign(bodies, dynamics::ContactMemory{});
  state_.moved.assign(bodies, 0);
  state_.is_loaded.assign(bodies, 0);
  state_.peak_force_n.assign(bodies, Vec3::Zero());
  state_.loaded_from_s.assign(bodies, 0.0);
  state_.deferred.assign(bodies, dynamics::StepLoads{});
  state_.held_peak_force_n.assign(bodies, 0.0);
  state_.wind.assign(bodies * model_.charges.size(), blast::BlastWind{});
  state_.wind_until_s.assign(bodies, -1.0);
  state_.loads.assign(bodies, dynamics::StepLoads{});
  state_.release_time_s.assign(bodies, -1.0);
  state_.launch_speed_m_s.assign(bodies, -1.0);
  state_.panel_loaded.assign(model_.panels.size(), 0);
  for (std::uint32_t b = 0; b < bodies; ++b)
    if (state_.motion[b] != Motion::anchored) state_.candidates.push_back(b);
  init_collisions();

  const Timing& sim = model_.timing;
  state_.frame_count =
      static_cast<std::size_t>(std::floor(sim.duration_s * sim.frame_rate_hz + 1e-9)) + 1;
  result_.frame_times_s.reserve(state_.frame_count);
  state_.candidate_poses.reserve(state_.frame_count * state_.candidates.size());
  result_.frame_times_s.push_back(0.0);
  record_frame();
}

// One step over [t0, t1], as named phases. integrate_awake resolves ground contact body by
// body, in the same pass as the integration, so the states are swept once; contacts between
// bodies follow (collide.cpp).
void Run::step(double t0, double t1) {
  state_.step_start_s = t0;
  activate_arrivals(t1);
  apply_loads(t0, t1);
  release_held(t0, t1);
  integrate_awake(t1 - t0);
  collide(t1 - t0);
  if (model_.collisions != Collisions::off) sleep_after_contacts(t1 - t0);
  ++result_.stats.steps;
}

void Run::activate_arrivals(double t1) {
  while (state_.next_event < model_.events.size() &&
         model_.events[state_.next_event].arrival_time_s < t1)
    activate(model_.events[state_.next_event++]);
}

bool Run::quiet() const {
  return state_.active.empty() && state_.next_event == model_.events.size() &&
         state_.pending_release.empty() &&
         std::find(state_.motion.begin(), state_.motion.end(), Motion::awake) ==
             state_.motion.end();
}

bool Run::loop(const RunHooks& hooks) {
  const Timing& sim = model_.timing;
  const std::size_t frame_count = state_.frame_count;
  double t = 0.0;
  std::size_t frame = 1;
  // Progress is the share of the run's work done: the steps and body steps so far against the
  // same plus the rest of the run at the present step's size and load. Simulated time is not
  // it: the first tens of milliseconds, every body awake under the wave with short steps, cost
  // most of a run whose bodies then fall asleep.
  double work_done = 0.0;
  double progress_reported = 0.0;
  while (t < sim.duration_s) {
    if (hooks.cancel_requested && hooks.cancel_requested()) return false;
    const double frame_time =
        frame < frame_count ? static_cast<double>(frame) / sim.frame_rate_hz : sim.duration_s;
    double dt = next_step(t, frame_time);
    double t1 = t + dt;
    if (frame_time - t1 <= 1e-12 * std::max(1.0, frame_time)) t1 = frame_time;
    dt = t1 - t;
    if (dt <= 0.0) break;

    const std::uint64_t body_steps_before = result_.stats.body_steps;
    step(t, t1);
    t = t1;
    const double step_work =
        1.0 + static_cast<double>(result_.stats.body_steps - body_steps_before);
    work_done += step_work;

    if (t == frame_time && frame < frame_count) {
      result_.frame_times_s.push_back(frame_time);
      record_frame();
      ++frame;
    }
    if (hooks.progress) {
      const double remaining = (sim.duration_s - t) / dt * step_work;
      const double fraction = std::min(1.0, work_done / (work_done + remaining));
      // Reported in steps of half a percent, never backwards (a wave arriving wakes bodies up
      // and raises the estimate of what is left).
      if (fraction >= progress_reported + 0.005) {
        progress_reported = fraction;
        hooks.progress(fraction);
      }
    }
    // Everything at rest and no wave still to come: the remaining frames are the same.
    if (quiet() && t < sim.duration_s) {
      result_.stats.ended_early = true;
      for (; frame < frame_count; ++frame) {
        result_.frame_times_s.push_back(static_cast<double>(frame) / sim.frame_rate_hz);
        record_frame();
      }
      break;
    }
  }
  result_.stats.simulated_time_s = t;
  return true;
}

void Run::finish() {
  const std::size_t bodies = model_.bodies.size();
  // Frames keep only the bodies that moved; the others are stored once (DESIGN.md decision 10).
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < state_.candidates.size(); ++k) {
    if (state_.moved[state_.candidates[k]]) {
      kept.push_back(k);
      result_.animated.push_back(state_.candidates[k]);
    }
  }
  result_.poses.reserve(result_.frame_times_s.size() * kept.size());
  for (std::size_t f = 0; f < result_.frame_times_s.size(); ++f)
    for (std::size_t k : kept)
      result_.poses.push_back(state_.candidate_poses[f * state_.candidates.size() + k]);
  result_.stats.bodies_static_in_frames = bodies - result_.animated.size();

  for (std::size_t b = 0; b < bodies; ++b) {
    FinalState final_state;
    final_state.name = result_.bodies[b].name;
    final_state.pose = origin_pose(model_, b, state_.bodies[b]);
    const Vec3 v = state_.bodies[b].velocity;
    const Vec3 w = dynamics::angular_velocity(model_.bodies[b], state_.bodies[b]);
    final_state.linear_velocity_m_s = {v.x(), v.y(), v.z()};
    final_state.angular_velocity_rad_s = {w.x(), w.y(), w.z()};
    result_.final_state.push_back(std::move(final_state));
    if (state_.motion[b] == Motion::held) {
      ++result_.stats.bodies_never_released;
      if (model_.fragment[b]) ++result_.stats.fragments_held_by_frame;
    }
  }
  // An anchored body (a window's frame) whose every neighbour was blown away floats in the air:
  // anchors hold to the world, not to the bodies around them (docs/scene-format.md).
  std::uint64_t floating = 0;
  for (const EmbeddedAnchor& anchor : model_.embedded_anchors) {
    const bool all_gone =
        std::all_of(anchor.neighbours.begin(), anchor.neighbours.end(), [&](std::uint32_t n) {
          return (state_.bodies[n].position - model_.initial_states[n].position).norm() >
                 kAnchorLeftAlone_m;
        });
    if (all_gone) ++floating;
  }
  if (floating > 0)
    warnings_.add("anchored_body_floating",
                  "an anchored body (such as a window's frame in a wall) was left in the air: "
                  "every movable body it was set into moved more than 5 cm away, and anchored "
                  "bodies hold to the world, not to their neighbours",
                  floating);
  std::vector<std::uint8_t> pending(model_.panels.size(), 0);
  for (std::size_t e = state_.next_event; e < model_.events.size(); ++e)
    pending[model_.events[e].panel] = !state_.panel_loaded[model_.events[e].panel];
  for (std::size_t p = 0; p < model_.panel_beyond_reach.size(); ++p)
    if (model_.panel_beyond_reach[p] && !state_.panel_loaded[p]) pending[p] = 1;
  result_.stats.panels_not_reached =
      static_cast<std::uint64_t>(std::count(pending.begin(), pending.end(), 1));
  result_.stats.panels_loaded = static_cast<std::uint64_t>(
      std::count(state_.panel_loaded.begin(), state_.panel_loaded.end(), 1));
}

bool Run::execute(const RunHooks& hooks) {
  init();
  if (!loop(hooks)) return false;
  finish();
  return true;
}

}  // namespace brisance::engine
