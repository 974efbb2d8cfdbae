// The occlusion pass of thesis chapter 4 (sim/occlusion) for 1 000 and 10 000 objects. Goals
// (issue 12): under 20 ms for 1 000 objects and under 300 ms for 10 000, on one core, at the
// thesis's 32 x 28 pixels a face.
//
//   occlusion_bench [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
//
// The scene is a yard of 0.5 m crates scattered 5-60 m around a ground-level charge, with a
// concrete wall every 50 crates, so many crates stand in the shadow of others; every crate face is
// a load panel whose attenuation is read (per-panel mode), as the engine would ask.
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "sim/engine/interrupt.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/panes.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/occlusion/shielding.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace {

using brisance::occlusion::Vec3;
namespace occlusion = brisance::occlusion;
namespace geometry = brisance::geometry;

struct Yard {
  std::vector<geometry::TriangleMesh> meshes;
  std::vector<occlusion::Object> objects;
  std::vector<occlusion::Panel> panels;
};

Yard make_yard(int count) {
  Yard yard;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < count; ++i) {
    const bool wall = i % 50 == 49;
    const Vec3 size = wall ? Vec3(3.0, 2.5, 0.3) : Vec3(0.5, 0.5, 0.5);
    const double radius = 5.0 + 55.0 * std::sqrt(unit(rng));
    const double azimuth = 2.0 * 3.141592653589793 * unit(rng);
    const Vec3 centre(radius * std::cos(azimuth), size.y() / 2, radius * std::sin(azimuth));
    geometry::TriangleMesh mesh = geometry::make_box(size);
    for (Vec3& v : mesh.vertices)
      v += centre;
    for (int a = 0; a < 3; ++a) {
      for (double s : {-0.5, 0.5}) {
        Vec3 face_centre = centre;
        face_centre[a] += s * size[a];
        yard.panels.push_back({static_cast<std::uint32_t>(i), face_centre, 0.25});
      }
    }
    yard.meshes.push_back(std::move(mesh));
  }
  for (const auto& mesh : yard.meshes)
    yard.objects.push_back({mesh.vertices, mesh.triangles, true, true});
  return yard;
}

void BM_Shielding(benchmark::State& state) {
  const Yard yard = make_yard(static_cast<int>(state.range(0)));
  occlusion::Settings settings;
  settings.face_columns = static_cast<int>(state.range(1));
  settings.face_rows = settings.face_columns * 7 / 8;
  const occlusion::SphereMap map(settings.face_columns, settings.face_rows);
  const Vec3 charge(0.0, 0.5, 0.0);
  std::uint32_t occluded = 0;
  for (auto _ : state) {
    const occlusion::Shielding s =
        occlusion::compute_shielding(map, charge, yard.objects, yard.panels, settings);
    occluded = s.objects_occluded;
    benchmark::DoNotOptimize(s.panel_attenuation.data());
  }
  state.counters["objects_occluded"] = occluded;
  state.counters["pixels"] = map.pixel_count();
}
BENCHMARK(BM_Shielding)
    ->ArgNames({"objects", "face_columns"})
    ->Args({1000, 32})
    ->Args({10000, 32})
    ->Args({1000, 64})
    ->Args({10000, 64})
    ->Args({1000, 128})
    ->Unit(benchmark::kMillisecond);

void BM_FootprintCheck(benchmark::State& state) {
  const Yard yard = make_yard(static_cast<int>(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(occlusion::footprints_may_overlap(Vec3(0, 0.5, 0), yard.objects));
}
BENCHMARK(BM_FootprintCheck)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_SphereMap(benchmark::State& state) {
  for (auto _ : state) {
    const occlusion::SphereMap map(static_cast<int>(state.range(0)),
                                   static_cast<int>(state.range(0)) * 7 / 8);
    benchmark::DoNotOptimize(map.pixel_count());
  }
}
BENCHMARK(BM_SphereMap)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

}  // namespace

// The part of a prepared model the clearing-surface search reads: each body's centre of mass
// and its load panels.
brisance::engine::Model panels_of(const std::vector<brisance::engine::BodySource>& sources) {
  brisance::engine::Model model;
  for (std::uint32_t b = 0; b < sources.size(); ++b) {
    const Vec3 com = sources[b].unit_mass.centre_of_mass;
    model.centre_of_mass.push_back(com);
    for (const geometry::Panel& panel : sources[b].load_panels)
      model.panels.push_back({b, panel.centre - com, panel.outward_normal, panel.area_m2,
                              panel.face_half_size_m, std::sqrt(panel.area_m2), false});
  }
  return model;
}

// Times the clearing-surface search over `sources` (a fresh copy of their panels each time).
void time_clearing(benchmark::State& state,
                   const std::vector<brisance::engine::BodySource>& sources) {
  const brisance::engine::Model model = panels_of(sources);
  brisance::engine::Checkpoint never;
  for (auto _ : state) {
    brisance::engine::Model run = model;
    brisance::engine::share_clearing_across_surfaces(sources, run, never);
    benchmark::DoNotOptimize(run.panels.data());
  }
  state.counters["panels"] = static_cast<double>(model.panels.size());
}

// Another prepare stage that looks across panels: the clearing-surface search
// (sim/engine/clearing_surfaces.cpp) over one 10 x 10 x 0.1 m slab whose faces are cut into
// panels of 100 / N m^2, so each large face holds about N coplanar panels (issue 15: the search
// was quadratic in the coplanar panels of one body; a 397k-triangle mesh took minutes).
void BM_ClearingSurfaces(benchmark::State& state) {
  namespace engine = brisance::engine;
  brisance::scene::ObjectSpec slab;
  slab.name = "slab";
  slab.shape = brisance::scene::ShapeType::box;
  slab.box_size_m = Vec3(10.0, 10.0, 0.1);
  slab.mesh = geometry::make_box(slab.box_size_m);
  slab.mass_kg = 1000.0;
  const std::vector<engine::BodySource> sources = {
      engine::object_source(slab, 100.0 / static_cast<double>(state.range(0)))};
  time_clearing(state, sources);
}
BENCHMARK(BM_ClearingSurfaces)
    ->Arg(1000)
    ->Arg(4000)
    ->Arg(16000)
    ->Arg(64000)
    ->Unit(benchmark::kMillisecond);

// The same search over a UV sphere of 2 x `around` x (`around` / 2 - 1) facets: every facet a
// plane of its own at the same offset (the 397k-triangle mesh of issue 15 was such a sphere).
void BM_ClearingSurfacesSphere(benchmark::State& state) {
  namespace engine = brisance::engine;
  const int around = static_cast<int>(state.range(0));
  const int rings = around / 2;
  brisance::scene::ObjectSpec ball;
  ball.name = "ball";
  ball.shape = brisance::scene::ShapeType::mesh;
  ball.mesh = brisance::testing::uv_sphere(rings, around);
  ball.mass_kg = 1.0;
  const std::vector<engine::BodySource> sources = {engine::object_source(ball, 1e9)};
  time_clearing(state, sources);
}
BENCHMARK(BM_ClearingSurfacesSphere)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Arg(256)
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
