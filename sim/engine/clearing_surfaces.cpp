// sim/engine/clearing_surfaces: the prepare stage that gives each panel the clearing distance
// of the contiguous coplanar surface it lies in (thesis eq. 2.31), so the bricks of a wall clear
// from the wall's edges, not each from its own.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>

#include "sim/engine/model.hpp"
#include "sim/geometry/disjoint_sets.hpp"

namespace brisance::engine {

// Clearing (thesis eq. 2.31) relieves a front face from the free edges of the surface it lies
// in. Bricks in a wall share one front surface, so a brick's own 15 cm face is not what clears:
// the wall's is. Panels in the same plane (normals within 1e-6, offsets within 1 mm) on bodies
// that touch (bounding boxes within 5 mm) form one surface; each panel's clearing distance S
// becomes half the smaller in-plane extent of its surface (never less than its own face's).
void share_clearing_across_surfaces(const std::vector<BodySource>& sources, Model& model,
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

}  // namespace brisance::engine
