// Contacts between bodies (issue 13): a dropped box lands on another, the example wall ends
// without bricks inside each other, reruns are bit-identical, and `auto` never pairs two of a
// pane's fragments.
#include <cmath>

#include <gtest/gtest.h>

#include "sim/dynamics/convex.hpp"
#include "sim/engine/simulator.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Eigen::Vector3d;
using testing::box_object;

Vector3d position(const FinalState& f) {
  return Vector3d(f.pose.position[0], f.pose.position[1], f.pose.position[2]);
}

// The deepest overlap of any two bodies at their final poses, m (the narrowphase with no
// margin, on the bodies' meshes).
double deepest_overlap(const Result& r) {
  std::vector<dynamics::CollisionShape> shapes;
  std::vector<std::vector<dynamics::PlacedPiece>> placed(r.bodies.size());
  for (std::size_t b = 0; b < r.bodies.size(); ++b) {
    shapes.push_back(dynamics::collision_shape(r.bodies[b].mesh, Vector3d::Zero()));
    const auto& p = r.final_state[b].pose;
    const Eigen::Quaterniond q(p.orientation[3], p.orientation[0], p.orientation[1],
                               p.orientation[2]);
    const Eigen::Matrix3d rotation = q.toRotationMatrix();
    for (const auto& piece : shapes.back().pieces) {
      placed[b].emplace_back();
      dynamics::place(piece, position(r.final_state[b]), rotation, placed[b].back());
    }
  }
  double deepest = 0.0;
  dynamics::Manifold manifold;
  for (std::size_t a = 0; a < placed.size(); ++a)
    for (std::size_t b = a + 1; b < placed.size(); ++b)
      for (const auto& pa : placed[a])
        for (const auto& pb : placed[b])
          if (dynamics::collide(pa, pb, 0.0, 0, manifold))
            for (const auto& point : manifold.points)
              deepest = std::max(deepest, point.depth_m);
  return deepest;
}

TEST(Contacts, DroppedBoxLandsOnTheOtherNotThroughIt) {
  // (Not yet: both coming to rest. The upper box still jitters 3-7 mm above the lower one and
  // the lower creeps; see docs/simulator.md.)
  scene::Scene s;
  s.simulation.collisions = scene::CollisionMode::automatic;
  s.objects.push_back(box_object("lower", Vector3d(0.5, 0.5, 0.5), Vector3d(0.0, 1.0, 0.0), 20.0));
  s.objects.push_back(box_object("upper", Vector3d(0.4, 0.4, 0.4), Vector3d(0.1, 2.5, 0.05), 10.0));
  s.simulation.duration_s = 4.0;
  const Result r = simulate(s).result;
  const Vector3d lower = position(r.final_state[0]);
  const Vector3d upper = position(r.final_state[1]);
  EXPECT_NEAR(lower.y(), 0.25, 1e-3);
  EXPECT_GT(upper.y(), 0.25 + 0.25 + 0.2 - 2e-3);
  EXPECT_LT(upper.y(), 0.25 + 0.25 + 0.2 + 1e-2);
  EXPECT_LT(std::abs(upper.x() - lower.x()), 0.25);
  EXPECT_GT(r.stats.contact_points, 0u);
  // Without contacts the upper box falls through the lower one to the ground.
  s.simulation.collisions = scene::CollisionMode::off;
  const Result through = simulate(s).result;
  EXPECT_NEAR(through.final_state[1].pose.position[1], 0.2, 1e-3);
}

TEST(Contacts, BrickWallEndsWithoutBricksInsideEachOther) {
  // Issue 13: without contacts 63 pairs of bricks overlapped by more than 1 mm at the end, 48
  // by more than 2 cm.
  scene::Scene s = testing::load_example_scene("brick_wall.json");
  s.simulation.collisions = scene::CollisionMode::automatic;
  const Result r = simulate(s).result;
  EXPECT_LT(deepest_overlap(r), 5e-3);
  const Result again = simulate(s).result;  // bit-identical rerun
  ASSERT_EQ(again.poses.size(), r.poses.size());
  for (std::size_t i = 0; i < r.poses.size(); ++i) {
    ASSERT_EQ(r.poses[i].position, again.poses[i].position) << i;
    ASSERT_EQ(r.poses[i].orientation, again.poses[i].orientation) << i;
  }
  scene::Scene off = s;
  off.simulation.collisions = scene::CollisionMode::off;
  EXPECT_GT(deepest_overlap(simulate(off).result), 0.02);  // the measure sees the old fault
}

TEST(Contacts, StrongWallEndsWithoutBricksInsideEachOther) {
  // Issue 13, "done means": the example walls end with no pair of bricks overlapping by more
  // than 5 mm, and the strong wall's lower rows stand. (With contacts the strong wall stands
  // whole, measured: every brick within 1.3 mm of where it started, as the wall slides as one
  // block on the ground instead of each brick on a fixed base; no brick is blown off its top.)
  scene::Scene s = testing::load_example_scene("brick_wall_strong.json");
  s.simulation.collisions = scene::CollisionMode::automatic;
  const Result r = simulate(s).result;
  EXPECT_LT(deepest_overlap(r), 5e-3);
  for (std::size_t b = 0; b < r.bodies.size(); ++b) {
    const int row = r.bodies[b].name[6] - '0';  // "wall/r<row>/..."
    if (row > 2) continue;
    const Vector3d start(r.bodies[b].initial_pose.position[0], r.bodies[b].initial_pose.position[1],
                         r.bodies[b].initial_pose.position[2]);
    EXPECT_LT((position(r.final_state[b]) - start).norm(), 0.01) << r.bodies[b].name;
  }
  scene::Scene off = s;
  off.simulation.collisions = scene::CollisionMode::off;
  EXPECT_GT(deepest_overlap(simulate(off).result), 0.02);  // the measure sees the old fault
}

}  // namespace
TEST(Contacts, AutoSweepsAPanesFragmentsOnlyAgainstOtherBodies) {
  // `auto` leaves pairs of two fragments out; the sweep no longer forms them. Before, the
  // pane's pieces flying side by side (each box grown by its speed) formed 9.7 M pairs over
  // window.json's 271 steps, every one then skipped: 12 times the run without contacts. Now a
  // fragment meets at most the frame's few boxes in a step.
  scene::Scene s = testing::load_example_scene("window.json");
  s.simulation.duration_s = 0.3;
  s.simulation.collisions = scene::CollisionMode::automatic;
  const Result r = simulate(s).result;
  ASSERT_GT(r.stats.fragments, 1000u);
  EXPECT_LT(r.stats.collision_pairs, r.stats.steps * r.stats.fragments / 4);
  EXPECT_GT(r.stats.collision_pairs, 0u);  // the fragments still meet the frame
  // Fragments that touch no other body fly as without contacts.
  scene::Scene off = s;
  off.simulation.collisions = scene::CollisionMode::off;
  const Result free = simulate(off).result;
  std::size_t same = 0;
  for (std::size_t b = 0; b < r.bodies.size(); ++b)
    same += r.final_state[b].pose.position == free.final_state[b].pose.position;
  EXPECT_GT(same, r.bodies.size() * 9 / 10);
}

}  // namespace brisance::engine
