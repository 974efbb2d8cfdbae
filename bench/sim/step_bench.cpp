// Simulator benchmarks: the brick wall end to end (goal: under 5 ms for 2 s at 30 fps on one
// core) and stepping throughput of free bodies (goal: 10 000 bodies at >= 5 million body-steps
// per second). Where Bullet is installed (Debian libbullet-dev, BENCH_DEB_PACKAGES in the
// Makefile), the same wall stepped by Bullet's btDiscreteDynamicsWorld side by side (issue 13).
// Run: make bench.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include <benchmark/benchmark.h>

#ifdef BRISANCE_HAVE_BULLET
#include <btBulletDynamicsCommon.h>
#endif

#include "sim/dynamics/convex.hpp"
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

brisance::scene::Scene example_scene(const char* file) {
  std::ifstream in(std::string(BRISANCE_SOURCE_DIR) + "/scenes/" + file);
  std::stringstream text;
  text << in.rdbuf();
  const auto parsed = brisance::scene::parse_scene_text(text.str());
  if (!parsed.scene) return {};
  return *parsed.scene;
}

brisance::scene::Scene brick_wall_scene() {
  return example_scene("brick_wall.json");
}

// 16 walls of scenes/brick_wall.json (528 bricks), in a 4 x 4 grid `apart_m` apart, each with
// its charge 15 m in front of it as there (the 528-brick case). 60 m apart, every
// charge's wave strikes every wall within the 2 s (16 waves a wall, arriving until about 0.6 s);
// 1 000 m apart, only its own charge's does (the next arrives after about 2.9 s): 16 copies of
// the example wall, the "16 such walls" Bullet is compared on.
brisance::scene::Scene brick_walls_16_scene(int apart_m) {
  std::string charges, generators;
  for (int i = 0; i < 16; ++i) {
    const std::string x = std::to_string(apart_m * (i % 4)), z = std::to_string(apart_m * (i / 4));
    const std::string charge_z = std::to_string(apart_m * (i / 4) - 15);
    charges += std::string(i ? "," : "") + "{\"position\": [" + x + ", 0.5, " + charge_z +
               "], \"mass\": 100, \"explosive\": \"TNT\", \"burst\": \"air\"}";
    generators += std::string(i ? "," : "") + "{\"type\": \"brick_wall\", \"name\": \"wall" +
                  std::to_string(i) + "\", \"position\": [" + x + ", 0, " + z +
                  "], \"rows\": 6, \"columns\": 5, \"brick_size\": [0.4, 0.15, 0.1], "
                  "\"brick_mass\": 10, \"friction\": 0.6}";
  }
  const auto parsed = brisance::scene::parse_scene_text(
      "{\"charges\": [" + charges + "], \"generators\": [" + generators +
      "], \"simulation\": {\"duration\": 2, \"frame_rate\": 30}}");
  if (!parsed.scene) return {};
  return *parsed.scene;
}

// Walls apart by this much meet no other wall's wave within their 2 s.
constexpr int kWallsApartAlone_m = 1000;

struct BodyPose {
  Vector3d position;
  Eigen::Quaterniond orientation;
};

// The deepest overlap of any two bodies at the given poses of their meshes' frames, m (the
// narrowphase with no margin), as the Contacts tests measure it; and how deep any vertex lies
// below the ground (y = 0), m.
double deepest_overlap(const std::vector<brisance::engine::BodyInfo>& bodies,
                       const std::vector<BodyPose>& poses, double* ground_depth_m) {
  std::vector<std::vector<brisance::dynamics::PlacedPiece>> placed(bodies.size());
  std::vector<brisance::dynamics::CollisionShape> shapes;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    shapes.push_back(brisance::dynamics::collision_shape(bodies[b].mesh, Vector3d::Zero()));
    for (const auto& piece : shapes.back().pieces) {
      placed[b].emplace_back();
      brisance::dynamics::place(piece, poses[b].position, poses[b].orientation.toRotationMatrix(),
                                placed[b].back());
    }
  }
  double deepest = 0.0;
  brisance::dynamics::Manifold manifold;
  if (ground_depth_m) {
    *ground_depth_m = 0.0;
    for (std::size_t b = 0; b < bodies.size(); ++b)
      for (const auto& v : bodies[b].mesh.vertices)
        *ground_depth_m =
            std::max(*ground_depth_m, -(poses[b].position + poses[b].orientation * v).y());
  }
  for (std::size_t a = 0; a < placed.size(); ++a)
    for (std::size_t b = a + 1; b < placed.size(); ++b)
      for (const auto& pa : placed[a])
        for (const auto& pb : placed[b])
          if (brisance::dynamics::collide(pa, pb, 0.0, 0, manifold))
            for (const auto& point : manifold.points)
              deepest = std::max(deepest, point.depth_m);
  return deepest;
}

std::vector<BodyPose> final_poses(const brisance::engine::Result& r) {
  std::vector<BodyPose> poses;
  for (const auto& f : r.final_state)
    poses.push_back({Vector3d(f.pose.position[0], f.pose.position[1], f.pose.position[2]),
                     Eigen::Quaterniond(f.pose.orientation[3], f.pose.orientation[0],
                                        f.pose.orientation[1], f.pose.orientation[2])});
  return poses;
}

// When the side-by-side Bullet run takes over the wall (BM_BulletBrickWall): the blast has
// passed and the bricks fly, s. A whole number of the wall's frames (30 fps), so that the run
// cut there takes the same steps as the whole run up to it.
constexpr double kHandover_s = 0.1;

// `tolerance`: the scene's simulation.tolerance (its adaptive step; the example's is the
// default, 1e-3).
void brick_wall(benchmark::State& state, double duration_s, double tolerance = 1e-3) {
  brisance::scene::Scene scene = brick_wall_scene();
  if (scene.objects.empty()) {
    state.SkipWithError("scenes/brick_wall.json does not parse");
    return;
  }
  scene.simulation.collisions = state.range(0) != 0 ? brisance::scene::CollisionMode::automatic
                                                    : brisance::scene::CollisionMode::off;
  scene.simulation.duration_s = duration_s;
  scene.simulation.tolerance = tolerance;
  std::uint64_t contact_points = 0;
  brisance::engine::Result last;
  for (auto _ : state) {
    auto outcome = simulate(scene);
    contact_points += outcome.result.stats.contact_points;
    benchmark::DoNotOptimize(outcome.result.poses.data());
    last = std::move(outcome.result);
  }
  state.counters["contact_points"] =
      benchmark::Counter(static_cast<double>(contact_points), benchmark::Counter::kAvgIterations);
  double ground_depth = 0.0;
  state.counters["deepest_overlap_mm"] =
      1e3 * deepest_overlap(last.bodies, final_poses(last), &ground_depth);
  state.counters["below_ground_mm"] = 1e3 * ground_depth;
  state.counters["steps"] = static_cast<double>(last.stats.steps);
}

// Goal: scenes/brick_wall.json (2 s at 30 fps) in under 5 ms of simulation on one core.
// Argument: contacts between bodies off (0, the wall before issue 13) or auto (1).
void BM_BrickWall(benchmark::State& state) {
  brick_wall(state, 2.0);
}
BENCHMARK(BM_BrickWall)->ArgName("collisions")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The same wall cut at kHandover_s: the blast and the first flight, which BM_BulletBrickWall
// does not run. BM_BrickWall less this is Brisance's time for the part Bullet runs.
void BM_BrickWallToHandover(benchmark::State& state) {
  brick_wall(state, kHandover_s);
}
BENCHMARK(BM_BrickWallToHandover)
    ->ArgName("collisions")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

// The wall with contacts at a coarser tolerance (the second argument, in units of 1e-4: 100 is
// 1e-2), whole and cut at kHandover_s: at 1e-2 the adaptive step takes about as many steps
// from 0.1 s to 2 s as Bullet at 60 Hz (114), so BM_BrickWallAtTolerance less
// BM_BrickWallAtToleranceToHandover against BM_BulletBrickWall/hz:60 compares the cost of a
// step, not the number of steps.
void BM_BrickWallAtTolerance(benchmark::State& state) {
  brick_wall(state, 2.0, 1e-4 * static_cast<double>(state.range(1)));
}
BENCHMARK(BM_BrickWallAtTolerance)
    ->ArgNames({"collisions", "tolerance_e4"})
    ->Args({1, 100})
    ->Args({1, 300})
    ->Unit(benchmark::kMillisecond);
void BM_BrickWallAtToleranceToHandover(benchmark::State& state) {
  brick_wall(state, kHandover_s, 1e-4 * static_cast<double>(state.range(1)));
}
BENCHMARK(BM_BrickWallAtToleranceToHandover)
    ->ArgNames({"collisions", "tolerance_e4"})
    ->Args({1, 100})
    ->Args({1, 300})
    ->Unit(benchmark::kMillisecond);

// The 528-brick case of issue 13 (goal: at least 3x faster than Bullet), contacts off or auto,
// the walls 60 or 1 000 m apart (brick_walls_16_scene), to `duration_s`.
void brick_walls_16(benchmark::State& state, double duration_s) {
  brisance::scene::Scene scene = brick_walls_16_scene(static_cast<int>(state.range(1)));
  if (scene.objects.size() != 528) {
    state.SkipWithError("the 16 walls do not parse");
    return;
  }
  scene.simulation.collisions = state.range(0) != 0 ? brisance::scene::CollisionMode::automatic
                                                    : brisance::scene::CollisionMode::off;
  scene.simulation.duration_s = duration_s;
  brisance::engine::Result last;
  for (auto _ : state) {
    auto outcome = simulate(scene);
    benchmark::DoNotOptimize(outcome.result.poses.data());
    last = std::move(outcome.result);
  }
  double ground_depth = 0.0;
  state.counters["deepest_overlap_mm"] =
      1e3 * deepest_overlap(last.bodies, final_poses(last), &ground_depth);
  state.counters["below_ground_mm"] = 1e3 * ground_depth;
  state.counters["steps"] = static_cast<double>(last.stats.steps);
}
void BM_BrickWalls16(benchmark::State& state) {
  brick_walls_16(state, 2.0);
}
BENCHMARK(BM_BrickWalls16)
    ->ArgNames({"collisions", "apart_m"})
    ->ArgsProduct({{0, 1}, {60, kWallsApartAlone_m}})
    ->Unit(benchmark::kMillisecond);
// Cut at kHandover_s: BM_BrickWalls16 less this is Brisance's time for the part
// BM_BulletBrickWalls16 runs (1 000 m apart: Bullet is given no later wave).
void BM_BrickWalls16ToHandover(benchmark::State& state) {
  brick_walls_16(state, kHandover_s);
}
BENCHMARK(BM_BrickWalls16ToHandover)
    ->ArgNames({"collisions", "apart_m"})
    ->Args({0, kWallsApartAlone_m})
    ->Args({1, kWallsApartAlone_m})
    ->Unit(benchmark::kMillisecond);

// 0 off, 1 auto, 2 on.
brisance::scene::CollisionMode collision_mode(std::int64_t arg) {
  return arg == 0   ? brisance::scene::CollisionMode::off
         : arg == 1 ? brisance::scene::CollisionMode::automatic
                    : brisance::scene::CollisionMode::on;
}

void run_and_count(benchmark::State& state, const brisance::scene::Scene& scene) {
  brisance::engine::Result last;
  for (auto _ : state) {
    auto outcome = simulate(scene);
    benchmark::DoNotOptimize(outcome.result.poses.data());
    last = std::move(outcome.result);
  }
  state.counters["steps"] = static_cast<double>(last.stats.steps);
  state.counters["contact_points"] = static_cast<double>(last.stats.contact_points);
}

// scenes/window.json end to end (prepare, the pane's fracture into about 1 900 pieces, 2 s at
// 30 fps), contacts off (0), auto (1: the fragments meet the frame and any other body, not each
// other; issue 13's goal: at most 1.5x the run without) or on (2: fragments meet each other
// too, once apart).
void BM_Window(benchmark::State& state) {
  brisance::scene::Scene scene = example_scene("window.json");
  if (scene.objects.empty()) {
    state.SkipWithError("scenes/window.json does not parse");
    return;
  }
  scene.simulation.collisions = collision_mode(state.range(0));
  run_and_count(state, scene);
}
BENCHMARK(BM_Window)->ArgName("collisions")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The same window over a ground, with an anchored wall 0.8 m behind it that the fragments strike
// and drop from, 4 s: its fragments pile up at the wall's foot (the scene of
// Contacts.BrokenPaneLandsWithoutFragmentsInsideEachOther, there with 22 fragments). No goal:
// what a pile costs. Without contacts (0) the fragments pass through the wall and each other;
// with auto (1) through each other.
void BM_WindowPile(benchmark::State& state) {
  brisance::scene::Scene scene = example_scene("window.json");
  if (scene.objects.empty()) {
    state.SkipWithError("scenes/window.json does not parse");
    return;
  }
  scene.environment.ground = brisance::scene::GroundSpec{};
  auto wall =
      testing::box_object("back_wall", Vector3d(4.0, 3.0, 0.2), Vector3d(0.0, 1.5, -0.8), 1000.0);
  wall.anchored = true;
  scene.objects.push_back(wall);
  scene.simulation.duration_s = 4.0;
  scene.simulation.collisions = collision_mode(state.range(0));
  run_and_count(state, scene);
}
BENCHMARK(BM_WindowPile)
    ->ArgName("collisions")
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);

#ifdef BRISANCE_HAVE_BULLET
// The same wall in Bullet (btDiscreteDynamicsWorld, its default sequential-impulse solver with
// 10 iterations, box shapes, a ground plane), handed over from Brisance once the blast has
// passed: each brick's pose and velocities at kHandover_s of BM_BrickWall/collisions:1, then
// stepped at a fixed rate to 2 s. Materials as in the scene: Bullet multiplies the two bodies'
// friction and restitution, so each body gets the square root of the pair's (bricks 0.6
// together, 0.5 and restitution 0.2 on the ground as Brisance's default ground). Argument: steps
// per second. Compare with BM_BrickWall/collisions:1 less BM_BrickWallToHandover/collisions:1
// (BM_BrickWall also runs the blast and the first kHandover_s).

// Brisance's walls at kHandover_s (one wall, or the 16 walls 1 000 m apart).
const brisance::engine::Result& handover(bool sixteen) {
  auto at_handover = [](brisance::scene::Scene scene) {
    scene.simulation.collisions = brisance::scene::CollisionMode::automatic;
    scene.simulation.duration_s = kHandover_s;
    scene.simulation.frame_rate_hz = 1.0 / kHandover_s;
    return simulate(scene).result;
  };
  static const brisance::engine::Result one = at_handover(brick_wall_scene());
  if (!sixteen) return one;
  static const brisance::engine::Result many =
      at_handover(brick_walls_16_scene(kWallsApartAlone_m));
  return many;
}

void bullet_walls(benchmark::State& state, bool sixteen) {
  const brisance::engine::Result& start = handover(sixteen);
  const double rate_hz = static_cast<double>(state.range(0));
  const int steps = static_cast<int>(std::lround((2.0 - kHandover_s) * rate_hz));
  const double brick_friction = std::sqrt(0.6), ground_friction = 0.5 / brick_friction;
  const double restitution = std::sqrt(0.2);
  std::vector<BodyPose> poses;
  for (auto _ : state) {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
    world.setGravity(btVector3(0, -9.81f, 0));
    btStaticPlaneShape ground_shape(btVector3(0, 1, 0), 0);
    btRigidBody ground(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &ground_shape));
    ground.setFriction(static_cast<btScalar>(ground_friction));
    ground.setRestitution(static_cast<btScalar>(restitution));
    world.addRigidBody(&ground);
    std::vector<std::unique_ptr<btBoxShape>> shapes;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    for (std::size_t b = 0; b < start.bodies.size(); ++b) {
      const auto& info = start.bodies[b];
      const auto& f = start.final_state[b];
      Vector3d low = info.mesh.vertices.front(), high = low;
      for (const auto& v : info.mesh.vertices) {
        low = low.cwiseMin(v);
        high = high.cwiseMax(v);
      }
      const Vector3d half = 0.5 * (high - low), centre = 0.5 * (high + low);
      shapes.push_back(std::make_unique<btBoxShape>(btVector3(static_cast<btScalar>(half.x()),
                                                              static_cast<btScalar>(half.y()),
                                                              static_cast<btScalar>(half.z()))));
      const btScalar mass = static_cast<btScalar>(info.mass_kg);
      btVector3 inertia;
      shapes.back()->calculateLocalInertia(mass, inertia);
      const Eigen::Quaterniond q(f.pose.orientation[3], f.pose.orientation[0],
                                 f.pose.orientation[1], f.pose.orientation[2]);
      const Vector3d at =
          Vector3d(f.pose.position[0], f.pose.position[1], f.pose.position[2]) + q * centre;
      btTransform transform(
          btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()),
                       static_cast<btScalar>(q.z()), static_cast<btScalar>(q.w())),
          btVector3(static_cast<btScalar>(at.x()), static_cast<btScalar>(at.y()),
                    static_cast<btScalar>(at.z())));
      btRigidBody::btRigidBodyConstructionInfo construction(mass, nullptr, shapes.back().get(),
                                                            inertia);
      construction.m_startWorldTransform = transform;
      bodies.push_back(std::make_unique<btRigidBody>(construction));
      btRigidBody& body = *bodies.back();
      body.setFriction(static_cast<btScalar>(brick_friction));
      body.setRestitution(static_cast<btScalar>(restitution));
      body.setLinearVelocity(btVector3(static_cast<btScalar>(f.linear_velocity_m_s[0]),
                                       static_cast<btScalar>(f.linear_velocity_m_s[1]),
                                       static_cast<btScalar>(f.linear_velocity_m_s[2])));
      body.setAngularVelocity(btVector3(static_cast<btScalar>(f.angular_velocity_rad_s[0]),
                                        static_cast<btScalar>(f.angular_velocity_rad_s[1]),
                                        static_cast<btScalar>(f.angular_velocity_rad_s[2])));
      world.addRigidBody(&body);
    }
    for (int k = 0; k < steps; ++k)
      world.stepSimulation(static_cast<btScalar>(1.0 / rate_hz), 0);
    poses.clear();
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const btTransform& t = bodies[b]->getWorldTransform();
      const btQuaternion r = t.getRotation();
      const Eigen::Quaterniond q(r.w(), r.x(), r.y(), r.z());
      Vector3d low = start.bodies[b].mesh.vertices.front(), high = low;
      for (const auto& v : start.bodies[b].mesh.vertices) {
        low = low.cwiseMin(v);
        high = high.cwiseMax(v);
      }
      const Vector3d centre = 0.5 * (high + low);
      poses.push_back(
          {Vector3d(t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z()) - q * centre, q});
    }
    for (auto& body : bodies)
      world.removeRigidBody(body.get());
    world.removeRigidBody(&ground);
  }
  double ground_depth = 0.0;
  state.counters["deepest_overlap_mm"] = 1e3 * deepest_overlap(start.bodies, poses, &ground_depth);
  state.counters["below_ground_mm"] = 1e3 * ground_depth;
}
void BM_BulletBrickWall(benchmark::State& state) {
  bullet_walls(state, false);
}
BENCHMARK(BM_BulletBrickWall)->ArgName("hz")->Arg(60)->Arg(240)->Unit(benchmark::kMillisecond);

// The 16 walls, 1 000 m apart (compare with BM_BrickWalls16/collisions:1/apart_m:1000 less
// BM_BrickWalls16ToHandover/collisions:1/apart_m:1000).
void BM_BulletBrickWalls16(benchmark::State& state) {
  bullet_walls(state, true);
}
BENCHMARK(BM_BulletBrickWalls16)->ArgName("hz")->Arg(60)->Arg(240)->Unit(benchmark::kMillisecond);
#endif

}  // namespace

BENCHMARK_MAIN();
