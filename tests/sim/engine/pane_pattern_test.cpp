// sim/engine/pane_pattern: the crack pattern a pane's load gives keeps refining as the pressure
// rises; annealed panes break into radial cracks and rings, tempered ones into dice
// (docs/fracture.md).
#include "sim/engine/pane_pattern.hpp"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "sim/fracture/fragments.hpp"
#include "sim/fracture/patterns.hpp"

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

TEST(PanePattern, FragmentCountGrowsWithPressure) {
  // Annealed glass: radial cracks n ~ sigma^2 (the star's branching with the mirror constant)
  // and rings closer with the pressure (x_1 = t sqrt(f / p)): x2.25 per stress step of x1.5,
  // more with the rings (docs/fracture.md, "Annealed glass: radial cracks and rings").
  scene::FractureSpec spec;
  spec.breakage = scene::FractureSpec::Breakage::static_plate;
  double previous = 0.0;
  for (double pressure_pa : {6e3, 9e3, 13.5e3, 20.25e3}) {
    PanePattern pattern;
    const double count = mean_count(spec, pressure_pa, 3, &pattern);
    EXPECT_EQ(pattern.kind, fracture::FractureParams::Kind::radial_ring);
    EXPECT_FALSE(pattern.radial_capped) << pressure_pa;
    EXPECT_GT(count, 1.8 * previous) << pressure_pa << " Pa: " << count << " fragments";
    previous = count;
  }
}

// window.json's pane (1.2 x 0.9 m, 6 mm annealed) under a 6.99 ms triangle (the reflected
// pulse's duration there) scaled to `times` its breaking pressure, as `brisance fracture`
// loads it.
std::vector<PanePattern> window_patterns(double times, int seeds,
                                         std::vector<fracture::FracturePattern>& out) {
  scene::FractureSpec spec;
  const PaneSize pane{1.2, 0.9, 0.006, 2500.0};
  const auto load_at = [](double peak_pa) {
    PaneLoad load;
    load.peak_pressure_pa = peak_pa;
    load.history.components.push_back(response::pulse_component(blast::make_pulse(
        blast::PulseShape::triangle_same_period, peak_pa, 6.99e-3, 0.5 * peak_pa * 6.99e-3)));
    return load;
  };
  const double breaking = breaking_pressure_pa(spec, pane, load_at(1e3));
  std::vector<PanePattern> patterns;
  for (int seed = 1; seed <= seeds; ++seed) {
    patterns.push_back(
        pane_pattern(spec, pane, load_at(times * breaking), static_cast<std::uint64_t>(seed)));
    out.push_back(fracture::fracture(patterns.back().params));
  }
  return patterns;
}

TEST(PanePattern, NoFragmentAboveFivePercentOfAPaneAtTwiceItsBreakingPressure) {
  // Issue 11: no single fragment above 5 % of a pane broken at twice its breaking pressure
  // (the crack tree's pattern gave 7 fragments there, the largest 25-28 % of the pane, seeds
  // 1-8). The pattern is radial cracks from the centre crossed by rings, as photographs of
  // broken windows show.
  std::vector<fracture::FracturePattern> broken;
  const std::vector<PanePattern> patterns = window_patterns(2.0, 8, broken);
  for (std::size_t k = 0; k < broken.size(); ++k) {
    ASSERT_EQ(patterns[k].kind, fracture::FractureParams::Kind::radial_ring);
    EXPECT_GE(patterns[k].params.radial.count, 20) << "seed " << k + 1;
    EXPECT_GE(patterns[k].params.radial.ring_radii_m.size(), 1u) << "seed " << k + 1;
    double largest = 0.0, total = 0.0;
    for (const fracture::Fragment& f : broken[k].fragments) {
      largest = std::max(largest, f.area_m2);
      total += f.area_m2;
    }
    EXPECT_NEAR(total, 1.2 * 0.9, 1e-9);
    EXPECT_LT(largest / total, 0.05)
        << "seed " << k + 1 << ": " << broken[k].fragments.size() << " fragments";
  }
}

TEST(PanePattern, FragmentAreasSpreadAsBrokenGlassDoesAtTwiceItsBreakingPressure) {
  // Issue 11: p90 / p10 of the fragment areas at least 20, the spread of real broken glass, for
  // window.json's pane at twice its breaking pressure (seeds 1-8; nearest-rank quantiles, as
  // the result's frontal_area_m2 distribution). Before the arms split their shares fork by fork
  // and branched again where a stopped arm left its neighbours too wide a share
  // (docs/fracture.md), it was 12.0-26.0, below 20 for seeds 2, 3, 5 and 6.
  std::vector<fracture::FracturePattern> broken;
  window_patterns(2.0, 8, broken);
  for (std::size_t k = 0; k < broken.size(); ++k) {
    std::vector<double> areas;
    for (const fracture::Fragment& f : broken[k].fragments)
      areas.push_back(f.area_m2);
    std::sort(areas.begin(), areas.end());
    const auto rank = [&](double q) {
      const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(areas.size())));
      return areas[std::max<std::size_t>(i, 1) - 1];
    };
    EXPECT_GE(rank(0.9) / rank(0.1), 20.0)
        << "seed " << k + 1 << ": " << areas.size() << " fragments, p10 " << rank(0.1) * 1e4
        << " cm2, p90 " << rank(0.9) * 1e4 << " cm2";
  }
}

TEST(PanePattern, TemperedPaneFallsIntoDiceThatPassEn12150) {
  // EN 12150-1 §8: at least 40 particles in any 50 mm x 50 mm square (4-12 mm glass), counted
  // away from a 25 mm band along the edges. A tempered pane (the material's 75 MPa surface
  // compression) broken by a blast: dice over the whole pane, whatever the load.
  scene::FractureSpec spec;
  spec.strength_pa = 120e6;
  spec.surface_compression_pa = 75e6;
  PaneSize pane;
  pane.width_m = 0.6;
  pane.height_m = 0.4;
  PaneLoad load;
  load.peak_pressure_pa = 1e6;
  spec.breakage = scene::FractureSpec::Breakage::static_plate;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const PanePattern pattern = pane_pattern(spec, pane, load, seed);
    ASSERT_TRUE(pattern.response.breaks);
    ASSERT_EQ(pattern.kind, fracture::FractureParams::Kind::dice);
    const fracture::FracturePattern dice = fracture::fracture(pattern.params);
    const fracture::WindowCount count = fracture::fragments_per_window(dice, 0.05, 0.025);
    ASSERT_GT(count.windows, 100u);
    EXPECT_GE(count.fewest, 40u) << "seed " << seed;
    double total = 0.0;
    for (const fracture::Fragment& f : dice.fragments)
      total += f.area_m2;
    EXPECT_NEAR(total, 0.24, 1e-12);
  }
  // Less temper, bigger dice: the count goes as the surface compression to the fourth power
  // (the energy balance, Barsom 1968); heat-strengthened glass (about 40 MPa) fails the count.
  spec.surface_compression_pa = 40e6;
  const PanePattern weak = pane_pattern(spec, pane, load, 1);
  EXPECT_LT(fracture::fragments_per_window(fracture::fracture(weak.params), 0.05, 0.025).most, 40u);
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
