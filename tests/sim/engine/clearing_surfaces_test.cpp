// The clearing-surface search (sim/engine/clearing_surfaces.cpp) groups panels by normal and
// offset runs instead of comparing every pair in a window of offsets (issue 15: that was
// quadratic in the coplanar panels of one body). Its surfaces must be exactly those of the pair
// search, which is kept here as the reference: the same clearing distance, bit for bit, for every
// panel of scenes made to sit on the edges (offsets 1 mm apart give or take a rounding, normals
// turned by less and by more than the 1e-12 dot-product tolerance, a sphere's many tangent
// planes at one offset, a face cut into thousands of panels, a wall of touching bricks).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/engine/interrupt.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/panes.hpp"
#include "sim/geometry/disjoint_sets.hpp"
#include "sim/geometry/mesh.hpp"
#include "tests/sim/engine/scene_builder.hpp"

namespace brisance::engine {
namespace {

// The search as it was before (git 6514434), every pair of panels within kPlaneGap_m of offset.
void reference_share_clearing(const std::vector<BodySource>& sources, Model& model,
                              Checkpoint& checkpoint) {
  constexpr double kPlaneGap_m = 1e-3;
  constexpr double kTouchGap_m = 5e-3;
  const std::size_t n = model.panels.size();
  std::vector<Box> boxes;
  for (const BodySource& source : sources)
    boxes.push_back(world_box(source));
  struct WorldPanel {
    Vec3 centre;
    Vec3 normal;
    double offset;
  };
  std::vector<WorldPanel> world(n);
  for (std::size_t p = 0; p < n; ++p) {
    const PanelModel& panel = model.panels[p];
    const BodySource& object = sources[panel.body];
    const Quat q = object.orientation.normalized();
    const Vec3 com = object.position + q * model.centre_of_mass[panel.body];
    world[p].centre = com + q * panel.centre;
    world[p].normal = q * panel.normal;
    world[p].offset = world[p].normal.dot(world[p].centre);
  }
  // Panels grouped into surfaces: same plane and touching bodies. (Which panel represents a
  // surface does not matter: every quantity below is per surface.)
  geometry::DisjointSets surface_of(n);
  auto touching = [&](std::uint32_t a, std::uint32_t b) {
    const Box& x = boxes[a];
    const Box& y = boxes[b];
    return (x.min.array() <= y.max.array() + kTouchGap_m).all() &&
           (y.min.array() <= x.max.array() + kTouchGap_m).all();
  };
  // Pairs of panels in one plane, on one body or on two touching bodies. Each body's panels
  // (contiguous in model.panels) sorted by plane offset keep the search to panels that can share
  // a plane, and touching pairs of bodies come from a sweep along x, so a scene of many separate
  // bodies costs n log n rather than (panels in one plane)^2.
  const std::size_t bodies = boxes.size();
  std::vector<std::size_t> sorted(n);
  std::vector<std::size_t> first(bodies + 1, 0);  // body b: sorted[first[b] .. first[b + 1])
  for (std::size_t p = 0; p < n; ++p)
    ++first[model.panels[p].body + 1];
  for (std::size_t b = 0; b < bodies; ++b)
    first[b + 1] += first[b];
  for (std::size_t p = 0; p < n; ++p)
    sorted[p] = p;  // panels are stored body by body
  auto by_offset = [&](std::size_t a, std::size_t b) { return world[a].offset < world[b].offset; };
  for (std::size_t b = 0; b < bodies; ++b)
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(first[b]),
              sorted.begin() + static_cast<std::ptrdiff_t>(first[b + 1]), by_offset);
  // Polled every few thousand pairs: panels of one body at one offset (every tangent plane of
  // a sphere lies at its radius) make the search quadratic in them.
  auto join_if_coplanar = [&](std::size_t a, std::size_t b) {
    checkpoint.tick();
    if (world[a].normal.dot(world[b].normal) >= 1.0 - 1e-12) surface_of.unite(a, b);
  };
  for (std::size_t b = 0; b < bodies; ++b)
    for (std::size_t i = first[b]; i < first[b + 1]; ++i)
      for (std::size_t j = i + 1;
           j < first[b + 1] && world[sorted[j]].offset - world[sorted[i]].offset <= kPlaneGap_m;
           ++j)
        join_if_coplanar(sorted[i], sorted[j]);
  auto join_bodies = [&](std::size_t body_a, std::size_t body_b) {
    const auto begin = sorted.begin() + static_cast<std::ptrdiff_t>(first[body_b]);
    const auto end = sorted.begin() + static_cast<std::ptrdiff_t>(first[body_b + 1]);
    for (std::size_t i = first[body_a]; i < first[body_a + 1]; ++i) {
      const std::size_t a = sorted[i];
      auto j = std::lower_bound(begin, end, world[a].offset - kPlaneGap_m,
                                [&](std::size_t q, double x) { return world[q].offset < x; });
      for (; j != end && world[*j].offset - world[a].offset <= kPlaneGap_m; ++j)
        join_if_coplanar(a, *j);
    }
  };
  std::vector<std::size_t> by_min_x(bodies);
  for (std::size_t b = 0; b < bodies; ++b)
    by_min_x[b] = b;
  std::sort(by_min_x.begin(), by_min_x.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].min.x() < boxes[b].min.x(); });
  for (std::size_t i = 0; i < bodies; ++i) {
    checkpoint.tick(64);
    const std::size_t a = by_min_x[i];
    if (first[a] == first[a + 1]) continue;  // no panels (anchored)
    for (std::size_t j = i + 1;
         j < bodies && boxes[by_min_x[j]].min.x() <= boxes[a].max.x() + kTouchGap_m; ++j) {
      const std::size_t b = by_min_x[j];
      if (first[b] != first[b + 1] &&
          touching(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)))
        join_bodies(a, b);
    }
  }
  // In-plane extents of each surface, from the vertices of its bodies that lie in its plane:
  // along the plane's horizontal axis and the one across it (for a vertical wall: its width and
  // its height).
  struct Surface {
    Vec3 normal;
    double offset;
    std::vector<std::uint32_t> bodies;
  };
  std::map<std::size_t, Surface> surfaces;
  for (std::size_t p = 0; p < n; ++p) {
    checkpoint.tick();
    Surface& surface = surfaces[surface_of.find(p)];
    surface.normal = world[p].normal;
    surface.offset = world[p].offset;
    if (std::find(surface.bodies.begin(), surface.bodies.end(), model.panels[p].body) ==
        surface.bodies.end())
      surface.bodies.push_back(model.panels[p].body);
  }
  std::map<std::size_t, double> half_size;
  for (const auto& [root, surface] : surfaces) {
    checkpoint.tick(64);
    Vec3 u = Vec3::UnitY().cross(surface.normal);
    if (u.norm() < 1e-6) u = Vec3::UnitX().cross(surface.normal);
    u.normalize();
    const Vec3 v = surface.normal.cross(u);
    double min_u = INFINITY, max_u = -INFINITY, min_v = INFINITY, max_v = -INFINITY;
    for (std::uint32_t body : surface.bodies) {
      const BodySource& object = sources[body];
      for (const Vec3& vertex : object.mesh.vertices) {
        const Vec3 x = object.position + object.orientation * vertex;
        if (std::abs(surface.normal.dot(x) - surface.offset) > kPlaneGap_m) continue;
        min_u = std::min(min_u, u.dot(x)), max_u = std::max(max_u, u.dot(x));
        min_v = std::min(min_v, v.dot(x)), max_v = std::max(max_v, v.dot(x));
      }
    }
    half_size[root] = max_u > min_u ? 0.5 * std::min(max_u - min_u, max_v - min_v) : 0.0;
  }
  for (std::size_t p = 0; p < n; ++p)
    model.panels[p].clearing_distance_m =
        std::max(model.panels[p].clearing_distance_m, half_size[surface_of.find(p)]);
}

// The Model's panels as prepare makes them (centre relative to the centre of mass, outward
// normal, the face's own clearing distance).
Model model_of(const std::vector<BodySource>& sources) {
  Model model;
  for (std::uint32_t b = 0; b < sources.size(); ++b) {
    const Vec3 com = sources[b].unit_mass.centre_of_mass;
    model.centre_of_mass.push_back(com);
    if (sources[b].anchored) continue;
    for (const geometry::Panel& panel : sources[b].load_panels)
      model.panels.push_back({b, panel.centre - com, panel.outward_normal, panel.area_m2,
                              panel.face_half_size_m, std::sqrt(panel.area_m2), false});
  }
  return model;
}

void expect_same_surfaces(const std::vector<BodySource>& sources) {
  const Model model = model_of(sources);
  Model searched = model;
  Model reference = model;
  Checkpoint never;
  share_clearing_across_surfaces(sources, searched, never);
  reference_share_clearing(sources, reference, never);
  ASSERT_EQ(searched.panels.size(), reference.panels.size());
  std::size_t widened = 0;
  for (std::size_t p = 0; p < model.panels.size(); ++p) {
    EXPECT_EQ(searched.panels[p].clearing_distance_m, reference.panels[p].clearing_distance_m)
        << "panel " << p << " of body " << model.panels[p].body;
    if (reference.panels[p].clearing_distance_m != model.panels[p].clearing_distance_m) ++widened;
  }
  // The scenes are made so that surfaces do widen clearing distances.
  EXPECT_GT(widened, 0u);
}

BodySource box_source(const std::string& name, const Vec3& size, const Vec3& position,
                      const Quat& orientation = Quat::Identity(), double max_panel_area_m2 = 1e9) {
  scene::ObjectSpec spec = testing::box_object(name, size, position, 1.0);
  spec.orientation = orientation;
  return object_source(spec, max_panel_area_m2);
}

TEST(ClearingSurfaces, SameSurfacesAsThePairSearchOnTheEdges) {
  std::vector<BodySource> sources;
  // A slab whose faces are cut into some 2 000 panels, and slabs touching it whose front faces
  // lie 0.9, 1, 1.1 mm and 1 mm +- a rounding behind or ahead of its own.
  sources.push_back(box_source("slab", Vec3(2.0, 2.0, 0.1), Vec3::Zero(), Quat::Identity(), 0.004));
  const double shifts[] = {
      0.9e-3, 1e-3, 1.1e-3, -1e-3, std::nextafter(1e-3, 1.0), std::nextafter(-1e-3, -1.0)};
  for (int i = 0; i < 6; ++i)
    sources.push_back(box_source("shifted" + std::to_string(i), Vec3(0.5, 0.5, 0.1),
                                 Vec3(1.25 + 0.5 * (i % 2), 0.75 - 0.5 * (i / 2), shifts[i]),
                                 Quat::Identity(), 0.01));
  // Turned by 1e-7 rad (coplanar within the tolerance) and by 1e-5 rad (not).
  sources.push_back(box_source("turned_a_little", Vec3(0.5, 0.5, 0.1), Vec3(-1.25, 0.75, 0.0),
                               Quat(Eigen::AngleAxisd(1e-7, Vec3::UnitX())), 0.01));
  sources.push_back(box_source("turned_more", Vec3(0.5, 0.5, 0.1), Vec3(-1.25, -0.75, 0.0),
                               Quat(Eigen::AngleAxisd(1e-5, Vec3::UnitY())), 0.01));
  // A stepped body (two blocks in one mesh, fronts 1.5 mm apart: two runs of one normal) and a
  // block touching it (first in the sweep along x) whose front lies between them, within 1 mm of
  // both: it joins both steps.
  scene::ObjectSpec stepped;
  stepped.name = "stepped";
  stepped.shape = scene::ShapeType::mesh;
  for (int step = 0; step < 2; ++step) {
    const geometry::TriangleMesh block = geometry::make_box(Vec3(0.3, 0.3, 0.1));
    const auto base = static_cast<std::uint32_t>(stepped.mesh.vertices.size());
    for (const Vec3& v : block.vertices)
      stepped.mesh.vertices.push_back(v + Vec3(0.3 * step, 0.0, 1.5e-3 * step));
    for (const auto& t : block.triangles)
      stepped.mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  stepped.mass_kg = 1.0;
  stepped.position = Vec3(0.0, 3.0, 0.0);
  sources.push_back(object_source(stepped, 0.01));
  sources.push_back(
      box_source("between", Vec3(0.3, 0.3, 0.1), Vec3(-0.1, 3.3, 0.75e-3), Quat::Identity(), 0.01));
  expect_same_surfaces(sources);
}

TEST(ClearingSurfaces, SameSurfacesAsThePairSearchForAWallAndRandomBlocks) {
  std::vector<BodySource> sources;
  for (int row = 0; row < 12; ++row)
    for (int column = 0; column < 10; ++column)
      sources.push_back(box_source("brick" + std::to_string(row * 10 + column), Vec3(0.2, 0.1, 0.1),
                                   Vec3(0.2 * column + (row % 2) * 0.1, 0.05 + 0.1 * row, 0.0)));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    // Blocks around and against the wall, some at the plane gap, some turned.
    const Vec3 size(0.1 + 0.3 * unit(rng), 0.1 + 0.3 * unit(rng), 0.1);
    const double z =
        i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 1e-3 * unit(rng) * 2.0 : 0.1 + 0.1 * unit(rng));
    const Quat q =
        i % 4 == 0 ? Quat(Eigen::AngleAxisd(1e-6 * unit(rng), Vec3::UnitZ())) : Quat::Identity();
    sources.push_back(box_source("block" + std::to_string(i), size,
                                 Vec3(-0.5 + 3.0 * unit(rng), 1.4 * unit(rng), z), q,
                                 0.002 + 0.01 * unit(rng)));
  }
  expect_same_surfaces(sources);
}

// An imported mesh whose top is a grid of 1 800 triangles lifted by up to 1 nm at random (their
// normals differ by about 1e-7: one plane within the tolerance, many normal groups of one body)
// and a pyramid beneath, beside a box whose top lies in the same plane.
TEST(ClearingSurfaces, SameSurfacesAsThePairSearchForANearlyFlatMesh) {
  const int k = 30;
  const double cell = 0.02;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> lift(0.0, 1e-9);
  scene::ObjectSpec slab;
  slab.name = "scanned";
  slab.shape = scene::ShapeType::mesh;
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j)
      slab.mesh.vertices.emplace_back(cell * i, cell * j, (i + j) % 3 == 0 ? lift(rng) : 0.0);
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * (k + 1) + j); };
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      slab.mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      slab.mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const auto apex = static_cast<std::uint32_t>(slab.mesh.vertices.size());
  slab.mesh.vertices.emplace_back(0.5 * cell * k, 0.5 * cell * k, -0.2);
  for (int m = 0; m < k; ++m) {
    slab.mesh.triangles.push_back({at(m + 1, 0), at(m, 0), apex});
    slab.mesh.triangles.push_back({at(k, m + 1), at(k, m), apex});
    slab.mesh.triangles.push_back({at(m, k), at(m + 1, k), apex});
    slab.mesh.triangles.push_back({at(0, m), at(0, m + 1), apex});
  }
  slab.mass_kg = 1.0;
  std::vector<BodySource> sources;
  sources.push_back(object_source(slab, 1e9));
  sources.push_back(
      box_source("box", Vec3(0.2, 0.2, 0.1), Vec3(0.7, 0.3, -0.05), Quat::Identity(), 0.001));
  expect_same_surfaces(sources);
}

// A sphere: every facet in a tangent plane of its own at the same offset, thousands of normal
// groups (the grid of normals), beside a box.
TEST(ClearingSurfaces, SameSurfacesAsThePairSearchForASphere) {
  const int around = 64;
  const int rings = 32;
  scene::ObjectSpec ball;
  ball.name = "ball";
  ball.shape = scene::ShapeType::mesh;
  ball.mesh = testing::uv_sphere(rings, around);
  ball.mass_kg = 1.0;
  std::vector<BodySource> sources;
  sources.push_back(object_source(ball, 1e9));
  sources.push_back(
      box_source("box", Vec3(1.0, 1.0, 1.0), Vec3(1.5, 0.0, 0.0), Quat::Identity(), 0.01));
  sources.push_back(
      box_source("box2", Vec3(1.0, 1.0, 1.0), Vec3(2.5, 0.0, 0.0), Quat::Identity(), 0.01));
  expect_same_surfaces(sources);
}

}  // namespace
}  // namespace brisance::engine
