// Tests of sim/dynamics/body_contact: the warm-start impulse table and the pair solve on the
// smallest cases whose answers are known without it.
#include "sim/dynamics/body_contact.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace brisance::dynamics {
namespace {

TEST(ContactImpulses, FindsEveryKeyAndKeepsTheLastOfEqualKeys) {
  ContactImpulses impulses;
  EXPECT_EQ(impulses.find(7), nullptr);  // empty, never sealed
  // Keys as the engine makes them (bodies in the high bits), many more than the first table.
  for (std::uint64_t a = 0; a < 40; ++a)
    for (std::uint64_t feature = 0; feature < 4; ++feature)
      impulses.add((a << 40) | ((a + 1) << 16) | feature,
                   Vec3(static_cast<double>(a), static_cast<double>(feature), 0.0));
  impulses.add((3ull << 40) | (4ull << 16) | 2, Vec3(-1.0, -2.0, -3.0));  // again: replaces
  impulses.seal();
  for (std::uint64_t a = 0; a < 40; ++a)
    for (std::uint64_t feature = 0; feature < 4; ++feature) {
      const Vec3* found = impulses.find((a << 40) | ((a + 1) << 16) | feature);
      ASSERT_NE(found, nullptr) << a << " " << feature;
      if (a == 3 && feature == 2)
        EXPECT_EQ(*found, Vec3(-1.0, -2.0, -3.0));
      else
        EXPECT_EQ(*found, Vec3(static_cast<double>(a), static_cast<double>(feature), 0.0));
    }
  EXPECT_EQ(impulses.find((5ull << 40) | (7ull << 16)), nullptr);
  impulses.clear();
  impulses.seal();
  EXPECT_EQ(impulses.find(0), nullptr);
}

// A 1 kg point-like body (no turning) meeting the static partner head on at 2 m/s with
// restitution 0.5 leaves at 1 m/s (Newton's law of restitution); a body resting on it, which
// gained g dt towards it in the step and sank g dt^2 into it (under the bounce threshold, and
// touching at the step's start), stops.
TEST(PairSolve, RestitutionAndRestAgainstAStaticPartner) {
  for (const double speed : {2.0, 0.0981}) {
    std::vector<SolverBody> bodies(2);
    bodies[1].inverse_mass = 1.0;
    bodies[1].velocity = Vec3(0.0, -speed, 0.0);
    PairContact c;
    c.a = 0;
    c.b = 1;
    c.normal = Vec3::UnitY();
    c.depth_m = speed < 1.0 ? speed * 0.01 : 0.0;
    c.restitution = 0.5;
    c.friction = 0.5;
    c.gravity_speed_m_s = speed < 1.0 ? -speed : 0.0;
    PairSolveSettings settings;
    settings.dt_s = 0.01;
    ContactImpulses last, next;
    last.seal();
    PairSolveBuffers buffers;
    std::vector<PairContact> contacts = {c};
    solve_pair_contacts(bodies, contacts, last, next, settings, buffers);
    const double expected = speed > 1.0 ? 0.5 * speed : 0.0;
    EXPECT_NEAR(bodies[1].velocity.y(), expected, 1e-12) << speed;
    EXPECT_EQ(bodies[0].velocity, Vec3::Zero());  // the static partner never moves
    EXPECT_NEAR(contacts[0].normal_impulse, speed + expected, 1e-12);
    next.seal();
    ASSERT_NE(next.find(c.key), nullptr);
    EXPECT_NEAR(next.find(c.key)->y(), speed + expected, 1e-12);
  }
}

}  // namespace
}  // namespace brisance::dynamics
