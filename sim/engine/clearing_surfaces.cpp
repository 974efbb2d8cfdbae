// sim/engine/clearing_surfaces: the prepare stage that gives each panel the clearing distance
// of the contiguous coplanar surface it lies in (thesis eq. 2.31), so the bricks of a wall clear
// from the wall's edges, not each from its own.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <tuple>

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
  // Pairs of panels in one plane, on one body or on two touching bodies: normals within 1e-12
  // (dot product) and offsets within kPlaneGap_m, joined transitively. Searched group by group
  // rather than pair by pair, so the cost stays near-linear in panels that share a plane (a face
  // cut into many panels) or an offset (every tangent plane of a sphere): each body's panels are
  // sorted by normal, then offset; panels of one exact normal form a group, and within a group
  // a run of offsets each within kPlaneGap_m of the next is one surface already. A panel then
  // needs joining only to the first panel of each run in its window of another group, and at
  // most a few runs fit in one window. Touching pairs of bodies come from a sweep along x. The
  // joins are exactly the pairs the all-pairs search joined (the same comparisons at the window's
  // edges), so the surfaces are the same. (All pairs within a sliding window of offsets, the
  // search before, was quadratic in the panels of one plane: 2.7 s for 33k of them.)
  const std::size_t bodies = boxes.size();
  std::vector<std::size_t> sorted(n);
  std::vector<std::size_t> first(bodies + 1, 0);  // body b: sorted[first[b] .. first[b + 1])
  for (std::size_t p = 0; p < n; ++p)
    ++first[model.panels[p].body + 1];
  for (std::size_t b = 0; b < bodies; ++b)
    first[b + 1] += first[b];
  for (std::size_t p = 0; p < n; ++p)
    sorted[p] = p;  // panels are stored body by body
  // Equal normals compare equal here exactly when their dot products with any normal are equal
  // (a signed zero changes neither), so a group's members are interchangeable in every test.
  const auto same_normal = [&](std::size_t a, std::size_t b) {
    return world[a].normal.x() == world[b].normal.x() &&
           world[a].normal.y() == world[b].normal.y() && world[a].normal.z() == world[b].normal.z();
  };
  const auto by_normal_then_offset = [&](std::size_t a, std::size_t b) {
    const Vec3& x = world[a].normal;
    const Vec3& y = world[b].normal;
    if (x.x() != y.x()) return x.x() < y.x();
    if (x.y() != y.y()) return x.y() < y.y();
    if (x.z() != y.z()) return x.z() < y.z();
    return world[a].offset < world[b].offset;
  };
  const auto coplanar_normals = [&](std::size_t a, std::size_t b) {
    return world[a].normal.dot(world[b].normal) >= 1.0 - 1e-12;
  };
  // Panels with a non-finite normal or offset join nothing (as before: every comparison with
  // NaN fails); they are left out of the groups so the sort stays well defined.
  const auto finite = [&](std::size_t p) {
    return world[p].normal.allFinite() && std::isfinite(world[p].offset);
  };
  struct Group {
    std::size_t begin;  // sorted[begin .. end): one exact normal, ascending offset
    std::size_t end;
  };
  std::vector<Group> groups;
  std::vector<std::size_t> first_group(bodies + 1, 0);  // body b: groups[first_group[b] ..)
  // run_end[i]: one past the last position of the run (in `sorted`) that position i is in.
  std::vector<std::size_t> run_end(n);
  for (std::size_t b = 0; b < bodies; ++b) {
    checkpoint.tick(64);
    const auto begin = sorted.begin() + static_cast<std::ptrdiff_t>(first[b]);
    const auto end =
        std::partition(begin, sorted.begin() + static_cast<std::ptrdiff_t>(first[b + 1]), finite);
    std::sort(begin, end, by_normal_then_offset);
    first_group[b] = groups.size();
    const std::size_t stop = static_cast<std::size_t>(end - sorted.begin());
    for (std::size_t i = first[b]; i < stop;) {
      std::size_t j = i + 1;
      while (j < stop && same_normal(sorted[i], sorted[j]))
        ++j;
      groups.push_back({i, j});
      i = j;
    }
    // Positions past `stop` (non-finite panels) are runs of their own.
    for (std::size_t i = stop; i < first[b + 1]; ++i)
      run_end[i] = i + 1;
  }
  first_group[bodies] = groups.size();
  // Within a group: offsets within kPlaneGap_m of the next are one run, and one surface (the
  // pairs the search joined: on one body, offsets o_j >= o_i with o_j - o_i <= kPlaneGap_m).
  for (const Group& g : groups) {
    checkpoint.tick(64);
    const bool joins_itself = coplanar_normals(sorted[g.begin], sorted[g.begin]);
    std::size_t run_start = g.begin;
    for (std::size_t i = g.begin; i < g.end; ++i) {
      const bool last_of_run =
          i + 1 == g.end || !joins_itself ||
          !(world[sorted[i + 1]].offset - world[sorted[i]].offset <= kPlaneGap_m);
      if (!last_of_run) {
        surface_of.unite(sorted[i], sorted[i + 1]);
        continue;
      }
      for (std::size_t k = run_start; k <= i; ++k)
        run_end[k] = i + 1;
      run_start = i + 1;
    }
  }
  // Joins each panel of group `from` to every run of group `to` with a panel in its window:
  // `below(a, b)`: b lies below a's window; `within_above(a, b)`: b, at or above that, is not
  // past its top. Both are monotone in b's offset, so the window is a range of `to`.
  const auto join_groups = [&](const Group& from, const Group& to, auto below, auto within_above) {
    for (std::size_t i = from.begin; i < from.end; ++i) {
      checkpoint.tick();
      const std::size_t a = sorted[i];
      std::size_t k = static_cast<std::size_t>(
          std::partition_point(sorted.begin() + static_cast<std::ptrdiff_t>(to.begin),
                               sorted.begin() + static_cast<std::ptrdiff_t>(to.end),
                               [&](std::size_t b) { return below(a, b); }) -
          sorted.begin());
      for (; k < to.end && within_above(a, sorted[k]); k = run_end[k])
        surface_of.unite(a, sorted[k]);
    }
  };
  // On one body: offsets o_lo <= o_hi with o_hi - o_lo <= kPlaneGap_m, whichever comes first.
  const auto below_on_body = [&](std::size_t a, std::size_t b) {
    return world[b].offset < world[a].offset && !(world[a].offset - world[b].offset <= kPlaneGap_m);
  };
  const auto within_on_body = [&](std::size_t a, std::size_t b) {
    return world[b].offset <= world[a].offset || world[b].offset - world[a].offset <= kPlaneGap_m;
  };
  // Across two bodies, a on the first of the sweep: o_b >= o_a - kPlaneGap_m and
  // o_b - o_a <= kPlaneGap_m.
  const auto below_across = [&](std::size_t a, std::size_t b) {
    return world[b].offset < world[a].offset - kPlaneGap_m;
  };
  const auto within_across = [&](std::size_t a, std::size_t b) {
    return world[b].offset - world[a].offset <= kPlaneGap_m;
  };
  // The pairs of groups (one from each list) whose normals are coplanar. Few groups (a box has
  // six) are compared all with all; many (a sphere's facets) through a grid of normals with
  // cells wider than any coplanar pair's difference (unit normals with a dot product of at least
  // 1 - 1e-12 differ by at most 1.5e-6 in each component), so each looks only at its own cell
  // and the 26 around it.
  constexpr double kNormalCell = 2e-6;
  struct CellKey {
    std::array<std::int64_t, 3> cell;
    std::size_t group;
    bool operator<(const CellKey& other) const {
      return std::tie(cell, group) < std::tie(other.cell, other.group);
    }
  };
  const auto cell_of = [&](const Group& g) {
    const Vec3& normal = world[sorted[g.begin]].normal;
    return std::array<std::int64_t, 3>{
        static_cast<std::int64_t>(std::floor(normal.x() / kNormalCell)),
        static_cast<std::int64_t>(std::floor(normal.y() / kNormalCell)),
        static_cast<std::int64_t>(std::floor(normal.z() / kNormalCell))};
  };
  std::vector<CellKey> cells;
  const auto for_coplanar_groups = [&](std::size_t from_begin, std::size_t from_end,
                                       std::size_t to_begin, std::size_t to_end, auto visit) {
    if ((from_end - from_begin) * (to_end - to_begin) <= 256) {
      for (std::size_t g = from_begin; g < from_end; ++g)
        for (std::size_t h = to_begin; h < to_end; ++h)
          if (coplanar_normals(sorted[groups[g].begin], sorted[groups[h].begin])) visit(g, h);
      return;
    }
    cells.clear();
    for (std::size_t h = to_begin; h < to_end; ++h)
      cells.push_back({cell_of(groups[h]), h});
    std::sort(cells.begin(), cells.end());
    for (std::size_t g = from_begin; g < from_end; ++g) {
      checkpoint.tick(256);
      const std::array<std::int64_t, 3> centre = cell_of(groups[g]);
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const std::array<std::int64_t, 3> cell = {centre[0] + dx, centre[1] + dy,
                                                      centre[2] + dz};
            auto it = std::lower_bound(cells.begin(), cells.end(), CellKey{cell, 0});
            for (; it != cells.end() && it->cell == cell; ++it)
              if (coplanar_normals(sorted[groups[g].begin], sorted[groups[it->group].begin]))
                visit(g, it->group);
          }
    }
  };
  // One body's groups of different normals that are still coplanar (normals within 1e-12).
  for (std::size_t b = 0; b < bodies; ++b)
    for_coplanar_groups(first_group[b], first_group[b + 1], first_group[b], first_group[b + 1],
                        [&](std::size_t g, std::size_t h) {
                          if (g < h)
                            join_groups(groups[g], groups[h], below_on_body, within_on_body);
                        });
  auto join_bodies = [&](std::size_t body_a, std::size_t body_b) {
    for_coplanar_groups(first_group[body_a], first_group[body_a + 1], first_group[body_b],
                        first_group[body_b + 1], [&](std::size_t g, std::size_t h) {
                          join_groups(groups[g], groups[h], below_across, within_across);
                        });
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
    // Panels come body by body, so a body already listed is the last one.
    if (surface.bodies.empty() || surface.bodies.back() != model.panels[p].body)
      surface.bodies.push_back(model.panels[p].body);
  }
  // A body in many surfaces (a sphere's facets are each a surface of their own) has its world
  // vertices in a tree of bounding boxes, so each surface visits only the boxes its plane's slab
  // reaches instead of every vertex (which was surfaces x vertices). A box is passed over only
  // when it lies outside the slab by more than any rounding (1e-9 relative); every vertex
  // visited gets the same test as before, so the extents are the same.
  constexpr std::size_t kTreeAfterSurfaces = 8;
  constexpr std::uint32_t kLeafVertices = 16;
  struct VertexTree {
    struct Node {
      Vec3 min, max;
      std::uint32_t begin, end;  // points[begin .. end)
      std::uint32_t left = 0;    // children left and left + 1; 0: a leaf
    };
    std::vector<Vec3> points;  // world frame, m
    std::vector<Node> nodes;
  };
  std::vector<std::size_t> surfaces_of_body(bodies, 0);
  for (const auto& [root, surface] : surfaces)
    for (std::uint32_t body : surface.bodies)
      ++surfaces_of_body[body];
  std::map<std::uint32_t, VertexTree> trees;
  for (std::uint32_t body = 0; body < bodies; ++body) {
    if (surfaces_of_body[body] <= kTreeAfterSurfaces) continue;
    checkpoint.poll();
    const BodySource& object = sources[body];
    VertexTree& tree = trees[body];
    for (const Vec3& vertex : object.mesh.vertices)
      tree.points.push_back(object.position + object.orientation * vertex);
    tree.nodes.push_back(
        {Vec3::Zero(), Vec3::Zero(), 0, static_cast<std::uint32_t>(tree.points.size()), 0});
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
      checkpoint.tick(64);
      const std::uint32_t begin = tree.nodes[k].begin, end = tree.nodes[k].end;
      Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
      for (std::uint32_t i = begin; i < end; ++i)
        lo = lo.cwiseMin(tree.points[i]), hi = hi.cwiseMax(tree.points[i]);
      tree.nodes[k].min = lo;
      tree.nodes[k].max = hi;
      if (end - begin <= kLeafVertices) continue;
      int axis = 0;
      (hi - lo).maxCoeff(&axis);
      const std::uint32_t middle = begin + (end - begin) / 2;
      std::nth_element(tree.points.begin() + begin, tree.points.begin() + middle,
                       tree.points.begin() + end,
                       [axis](const Vec3& a, const Vec3& b) { return a[axis] < b[axis]; });
      tree.nodes[k].left = static_cast<std::uint32_t>(tree.nodes.size());
      tree.nodes.push_back({Vec3::Zero(), Vec3::Zero(), begin, middle, 0});
      tree.nodes.push_back({Vec3::Zero(), Vec3::Zero(), middle, end, 0});
    }
  }
  std::map<std::size_t, double> half_size;
  std::vector<std::uint32_t> stack;
  for (const auto& entry : surfaces) {
    // Not a structured binding: clang before 16 cannot capture one in the lambda below.
    const std::size_t root = entry.first;
    const auto& surface = entry.second;
    checkpoint.tick(64);
    Vec3 u = Vec3::UnitY().cross(surface.normal);
    if (u.norm() < 1e-6) u = Vec3::UnitX().cross(surface.normal);
    u.normalize();
    const Vec3 v = surface.normal.cross(u);
    double min_u = INFINITY, max_u = -INFINITY, min_v = INFINITY, max_v = -INFINITY;
    const auto take = [&](const Vec3& x) {
      if (std::abs(surface.normal.dot(x) - surface.offset) > kPlaneGap_m) return;
      min_u = std::min(min_u, u.dot(x)), max_u = std::max(max_u, u.dot(x));
      min_v = std::min(min_v, v.dot(x)), max_v = std::max(max_v, v.dot(x));
    };
    for (std::uint32_t body : surface.bodies) {
      const auto tree = trees.find(body);
      if (tree == trees.end()) {
        const BodySource& object = sources[body];
        for (const Vec3& vertex : object.mesh.vertices)
          take(object.position + object.orientation * vertex);
        continue;
      }
      const Vec3 reach = surface.normal.cwiseAbs();
      stack.assign(1, 0);
      while (!stack.empty()) {
        const VertexTree::Node& node = tree->second.nodes[stack.back()];
        stack.pop_back();
        const Vec3 centre = 0.5 * (node.min + node.max);
        const double radius = reach.dot(0.5 * (node.max - node.min));
        const double distance = surface.normal.dot(centre) - surface.offset;
        const double rounding =
            1e-9 * (1.0 + std::abs(surface.offset) + std::abs(distance) + radius);
        if (std::abs(distance) > radius + kPlaneGap_m + rounding) continue;
        if (node.left == 0) {
          for (std::uint32_t i = node.begin; i < node.end; ++i)
            take(tree->second.points[i]);
        } else {
          stack.push_back(node.left);
          stack.push_back(node.left + 1);
        }
      }
    }
    half_size[root] = max_u > min_u ? 0.5 * std::min(max_u - min_u, max_v - min_v) : 0.0;
  }
  for (std::size_t p = 0; p < n; ++p)
    model.panels[p].clearing_distance_m =
        std::max(model.panels[p].clearing_distance_m, half_size[surface_of.find(p)]);
}

}  // namespace brisance::engine
