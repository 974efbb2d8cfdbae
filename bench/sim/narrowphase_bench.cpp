// The narrowphase against libccd (Debian libccd-dev, GJK/EPA and MPR) on the same box pairs
// (issue 13): time per pair, and how far libccd's normal and depth are from ours on the pairs
// both find penetrating. Built only when libccd is installed (bench/CMakeLists.txt).
//
// Ours gives a manifold (up to four points, normal, depths); libccd gives one point, a direction
// and a depth, so ours does more per pair. Pairs: a 0.4 m box and a 0.215 x 0.065 x 0.1025 m
// brick at random orientations, their centres 0.2-0.35 m apart (about two thirds overlap), from
// a fixed seed.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <ccd/ccd.h>
#include <ccd/vec3.h>

#include "sim/dynamics/convex.hpp"
#include "sim/geometry/mesh.hpp"

namespace {

using brisance::dynamics::Mat3;
using brisance::dynamics::Vec3;

struct Box {
  Vec3 half;
  Vec3 centre;
  Mat3 rotation;
};

// libccd's support function of a box: the corner farthest along `dir`.
void box_support(const void* object, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const Box& box = *static_cast<const Box*>(object);
  const Vec3 d(ccdVec3X(dir), ccdVec3Y(dir), ccdVec3Z(dir));
  const Vec3 local = box.rotation.transpose() * d;
  const Vec3 corner(std::copysign(box.half.x(), local.x()), std::copysign(box.half.y(), local.y()),
                    std::copysign(box.half.z(), local.z()));
  const Vec3 world = box.centre + box.rotation * corner;
  ccdVec3Set(out, world.x(), world.y(), world.z());
}

void box_centre(const void* object, ccd_vec3_t* out) {
  const Box& box = *static_cast<const Box*>(object);
  ccdVec3Set(out, box.centre.x(), box.centre.y(), box.centre.z());
}

struct Pairs {
  std::vector<Box> a, b;
  brisance::dynamics::CollisionShape shape_a, shape_b;
  std::vector<brisance::dynamics::PlacedPiece> placed_a, placed_b;
};

const Pairs& pairs() {
  static const Pairs p = [] {
    Pairs made;
    const Vec3 size_a = Vec3::Constant(0.4), size_b(0.215, 0.065, 0.1025);
    made.shape_a =
        brisance::dynamics::collision_shape(brisance::geometry::make_box(size_a), Vec3::Zero());
    made.shape_b =
        brisance::dynamics::collision_shape(brisance::geometry::make_box(size_b), Vec3::Zero());
    std::mt19937_64 random(13);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), gap(0.2, 0.35);
    for (int i = 0; i < 1000; ++i) {
      auto orientation = [&] {
        return Eigen::Quaterniond(unit(random), unit(random), unit(random), unit(random))
            .normalized()
            .toRotationMatrix();
      };
      const Vec3 direction = Vec3(unit(random), unit(random), unit(random)).normalized();
      made.a.push_back(Box{0.5 * size_a, Vec3::Zero(), orientation()});
      made.b.push_back(Box{0.5 * size_b, gap(random) * direction, orientation()});
      made.placed_a.emplace_back();
      made.placed_b.emplace_back();
      brisance::dynamics::place(made.shape_a.pieces[0], made.a.back().centre,
                                made.a.back().rotation, made.placed_a.back());
      brisance::dynamics::place(made.shape_b.pieces[0], made.b.back().centre,
                                made.b.back().rotation, made.placed_b.back());
    }
    return made;
  }();
  return p;
}

ccd_t ccd_settings() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = box_support;
  ccd.support2 = box_support;
  ccd.center1 = box_centre;
  ccd.center2 = box_centre;
  ccd.max_iterations = 100;
  ccd.epa_tolerance = 1e-6;
  ccd.mpr_tolerance = 1e-6;
  return ccd;
}

void BM_OurSat(benchmark::State& state) {
  const Pairs& p = pairs();
  brisance::dynamics::Manifold manifold;
  std::size_t touching = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < p.a.size(); ++i)
      touching += brisance::dynamics::collide(p.placed_a[i], p.placed_b[i], 0.0, 0, manifold);
    benchmark::DoNotOptimize(manifold);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(p.a.size()));
  state.counters["touching"] =
      static_cast<double>(touching) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_OurSat);

template <int (*Penetration)(const void*, const void*, const ccd_t*, ccd_real_t*, ccd_vec3_t*,
                             ccd_vec3_t*)>
void BM_Ccd(benchmark::State& state) {
  const Pairs& p = pairs();
  const ccd_t ccd = ccd_settings();
  std::size_t touching = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < p.a.size(); ++i) {
      ccd_real_t depth;
      ccd_vec3_t dir, pos;
      touching += Penetration(&p.a[i], &p.b[i], &ccd, &depth, &dir, &pos) == 0;
      benchmark::DoNotOptimize(depth);
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(p.a.size()));
  state.counters["touching"] =
      static_cast<double>(touching) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Ccd<ccdGJKPenetration>)->Name("BM_CcdGjkEpa");
BENCHMARK(BM_Ccd<ccdMPRPenetration>)->Name("BM_CcdMpr");

// Agreement on the pairs both find penetrating: the largest angle between the normals (rad) and
// the largest depth difference (m), with GJK/EPA (exact to its tolerance for boxes).
void BM_Agreement(benchmark::State& state) {
  const Pairs& p = pairs();
  const ccd_t ccd = ccd_settings();
  brisance::dynamics::Manifold manifold;
  double worst_angle = 0.0, worst_depth = 0.0, median_pool = 0.0;
  std::size_t both = 0;
  for (auto _ : state) {
    worst_angle = worst_depth = median_pool = 0.0;
    both = 0;
    for (std::size_t i = 0; i < p.a.size(); ++i) {
      ccd_real_t depth;
      ccd_vec3_t dir, pos;
      if (ccdGJKPenetration(&p.a[i], &p.b[i], &ccd, &depth, &dir, &pos) != 0) continue;
      if (!brisance::dynamics::collide(p.placed_a[i], p.placed_b[i], 0.0, 0, manifold)) continue;
      double ours = 0.0;
      for (const auto& point : manifold.points)
        ours = std::max(ours, point.depth_m);
      // libccd's direction moves b out of a: the normal from a to b.
      const Vec3 n(ccdVec3X(&dir), ccdVec3Y(&dir), ccdVec3Z(&dir));
      const double angle = std::acos(std::clamp(n.normalized().dot(manifold.normal), -1.0, 1.0));
      worst_angle = std::max(worst_angle, angle);
      worst_depth = std::max(worst_depth, std::abs(ours - depth));
      median_pool += std::abs(ours - depth);
      ++both;
    }
  }
  state.counters["pairs_both"] = static_cast<double>(both);
  state.counters["worst_angle_rad"] = worst_angle;
  state.counters["worst_depth_diff_m"] = worst_depth;
  state.counters["mean_depth_diff_m"] = both ? median_pool / static_cast<double>(both) : 0.0;
}
BENCHMARK(BM_Agreement)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
