// Stability of the simulator on extreme scenes: no NaN or infinity anywhere, bounded energy,
// clear warnings (issue: "impossible to crash").
#include <cmath>

#include <gtest/gtest.h>

#include "sim/engine/simulator.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Eigen::Vector3d;
using testing::box_object;
using testing::tnt;

void expect_all_finite(const Result& r) {
  for (const Pose& p : r.poses) {
    for (double v : p.position)
      ASSERT_TRUE(std::isfinite(v));
    for (double v : p.orientation)
      ASSERT_TRUE(std::isfinite(v));
  }
  for (const FinalState& f : r.final_state) {
    for (double v : f.pose.position)
      ASSERT_TRUE(std::isfinite(v)) << f.name;
    for (double v : f.linear_velocity_m_s)
      ASSERT_TRUE(std::isfinite(v)) << f.name;
    for (double v : f.angular_velocity_rad_s)
      ASSERT_TRUE(std::isfinite(v)) << f.name;
    double norm = 0.0;
    for (double v : f.pose.orientation)
      norm += v * v;
    EXPECT_NEAR(norm, 1.0, 1e-9) << f.name;
  }
}

bool has_warning(const Result& r, const std::string& code) {
  for (const Warning& w : r.warnings)
    if (w.code == code) return true;
  return false;
}

double kinetic_energy(const Result& r) {
  double energy = 0.0;
  for (std::size_t b = 0; b < r.bodies.size(); ++b) {
    double v2 = 0.0;
    for (double v : r.final_state[b].linear_velocity_m_s)
      v2 += v * v;
    energy += 0.5 * r.bodies[b].mass_kg * v2;
  }
  return energy;
}

TEST(Stability, ChargeTouchingAnObject) {
  scene::Scene s;
  s.charges.push_back(tnt(5.0, Vector3d(0.0, 0.5, -0.2001)));  // 0.1 mm from the face
  s.objects.push_back(box_object("block", Vector3d(0.4, 0.4, 0.4), Vector3d(0.0, 0.5, 0.0), 20.0));
  s.simulation.duration_s = 3.0;
  const Result r = simulate(s).result;
  expect_all_finite(r);
  EXPECT_TRUE(has_warning(r, "blast_out_of_range"));
  EXPECT_EQ(r.animated.size(), 1u);
}

TEST(Stability, OneGramAndHundredTonneBodies) {
  scene::Scene s;
  s.charges.push_back(tnt(100.0, Vector3d(0.0, 1.0, -10.0)));
  s.objects.push_back(
      box_object("pebble", Vector3d(0.01, 0.01, 0.01), Vector3d(-2.0, 0.005, 0.0), 1e-3));
  s.objects.push_back(box_object("bunker", Vector3d(4.0, 2.5, 4.0), Vector3d(2.0, 1.25, 0.0), 1e5));
  s.simulation.duration_s = 5.0;
  const Result r = simulate(s).result;
  expect_all_finite(r);
  // Both are released (the bunker's 10 m^2 face takes about 6 MN against mu m g = 0.49 MN),
  // but the bunker only creeps: its impulse of about 1e4 N s gives it 0.1 m/s.
  ASSERT_EQ(r.animated.size(), 2u);
  const double creep =
      std::hypot(r.final_state[1].pose.position[0] - 2.0, r.final_state[1].pose.position[2]);
  EXPECT_LT(creep, 0.05);
  EXPECT_GT(std::abs(r.final_state[0].pose.position[2]), 1.0);  // the pebble flies off
}

TEST(Stability, ThinPlateSpinningFast) {
  // A 1 mm plate loaded off-centre by a close charge: thousands of rad/s, torque-free afterwards.
  for (auto integrator : {scene::Integrator::explicit_euler, scene::Integrator::semi_implicit_euler,
                          scene::Integrator::rk4}) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(1.0, Vector3d(0.25, 0.0, -0.5)));
    scene::ObjectSpec plate = box_object("plate", Vector3d(0.5, 0.3, 0.001), Vector3d::Zero(), 0.4);
    s.objects.push_back(plate);
    s.simulation.duration_s = 1.0;
    s.simulation.integrator = integrator;
    const Result r = simulate(s).result;
    expect_all_finite(r);
    double w2 = 0.0;
    for (double w : r.final_state[0].angular_velocity_rad_s)
      w2 += w * w;
    EXPECT_GT(std::sqrt(w2), 100.0) << static_cast<int>(integrator);
  }
}

// Rotational energy of a box of full edge lengths `size` from its final state in `r`.
double box_rotational_energy(const Result& r, std::size_t body, const Vector3d& size) {
  const FinalState& f = r.final_state[body];
  const double m = r.bodies[body].mass_kg;
  const Eigen::Vector3d inertia_body(m / 12.0 * (size.y() * size.y() + size.z() * size.z()),
                                     m / 12.0 * (size.x() * size.x() + size.z() * size.z()),
                                     m / 12.0 * (size.x() * size.x() + size.y() * size.y()));
  const Eigen::Quaterniond q(f.pose.orientation[3], f.pose.orientation[0], f.pose.orientation[1],
                             f.pose.orientation[2]);
  const Vector3d w(f.angular_velocity_rad_s[0], f.angular_velocity_rad_s[1],
                   f.angular_velocity_rad_s[2]);
  const Vector3d w_body = q.conjugate() * w;
  return 0.5 * w_body.dot(inertia_body.cwiseProduct(w_body));
}

TEST(Stability, TumblingPlateKeepsItsRotationalEnergy) {
  // Issue 13: a 1 mm plate tumbling torque-free after a blast gained +5 % rotational energy in
  // 1 s and +65 % in 10 s with the default integrator at tolerance 1e-3 (the step turns it by
  // 0.06 rad). Every integrator that keeps angular momentum must keep the energy too.
  for (auto [integrator, bound] :
       {std::pair{scene::Integrator::semi_implicit_euler, 1e-9}, {scene::Integrator::rk4, 1e-4}}) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(1.0, Vector3d(0.25, 0.1, -0.5)));
    const Vector3d size(0.5, 0.3, 0.001);
    s.objects.push_back(box_object("plate", size, Vector3d::Zero(), 0.4));
    s.simulation.integrator = integrator;
    s.simulation.duration_s = 1.0 / 3.0;  // the pulses are long over
    const Result early = simulate(s).result;
    s.simulation.duration_s = 10.0;
    const Result late = simulate(s).result;
    expect_all_finite(late);
    const double e0 = box_rotational_energy(early, 0, size);
    const double e1 = box_rotational_energy(late, 0, size);
    ASSERT_GT(e0, 1.0);  // it does tumble
    EXPECT_LE(std::abs(e1 / e0 - 1.0), bound)
        << static_cast<int>(integrator) << " " << e0 << " -> " << e1;
  }
}

TEST(Stability, VeryLargeAndVerySmallSteps) {
  for (double step : {0.1, 1e-6}) {
    scene::Scene s;
    s.charges.push_back(tnt(50.0, Vector3d(0.0, 0.5, -5.0)));
    testing::add_box_grid(s, 4, 4, Vector3d(0.3, 0.2, 0.2), 0.4, -0.6, 0.0, 6.0);
    s.simulation.time_step_s = step;
    s.simulation.duration_s = step > 0.01 ? 5.0 : 0.05;
    const Result r = simulate(s).result;
    expect_all_finite(r);
    for (const FinalState& f : r.final_state)
      EXPECT_GT(f.pose.position[1], -0.01) << step;
  }
}

TEST(Stability, SixtySecondRunComesToRest) {
  scene::Scene s;
  s.charges.push_back(tnt(200.0, Vector3d(0.0, 0.5, -8.0)));
  testing::add_box_grid(s, 20, 5, Vector3d(0.3, 0.15, 0.15), 0.35, -0.7, 0.0, 8.0);
  s.simulation.duration_s = 60.0;
  s.simulation.frame_rate_hz = 10.0;
  const Result r = simulate(s).result;
  expect_all_finite(r);
  EXPECT_TRUE(r.stats.ended_early);
  EXPECT_EQ(r.frame_times_s.size(), 601u);
  EXPECT_EQ(kinetic_energy(r), 0.0);
  for (const FinalState& f : r.final_state)
    EXPECT_GT(f.pose.position[1], 0.0);
}

TEST(Stability, ThousandsOfBodies) {
  scene::Scene s;
  s.charges.push_back(tnt(500.0, Vector3d(0.0, 2.0, -15.0)));
  testing::add_box_grid(s, 2500, 50, Vector3d(0.2, 0.1, 0.1), 0.25, -6.0, 0.0, 2.0);
  s.simulation.duration_s = 1.0;
  const Result r = simulate(s).result;
  expect_all_finite(r);
  EXPECT_GT(r.animated.size(), 100u);
}

TEST(Stability, EnergyIsConstantAfterTheLoadInVacuum) {
  // No gravity, air or ground: once the pulses end, kinetic energy must stay what it was.
  // Measured drift between t = 1 s and 3 s: semi-implicit and rk4 below 1e-6; the thesis's
  // explicit Euler lets a spinning body's energy grow, bounded here at 5 %.
  for (auto [integrator, bound] : {std::pair{scene::Integrator::explicit_euler, 0.05},
                                   {scene::Integrator::semi_implicit_euler, 1e-6},
                                   {scene::Integrator::rk4, 1e-6}}) {
    scene::Scene s = testing::vacuum_scene();
    s.charges.push_back(tnt(20.0, Vector3d(0.3, 0.2, -3.0)));
    testing::add_box_grid(s, 5, 5, Vector3d(0.3, 0.15, 0.1), 0.4, -0.8, -0.075,
                          5.0);  // centred on y = 0
    s.simulation.integrator = integrator;
    s.simulation.duration_s = 1.0;
    const Result early = simulate(s).result;
    s.simulation.duration_s = 3.0;
    const Result late = simulate(s).result;
    expect_all_finite(late);
    // Rotational energy from the final angular velocity and the body's inertia is not in the
    // result; translation is exact, so compare linear energy tightly and check spin stays finite.
    EXPECT_NEAR(kinetic_energy(late), kinetic_energy(early), 1e-9 * kinetic_energy(early));
    for (std::size_t b = 0; b < late.final_state.size(); ++b) {
      double w_early = 0.0, w_late = 0.0;
      for (int k = 0; k < 3; ++k) {
        w_early += std::pow(early.final_state[b].angular_velocity_rad_s[k], 2);
        w_late += std::pow(late.final_state[b].angular_velocity_rad_s[k], 2);
      }
      EXPECT_LE(std::sqrt(w_late), std::sqrt(w_early) * (1.0 + bound) + 1e-9)
          << static_cast<int>(integrator) << " body " << b;
    }
  }
}

}  // namespace
}  // namespace brisance::engine
