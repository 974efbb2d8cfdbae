// Tests for sim/occlusion/shielding: thesis chapter 4's propagation heuristic, per object and per
// panel.
#include "sim/occlusion/shielding.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/geometry/mesh.hpp"

namespace brisance::occlusion {
namespace {

// Boxes in the world, kept alive for the Objects that view them.
class Boxes {
 public:
  std::uint32_t add(const Vec3& centre, const Vec3& size, bool blocks = true,
                    bool receives = true) {
    geometry::TriangleMesh mesh = geometry::make_box(size);
    for (Vec3& v : mesh.vertices)
      v += centre;
    meshes_.push_back(std::move(mesh));
    flags_.emplace_back(blocks, receives);
    return static_cast<std::uint32_t>(meshes_.size() - 1);
  }
  std::vector<Object> objects() const {
    std::vector<Object> out;
    for (std::size_t i = 0; i < meshes_.size(); ++i)
      out.push_back({meshes_[i].vertices, meshes_[i].triangles, flags_[i].first, flags_[i].second});
    return out;
  }

 private:
  std::vector<geometry::TriangleMesh> meshes_;
  std::vector<std::pair<bool, bool>> flags_;
};

Shielding shield(const Boxes& boxes, std::span<const Panel> panels = {}, Settings settings = {}) {
  const SphereMap map(settings.face_columns, settings.face_rows);
  const std::vector<Object> objects = boxes.objects();
  Shielding s = compute_shielding(map, Vec3::Zero(), objects, panels, settings);
  for (std::size_t o = 0; o < s.objects.size(); ++o) {
    ::testing::Test::RecordProperty("object" + std::to_string(o),
                                    std::to_string(s.objects[o].blocking_factor) + " " +
                                        std::to_string(s.objects[o].radial_separation) + " " +
                                        std::to_string(s.objects[o].attenuation));
  }
  return s;
}

TEST(Attenuation, FollowsEquation41) {
  EXPECT_DOUBLE_EQ(attenuation(0.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(attenuation(1.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(attenuation(8.0, 1.0), 0.0);  // b = 1 + 7k
  EXPECT_DOUBLE_EQ(attenuation(20.0, 0.5), 0.0);
  // x = 0.5: 0.125 - 2 * 0.5^1.5 + 1.
  EXPECT_NEAR(attenuation(0.5, 0.0), 0.125 - 2.0 * std::pow(0.5, 1.5) + 1.0, 1e-15);
  EXPECT_NEAR(attenuation(4.0, 1.0), attenuation(0.5, 0.0), 1e-15);
  // The constants are parameters: f reaches 0 at b = offset + slope * k.
  EXPECT_DOUBLE_EQ(attenuation(3.0, 1.0, 1.0, 2.0), 0.0);
  EXPECT_GT(attenuation(2.9, 1.0, 1.0, 2.0), 0.0);
  double previous = 1.0;
  for (double b = 0.1; b < 8.0; b += 0.1) {
    const double f = attenuation(b, 1.0);
    EXPECT_LE(f, previous);             // more blocking, less load
    EXPECT_GE(attenuation(b, 1.2), f);  // more separation, more load
    previous = f;
  }
}

TEST(Shielding, NothingInTheWayLeavesEveryLoadWhole) {
  Boxes boxes;
  boxes.add({0.5, 0, 6}, Vec3::Constant(0.5));
  boxes.add({1.75, 0, 6}, Vec3::Constant(0.5));
  boxes.add({3.0, 0, 6}, Vec3::Constant(0.5));
  const Shielding s = shield(boxes);
  for (const ObjectShielding& o : s.objects) {
    EXPECT_EQ(o.attenuation, 1.0);
    EXPECT_TRUE(o.occluders.empty());
    EXPECT_GT(o.mask_pixels, 0u);
  }
  EXPECT_EQ(s.objects_occluded, 0u);
}

TEST(Shielding, AWallShieldsTheBlockBehindItUnlessItDoesNotBlock) {
  for (bool wall_blocks : {true, false}) {
    Boxes boxes;
    const auto wall = boxes.add({0, 0, 3}, {4, 3, 0.3}, wall_blocks);
    const auto block = boxes.add({0, 0, 5}, Vec3::Constant(0.5));
    const Shielding s = shield(boxes);
    EXPECT_EQ(s.objects[wall].attenuation, 1.0);  // nothing in front of the wall
    if (wall_blocks) {
      EXPECT_EQ(s.objects[block].occluders, std::vector<std::uint32_t>{wall});
      EXPECT_LT(s.objects[block].attenuation, 0.05);
      EXPECT_GT(s.objects[block].blocking_factor, 5.0);
    } else {
      EXPECT_TRUE(s.objects[block].occluders.empty());
      EXPECT_EQ(s.objects[block].attenuation, 1.0);
    }
  }
}

// Found by tests/fuzz/fuzz_writers under UBSan: a triangle clipped at a face's horizon has a
// vertex that projects some 1e10 pixels out; its conversion to int overflowed, and on x86 the
// triangle was dropped from that face, leaving holes in the mask of anything large and near.
TEST(Shielding, AWallFillingHalfTheSkyMasksHalfTheSphere) {
  Boxes boxes;
  const auto wall = boxes.add({0, 0, 3}, {400, 400, 0.3});
  const auto block = boxes.add({0.5, 0.5, 6}, Vec3::Constant(0.5));
  const Settings settings;
  const Shielding s = shield(boxes, {}, settings);
  // Half-angle atan(200 / 2.85) = 89.2 degrees: (1 - cos) / 2 = 49.3 % of the sphere.
  const SphereMap map(settings.face_columns, settings.face_rows);
  EXPECT_GT(s.objects[wall].mask_pixels, 0.47 * map.pixel_count());
  EXPECT_LT(s.objects[wall].mask_pixels, 0.52 * map.pixel_count());
  EXPECT_EQ(s.objects[block].occluders, std::vector<std::uint32_t>{wall});
  EXPECT_LT(s.objects[block].attenuation, 0.05);
}

// Thesis fig. 4.6: blocks at about the same distance behind a large occluder; the one nearest to
// being exposed is shielded least.
TEST(Shielding, TheBlockNearestTheOccludersEdgeIsShieldedLeast) {
  Boxes boxes;
  boxes.add({0, 0, 3}, {4, 4, 0.4});
  const auto centred = boxes.add({0, 0, 6}, Vec3::Constant(0.5));
  const auto off_centre = boxes.add({2.5, 0, 6}, Vec3::Constant(0.5));
  const auto near_edge = boxes.add({3.6, 0, 6}, Vec3::Constant(0.5));
  const Shielding s = shield(boxes);
  EXPECT_GT(s.objects[centred].blocking_factor, s.objects[off_centre].blocking_factor);
  EXPECT_GT(s.objects[off_centre].blocking_factor, s.objects[near_edge].blocking_factor);
  EXPECT_LE(s.objects[centred].attenuation, s.objects[off_centre].attenuation);
  EXPECT_LT(s.objects[off_centre].attenuation, s.objects[near_edge].attenuation);
  EXPECT_GT(s.objects[near_edge].attenuation, 0.3);
}

// Thesis fig. 4.7: the block close behind the occluder is protected more than the one far behind
// it, where the wave has reformed.
TEST(Shielding, TheBlockCloseBehindTheOccluderIsShieldedMoreThanTheFarOne) {
  Boxes boxes;
  boxes.add({0, 0, 3}, {0.4, 0.4, 0.3});
  const auto close = boxes.add({0, 0, 3.6}, Vec3::Constant(0.3));
  const auto far = boxes.add({0, 0, 9}, Vec3::Constant(0.3));
  const Shielding s = shield(boxes);
  EXPECT_LT(s.objects[close].radial_separation, s.objects[far].radial_separation);
  EXPECT_LT(s.objects[close].attenuation, s.objects[far].attenuation);
  EXPECT_GT(s.objects[far].attenuation, 0.2);
}

// The blocking factor is counted in pixels of the reference resolution, so a finer map gives
// about the same b.
TEST(Shielding, BlockingFactorHardlyDependsOnResolution) {
  Boxes boxes;
  boxes.add({0, 0, 3}, {2, 2, 0.2});
  const auto block = boxes.add({0, 0, 5}, Vec3::Constant(0.2));
  Settings coarse;
  Settings fine;
  fine.face_columns = 64;
  fine.face_rows = 56;
  const double b_coarse = shield(boxes, {}, coarse).objects[block].blocking_factor;
  const double b_fine = shield(boxes, {}, fine).objects[block].blocking_factor;
  // The wall's half-width seen from the charge is atan(1 / 2.9) = 19 deg, about 9.6 reference
  // pixels of 2 deg; its centre is numbered about that far from its edge.
  EXPECT_NEAR(b_coarse, 9.6, 2.5);
  EXPECT_NEAR(b_fine / b_coarse, 1.0, 0.15);
}

// Beyond the thesis: the exposed half of a half-hidden wall takes its full load, the hidden half
// is shielded; the thesis's per-object mode gives both halves one factor.
TEST(Shielding, PerPanelModeLoadsOnlyWhatIsExposed) {
  Boxes boxes;
  boxes.add({0, -1, 3}, {4, 2, 0.4});                        // low wall, top at y = 0
  const auto target = boxes.add({0, 0, 6.15}, {2, 4, 0.3});  // tall, front face at z = 6
  const std::array<Panel, 2> panels = {Panel{target, {0, 1.5, 6}, 0.25},
                                       Panel{target, {0, -1.5, 6}, 0.25}};
  const Shielding per_panel = shield(boxes, panels);
  EXPECT_EQ(per_panel.panel_attenuation[0], 1.0);
  EXPECT_LT(per_panel.panel_attenuation[1], 0.5);
  Settings whole;
  whole.per_panel = false;
  const Shielding per_object = shield(boxes, panels, whole);
  EXPECT_EQ(per_object.panel_attenuation[0], per_object.panel_attenuation[1]);
  EXPECT_EQ(per_object.panel_attenuation[0], per_object.objects[target].attenuation);
  EXPECT_LT(per_object.objects[target].attenuation, 1.0);
}

TEST(Shielding, ATinyFarObjectStillHasAMaskAndCanBeShielded) {
  Boxes boxes;
  const auto wall = boxes.add({0, 0, 2}, {3, 3, 0.2});
  const auto pebble = boxes.add({0, 0, 40}, Vec3::Constant(0.01));
  const Shielding s = shield(boxes);
  EXPECT_EQ(s.objects[pebble].mask_pixels, 1u);
  EXPECT_EQ(s.objects[pebble].occluders, std::vector<std::uint32_t>{wall});
}

TEST(Shielding, SideBySideBricksDoNotShieldEachOther) {
  Boxes boxes;
  for (int i = 0; i < 5; ++i)
    boxes.add({-1.0 + 0.5 * i, 0, 4}, {0.5, 0.25, 0.25});
  const Shielding s = shield(boxes);
  EXPECT_EQ(s.objects_occluded, 0u);
}

TEST(FootprintsMayOverlap, OnlyWhenABlockerCanShadowAReceiver) {
  Boxes spread;
  spread.add({0, 0, 6}, Vec3::Constant(0.5));
  spread.add({6, 0, 0}, Vec3::Constant(0.5));
  spread.add({0, 0, -6}, Vec3::Constant(0.5));
  EXPECT_FALSE(footprints_may_overlap(Vec3::Zero(), spread.objects()));

  Boxes behind;
  behind.add({0, 0, 3}, {2, 2, 0.3});
  behind.add({0, 0, 6}, Vec3::Constant(0.5));
  EXPECT_TRUE(footprints_may_overlap(Vec3::Zero(), behind.objects()));

  Boxes nothing_blocks;
  nothing_blocks.add({0, 0, 3}, {2, 2, 0.3}, false);
  nothing_blocks.add({0, 0, 6}, Vec3::Constant(0.5), false);
  EXPECT_FALSE(footprints_may_overlap(Vec3::Zero(), nothing_blocks.objects()));
}

}  // namespace
}  // namespace brisance::occlusion
