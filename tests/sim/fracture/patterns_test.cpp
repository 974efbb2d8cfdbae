// sim/fracture/patterns: the radial-ring and dice patterns keep the fragment invariants, and
// their sizes follow the closed forms they are built on (docs/fracture.md).
#include "sim/fracture/patterns.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/geometry/polygon.hpp"

namespace brisance::fracture {
namespace {

void expect_partition(const FracturePattern& pattern, double w, double h) {
  double total = 0.0;
  for (const Fragment& f : pattern.fragments) {
    EXPECT_GT(f.area_m2, 0.0);
    EXPECT_NEAR(geometry::signed_area(f.polygon_m), f.area_m2, 1e-15);
    for (const Vec2& v : f.polygon_m) {
      EXPECT_GE(v.x(), -1e-12);
      EXPECT_LE(v.x(), w + 1e-12);
      EXPECT_GE(v.y(), -1e-12);
      EXPECT_LE(v.y(), h + 1e-12);
    }
    total += f.area_m2;
  }
  EXPECT_NEAR(total, w * h, 1e-9 * w * h);
}

FractureParams radial(double w, double h, int count, std::vector<double> rings,
                      std::uint64_t seed) {
  FractureParams p;
  p.width_m = w;
  p.height_m = h;
  p.kind = FractureParams::Kind::radial_ring;
  p.radial.count = count;
  p.radial.ring_radii_m = std::move(rings);
  p.branch_angle_deg = 25.0;
  p.angle_variance_deg = 34.5;
  p.wiggle_probability = 0.3;
  p.wiggle_variance_deg = 30.0;
  p.seed = seed;
  return p;
}

TEST(RadialRing, FragmentsPartitionThePaneAndRepeatBitForBit) {
  for (const auto& [w, h, n] : {std::tuple{1.2, 0.9, 58}, std::tuple{2.0, 0.2, 30},
                                std::tuple{0.3, 0.3, 400}, std::tuple{1.0, 1.0, 2}}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const FractureParams p = radial(w, h, n, {0.2 * std::min(w, h), 0.45 * std::max(w, h)}, seed);
      ASSERT_EQ(validate(p), std::nullopt);
      const FracturePattern a = fracture(p);
      SCOPED_TRACE(testing::Message() << w << " x " << h << ", " << n << " arms, seed " << seed);
      EXPECT_GE(a.fragments.size(), static_cast<std::size_t>(n / 2));
      expect_partition(a, w, h);
      const FracturePattern b = fracture(p);
      ASSERT_EQ(a.fragments.size(), b.fragments.size());
      for (std::size_t k = 0; k < a.fragments.size(); ++k)
        EXPECT_EQ(a.fragments[k].polygon_m, b.fragments[k].polygon_m);
    }
  }
}

TEST(RadialRing, RingsCutThePetals) {
  // Rings add pieces: each ring that crosses the pane cuts the sectors it passes.
  const FracturePattern bare = fracture(radial(1.2, 0.9, 40, {}, 1));
  const FracturePattern ringed = fracture(radial(1.2, 0.9, 40, {0.2, 0.4}, 1));
  EXPECT_GT(ringed.fragments.size(), bare.fragments.size() + 40);
}

TEST(RadialRing, StarFollowsTheMirrorConstant) {
  // n = 2 r sigma_e^2 / A_b^2 summed over directions: n goes as the stress squared, r_b as its
  // inverse square; sigma_e = (1 + nu) / (3 + nu) sigma.
  const RadialStar a = radial_star(1.2, 0.9, 45e6);
  const RadialStar b = radial_star(1.2, 0.9, 90e6);
  EXPECT_NEAR(b.count / a.count, 4.0, 1e-9);
  const double sigma_e = 45e6 * 1.2 / 3.2;
  EXPECT_NEAR(a.branching_length_m, std::pow(2e6 / sigma_e, 2), 1e-15);
  EXPECT_NEAR(a.count, 20.0, 1.0);  // docs/fracture.md: 20 arms at the breaking stress
  // A uniform stress over a disc of radius R would give 2 R / r_b arms; the mode shape's decay
  // keeps the branching zone well inside the pane.
  EXPECT_LT(a.branch_zone_m, 0.45);
  EXPECT_GT(a.branch_zone_m, 0.1);
}

TEST(RadialRing, FirstRingIsWhereTheWedgeReachesTheStrength) {
  // sigma(x) = p x^2 / t^2 from the centre: x_1 = t sqrt(f / p), closed form.
  const std::vector<double> rings = ring_radii_m(14.42e3, 45e6, 0.006, 0.75);
  ASSERT_GE(rings.size(), 2u);
  EXPECT_NEAR(rings[0], 0.006 * std::sqrt(45e6 / 14.42e3), 1e-9);
  for (std::size_t k = 1; k < rings.size(); ++k)
    EXPECT_GT(rings[k], rings[k - 1]);
  EXPECT_TRUE(ring_radii_m(1e3, 45e6, 0.006, 0.75).empty());  // x_1 = 1.27 m: beyond the pane
}

// A stop request that says "stop" from its `at`-th call on, counting its calls.
struct CountingStop {
  int at = 0;
  int calls = 0;
  StopRequest request() {
    return [this] { return ++calls >= at; };
  }
};

TEST(RadialRing, AStopRequestEndsTheBuildWithinOneArm) {
  // A job's cancel or time limit reaches the radial pattern while it is built (as the crack tree
  // polls its growth): before each arm and each ring. Before, radial_ring_cracks took no stop
  // request and fracture() built the whole pattern whatever it said.
  const FractureParams p = radial(1.2, 0.9, 2048, {0.14, 0.23, 0.3, 0.36, 0.42, 0.5, 0.6}, 1);
  ASSERT_EQ(validate(p), std::nullopt);
  CountingStop never{1 << 30};
  const CrackTree whole = radial_ring_cracks(p, never.request());
  EXPECT_FALSE(whole.stopped);
  EXPECT_FALSE(whole.segments.empty());
  EXPECT_GE(never.calls, 2048 + 7);  // an arm (some microseconds) or a ring apart
  for (const int at : {1, 3, 1000, 2050}) {
    CountingStop stop{at};
    const CrackTree tree = radial_ring_cracks(p, stop.request());
    EXPECT_TRUE(tree.stopped) << at;
    EXPECT_TRUE(tree.segments.empty()) << at;
    EXPECT_EQ(stop.calls, at);  // returned at the first "stop"
    CountingStop again{at};
    const FracturePattern pattern = fracture(p, again.request());
    EXPECT_TRUE(pattern.stopped) << at;
    EXPECT_TRUE(pattern.fragments.empty()) << at;
    EXPECT_EQ(again.calls, at);
  }
  // A stop after the cracks, before the fragments are extracted.
  CountingStop late{never.calls + 1};
  EXPECT_TRUE(fracture(p, late.request()).stopped);
}

TEST(Dice, CellSizeFollowsTheTemperEnergy) {
  // The reference point sets eta: 69 MPa gives 40 cells per 50 mm x 50 mm (d = 7.9 mm); the cell
  // goes as (K_c / sigma)^2.
  EXPECT_NEAR(dice_cell_m(69e6, 0.75e6), 0.05 / std::sqrt(40.0), 1e-12);
  EXPECT_NEAR(dice_cell_m(138e6, 0.75e6), 0.25 * 0.05 / std::sqrt(40.0), 1e-12);
  EXPECT_NEAR(temper_energy_ratio(), 5.35, 0.01);
  EXPECT_NEAR(dice_cell_m(75e6, 0.75e6), 0.00669, 1e-5);  // tempered_glass: 6.7 mm
}

TEST(Dice, CellsPartitionThePaneAndCountAsEn12150Does) {
  FractureParams p;
  p.width_m = 0.5;
  p.height_m = 0.3;
  p.kind = FractureParams::Kind::dice;
  p.dice_cell_m = 0.005;
  ASSERT_EQ(validate(p), std::nullopt);
  const FracturePattern dice = fracture(p);
  EXPECT_EQ(dice.fragments.size(), 100u * 60u);
  expect_partition(dice, 0.5, 0.3);
  // 100 cells per 50 mm square on average; jitter moves a few centroids across a square's edge.
  const WindowCount count = fragments_per_window(dice, 0.05, 0.025);
  EXPECT_GT(count.windows, 100u);
  EXPECT_GE(count.fewest, 85u);
  EXPECT_LE(count.most, 115u);
  p.dice_cell_m = 1e-5;  // 1.5e9 cells: refused
  EXPECT_NE(validate(p), std::nullopt);
}

TEST(Dice, AStopRequestEndsTheBuildWithinOneRow) {
  // A cancel reaches the dice while they are made, once per row of cells (under a millisecond of
  // work for the largest pane allowed). Before, dice_pattern took no stop request.
  FractureParams p;
  p.width_m = 1.2;
  p.height_m = 0.9;
  p.kind = FractureParams::Kind::dice;
  p.dice_cell_m = 0.002;  // 600 x 450 cells
  ASSERT_EQ(validate(p), std::nullopt);
  CountingStop never{1 << 30};
  EXPECT_EQ(dice_pattern(p, never.request()).fragments.size(), 600u * 450u);
  EXPECT_GE(never.calls, 2 * 450);
  for (const int at : {1, 200, 700}) {
    CountingStop stop{at};
    const FracturePattern dice = fracture(p, stop.request());
    EXPECT_TRUE(dice.stopped) << at;
    EXPECT_TRUE(dice.fragments.empty()) << at;
    EXPECT_EQ(stop.calls, at);
  }
}

}  // namespace
}  // namespace brisance::fracture
