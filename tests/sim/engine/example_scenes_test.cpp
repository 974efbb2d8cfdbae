// The example scenes of scenes/ behave as the thesis describes them.
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "sim/engine/simulator.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

scene::Scene load(const std::string& name) {
  return testing::load_example_scene(name);
}

std::set<std::string> moved(const Result& r) {
  std::set<std::string> names;
  for (std::uint32_t b : r.animated)
    names.insert(r.bodies[b].name);
  return names;
}

TEST(ExampleScenes, BrickWallIsBlownApart) {
  // Thesis §3.6: 100 kg of TNT 15 m behind the wall; every brick goes, and bricks high on the
  // wall, carrying less weight, fly farther (measured: bottom row 0.09 m, top row 0.2-0.87 m).
  const Result r = simulate(load("brick_wall.json")).result;
  EXPECT_EQ(r.bodies.size(), 33u);
  EXPECT_EQ(r.animated.size(), 33u);
  double bottom = 0.0, top = 0.0;
  int bottom_count = 0, top_count = 0;
  for (const FinalState& f : r.final_state) {
    EXPECT_GT(f.pose.position[2], 0.05) << f.name;  // away from the charge at z = -15
    if (f.name.rfind("wall/r0/", 0) == 0) bottom += f.pose.position[2], ++bottom_count;
    if (f.name.rfind("wall/r5/", 0) == 0) top += f.pose.position[2], ++top_count;
  }
  EXPECT_GT(top / top_count, 3.0 * bottom / bottom_count);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ExampleScenes, StrongWallKeepsItsLowerRows) {
  // Thesis fig. 3.7: a weaker bomb and high friction; bricks high on the wall carry less weight,
  // have less resistance and are blown off; the lower rows withstand the blast.
  const Result r = simulate(load("brick_wall_strong.json")).result;
  const std::set<std::string> names = moved(r);
  for (const BodyInfo& body : r.bodies) {
    const bool lower = body.name.rfind("wall/r0/", 0) == 0 || body.name.rfind("wall/r1/", 0) == 0 ||
                       body.name.rfind("wall/r2/", 0) == 0;
    EXPECT_EQ(names.count(body.name), lower ? 0u : 1u) << body.name;
  }
  EXPECT_EQ(r.stats.bodies_never_released, 16u);
}

TEST(ExampleScenes, ThreeBlocksAllMoveTheNearestFarthest) {
  // Thesis fig. 4.6, top row: three blocks at 6.0, 6.3 and 6.7 m, none shading another; the
  // nearest takes the strongest wave and slides farthest (measured 22, 18 and 14 mm).
  const scene::Scene s = load("three_blocks.json");
  const Result r = simulate(s).result;
  ASSERT_EQ(r.animated.size(), 3u);
  double moved[3];
  for (std::size_t b = 0; b < 3; ++b) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k)
      d2 += std::pow(r.final_state[b].pose.position[k] - r.bodies[b].initial_pose.position[k], 2);
    moved[b] = std::sqrt(d2);
  }
  EXPECT_GT(moved[0], moved[1]);
  EXPECT_GT(moved[1], moved[2]);
  EXPECT_GT(moved[2], 0.005);
}

TEST(ExampleScenes, BrickWallIsBitForBitRepeatable) {
  const scene::Scene s = load("brick_wall.json");
  const Result a = simulate(s).result;
  const Result b = simulate(s).result;
  ASSERT_EQ(a.poses.size(), b.poses.size());
  EXPECT_EQ(std::memcmp(a.poses.data(), b.poses.data(), a.poses.size() * sizeof(Pose)), 0);
}

}  // namespace
}  // namespace brisance::engine
