// Cancel and the time limit reach every phase of a run (issue 15): breaking panes and prepare
// poll the same hook as the step loop, so a job stops within a moment wherever it is. Before,
// only the step loop polled: 100 breakable panes ran 44 s past a 3 s limit and a valid mesh of
// 397k triangles 302 s past a 30 s one (its clearing-surface search is quadratic in panels that
// share one plane offset, as every tangent plane of a sphere does).
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "sim/engine/simulator.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// `count` framed 1.2 x 0.9 m annealed panes in rows of ten, a facade, 50 kg of TNT 6 m in front:
// a hundred break into 47 000 fragments on the default grid of 2048 cells (5 s to break and
// prepare in a release build on the reference machine, 630 MB).
scene::Scene many_panes(int count, int grid = 2048) {
  scene::Scene s;
  s.charges.push_back(testing::tnt(50.0, Vec3(0.0, 6.0, 6.0)));
  s.environment.ground.reset();
  for (int i = 0; i < count; ++i) {
    scene::ObjectSpec pane;
    pane.name = "pane" + std::to_string(i);
    pane.shape = scene::ShapeType::box;
    pane.box_size_m = Vec3(1.2, 0.9, 0.006);
    pane.mesh = geometry::make_box(pane.box_size_m);
    pane.position = Vec3(1.6 * (i % 10) - 7.2, 1.0 + 1.2 * (i / 10), 0.0);
    pane.mass_kg = 2500.0 * pane.box_size_m.prod();
    pane.material = "annealed_glass";
    pane.fracture = scene::FractureSpec{};
    pane.fracture->framed = true;
    pane.fracture->grid = grid;
    pane.fracture->trigger = scene::FractureSpec::Trigger::always;
    s.objects.push_back(pane);
  }
  s.simulation.duration_s = 0.1;
  return s;
}

TEST(Interrupt, CancelStopsWhileThePanesBreak) {
  const scene::Scene s = many_panes(100);
  // Cancelled at the first poll: the run stops while breaking the first pane. Before, the first
  // poll came in the step loop, after every pane was broken.
  int polls = 0;
  RunHooks hooks;
  hooks.cancel_requested = [&] { return ++polls >= 1; };
  const RunOutcome outcome = simulate(s, hooks);
  EXPECT_TRUE(outcome.cancelled);
  EXPECT_EQ(outcome.cancelled_in, RunPhase::fracture);
  EXPECT_EQ(polls, 1);
  EXPECT_EQ(outcome.result.stats.steps, 0u);
}

TEST(Interrupt, CancelStopsInsideOnePanesCrackGrowth) {
  // One pane on a fine grid with a short growth length: its crack tree grows for a long time.
  scene::Scene s = many_panes(1, 8192);
  s.objects[0].fracture->growth_length_m = 0.004;
  // The first poll (after the plate model) lets it go on; the second, in the crack growth, stops.
  int polls = 0;
  RunHooks hooks;
  hooks.cancel_requested = [&] { return ++polls >= 2; };
  const auto start = Clock::now();
  const RunOutcome outcome = simulate(s, hooks);
  const double elapsed_s = seconds_since(start);
  EXPECT_TRUE(outcome.cancelled);
  EXPECT_EQ(outcome.cancelled_in, RunPhase::fracture);
  EXPECT_EQ(polls, 2);
  // Generous: the same pane grown to its end takes many seconds under the sanitizers.
  EXPECT_LT(elapsed_s, 10.0);
}

TEST(Interrupt, ATimeLimitEndsManyBreakingPanesWithinASecond) {
  const scene::Scene s = many_panes(100);
  // The worker's hook: true once the limit is past (server/worker_pool.cpp).
  const auto start = Clock::now();
  RunHooks hooks;
  hooks.cancel_requested = [&] { return seconds_since(start) > 0.2; };
  const RunOutcome outcome = simulate(s, hooks);
  const double elapsed_s = seconds_since(start);
  EXPECT_TRUE(outcome.cancelled);
  EXPECT_EQ(outcome.cancelled_in, RunPhase::fracture);
  // The panes alone take minutes (44 s at 3 s's limit in the issue); a wide margin for the
  // sanitizer build on a loaded machine.
  EXPECT_LT(elapsed_s, 10.0);
}

TEST(Interrupt, ATimeLimitEndsPrepareOfALargeMesh) {
  scene::Scene s;
  s.charges.push_back(testing::tnt(10.0, Vec3(0.0, 1.0, 5.0)));
  s.environment.ground.reset();
  scene::ObjectSpec ball;
  ball.name = "ball";
  ball.shape = scene::ShapeType::mesh;
  ball.mesh = testing::uv_sphere(100, 200);  // 39 600 triangles, 19 802 vertices
  ASSERT_FALSE(geometry::check_closed_mesh(ball.mesh));
  ball.position = Vec3(0.0, 1.0, 0.0);
  ball.mass_kg = 100.0;
  s.objects.push_back(ball);
  s.simulation.duration_s = 0.1;
  // The limit counts from the first poll, which comes once prepare starts: whatever breaking
  // panes (none here) took does not count. It is already past at the next poll: a limit of
  // 0.2 s, as this test had, outlived the whole prepare in a release build (under 0.2 s), so
  // whether the test saw prepare stop depended on the build's speed. With the limit at zero it
  // checks what matters in any build: prepare polls as it goes, and stops at the poll after the
  // limit rather than running on to the steps.
  std::optional<Clock::time_point> first_poll;
  RunHooks hooks;
  hooks.cancel_requested = [&] {
    if (!first_poll) first_poll = Clock::now();
    return seconds_since(*first_poll) > 0.0;
  };
  const RunOutcome outcome = simulate(s, hooks);
  ASSERT_TRUE(first_poll);
  const double elapsed_s = seconds_since(*first_poll);
  EXPECT_TRUE(outcome.cancelled);
  EXPECT_EQ(outcome.cancelled_in, RunPhase::prepare);
  EXPECT_EQ(outcome.result.stats.steps, 0u);
  // Its prepare alone took 13 s for half as many triangles on this machine (quadratic).
  EXPECT_LT(elapsed_s, 10.0);
}

}  // namespace
}  // namespace brisance::engine

namespace brisance::engine {
namespace {

// What breaking panes creates is counted as the panes break (issue 15): past a limit or the
// memory budget the run stops with a message naming what to change, before prepare and the
// frames allocate for what it made.
TEST(Budget, TooManyFragmentsStopTheRunWithinAPane) {
  const scene::Scene s = many_panes(100);
  RunBudget budget;
  budget.limits.max_fragments = 1000;  // the facade makes 47 000
  int polls = 0;
  RunHooks hooks;
  hooks.cancel_requested = [&] {
    ++polls;
    return false;
  };
  const RunOutcome outcome = simulate(s, hooks, budget);
  ASSERT_TRUE(outcome.over_budget);
  EXPECT_EQ(outcome.over_budget->kind, OverBudget::Kind::limit);
  EXPECT_NE(outcome.over_budget->message.find("more than 1000 fragments (the limit max_fragments)"),
            std::string::npos);
  EXPECT_NE(outcome.over_budget->message.find("fracture.growth_length"), std::string::npos);
  EXPECT_FALSE(outcome.cancelled);
  EXPECT_EQ(outcome.result.stats.steps, 0u);
  // Work done: a pane polls a few hundred times while it breaks (crack growth, fragments), so
  // the few panes up to 1000 fragments poll far fewer times than the hundred panes would.
  int polls_all = 0;
  hooks.cancel_requested = [&] {
    ++polls_all;
    return false;
  };
  budget.limits.max_fragments = 1000000;
  budget.limits.max_panels = 100000000;
  const scene::Scene ten = many_panes(10);
  EXPECT_FALSE(simulate(ten, hooks, budget).over_budget);
  EXPECT_LT(polls, polls_all);
}

TEST(Budget, TheFramesOfTheFragmentsCountAgainstTheFrameSamples) {
  scene::Scene s = many_panes(2);
  RunBudget budget;
  budget.limits.max_frame_samples = 500;  // 4 frames x a few hundred fragments is more
  s.simulation.frame_rate_hz = 30.0;
  const RunOutcome outcome = simulate(s, {}, budget);
  ASSERT_TRUE(outcome.over_budget);
  EXPECT_EQ(outcome.over_budget->kind, OverBudget::Kind::limit);
  EXPECT_NE(outcome.over_budget->message.find("max_frame_samples = 500"), std::string::npos);
}

TEST(Budget, AMemoryBudgetStopsARunThatWouldHoldMore) {
  const scene::Scene s = many_panes(100);
  RunBudget budget;
  budget.memory_bytes = 64u << 20;  // the facade holds some 600 MB
  const RunOutcome outcome = simulate(s, {}, budget);
  ASSERT_TRUE(outcome.over_budget);
  EXPECT_EQ(outcome.over_budget->kind, OverBudget::Kind::memory);
  EXPECT_NE(outcome.over_budget->message.find("over the job memory budget of 64 MB"),
            std::string::npos);
  // The same scene's first pane alone fits.
  EXPECT_FALSE(simulate(many_panes(1), {}, budget).over_budget);
}

}  // namespace
}  // namespace brisance::engine
