// The brick wall against a peer (issue 13, "Peers and speed"): Brisance with contacts between
// bodies against Bullet 3 (Debian libbullet-dev, btDiscreteDynamicsWorld) on the same debris, in
// one invocation, so the ratio is measured on one machine at one moment.
//
// Both start from what Brisance's blast gives the bricks: the scene is run to `--blast-end`
// (0.05 s: the 100 kg charge's wave has passed the wall), and every brick's pose and velocity
// then seed Bullet's bodies (same box, mass, friction; gravity, a ground plane). Bullet then
// steps the rest of the 2 s at 60 and 240 Hz (one substep per step), Brisance runs the whole
// scene end to end (parse excluded: blast, holds, contacts, frames). The times are the best of
// `--reps` runs. Overlap is judged for both by one referee, Bullet's box–box detector on the
// final poses: pairs of bricks interpenetrating by more than 1 mm and 5 mm, and the worst depth.
//
// Run: make peer-bench (installs libbullet-dev; output in bench/results/peer_bench.txt).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "sim/engine/simulator.hpp"
#include "sim/scene/scene.hpp"

namespace {

using brisance::engine::FinalState;
using brisance::engine::simulate;
using brisance::scene::Scene;

struct Options {
  int reps = 5;
  double blast_end_s = 0.05;
};

// Bullet is built with single-precision btScalar.
btScalar f(double x) {
  return static_cast<btScalar>(x);
}

btVector3 vec(double x, double y, double z) {
  return btVector3(f(x), f(y), f(z));
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Scene load_wall() {
  std::ifstream in(std::string(BRISANCE_SOURCE_DIR) + "/scenes/brick_wall.json");
  std::stringstream text;
  text << in.rdbuf();
  const auto parsed = brisance::scene::parse_scene_text(text.str());
  if (!parsed.scene) {
    std::fprintf(stderr, "scenes/brick_wall.json does not parse\n");
    std::exit(1);
  }
  return *parsed.scene;
}

// `copies` walls side by side along x, 3 m apart (the charge stays where it is: the outer walls
// take less of the wave, as a street of walls would).
Scene walls(int copies) {
  Scene one = load_wall();
  Scene s = one;
  s.objects.clear();
  for (int c = 0; c < copies; ++c) {
    for (brisance::scene::ObjectSpec object : one.objects) {
      object.position.x() += 3.0 * (c - (copies - 1) / 2.0);
      object.name += "#" + std::to_string(c);
      s.objects.push_back(object);
    }
  }
  return s;
}

// One referee for both engines: the deepest interpenetration of every pair of boxes at the
// given poses, by Bullet's collision detection (box–box: an exact separating-axis test).
struct Overlap {
  int over_1mm = 0;
  int over_5mm = 0;
  double worst_m = 0.0;
};

btTransform transform_of(const brisance::engine::Pose& pose) {
  const auto& p = pose.position;
  const auto& q = pose.orientation;  // x, y, z, w
  return btTransform(btQuaternion(f(q[0]), f(q[1]), f(q[2]), f(q[3])), vec(p[0], p[1], p[2]));
}

Overlap judge(const Scene& scene, const std::vector<brisance::engine::Pose>& poses) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &config);
  std::vector<std::unique_ptr<btBoxShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& size = scene.objects[i].box_size_m;
    shapes.push_back(
        std::make_unique<btBoxShape>(vec(0.5 * size.x(), 0.5 * size.y(), 0.5 * size.z())));
    objects.push_back(std::make_unique<btCollisionObject>());
    objects.back()->setCollisionShape(shapes.back().get());
    objects.back()->setWorldTransform(transform_of(poses[i]));
    world.addCollisionObject(objects.back().get());
  }
  world.performDiscreteCollisionDetection();
  Overlap o;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    double deepest = 0.0;
    for (int c = 0; c < manifold->getNumContacts(); ++c)
      deepest = std::max(deepest, -static_cast<double>(manifold->getContactPoint(c).getDistance()));
    o.over_1mm += deepest > 1e-3;
    o.over_5mm += deepest > 5e-3;
    o.worst_m = std::max(o.worst_m, deepest);
  }
  return o;
}

struct Run {
  double seconds = 0.0;
  std::vector<brisance::engine::Pose> final_poses;
};

Run run_brisance(const Scene& scene, int reps) {
  Run best{1e300, {}};
  for (int r = 0; r < reps; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const auto outcome = simulate(scene);
    const double t = seconds_since(start);
    if (t < best.seconds) {
      best.seconds = t;
      best.final_poses.clear();
      for (const FinalState& f : outcome.result.final_state)
        best.final_poses.push_back(f.pose);
    }
  }
  return best;
}

Run run_bullet(const Scene& scene, const std::vector<FinalState>& start, double from_s,
               double rate_hz, int reps) {
  Run best{1e300, {}};
  for (int r = 0; r < reps; ++r) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    const auto& g = scene.environment.gravity_m_s2;
    world.setGravity(vec(g.x(), g.y(), g.z()));
    const double ground_y = scene.environment.ground ? scene.environment.ground->height_m : -1e3;
    btStaticPlaneShape plane(btVector3(0, 1, 0), f(ground_y));
    btRigidBody ground(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, &plane));
    ground.setFriction(f(scene.environment.ground ? scene.environment.ground->friction : 0.5));
    ground.setRestitution(
        f(scene.environment.ground ? scene.environment.ground->restitution : 0.2));
    world.addRigidBody(&ground);
    std::vector<std::unique_ptr<btBoxShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> states;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    for (std::size_t i = 0; i < start.size(); ++i) {
      const brisance::scene::ObjectSpec& object = scene.objects[i];
      const auto& size = object.box_size_m;
      shapes.push_back(
          std::make_unique<btBoxShape>(vec(0.5 * size.x(), 0.5 * size.y(), 0.5 * size.z())));
      btVector3 inertia;
      shapes.back()->calculateLocalInertia(f(object.mass_kg), inertia);
      states.push_back(std::make_unique<btDefaultMotionState>(transform_of(start[i].pose)));
      bodies.push_back(std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(
          f(object.mass_kg), states.back().get(), shapes.back().get(), inertia)));
      btRigidBody& body = *bodies.back();
      const auto& v = start[i].linear_velocity_m_s;
      const auto& w = start[i].angular_velocity_rad_s;
      body.setLinearVelocity(vec(v[0], v[1], v[2]));
      body.setAngularVelocity(vec(w[0], w[1], w[2]));
      body.setFriction(f(object.friction));
      body.setRestitution(f(0.2));
      world.addRigidBody(&body);
    }
    const double dt = 1.0 / rate_hz;
    const int steps = static_cast<int>(std::ceil((scene.simulation.duration_s - from_s) * rate_hz));
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s)
      world.stepSimulation(f(dt), 1, f(dt));
    const double t = seconds_since(t0);
    if (t < best.seconds) {
      best.seconds = t;
      best.final_poses.clear();
      for (const auto& body : bodies) {
        const btTransform x = body->getWorldTransform();
        const btQuaternion q = x.getRotation();
        brisance::engine::Pose p;
        p.position = {x.getOrigin().x(), x.getOrigin().y(), x.getOrigin().z()};
        p.orientation = {q.x(), q.y(), q.z(), q.w()};
        best.final_poses.push_back(p);
      }
    }
    for (const auto& body : bodies)
      world.removeRigidBody(body.get());
    world.removeRigidBody(&ground);
  }
  return best;
}

void compare(const char* label, const Scene& scene, const Options& options) {
  // The debris both engines start from.
  Scene blast = scene;
  blast.simulation.duration_s = options.blast_end_s;
  blast.simulation.collisions = brisance::scene::CollisionMode::automatic;
  const std::vector<FinalState> start = simulate(blast).result.final_state;

  Scene on = scene;
  on.simulation.collisions = brisance::scene::CollisionMode::automatic;
  Scene off = scene;
  off.simulation.collisions = brisance::scene::CollisionMode::off;
  const Run brisance_on = run_brisance(on, options.reps);
  const Run brisance_off = run_brisance(off, options.reps);
  const Run bullet_60 = run_bullet(scene, start, options.blast_end_s, 60.0, options.reps);
  const Run bullet_240 = run_bullet(scene, start, options.blast_end_s, 240.0, options.reps);

  const auto row = [&](const char* engine, const Run& run) {
    const Overlap o = judge(scene, run.final_poses);
    std::printf("%-22s %-28s %10.2f %14.2f %9d %9d %9.1f\n", label, engine, 1e3 * run.seconds,
                bullet_60.seconds / run.seconds, o.over_1mm, o.over_5mm, 1e3 * o.worst_m);
  };
  row("brisance auto", brisance_on);
  row("brisance off", brisance_off);
  row("bullet 60 Hz", bullet_60);
  row("bullet 240 Hz", bullet_240);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--reps" && i + 1 < argc) {
      options.reps = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--blast-end" && i + 1 < argc) {
      options.blast_end_s = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: wall_peer_bench [--reps N] [--blast-end SECONDS]\n");
      return 2;
    }
  }
  std::printf(
      "# wall_peer_bench: scenes/brick_wall.json, 2 s; Bullet %d from Brisance's debris at "
      "t = %.3f s; best of %d\n",
      btGetVersion(), options.blast_end_s, options.reps);
  std::printf("%-22s %-28s %10s %14s %9s %9s %9s\n", "scene", "engine", "time_ms", "bullet60/this",
              "pairs>1mm", "pairs>5mm", "worst_mm");
  compare("wall (33 bricks)", walls(1), options);
  compare("16 walls (528 bricks)", walls(16), options);
  return 0;
}
