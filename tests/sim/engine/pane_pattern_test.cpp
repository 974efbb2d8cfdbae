// sim/engine/pane_pattern: the crack pattern a pane's load gives keeps refining as the pressure
// rises, past the growth length the scene's grid can hold (docs/fracture.md).
#include "sim/engine/pane_pattern.hpp"

#include <gtest/gtest.h>

#include "sim/fracture/fragments.hpp"

namespace brisance::engine {
namespace {

// Mean fragment count over `seeds` seeds of a 1.2 x 0.8 m, 6 mm annealed pane under a static
// peak pressure (Roark's stress: the pattern depends only on the stress, so the cheap model does).
double mean_count(const scene::FractureSpec& spec, double pressure_pa, int seeds,
                  PanePattern* last = nullptr) {
  PaneSize pane;
  pane.width_m = 1.2;
  pane.height_m = 0.8;
  PaneLoad load;
  load.peak_pressure_pa = pressure_pa;
  double sum = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const PanePattern pattern = pane_pattern(spec, pane, load, static_cast<std::uint64_t>(seed));
    EXPECT_TRUE(pattern.response.breaks) << pressure_pa;
    EXPECT_EQ(fracture::validate(pattern.params), std::nullopt);
    sum += static_cast<double>(fracture::fracture(pattern.params).fragments.size());
    if (last) *last = pattern;
  }
  return sum / seeds;
}

TEST(PanePattern, FragmentCountGrowsWithPressurePastTheScenesGrid) {
  // A coarse grid (256 cells, two of them 9.4 mm): the growth length used to stop there, and the
  // count with it. The thesis's algorithm forks once per growth length of front advance, so the
  // count goes about as a_c^-1, here as (stress)^2: x2.8 per pressure step of x1.6-1.7.
  scene::FractureSpec spec;
  spec.breakage = scene::FractureSpec::Breakage::static_plate;
  spec.grid = 256;
  double previous = 0.0;
  for (double pressure_pa : {15e3, 25e3, 40e3, 65e3}) {
    PanePattern pattern;
    const double count = mean_count(spec, pressure_pa, 3, &pattern);
    EXPECT_FALSE(pattern.growth_length_clamped) << pressure_pa;
    EXPECT_GE(pattern.params.grid_x * pattern.growth_length_m, 4.0 * 1.2 * (1.0 - 1e-12))
        << "at least four cells per growth length, " << pressure_pa;
    EXPECT_GT(count, 1.8 * previous) << pressure_pa << " Pa: " << count << " fragments";
    previous = count;
  }
}

TEST(PanePattern, GridIsRefinedOnlyWhereTheGrowthLengthNeedsIt) {
  EXPECT_EQ(pattern_grid(2048, 1.2, 0.1), 2048);  // 170 cells per growth length
  EXPECT_EQ(pattern_grid(2048, 1.2, 4.0 * 1.2 / 2048), 2048);
  EXPECT_EQ(pattern_grid(2048, 1.2, 0.002), 2400);
  EXPECT_EQ(pattern_grid(2048, 1.2, 1e-5), kFinestPatternGrid);
  EXPECT_EQ(pattern_grid(8192, 1.2, 1e-5), 8192);  // a finer grid given stays
}

}  // namespace
}  // namespace brisance::engine
