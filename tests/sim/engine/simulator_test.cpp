// Tests of sim/engine/simulator: the analytic plate, frames, skipping, determinism, hooks.
#include "sim/engine/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/panel_load.hpp"
#include "sim/blast/pulse.hpp"
#include "tests/sim/engine/scene_builder.hpp"
#include "tests/support/quadrature.hpp"

namespace brisance::engine {
namespace {

using Eigen::Vector3d;
using testing::box_object;
using testing::tnt;

// A free square plate facing a charge head-on, far enough that every panel sees nearly the
// same Z and angle. Clearing off: its front takes the reflected pulse, its back the side-on
// pulse with the rear drag, building up over 3 S / U (S = 0.1 m), and its edges balance.
scene::Scene plate_scene(double distance_m) {
  scene::Scene s = testing::vacuum_scene();
  s.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, -distance_m)));
  scene::ObjectSpec plate = box_object("plate", Vector3d(0.2, 0.2, 0.01), Vector3d::Zero(), 4.0);
  plate.friction = 0.0;
  s.objects.push_back(plate);
  s.simulation.duration_s = 0.1;
  s.simulation.frame_rate_hz = 100.0;
  s.simulation.clearing = false;
  return s;
}

// The impulse per area on the plate's back, by quadrature of the rear-face load written out:
// min(1, t / t_r) (p_s(t) + C_D q(t)), with q(t) = q_s (p_s(t) / P_so)^2 and t_r = 3 S / U.
double rear_impulse_by_hand(const blast::BlastPoint& p, double half_size_m) {
  const blast::Pulse side_on =
      blast::make_pulse(blast::PulseShape::friedlander, p.incident_overpressure_pa,
                        p.positive_duration_s, p.incident_impulse_pa_s);
  const double rise = 3.0 * half_size_m / p.shock_velocity_m_s;
  const auto pressure = [&](double t) {
    const double ps = side_on.pressure_pa(t);
    const double shape = ps / p.incident_overpressure_pa;
    return std::min(1.0, t / rise) *
           (ps + blast::kRearDragCoefficient * p.dynamic_pressure_pa * shape * shape);
  };
  return testing::simpson(pressure, 0.0, rise, 2000) +
         testing::simpson(pressure, rise, side_on.duration_s * (1 - 1e-12), 20000);
}

TEST(Simulator, FreePlateEndsWithAreaTimesNetImpulseOverMassWhateverTheStep) {
  // Thesis eq. 2.41 face by face: v = A (i_r - i_rear) / M, the front at 7.995 m taking the
  // reflected impulse, the back at 8.005 m the rear-face load (DESIGN.md §5-6).
  const double distance = 8.0;
  const blast::BlastPoint front = blast::blast_point(blast::Charge{10.0}, distance - 0.005);
  const blast::BlastPoint back = blast::blast_point(blast::Charge{10.0}, distance + 0.005);
  const double rear = rear_impulse_by_hand(back, 0.1);
  EXPECT_GT(rear, 0.8 * back.incident_impulse_pa_s);  // close to i_s: the back fills quickly
  EXPECT_LT(rear, back.incident_impulse_pa_s);
  const double expected = 0.2 * 0.2 * (front.reflected_impulse_pa_s - rear) / 4.0;
  for (double step : {1e-5, 1e-4, 1e-3, 1e-2, 0.0}) {
    for (auto integrator : {scene::Integrator::explicit_euler,
                            scene::Integrator::semi_implicit_euler, scene::Integrator::rk4}) {
      scene::Scene s = plate_scene(distance);
      if (step > 0.0) s.simulation.time_step_s = step;  // 0: the adaptive step
      s.simulation.integrator = integrator;
      const RunOutcome run = simulate(s);
      const auto& v = run.result.final_state.at(0).linear_velocity_m_s;
      EXPECT_NEAR(v[2], expected, 0.005 * expected) << "step " << step;
      EXPECT_NEAR(v[0], 0.0, 1e-9);
      EXPECT_NEAR(v[1], 0.0, 1e-9);
    }
  }
}

TEST(Simulator, APlateFacingTheChargeDoesNotSpinWhateverItsPanels) {
  // A 1 x 0.1 m plate face-on to a charge on its axis: by symmetry no torque, however finely
  // its faces are cut (the panels follow each face's own grid, not its two triangles).
  for (double panel_area : {1.0, 0.05, 0.01, 0.001}) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, -2.0)));
    scene::ObjectSpec plate = box_object("plate", Vector3d(1.0, 0.1, 0.02), Vector3d::Zero(), 5.0);
    plate.friction = 0.0;
    s.objects.push_back(plate);
    s.simulation.duration_s = 0.05;
    s.simulation.max_panel_area_m2 = panel_area;
    const RunOutcome run = simulate(s);
    const auto& w = run.result.final_state.at(0).angular_velocity_rad_s;
    const double v = run.result.final_state.at(0).linear_velocity_m_s[2];
    EXPECT_GT(v, 1.0) << panel_area;
    EXPECT_LT(std::hypot(w[0], w[1], w[2]), 1e-6 * v / 0.1) << panel_area;
  }
}

TEST(Simulator, FramesAreExactMultiplesOfTheFramePeriod) {
  scene::Scene s = plate_scene(8.0);
  s.simulation.duration_s = 0.25;
  s.simulation.frame_rate_hz = 30.0;
  const Result r = simulate(s).result;
  ASSERT_EQ(r.frame_times_s.size(), 8u);  // 0, 1/30, ..., 7/30 <= 0.25
  for (std::size_t k = 0; k < r.frame_times_s.size(); ++k)
    EXPECT_EQ(r.frame_times_s[k], static_cast<double>(k) / 30.0);
  EXPECT_EQ(r.poses.size(), r.frame_times_s.size() * r.animated.size());
}

TEST(Simulator, FramePosesFollowTheMotion) {
  // Constant velocity after the pulse: positions advance linearly between late frames.
  const Result r = simulate(plate_scene(8.0)).result;
  ASSERT_EQ(r.animated.size(), 1u);
  const std::size_t n = r.frame_times_s.size();
  const double v = r.final_state[0].linear_velocity_m_s[2];
  const double dz = r.pose(n - 1, 0).position[2] - r.pose(n - 2, 0).position[2];
  EXPECT_NEAR(dz, v * (r.frame_times_s[n - 1] - r.frame_times_s[n - 2]), 1e-9);
  EXPECT_EQ(r.pose(0, 0).position[2], 0.0);
}

TEST(Simulator, LoadsEveryFaceAndSkipsAnchoredAndHeldBodies) {
  scene::Scene s;
  s.charges.push_back(tnt(1.0, Vector3d(0.0, 0.5, -20.0)));
  // Heavy, far: its load never beats mu m g, so it is never integrated.
  s.objects.push_back(
      box_object("block", Vector3d(1.0, 1.0, 1.0), Vector3d(0.0, 0.5, 0.0), 2000.0));
  scene::ObjectSpec post =
      box_object("post", Vector3d(0.2, 2.0, 0.2), Vector3d(3.0, 1.0, 0.0), 50.0);
  post.anchored = true;
  s.objects.push_back(post);
  s.simulation.duration_s = 0.5;
  s.simulation.max_panel_area_m2 = 10.0;  // one panel per face
  const Result r = simulate(s).result;
  EXPECT_EQ(r.stats.bodies, 2u);
  EXPECT_EQ(r.stats.bodies_anchored, 1u);
  EXPECT_EQ(r.stats.bodies_never_released, 1u);
  EXPECT_TRUE(r.animated.empty());
  EXPECT_EQ(r.stats.bodies_static_in_frames, 2u);
  EXPECT_EQ(r.stats.panels, 12u);
  // The block: every face is loaded, its front head-on, its rear after the wave wraps around,
  // the others as the wave crosses them. The post is anchored: no panels loaded.
  EXPECT_EQ(r.stats.panels_loaded, 6u);
  EXPECT_EQ(r.stats.panels_back_facing, 0u);
  EXPECT_EQ(r.stats.body_steps, 0u);
  EXPECT_TRUE(r.stats.ended_early);
}

TEST(Simulator, APanelTheWaveReachesOnlyAfterTheRunIsNotReached) {
  // The plate 300 m from 10 kg: the wave arrives after about 0.8 s. Within 0.1 s none of its
  // panels is reached (they get no event at all: prepare_events works out no blast point
  // beyond the wave's reach); a second charge 8 m away reaches them all.
  scene::Scene far = plate_scene(300.0);
  const Result alone = simulate(far).result;
  EXPECT_EQ(alone.stats.panels_loaded, 0u);
  EXPECT_EQ(alone.stats.panels_not_reached, alone.stats.panels);
  EXPECT_EQ(alone.stats.body_steps, 0u);
  EXPECT_TRUE(alone.warnings.empty());  // the far charge's Z is never worked out
  far.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, 8.0)));
  const Result both = simulate(far).result;
  EXPECT_EQ(both.stats.panels_loaded, both.stats.panels);
  EXPECT_EQ(both.stats.panels_not_reached, 0u);
  // Given the time, the far wave arrives too: its panels are loaded then.
  far.charges.pop_back();
  far.simulation.duration_s = 1.5;
  EXPECT_EQ(simulate(far).result.stats.panels_not_reached, 0u);
}

TEST(Simulator, StackedBodiesAreHeldByTheWeightAboveThem) {
  // Thesis §3.6: lower bricks have more resistance. A column of three 10 kg blocks: the top one
  // is held by mu m g, the middle by mu 2 m g, the bottom by mu 3 m g. With mu set so that the
  // blast's peak push lies between 2 and 3 m g mu, the two upper blocks go and the bottom stays.
  // The peak push is the front's reflected pressure on arrival, before the wave loads the rear.
  const double distance = 12.0;
  const blast::BlastPoint p = blast::blast_point(blast::Charge{30.0}, distance);
  const double area = 0.3 * 0.3;
  const double peak_force = area * p.reflected_overpressure_pa;
  const double mu = peak_force / (2.5 * 10.0 * 9.81);
  scene::Scene s;
  s.charges.push_back(tnt(30.0, Vector3d(0.0, 0.45, -distance)));
  for (int i = 0; i < 3; ++i) {
    scene::ObjectSpec block = box_object("block" + std::to_string(i), Vector3d(0.3, 0.3, 0.3),
                                         Vector3d(0.0, 0.15 + 0.3 * i, 0.0), 10.0);
    block.friction = mu;
    s.objects.push_back(block);
  }
  // Just after the pulse (arrival about 25 ms, duration about 8 ms), before anything lands.
  s.simulation.duration_s = 0.06;
  s.simulation.clearing = false;
  s.simulation.max_panel_area_m2 = 1.0;
  const Result r = simulate(s).result;
  EXPECT_EQ(r.stats.bodies_never_released, 1u);
  ASSERT_EQ(r.animated.size(), 2u);
  EXPECT_EQ(r.animated[0], 1u);
  EXPECT_EQ(r.animated[1], 2u);
  // Friction takes mu N of the push while it lasts: the middle block, held twice as hard,
  // leaves slower than the top one.
  EXPECT_GT(r.final_state[2].linear_velocity_m_s[2], r.final_state[1].linear_velocity_m_s[2]);
  EXPECT_GT(r.final_state[1].linear_velocity_m_s[2], 0.0);
}

TEST(Simulator, AHoldNeedsSomethingToHoldOnTo) {
  // Issue 13: a 1 m box 2 m above the ground with friction 0.6 and no load stayed frozen in
  // mid-air ("never released"). Friction holds only a body standing on the ground or on a body
  // that stands; the floating box falls, and so does a box resting on it. A box on the ground
  // and one on top of it stay held.
  scene::Scene s;
  auto add = [&](const std::string& name, double x, double y) {
    scene::ObjectSpec box = box_object(name, Vector3d(1.0, 1.0, 1.0), Vector3d(x, y, 0.0), 100.0);
    box.friction = 0.6;
    s.objects.push_back(box);
  };
  add("floating", 0.0, 2.5);
  add("on_floating", 0.0, 3.5);
  add("grounded", 5.0, 0.5);
  add("on_grounded", 5.0, 1.5);
  s.simulation.duration_s = 0.5;
  const Result r = simulate(s).result;
  EXPECT_EQ(r.stats.bodies_never_released, 2u);
  ASSERT_EQ(r.animated.size(), 2u);
  EXPECT_EQ(r.animated[0], 0u);
  EXPECT_EQ(r.animated[1], 1u);
  // Free fall for 0.5 s: 1.23 m (semi-implicit Euler at steps of 9.5 ms: 2 cm more).
  EXPECT_NEAR(r.final_state[0].pose.position[1], 2.5 - 0.5 * 9.81 * 0.25, 0.03);
  EXPECT_EQ(r.final_state[2].pose.position[1], 0.5);
  EXPECT_EQ(r.final_state[3].pose.position[1], 1.5);
}

TEST(Simulator, ClearingRunsFromTheEdgesOfTheWholeSurface) {
  // Five 5 cm x 40 cm plates side by side form one 25 x 40 cm front surface (S = 12.5 cm),
  // which clears far slower than a lone plate whose own edges are 2.5 cm away (S = 2.5 cm). The
  // row keeps more of the reflected pulse, so its middle plate leaves faster than the lone one.
  // Plates 1 cm apart do not touch: each clears from its own edges, as a lone one does.
  auto run = [](int count, double gap = 0.0) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, -8.0)));
    for (int i = 0; i < count; ++i) {
      scene::ObjectSpec plate = box_object("p" + std::to_string(i), Vector3d(0.05, 0.4, 0.01),
                                           Vector3d((0.05 + gap) * (i - count / 2), 0.0, 0.0), 0.5);
      plate.friction = 0.0;
      s.objects.push_back(plate);
    }
    s.simulation.duration_s = 0.05;
    const Result r = simulate(s).result;
    return r.final_state[static_cast<std::size_t>(count / 2)].linear_velocity_m_s[2];
  };
  const double alone = run(1);
  const double in_row = run(5);
  EXPECT_GT(alone, 0.0);
  EXPECT_GT(in_row, 1.2 * alone);
  EXPECT_EQ(run(5, 0.01), alone);
}

TEST(Simulator, AFacesPushGrowsAsTheChargeComesCloserDownToContact) {
  // A 1 m concrete cube (2 400 kg) in vacuum, 10 kg of TNT head-on before its front face's
  // centre, from 2 m down to contact (the charge's surface touching the face: a TNT sphere of
  // 10 kg has radius 0.1142 m). With clearing from the face's edges after the wave has reached
  // them the push grows all the way; with the relief starting everywhere at once it peaked near
  // 0.3 m and fell by 17 % to contact (1.87 -> 1.55 m/s).
  const double radius = std::cbrt(3.0 * 10.0 / (4.0 * std::numbers::pi * 1600.0));
  auto push = [](double centre_to_face_m, std::vector<Warning>* warnings = nullptr) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, -0.5 - centre_to_face_m)));
    scene::ObjectSpec cube = box_object("cube", Vector3d(1.0, 1.0, 1.0), Vector3d::Zero(), 2400.0);
    cube.friction = 0.0;
    s.objects.push_back(cube);
    s.simulation.duration_s = 0.02;
    const Result r = simulate(s).result;
    if (warnings) *warnings = r.warnings;
    return r.final_state[0].linear_velocity_m_s[2];
  };
  double farther = 0.0;
  for (double d : {2.0, 1.0, 0.5, 0.3, 0.2, 0.15, 0.12, radius + 1e-4}) {
    const double v = push(d);
    EXPECT_GT(v, farther) << "centre " << d << " m from the face";
    farther = v;
  }
  // A charge set into the object is said.
  std::vector<Warning> warnings;
  push(0.01, &warnings);
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(),
                          [](const Warning& w) { return w.code == "charge_inside_object"; }));
  push(0.3, &warnings);
  EXPECT_TRUE(std::none_of(warnings.begin(), warnings.end(),
                           [](const Warning& w) { return w.code == "charge_inside_object"; }));
}

TEST(Simulator, BlownBrickFliesFallsAndSleeps) {
  scene::Scene s;
  s.charges.push_back(tnt(20.0, Vector3d(0.0, 0.3, -4.0)));
  s.objects.push_back(box_object("brick", Vector3d(0.4, 0.2, 0.2), Vector3d(0.0, 0.1, 0.0), 10.0));
  s.simulation.duration_s = 10.0;
  const Result r = simulate(s).result;
  ASSERT_EQ(r.animated.size(), 1u);
  const FinalState& f = r.final_state[0];
  EXPECT_GT(f.pose.position[2], 0.3);          // pushed away from the charge, then slid
  EXPECT_NEAR(f.pose.position[1], 0.1, 0.11);  // lying on the ground (some face down)
  EXPECT_EQ(r.stats.bodies_slept, 1u);
  EXPECT_TRUE(r.stats.ended_early);
  EXPECT_EQ(r.frame_times_s.size(), 301u);  // frames still cover the whole duration
  for (double value : f.linear_velocity_m_s)
    EXPECT_EQ(value, 0.0);
}

TEST(Simulator, DeterministicBitForBit) {
  scene::Scene s;
  s.charges.push_back(tnt(50.0, Vector3d(0.2, 0.6, -6.0)));
  testing::add_box_grid(s, 12, 4, Vector3d(0.3, 0.15, 0.15), 0.35, -0.5, 0.0, 8.0);
  s.simulation.duration_s = 1.0;
  const Result a = simulate(s).result;
  const Result b = simulate(s).result;
  ASSERT_EQ(a.poses.size(), b.poses.size());
  ASSERT_GT(a.animated.size(), 0u);
  EXPECT_EQ(std::memcmp(a.poses.data(), b.poses.data(), a.poses.size() * sizeof(Pose)), 0);
  EXPECT_EQ(a.stats.steps, b.stats.steps);
}

TEST(Simulator, ProgressRisesToOneAndCancelStops) {
  scene::Scene s = plate_scene(8.0);
  s.simulation.time_step_s = 1e-4;
  std::vector<double> seen;
  RunHooks hooks;
  hooks.progress = [&](double f) { seen.push_back(f); };
  EXPECT_FALSE(simulate(s, hooks).cancelled);
  ASSERT_FALSE(seen.empty());
  for (std::size_t i = 1; i < seen.size(); ++i)
    EXPECT_GE(seen[i], seen[i - 1]);
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_LE(seen.size(), 202u);

  // The hook is polled in prepare too, then once per step: cancelled after ten steps.
  int polls = 0;
  hooks.progress = nullptr;
  hooks.cancel_requested = [&] {
    ++polls;
    return false;
  };
  const RunOutcome full = simulate(s, hooks);
  ASSERT_GT(polls, static_cast<int>(full.result.stats.steps));
  const int before_stepping = polls - static_cast<int>(full.result.stats.steps);
  polls = 0;
  hooks.cancel_requested = [&] { return ++polls > before_stepping + 10; };
  const RunOutcome cancelled = simulate(s, hooks);
  EXPECT_TRUE(cancelled.cancelled);
  EXPECT_EQ(cancelled.cancelled_in, RunPhase::stepping);
  EXPECT_EQ(cancelled.result.stats.steps, 10u);
}

TEST(Simulator, ChargesAddAndOutOfRangeIsWarned) {
  // Two equal charges on both sides of a plate: the net push cancels.
  scene::Scene s = plate_scene(8.0);
  s.charges.push_back(tnt(10.0, Vector3d(0.0, 0.0, 8.0)));
  const Result r = simulate(s).result;
  EXPECT_NEAR(r.final_state[0].linear_velocity_m_s[2], 0.0, 1e-6);
  EXPECT_TRUE(r.warnings.empty());
  // A charge 300 m away: Z far beyond 40 is continued and counted.
  scene::Scene far = plate_scene(300.0);
  far.simulation.duration_s = 1.5;
  const Result f = simulate(far).result;
  // Z = 139: beyond the fits (continued) and below the reflection chart's 1.4 kPa (clamped).
  ASSERT_EQ(f.warnings.size(), 2u);
  EXPECT_EQ(f.warnings[0].code, "blast_out_of_range");
  EXPECT_EQ(f.warnings[1].code, "reflection_out_of_chart");
  EXPECT_EQ(f.warnings[0].count, f.stats.panels_loaded);
}

}  // namespace
}  // namespace brisance::engine
