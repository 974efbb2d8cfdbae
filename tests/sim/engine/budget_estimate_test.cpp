// The run's size judged before it runs (issue 15): refuse_before_run counts a lower bound of what
// the run creates, so it refuses a scene the run would stop for (fine fragments on many panes)
// and never one the run takes: with limits and a budget set exactly to what a run creates, every
// example scene is still accepted.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "sim/engine/budget.hpp"
#include "sim/engine/interrupt.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/pane_pattern.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/fracture/fragments.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {
namespace {

scene::Scene parse(const std::string& text) {
  const scene::ParseResult parsed = scene::parse_scene_text(text);
  EXPECT_TRUE(parsed.errors.empty())
      << parsed.errors.front().pointer << ": " << parsed.errors.front().message;
  return parsed.scene.value_or(scene::Scene{});
}

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The service's limits (server::service_limits: 5e6 frames x bodies) and memory budget (2 GiB).
RunBudget service_budget() {
  RunBudget budget;
  budget.limits.max_frame_samples = 5000000;
  budget.memory_bytes = std::uint64_t{2048} << 20;
  return budget;
}

// `count` 2 x 2 m panes that always break with 2 mm between forks (about 1 000 fragments each),
// recorded for 1 s at 1 000 frames/s: the run stops past 5e6 frames x bodies once some five
// panes have broken.
scene::Scene fine_panes(int count) {
  std::string objects;
  for (int i = 0; i < count; ++i) {
    if (i > 0) objects += ",";
    objects += R"({"name": "pane)" + std::to_string(i) +
               R"(", "shape": {"type": "box", "size": [2, 2, 0.006]}, "position": [)" +
               std::to_string(2.5 * i) + R"(, 1.5, 0], "material": "annealed_glass",
               "fracture": {"break": "always", "growth_length": 0.002}})";
  }
  return parse(R"({"charges": [{"position": [0, 1.5, 8], "mass": 1}],
                   "environment": {"ground": null}, "objects": [)" +
               objects + R"(], "simulation": {"duration": 1, "frame_rate": 1000}})");
}

TEST(BudgetEstimate, RefusesAScenePastTheFrameSamplesThatTheRunAlsoStops) {
  const scene::Scene scene = fine_panes(30);
  const RunBudget budget = service_budget();
  const std::optional<BudgetRefusal> refusal = refuse_before_run(scene, budget);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_EQ(refusal->what.kind, OverBudget::Kind::limit);
  EXPECT_NE(refusal->what.message.find("max_frame_samples"), std::string::npos)
      << refusal->what.message;
  EXPECT_LT(refusal->object, 30u);
  // The run itself: it stops too, and no later than the estimate says (a lower bound crosses
  // the line at the same pane or after the run does).
  const RunOutcome run = simulate(scene, {}, budget);
  ASSERT_TRUE(run.over_budget.has_value());
  EXPECT_EQ(run.over_budget->kind, OverBudget::Kind::limit);
}

TEST(BudgetEstimate, RefusesAScenePastTheMemoryBudget) {
  RunBudget budget = service_budget();
  budget.memory_bytes = std::uint64_t{64} << 20;
  const std::optional<BudgetRefusal> refusal = refuse_before_run(fine_panes(30), budget);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_EQ(refusal->what.kind, OverBudget::Kind::memory);
}

// What body_sources creates for the scene, counted as the run counts it.
struct RunSize {
  std::uint64_t bodies = 0;
  std::uint64_t fragments = 0;
  std::uint64_t panels = 0;
  std::uint64_t bytes = 0;
};
RunSize run_size(const scene::Scene& scene) {
  RunBudget unlimited;
  unlimited.limits.max_fragments = std::numeric_limits<std::size_t>::max();
  unlimited.limits.max_panels = std::numeric_limits<std::size_t>::max();
  unlimited.limits.max_frame_samples = std::numeric_limits<std::size_t>::max();
  BudgetTally tally(unlimited, scene);
  Checkpoint never;
  const BodySources sources = body_sources(scene, never, &tally);
  RunSize size;
  size.bodies = sources.bodies.size();
  for (const BodySource& body : sources.bodies) {
    size.fragments += body.fragment ? 1 : 0;
    size.panels += body.load_panels.size();
  }
  size.bytes = tally.bytes();
  return size;
}

TEST(BudgetEstimate, ATemperedPaneIsCountedAsItsDice) {
  // A 3 x 2 m tempered pane breaks into about 134 000 dice (6.7 mm): past the default
  // max_fragments (100 000), refused at submission, and the run stops for the same limit. At
  // 1.2 x 0.9 m (24 165 dice) it is accepted, and the estimate's count is the run's.
  const auto tempered = [](double w, double h) {
    return parse(R"({"charges": [{"position": [0, 1.5, 5], "mass": 10}],
                     "environment": {"ground": null},
                     "objects": [{"name": "pane", "shape": {"type": "box", "size": [)" +
                 std::to_string(w) + ", " + std::to_string(h) +
                 R"(, 0.006]}, "position": [0, 1.5, 0], "material": "tempered_glass",
                     "fracture": {"break": "always"}}],
                     "simulation": {"duration": 0.05, "frame_rate": 30}})");
  };
  const RunBudget budget = service_budget();
  const std::optional<BudgetRefusal> refusal = refuse_before_run(tempered(3.0, 2.0), budget);
  ASSERT_TRUE(refusal.has_value());
  EXPECT_EQ(refusal->what.kind, OverBudget::Kind::limit);
  EXPECT_NE(refusal->what.message.find("max_fragments"), std::string::npos)
      << refusal->what.message;
  const RunOutcome run = simulate(tempered(3.0, 2.0), {}, budget);
  ASSERT_TRUE(run.over_budget.has_value());
  EXPECT_NE(run.over_budget->message.find("max_fragments"), std::string::npos);

  const scene::Scene window = tempered(1.2, 0.9);
  EXPECT_FALSE(refuse_before_run(window, budget).has_value());
  RunBudget exact = budget;
  exact.limits.max_fragments = run_size(window).fragments;
  EXPECT_EQ(exact.limits.max_fragments, 24165u);
  EXPECT_FALSE(refuse_before_run(window, exact).has_value());
  exact.limits.max_fragments -= 1;
  EXPECT_TRUE(refuse_before_run(window, exact).has_value());  // the dice are counted exactly
}

// Every example scene (and the pane variants of the golden set, and a few fine panes) with every
// limit and the memory budget set to exactly what its run creates: the run takes it, so the
// estimate must too. And each is accepted under the service's own limits.
TEST(BudgetEstimate, NeverRefusesAScenePastNothingTheRunCreates) {
  std::vector<std::pair<std::string, scene::Scene>> scenes;
  const std::filesystem::path root = BRISANCE_SOURCE_DIR;
  for (const auto& entry : std::filesystem::directory_iterator(root / "scenes"))
    if (entry.path().extension() == ".json")
      scenes.emplace_back(entry.path().filename().string(), parse(read(entry.path())));
  scenes.emplace_back("pane_variants",
                      parse(read(root / "tests/golden/scenes/pane_variants.json")));
  scenes.emplace_back("fine_panes(3)", fine_panes(3));
  ASSERT_GE(scenes.size(), 9u);
  for (const auto& [name, scene] : scenes) {
    SCOPED_TRACE(name);
    EXPECT_FALSE(refuse_before_run(scene, service_budget()).has_value());
    const RunSize size = run_size(scene);
    const std::uint64_t frames =
        static_cast<std::uint64_t>(
            std::floor(scene.simulation.duration_s * scene.simulation.frame_rate_hz + 1e-9)) +
        1;
    RunBudget exact;
    exact.limits.max_fragments = size.fragments;
    exact.limits.max_panels = size.panels;
    exact.limits.max_frame_samples = frames * size.bodies;
    exact.memory_bytes = size.bytes;
    const std::optional<BudgetRefusal> refusal = refuse_before_run(scene, exact);
    EXPECT_FALSE(refusal.has_value()) << refusal->what.message;
  }
}

// The lower bound of a pane's fragments against patterns grown as a job grows them, over pane
// shapes, growth lengths, branch angles, angle variances, wiggles and seeds.
TEST(BudgetEstimate, FewestFragmentsIsBelowEveryGrownPattern) {
  struct Case {
    double width, height, growth;
    double branch, variance, wiggle_probability, wiggle;
  };
  const Case cases[] = {
      {1.2, 0.8, 0.02, 25, 34.5, 0.3, 30},  {1.2, 0.8, 0.005, 25, 34.5, 0.3, 30},
      {1.5, 0.15, 0.045, 90, 34.5, 1.0, 0}, {0.1, 0.025, 0.0025, 5, 34.5, 1.0, 60},
      {0.6, 1.8, 0.06, 10, 60, 1.0, 90},    {0.1, 0.1, 0.001, 10, 10, 0.0, 0},
      {1.0, 1.0, 0.5, 45, 90, 0.0, 0},      {2.0, 0.2, 0.1, 5, 0, 0.0, 0},
      {0.5, 0.5, 0.01, 89, 0, 1.0, 90},     {0.3, 0.9, 0.003, 60, 90, 0.5, 45},
  };
  int checked = 0;
  for (const Case& c : cases) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      scene::FractureSpec spec;
      spec.trigger = scene::FractureSpec::Trigger::always;
      spec.growth_length_m = c.growth;
      spec.branch_angle_deg = c.branch;
      spec.angle_variance_deg = c.variance;
      spec.wiggle_probability = c.wiggle_probability;
      spec.wiggle_variance_deg = c.wiggle;
      const PaneSize pane{c.width, c.height, 0.006, 2500.0};
      const PanePattern plan = pane_pattern(spec, pane, PaneLoad{}, seed);
      const std::size_t grown = fracture::fracture(plan.params).fragments.size();
      EXPECT_LE(fewest_fragments(c.width, c.height, plan.growth_length_m), grown)
          << c.width << " x " << c.height << " m, growth " << plan.growth_length_m << ", seed "
          << seed;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 30);
}

// The same for the patterns a job grows without a given growth length: radial cracks and rings
// (annealed glass) over pane shapes and pressures, and tempered dice (exact).
TEST(BudgetEstimate, FewestFragmentsIsBelowRadialAndDicePatterns) {
  struct Case {
    double width, height, pressure_pa;
  };
  const Case cases[] = {
      {1.2, 0.9, 4.0e3}, {1.2, 0.9, 20e3},  {1.5, 0.15, 400e3}, {0.1, 0.025, 3e6},
      {0.6, 1.8, 3e3},   {0.3, 0.3, 100e3}, {2.0, 0.2, 60e3},   {0.5, 0.5, 8e3},
  };
  double least_ratio = 1e9;
  for (const Case& c : cases) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      scene::FractureSpec spec;
      spec.breakage = scene::FractureSpec::Breakage::static_plate;
      spec.trigger = scene::FractureSpec::Trigger::always;
      const PaneSize pane{c.width, c.height, 0.006, 2500.0};
      PaneLoad load;
      load.peak_pressure_pa = c.pressure_pa;
      const PanePattern plan = pane_pattern(spec, pane, load, seed);
      ASSERT_EQ(plan.kind, fracture::FractureParams::Kind::radial_ring);
      const std::size_t grown = fracture::fracture(plan.params).fragments.size();
      EXPECT_LE(fewest_fragments(plan, c.width, c.height), grown)
          << c.width << " x " << c.height << " m at " << c.pressure_pa << " Pa, "
          << plan.params.radial.count << " radial cracks, seed " << seed;
      least_ratio = std::min(least_ratio, static_cast<double>(grown) / plan.params.radial.count);
      spec.surface_compression_pa = 75e6;
      const PanePattern dice = pane_pattern(spec, pane, load, seed);
      ASSERT_EQ(dice.kind, fracture::FractureParams::Kind::dice);
      EXPECT_EQ(fewest_fragments(dice, c.width, c.height),
                fracture::fracture(dice.params).fragments.size());
    }
  }
  std::printf("  least fragments per radial crack: %.2f\n", least_ratio);
}

}  // namespace
}  // namespace brisance::engine
