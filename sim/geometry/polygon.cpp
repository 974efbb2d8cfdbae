// sim/geometry/polygon: simple polygons, ear clipping, prisms and their mass properties.
#include "sim/geometry/polygon.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>

namespace brisance::geometry {

namespace {

// Relative tolerance of the collinearity test: |cross| <= kCollinear * |a| * |b|.
constexpr double kCollinear = 1e-12;

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Twice the signed area of triangle (o, a, b): positive when o → a → b turns left.
double orient(const Vec2& o, const Vec2& a, const Vec2& b) {
  return cross(a - o, b - o);
}

bool on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// Whether closed segments [a, b] and [c, d] share a point (exact orientation signs).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c);
  const double o2 = orient(a, b, d);
  const double o3 = orient(c, d, a);
  const double o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  if (o1 == 0 && on_segment(c, a, b)) return true;
  if (o2 == 0 && on_segment(d, a, b)) return true;
  if (o3 == 0 && on_segment(a, c, d)) return true;
  if (o4 == 0 && on_segment(b, c, d)) return true;
  return false;
}

// Whether b lies on the straight line from a to c, passing straight through (not folding back).
bool straight_through(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a;
  const Vec2 v = c - b;
  return std::abs(cross(u, v)) <= kCollinear * u.norm() * v.norm() && u.dot(v) > 0.0;
}

// Indices of the polygon's vertices without straight-through vertices, counter-clockwise.
std::vector<std::uint32_t> reduced_ccw_indices(std::span<const Vec2> polygon) {
  const std::size_t n = polygon.size();
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i)
    order[i] = static_cast<std::uint32_t>(i);
  if (signed_area(polygon) < 0.0) std::reverse(order.begin(), order.end());
  // Repeat until stable: removing one vertex can make its neighbour collinear.
  bool removed = true;
  while (removed && order.size() > 3) {
    removed = false;
    std::vector<std::uint32_t> kept;
    kept.reserve(order.size());
    const std::size_t m = order.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Vec2& prev = kept.empty() ? polygon[order[m - 1]] : polygon[kept.back()];
      const Vec2& next = polygon[order[(i + 1) % m]];
      if (m - (i - kept.size()) > 3 && straight_through(prev, polygon[order[i]], next)) {
        removed = true;
        continue;
      }
      kept.push_back(order[i]);
    }
    order = std::move(kept);
  }
  return order;
}

}  // namespace

double signed_area(std::span<const Vec2> polygon) {
  if (polygon.size() < 3) return 0.0;
  const Vec2 origin = polygon[0];  // relative coordinates keep the sum accurate
  double twice = 0.0;
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
    twice += cross(polygon[i] - origin, polygon[i + 1] - origin);
  return 0.5 * twice;
}

Vec2 centroid(std::span<const Vec2> polygon) {
  assert(polygon.size() >= 3);
  const Vec2 origin = polygon[0];
  double twice_area = 0.0;
  Vec2 six_moment = Vec2::Zero();  // 6 ∫ (r − origin) dA, thesis eqs. 6.7–6.8
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Vec2 a = polygon[i] - origin;
    const Vec2 b = polygon[i + 1] - origin;
    const double c = cross(a, b);
    twice_area += c;
    six_moment += c * (a + b);
  }
  assert(twice_area != 0.0);
  return origin + six_moment / (3.0 * twice_area);
}

bool is_simple(std::span<const Vec2> polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return false;
  for (const Vec2& p : polygon)
    if (!p.allFinite()) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (polygon[i] == polygon[(i + 1) % n]) return false;
  if (signed_area(polygon) == 0.0) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % n];
    // Adjacent edge (b → c): only b in common unless it folds back along (a → b).
    const Vec2& c = polygon[(i + 2) % n];
    if (n > 3 && orient(a, b, c) == 0.0 && (b - a).dot(c - b) < 0.0) return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the wrap-around
      if (segments_meet(a, b, polygon[j], polygon[(j + 1) % n])) return false;
    }
  }
  return true;
}

bool contains(std::span<const Vec2> polygon, const Vec2& p) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

Polygon remove_collinear(std::span<const Vec2> polygon) {
  std::vector<std::uint32_t> order = reduced_ccw_indices(polygon);
  if (signed_area(polygon) < 0.0) std::reverse(order.begin(), order.end());
  Polygon out;
  out.reserve(order.size());
  for (std::uint32_t i : order)
    out.push_back(polygon[i]);
  return out;
}

std::vector<std::array<std::uint32_t, 3>> triangulate(std::span<const Vec2> polygon) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  if (polygon.size() < 3) return triangles;
  std::vector<std::uint32_t> ring = reduced_ccw_indices(polygon);
  triangles.reserve(ring.size());
  const auto at = [&](std::size_t k) -> const Vec2& { return polygon[ring[k % ring.size()]]; };

  // Ear clipping (Meisters, "Polygons have ears", 1975): a convex corner whose triangle holds no
  // other vertex is cut off. Rejected: monotone decomposition, O(n log n) but far more code for
  // polygons of a few hundred vertices.
  std::size_t k = 0;
  std::size_t misses = 0;
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    const Vec2& a = at(k + m - 1);
    const Vec2& b = at(k);
    const Vec2& c = at(k + 1);
    bool ear = orient(a, b, c) > 0.0;
    for (std::size_t j = 0; ear && j < m; ++j) {
      if (j == k || j == (k + 1) % m || j == (k + m - 1) % m) continue;
      const Vec2& p = at(j);
      if (p == a || p == b || p == c) continue;
      // Inside or on the boundary of the closed triangle blocks the ear.
      if (orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0) ear = false;
    }
    // After a full lap without an ear (rounding on a nearly degenerate polygon), cut the most
    // convex corner so the loop always ends.
    if (!ear && misses >= m) {
      double best = -std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < m; ++j) {
        const double turn = orient(at(j + m - 1), at(j), at(j + 1));
        if (turn > best) {
          best = turn;
          k = j;
        }
      }
      ear = true;
    }
    if (ear) {
      triangles.push_back({ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
      k = (k + ring.size() - 1) % ring.size();  // the previous corner may have become an ear
      misses = 0;
    } else {
      k = (k + 1) % m;
      ++misses;
    }
  }
  triangles.push_back({ring[0], ring[1], ring[2]});
  return triangles;
}

TriangleMesh extrude(std::span<const Vec2> polygon, double thickness_m) {
  assert(thickness_m > 0.0);
  Polygon outline = remove_collinear(polygon);
  if (signed_area(outline) < 0.0) std::reverse(outline.begin(), outline.end());
  const std::size_t n = outline.size();
  const double half = 0.5 * thickness_m;
  TriangleMesh mesh;
  mesh.vertices.reserve(2 * n);
  for (const Vec2& p : outline)
    mesh.vertices.emplace_back(p.x(), p.y(), -half);  // back cap: indices 0 … n−1
  for (const Vec2& p : outline)
    mesh.vertices.emplace_back(p.x(), p.y(), half);  // front cap: indices n … 2n−1
  const auto un = static_cast<std::uint32_t>(n);
  for (const auto& tri : triangulate(outline)) {
    mesh.triangles.push_back({tri[0] + un, tri[1] + un, tri[2] + un});  // front: +z, CCW
    mesh.triangles.push_back({tri[0], tri[2], tri[1]});                 // back: −z, reversed
  }
  for (std::uint32_t i = 0; i < un; ++i) {
    const std::uint32_t j = (i + 1) % un;
    // Side wall of edge i → j; outward because the outline runs counter-clockwise.
    mesh.triangles.push_back({i, j, j + un});
    mesh.triangles.push_back({i, j + un, i + un});
  }
  return mesh;
}

MassProperties prism_mass_properties(std::span<const Vec2> polygon, double thickness_m,
                                     double density_kg_m3) {
  assert(polygon.size() >= 3 && thickness_m > 0.0 && density_kg_m3 > 0.0);
  const double area = signed_area(polygon);
  const Vec2 centre = centroid(polygon);
  // Second moments of the area about its centroid by Green's theorem, edge by edge:
  //   ∫x² dA = Σ (x_i² + x_i x_j + x_j²) c / 12,  ∫y² dA likewise,
  //   ∫xy dA = Σ (x_i y_j + 2 x_i y_i + 2 x_j y_j + x_j y_i) c / 24,  c = x_i y_j − x_j y_i,
  // which sums the thesis's per-triangle integrals (eqs. 6.2–6.5) in one pass.
  double sxx = 0.0;
  double syy = 0.0;
  double sxy = 0.0;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = polygon[i] - centre;
    const Vec2 b = polygon[(i + 1) % n] - centre;
    const double c = cross(a, b);
    sxx += (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) * c;
    syy += (a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) * c;
    sxy += (a.x() * b.y() + 2.0 * a.x() * a.y() + 2.0 * b.x() * b.y() + b.x() * a.y()) * c;
  }
  const double sign = area < 0.0 ? -1.0 : 1.0;  // clockwise input gives negated sums
  sxx *= sign / 12.0;
  syy *= sign / 12.0;
  sxy *= sign / 24.0;
  const double abs_area = std::abs(area);
  const double t = thickness_m;
  const double szz = abs_area * t * t * t / 12.0;  // ∫z² dV over z ∈ [−t/2, t/2]

  MassProperties props;
  props.volume_m3 = abs_area * t;
  props.mass_kg = density_kg_m3 * props.volume_m3;
  props.centre_of_mass = Vec3(centre.x(), centre.y(), 0.0);
  // Covariance C = ∫ r rᵀ dV; the xz and yz entries vanish by symmetry in z (thesis eq. 6.6).
  Mat3 second_moment = Mat3::Zero();
  second_moment(0, 0) = t * sxx;
  second_moment(1, 1) = t * syy;
  second_moment(2, 2) = szz;
  second_moment(0, 1) = second_moment(1, 0) = t * sxy;
  props.inertia_kg_m2 = density_kg_m3 * (second_moment.trace() * Mat3::Identity() - second_moment);
  return props;
}

double minimal_width(std::span<const Vec2> polygon) {
  // Convex hull (monotone chain), then for each hull edge the farthest hull vertex; the minimum
  // over edges is the width. O(h^2) over the hull, which has few vertices for fragments.
  std::vector<Vec2> points(polygon.begin(), polygon.end());
  std::sort(points.begin(), points.end(), [](const Vec2& p, const Vec2& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  if (points.size() < 3) return 0.0;
  std::vector<Vec2> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const std::size_t base = hull.size();
    for (const Vec2& p : points) {
      while (hull.size() >= base + 2 && orient(hull[hull.size() - 2], hull.back(), p) <= 0.0)
        hull.pop_back();
      hull.push_back(p);
    }
    hull.pop_back();
    std::reverse(points.begin(), points.end());
  }
  if (hull.size() < 3) return 0.0;
  double width = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % hull.size()];
    const double length = (b - a).norm();
    if (length == 0.0) continue;
    double farthest = 0.0;
    for (const Vec2& p : hull)
      farthest = std::max(farthest, orient(a, b, p) / length);
    width = std::min(width, farthest);
  }
  return width;
}

std::vector<Panel> front_panels(std::span<const Vec2> polygon, double thickness_m,
                                std::size_t min_panels, std::size_t max_panels) {
  assert(min_panels >= 1);
  struct Piece {
    Vec2 a, b, c;
    double area() const { return 0.5 * orient(a, b, c); }
  };
  std::vector<Piece> pieces;
  for (const auto& tri : triangulate(polygon))
    pieces.push_back({polygon[tri[0]], polygon[tri[1]], polygon[tri[2]]});
  // Too few: halve the largest triangle across its longest edge (thesis §6.2 wants ≥ 5 samples).
  while (!pieces.empty() && pieces.size() < min_panels) {
    std::size_t largest = 0;
    for (std::size_t i = 1; i < pieces.size(); ++i)
      if (pieces[i].area() > pieces[largest].area()) largest = i;
    Piece p = pieces[largest];
    // Rotate so that a → b is the longest edge.
    for (int turn = 0; turn < 2; ++turn) {
      const double ab = (p.b - p.a).squaredNorm();
      if (ab >= (p.c - p.b).squaredNorm() && ab >= (p.a - p.c).squaredNorm()) break;
      p = Piece{p.b, p.c, p.a};
    }
    const Vec2 mid = 0.5 * (p.a + p.b);
    pieces[largest] = Piece{p.a, mid, p.c};
    pieces.insert(pieces.begin() + static_cast<std::ptrdiff_t>(largest) + 1, Piece{mid, p.b, p.c});
  }
  const std::size_t count = std::max(min_panels, std::min(max_panels, pieces.size()));
  const double half_size_m = 0.5 * minimal_width(polygon);
  std::vector<Panel> panels;
  panels.reserve(count);
  // Group i takes pieces [i·n/count, (i+1)·n/count): consecutive triangles of the ear clipping.
  for (std::size_t g = 0; g < count && !pieces.empty(); ++g) {
    const std::size_t first = g * pieces.size() / count;
    const std::size_t last = (g + 1) * pieces.size() / count;
    double area = 0.0;
    Vec2 moment = Vec2::Zero();
    for (std::size_t i = first; i < last; ++i) {
      const double a = pieces[i].area();
      area += a;
      moment += a * (pieces[i].a + pieces[i].b + pieces[i].c) / 3.0;
    }
    if (last == first) continue;
    const Vec2 centre = area > 0.0 ? Vec2(moment / area) : pieces[first].a;
    Panel panel;
    panel.centre = Vec3(centre.x(), centre.y(), 0.5 * thickness_m);
    panel.outward_normal = Vec3::UnitZ();
    panel.area_m2 = area;
    panel.face_half_size_m = half_size_m;
    panels.push_back(panel);
  }
  return panels;
}

}  // namespace brisance::geometry
