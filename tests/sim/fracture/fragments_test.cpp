// Tests of sim/fracture/fragments: the partition invariants over thousands of seeds and
// parameter sets, determinism, fragment count against a_c, and fragments as prisms.
#include "sim/fracture/fragments.hpp"

#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include <gtest/gtest.h>

#include "sim/geometry/mesh.hpp"
#include "sim/geometry/polygon.hpp"

namespace brisance::fracture {
namespace {

using Key = std::tuple<double, double, double, double>;
Key directed(const Vec2& a, const Vec2& b) {
  return {a.x(), a.y(), b.x(), b.y()};
}

// The invariants of fragments.hpp, each able to fail on its own.
void expect_partition(const FracturePattern& pattern, const std::string& label, int samples = 64) {
  SCOPED_TRACE(label);
  const double pane = pattern.width_m * pattern.height_m;
  ASSERT_FALSE(pattern.fragments.empty());
  double sum = 0.0;
  std::map<Key, int> edge_uses;
  for (const Fragment& f : pattern.fragments) {
    EXPECT_TRUE(geometry::is_simple(f.polygon_m)) << f.polygon_m.size() << " vertices";
    EXPECT_GT(f.area_m2, 0.0);
    EXPECT_NEAR(f.area_m2, geometry::signed_area(f.polygon_m), 1e-15);
    sum += f.area_m2;
    for (std::size_t i = 0; i < f.polygon_m.size(); ++i) {
      const Vec2& a = f.polygon_m[i];
      const Vec2& b = f.polygon_m[(i + 1) % f.polygon_m.size()];
      ++edge_uses[directed(a, b)];
      EXPECT_TRUE(a.x() >= 0.0 && a.x() <= pattern.width_m && a.y() >= 0.0 &&
                  a.y() <= pattern.height_m);
    }
  }
  EXPECT_NEAR(sum, pane, 1e-9 * pane);
  // Every crack edge borders two fragments (once each way), every outline edge one.
  for (const auto& [a, b] : pattern.crack_edges) {
    EXPECT_EQ(edge_uses[directed(a, b)], 1);
    EXPECT_EQ(edge_uses[directed(b, a)], 1);
  }
  for (const auto& [a, b] : pattern.border_edges)
    EXPECT_EQ(edge_uses[directed(a, b)] + edge_uses[directed(b, a)], 1);
  std::size_t polygon_edges = 0;
  for (const auto& [key, uses] : edge_uses)
    polygon_edges += static_cast<std::size_t>(uses);
  EXPECT_EQ(polygon_edges, 2 * pattern.crack_edges.size() + pattern.border_edges.size());
  // No overlaps and no gaps: sample points lie in exactly one fragment.
  std::mt19937_64 engine(12345);
  for (int s = 0; s < samples; ++s) {
    const Vec2 p(pattern.width_m * static_cast<double>(engine() >> 11) * 0x1.0p-53,
                 pattern.height_m * static_cast<double>(engine() >> 11) * 0x1.0p-53);
    int inside = 0;
    for (const Fragment& f : pattern.fragments)
      inside += geometry::contains(f.polygon_m, p) ? 1 : 0;
    EXPECT_EQ(inside, 1) << p.transpose();
  }
}

TEST(Fragments, PartitionThePaneOverThousandsOfSeedsAndParameterSets) {
  const auto started = std::chrono::steady_clock::now();
  int runs = 0;
  for (std::uint64_t seed = 1; seed <= 2500; ++seed) {
    std::mt19937_64 engine(seed);
    const auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
    FractureParams p;
    p.seed = seed;
    p.width_m = 0.5 + 1.5 * uniform();
    p.height_m = 0.5 + 1.5 * uniform();
    p.grid_x = seed % 3 == 0 ? 256 : 128;
    p.grid_y = seed % 5 == 0 ? 96 : p.grid_x;
    const double cell = std::max(p.width_m / p.grid_x, p.height_m / p.grid_y);
    p.growth_length_m = std::max(cell, (0.02 + 0.1 * uniform()) * std::min(p.width_m, p.height_m));
    p.branch_angle_deg = 10.0 + 80.0 * uniform();
    p.angle_variance_deg = seed % 2 ? 40.0 * uniform() : 0.0;
    p.wiggle_probability = seed % 4 < 2 ? uniform() : 0.0;
    p.wiggle_variance_deg = 60.0 * uniform();
    p.initial.length_m = 0.1 * uniform() * p.width_m;
    p.initial.angle_deg = 360.0 * uniform();
    if (seed % 7 == 0) p.initial.shape = InitialCrack::Shape::cross;
    if (seed % 11 == 0)
      p.initial.centres_m = {Vec2(0.2 * p.width_m, 0.3 * p.height_m),
                             Vec2(0.8 * p.width_m, 0.6 * p.height_m)};
    if (seed % 13 == 0) p.growth_limit_m = 0.2 * p.width_m;
    ASSERT_EQ(validate(p), std::nullopt);
    expect_partition(fracture(p), "seed " + std::to_string(seed), 16);
    ++runs;
    if (::testing::Test::HasFailure()) break;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  RecordProperty("runs", runs);
  std::printf("  %d patterns in %.2f s\n", runs, seconds);
}

TEST(Fragments, PartitionAtTheThesisResolution) {
  for (const FractureParams& preset : {combined_preset(), base_preset(25.0)}) {
    FractureParams p = preset;
    p.growth_length_m = 0.004;
    const FracturePattern pattern = fracture(p);
    EXPECT_GT(pattern.fragments.size(), 150u);
    expect_partition(pattern, "2048^2", 200);
  }
}

TEST(Fragments, EveryThesisVariantPartitions) {
  const std::pair<const char*, FractureParams> variants[] = {
      {"base 25 (fig. 5.10)", base_preset(25.0)},        {"base 35 (fig. 5.11)", base_preset(35.0)},
      {"variance (fig. 5.12)", angle_variance_preset()}, {"wiggle (fig. 5.13)", wiggle_preset()},
      {"both (fig. 5.14)", combined_preset()},           {"creep (fig. 5.16)", creep_preset()}};
  for (const auto& [name, preset] : variants) {
    FractureParams p = preset;
    p.grid_x = p.grid_y = 512;
    expect_partition(fracture(p), name);
  }
}

TEST(Fragments, DeterministicBitForBit) {
  FractureParams p = combined_preset();
  p.grid_x = p.grid_y = 512;
  const FracturePattern a = fracture(p);
  const FracturePattern b = fracture(p);
  ASSERT_EQ(a.fragments.size(), b.fragments.size());
  for (std::size_t i = 0; i < a.fragments.size(); ++i) {
    ASSERT_EQ(a.fragments[i].polygon_m.size(), b.fragments[i].polygon_m.size());
    for (std::size_t k = 0; k < a.fragments[i].polygon_m.size(); ++k)
      EXPECT_EQ(a.fragments[i].polygon_m[k], b.fragments[i].polygon_m[k]);
    EXPECT_EQ(a.fragments[i].area_m2, b.fragments[i].area_m2);
  }
}

TEST(Fragments, SmallerGrowthLengthGivesMoreSmallerFragments) {
  double previous_count = 0.0;
  for (double a_c : {0.2, 0.1, 0.05, 0.025, 0.0125}) {
    double count = 0.0;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      FractureParams p = combined_preset();
      p.grid_x = p.grid_y = 512;
      p.growth_length_m = a_c;
      p.wiggle_length_m = 0.01;
      p.seed = seed;
      count += static_cast<double>(fracture(p).fragments.size());
    }
    EXPECT_GT(count, previous_count * 1.3) << "a_c " << a_c;
    previous_count = count;
  }
}

// The pattern a job grows for a 1.2 x 0.8 m pane (combined preset as the scene's defaults, an X
// of twice the growth length at the centre, 2048 x 1365 cells) at a growth length of two cells.
FractureParams window_at_two_cells(std::uint64_t seed, double growth_length_m) {
  FractureParams p;
  p.width_m = 1.2;
  p.height_m = 0.8;
  p.grid_x = 2048;
  p.grid_y = 1365;
  p.growth_length_m = growth_length_m;
  p.initial.shape = InitialCrack::Shape::cross;
  p.initial.length_m = 2.0 * growth_length_m;
  p.branch_angle_deg = 25.0;
  p.angle_variance_deg = 34.5;
  p.wiggle_probability = 0.3;
  p.wiggle_variance_deg = 30.0;
  p.seed = seed;
  return p;
}

TEST(Fragments, BranchesCrossingNearTheirForkDoNotKillTheTree) {
  // Seeds 1, 6 and 7 gave one fragment: two branches crossed near their fork (where they ignore
  // each other's cells), the cycle a later hit closed through them crossed itself, and the kill
  // rule judged by the cycle's turn at that fork called the whole rest of the tree inside it.
  // The thesis's algorithm forks once per growth length of front advance, so halving the growth
  // length should about double the count (measured 1.7-2.2x over 8 seeds): compare with the
  // same seed at twice the growth length (four cells).
  const double cell = 1.2 / 2048;
  for (std::uint64_t seed : {1u, 6u, 7u}) {
    const CrackTree tree = grow_crack_tree(window_at_two_cells(seed, 2.0 * cell));
    const std::size_t fine = extract_fragments(tree, 1.2, 0.8).fragments.size();
    const std::size_t coarse = fracture(window_at_two_cells(seed, 4.0 * cell)).fragments.size();
    EXPECT_GT(static_cast<double>(fine), 1.4 * static_cast<double>(coarse)) << "seed " << seed;
    // The kill rule stays what the thesis calls it, rare: a tenth of the tips or fewer.
    EXPECT_LT(static_cast<double>(tree.killed), 0.1 * static_cast<double>(tree.tips.size()))
        << "seed " << seed;
  }
}

TEST(Fragments, NoCrackMeansOneFragment) {
  // A crack that never forks and stops early leaves only dangling cracks: the pane is whole.
  FractureParams p;
  p.grid_x = p.grid_y = 128;
  p.growth_limit_m = 0.05;
  p.growth_length_m = 0.5;
  const FracturePattern pattern = fracture(p);
  ASSERT_EQ(pattern.fragments.size(), 1u);
  EXPECT_NEAR(pattern.fragments[0].area_m2, 1.0, 1e-15);
  EXPECT_GT(pattern.dropped_edges, 0u);
  EXPECT_TRUE(pattern.crack_edges.empty());
}

TEST(Fragments, BecomeClosedPrismsWithExactMassProperties) {
  FractureParams p = combined_preset();
  p.grid_x = p.grid_y = 512;
  const FracturePattern pattern = fracture(p);
  for (const Fragment& f : pattern.fragments) {
    const geometry::TriangleMesh mesh = geometry::extrude(f.polygon_m, 0.006);
    ASSERT_EQ(geometry::check_closed_mesh(mesh), std::nullopt);
    const auto closed = geometry::prism_mass_properties(f.polygon_m, 0.006, 2500.0);
    const auto integrated = geometry::mass_properties(mesh, 2500.0);
    EXPECT_NEAR(closed.mass_kg, integrated.mass_kg, 1e-9 * integrated.mass_kg);
    EXPECT_NEAR((closed.inertia_kg_m2 - integrated.inertia_kg_m2).norm(), 0.0,
                1e-9 * integrated.inertia_kg_m2.norm());
    const auto panels = geometry::front_panels(f.polygon_m, 0.006);
    EXPECT_GE(panels.size(), 5u);
  }
}

}  // namespace
}  // namespace brisance::fracture
