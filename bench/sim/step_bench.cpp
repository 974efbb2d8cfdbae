// Simulator benchmarks: the brick wall end to end (goal: under 5 ms for 2 s at 30 fps on one
// core) and stepping throughput of free bodies (goal: 10 000 bodies at >= 5 million body-steps
// per second). Run: make bench.
#include <fstream>
#include <sstream>

#include <benchmark/benchmark.h>

#include "sim/engine/simulator.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace {

using brisance::engine::simulate;
using Eigen::Vector3d;
namespace testing = brisance::testing;

// Bodies in the air, blown sideways and spun by a charge below them at the start, then flying
// under gravity and drag: loads, rotation and drag every step. With `ground`, they land,
// slide and fall asleep, as debris does.
brisance::scene::Scene blown_bodies(int count, bool ground) {
  brisance::scene::Scene s;
  s.charges.push_back(testing::tnt(50.0, Vector3d(-5.0, 2.0, -3.0)));
  for (int i = 0; i < count; ++i) {
    auto object = testing::box_object(
        "b" + std::to_string(i), Vector3d(0.1, 0.05, 0.08),
        Vector3d(0.3 * (i % 100), 5.0 + 0.5 * (i / 100 % 20), 0.3 * (i / 2000)), 1.0);
    object.friction = 0.0;  // nothing holds it
    s.objects.push_back(object);
  }
  if (!ground) s.environment.ground.reset();
  s.simulation.collisions = brisance::scene::CollisionMode::off;
  s.simulation.duration_s = ground ? 4.0 : 1.0;
  s.simulation.time_step_s = 1e-3;
  return s;
}

void run(benchmark::State& state, bool ground) {
  const auto scene = blown_bodies(static_cast<int>(state.range(0)), ground);
  std::uint64_t body_steps = 0;
  for (auto _ : state) {
    const auto outcome = simulate(scene);
    body_steps += outcome.result.stats.body_steps;
    benchmark::DoNotOptimize(outcome.result.poses.data());
  }
  state.counters["body_steps_per_s"] =
      benchmark::Counter(static_cast<double>(body_steps), benchmark::Counter::kIsRate);
}

// Goal: 10 000 free bodies at >= 5 million body-steps per second (prepare and the blast's
// loading phase included).
void BM_FreeFlight(benchmark::State& state) {
  run(state, false);
}
BENCHMARK(BM_FreeFlight)->Arg(10)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

// Debris: the same bodies landing, sliding and sleeping over 4 s (contacts between them off:
// this measures the ground contact and the stepping).
void BM_Debris(benchmark::State& state) {
  run(state, true);
}
BENCHMARK(BM_Debris)->Arg(1000)->Unit(benchmark::kMillisecond);

// Goal: scenes/brick_wall.json (2 s at 30 fps) in under 5 ms of simulation on one core.
// Argument: contacts between bodies off (0, the wall before issue 13) or auto (1, the default).
void BM_BrickWall(benchmark::State& state) {
  std::ifstream in(std::string(BRISANCE_SOURCE_DIR) + "/scenes/brick_wall.json");
  std::stringstream text;
  text << in.rdbuf();
  const auto parsed = brisance::scene::parse_scene_text(text.str());
  if (!parsed.scene) {
    state.SkipWithError("scenes/brick_wall.json does not parse");
    return;
  }
  brisance::scene::Scene scene = *parsed.scene;
  scene.simulation.collisions = state.range(0) != 0 ? brisance::scene::CollisionMode::automatic
                                                    : brisance::scene::CollisionMode::off;
  std::uint64_t contact_points = 0;
  for (auto _ : state) {
    const auto outcome = simulate(scene);
    contact_points += outcome.result.stats.contact_points;
    benchmark::DoNotOptimize(outcome.result.poses.data());
  }
  state.counters["contact_points"] =
      benchmark::Counter(static_cast<double>(contact_points), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_BrickWall)->ArgName("collisions")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
