// sim/dynamics/convex: collision shapes (convex pieces) and the separating-axis narrowphase.
#include "sim/dynamics/convex.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace brisance::dynamics {

namespace {

struct Plane {
  Vec3 normal;
  double offset;
};

// Records an edge direction for the separating-axis test, unless a parallel one is known.
void add_edge_direction(ConvexPiece& piece, const Vec3& direction) {
  const bool known =
      std::any_of(piece.edge_directions.begin(), piece.edge_directions.end(),
                  [&](const Vec3& e) { return std::abs(e.dot(direction)) > 1.0 - 1e-9; });
  if (!known) piece.edge_directions.push_back(direction);
}

// The piece's bounding sphere: centred on its vertices' box, out to the farthest vertex.
void set_bounding_sphere(ConvexPiece& piece) {
  Vec3 low = piece.vertices.front(), high = low;
  for (const Vec3& v : piece.vertices) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  piece.centre = 0.5 * (low + high);
  for (const Vec3& v : piece.vertices)
    piece.radius_m = std::max(piece.radius_m, (v - piece.centre).norm());
}

// Each face's vertices (those on its plane), in order around the face.
void set_faces(ConvexPiece& piece) {
  const double tolerance = 1e-7 * std::max(piece.radius_m, 1e-9);
  piece.faces.assign(piece.normals.size(), {});
  for (std::size_t f = 0; f < piece.normals.size(); ++f) {
    const Vec3& n = piece.normals[f];
    std::vector<std::uint8_t>& face = piece.faces[f];
    Vec3 centre = Vec3::Zero();
    for (std::size_t i = 0; i < piece.vertices.size(); ++i)
      if (std::abs(n.dot(piece.vertices[i]) - piece.offsets[f]) <= tolerance) {
        face.push_back(static_cast<std::uint8_t>(i));
        centre += piece.vertices[i];
      }
    if (face.empty()) continue;
    centre /= static_cast<double>(face.size());
    const Vec3 e1 = std::abs(n.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(n).normalized())
                                           : Vec3(Vec3::UnitY().cross(n).normalized());
    const Vec3 e2 = n.cross(e1);
    std::vector<std::pair<double, std::uint8_t>> around;
    for (std::uint8_t i : face) {
      const Vec3 d = piece.vertices[i] - centre;
      around.emplace_back(std::atan2(e2.dot(d), e1.dot(d)), i);
    }
    std::sort(around.begin(), around.end());
    for (std::size_t k = 0; k < around.size(); ++k)
      face[k] = around[k].second;
  }
}

// The faces of the convex hull of `points` by brute force: every plane through three points
// with all points on one side. O(n^4) for n points, which is why only pieces of at most
// kMaxHullVertices points come here (a box: 56 triples).
std::vector<Plane> hull_planes(const std::vector<Vec3>& points, double scale) {
  std::vector<Plane> planes;
  const std::size_t n = points.size();
  const double tolerance = 1e-9 * scale;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        Vec3 normal = (points[j] - points[i]).cross(points[k] - points[i]);
        const double length = normal.norm();
        if (length <= 1e-12 * scale * scale) continue;
        normal /= length;
        const double offset = normal.dot(points[i]);
        bool above = false, below = false;
        for (const Vec3& p : points) {
          const double d = normal.dot(p) - offset;
          above = above || d > tolerance;
          below = below || d < -tolerance;
        }
        if (above && below) continue;
        const Plane plane = above ? Plane{-normal, -offset} : Plane{normal, offset};
        const bool known = std::any_of(planes.begin(), planes.end(), [&](const Plane& q) {
          return q.normal.dot(plane.normal) > 1.0 - 1e-9;
        });
        if (!known) planes.push_back(plane);
      }
  return planes;
}

// A piece from its points and its face planes: the points on the hull, its edges (pairs of
// points sharing two faces) and their directions, and its bounding sphere.
ConvexPiece piece_from(const std::vector<Vec3>& points, const std::vector<Plane>& planes,
                       double scale) {
  ConvexPiece piece;
  const double tolerance = 1e-7 * scale;
  std::vector<std::vector<std::size_t>> faces_of;  // per kept vertex: the planes it lies on
  for (const Vec3& p : points) {
    std::vector<std::size_t> on;
    for (std::size_t f = 0; f < planes.size(); ++f)
      if (std::abs(planes[f].normal.dot(p) - planes[f].offset) <= tolerance) on.push_back(f);
    if (on.empty()) continue;  // inside the hull
    piece.vertices.push_back(p);
    faces_of.push_back(std::move(on));
  }
  for (const Plane& plane : planes) {
    piece.normals.push_back(plane.normal);
    piece.offsets.push_back(plane.offset);
  }
  const std::size_t n = piece.vertices.size();
  assert(n <= 255);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      // An edge: the two points share two faces (sorted lists).
      std::size_t shared = 0;
      for (std::size_t f : faces_of[i])
        shared += std::count(faces_of[j].begin(), faces_of[j].end(), f);
      if (shared < 2) continue;
      piece.edges.push_back({static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)});
      const Vec3 direction = (piece.vertices[j] - piece.vertices[i]).normalized();
      add_edge_direction(piece, direction);
    }
  set_bounding_sphere(piece);
  set_faces(piece);
  return piece;
}

ConvexPiece hull_piece(const std::vector<Vec3>& points, double scale) {
  return piece_from(points, hull_planes(points, scale), scale);
}

// The mesh's own triangle planes, if every vertex lies behind every one of them (convex).
bool convex_planes(const geometry::TriangleMesh& mesh, const std::vector<Vec3>& points,
                   double scale, std::vector<Plane>& planes) {
  const double tolerance = 1e-9 * scale;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = points[t[0]], b = points[t[1]], c = points[t[2]];
    const Vec3 normal = (b - a).cross(c - a).normalized();
    const double offset = normal.dot(a);
    for (const Vec3& p : points)
      if (normal.dot(p) - offset > tolerance) return false;
    const bool known = std::any_of(planes.begin(), planes.end(), [&](const Plane& q) {
      return q.normal.dot(normal) > 1.0 - 1e-9;
    });
    if (!known) planes.push_back(Plane{normal, offset});
  }
  return true;
}

// A prism (a polygon extruded along one axis, as fragments are) collides as the prism of its
// outline's convex hull: one piece, built directly (caps, one side per hull edge). False if
// the mesh is not such a prism. Rejected: one triangular prism per triangle of the cap (the
// triangulation the fragment was built from) — up to 80 pieces for a wiggly crack outline,
// whose inner faces gave poor contact normals; fragments spun up to 250 rad/s on window.json.
bool prism_piece(const geometry::TriangleMesh& mesh, const std::vector<Vec3>& points, double scale,
                 CollisionShape& shape) {
  // The axis: the normal of the first triangle; every vertex on one of two planes across it.
  const auto& first = mesh.triangles.front();
  const Vec3 axis =
      (points[first[1]] - points[first[0]]).cross(points[first[2]] - points[first[0]]).normalized();
  const double tolerance = 1e-7 * scale;
  const double top = axis.dot(points[first[0]]);
  double bottom = top;
  for (const Vec3& p : points) {
    const double h = axis.dot(p);
    if (std::abs(h - top) <= tolerance) continue;
    if (bottom == top) bottom = h;
    if (std::abs(h - bottom) > tolerance) return false;
  }
  if (bottom == top) return false;
  // The outline's convex hull in the cap plane (Andrew's monotone chain), counter-clockwise
  // seen from +axis.
  const Vec3 e1 = std::abs(axis.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(axis).normalized())
                                            : Vec3(Vec3::UnitY().cross(axis).normalized());
  const Vec3 e2 = axis.cross(e1);
  std::vector<std::pair<double, double>> cap;
  for (const Vec3& p : points)
    if (std::abs(axis.dot(p) - top) <= tolerance) cap.emplace_back(e1.dot(p), e2.dot(p));
  std::sort(cap.begin(), cap.end());
  cap.erase(std::unique(cap.begin(), cap.end()), cap.end());
  if (cap.size() < 3) return false;
  auto turn = [](const std::pair<double, double>& o, const std::pair<double, double>& a,
                 const std::pair<double, double>& b) {
    return (a.first - o.first) * (b.second - o.second) -
           (a.second - o.second) * (b.first - o.first);
  };
  std::vector<std::pair<double, double>> hull(2 * cap.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < cap.size(); ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], cap[i]) <= 0.0)
      --k;
    hull[k++] = cap[i];
  }
  for (std::size_t i = cap.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], cap[i]) <= 0.0)
      --k;
    hull[k++] = cap[i];
  }
  hull.resize(k - 1);
  const std::size_t h = std::min<std::size_t>(hull.size(), 127);
  ConvexPiece piece;
  for (std::size_t i = 0; i < h; ++i)
    piece.vertices.push_back(hull[i].first * e1 + hull[i].second * e2 + top * axis);
  for (std::size_t i = 0; i < h; ++i)
    piece.vertices.push_back(hull[i].first * e1 + hull[i].second * e2 + bottom * axis);
  const double up = top > bottom ? 1.0 : -1.0;
  piece.normals = {up * axis, -up * axis};
  piece.offsets = {up * top, -up * bottom};
  piece.edge_directions.push_back(axis);
  for (std::size_t i = 0; i < h; ++i) {
    const std::size_t j = (i + 1) % h;
    const Vec3 along = piece.vertices[j] - piece.vertices[i];
    const Vec3 outward = along.cross(axis).normalized();  // counter-clockwise about +axis
    piece.normals.push_back(outward);
    piece.offsets.push_back(outward.dot(piece.vertices[i]));
    piece.edges.push_back({static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)});
    piece.edges.push_back({static_cast<std::uint8_t>(h + i), static_cast<std::uint8_t>(h + j)});
    piece.edges.push_back({static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(h + i)});
    const Vec3 direction = along.normalized();
    add_edge_direction(piece, direction);
  }
  set_bounding_sphere(piece);
  set_faces(piece);
  shape.pieces.push_back(std::move(piece));
  return true;
}

}  // namespace

CollisionShape collision_shape(const geometry::TriangleMesh& mesh, const Vec3& centre_of_mass) {
  CollisionShape shape;
  std::vector<Vec3> points;
  points.reserve(mesh.vertices.size());
  double scale = 0.0;
  for (const Vec3& v : mesh.vertices) {
    points.push_back(v - centre_of_mass);
    scale = std::max(scale, points.back().cwiseAbs().maxCoeff());
  }
  if (points.empty() || mesh.triangles.empty()) return shape;
  std::vector<Plane> planes;
  std::vector<Vec3> unique;
  for (const Vec3& p : points)
    if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
  if (convex_planes(mesh, points, scale, planes)) {
    shape.pieces.push_back(unique.size() <= kMaxHullVertices ? hull_piece(unique, scale)
                                                             : piece_from(unique, planes, scale));
    return shape;
  }
  if (prism_piece(mesh, points, scale, shape)) return shape;
  shape.from_hull = true;
  if (unique.size() <= kMaxHullVertices) {
    shape.pieces.push_back(hull_piece(unique, scale));
    return shape;
  }
  // Too many points for the brute-force hull: the body-frame bounding box.
  Vec3 low = unique.front(), high = low;
  for (const Vec3& v : unique) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back(i & 1 ? high.x() : low.x(), i & 2 ? high.y() : low.y(),
                         i & 4 ? high.z() : low.z());
  shape.pieces.push_back(hull_piece(corners, scale));
  return shape;
}

void place(const ConvexPiece& piece, const Vec3& position, const Mat3& rotation, PlacedPiece& out) {
  out.piece = &piece;
  out.vertices.resize(piece.vertices.size());
  out.min = Vec3::Constant(INFINITY);
  out.max = Vec3::Constant(-INFINITY);
  for (std::size_t i = 0; i < piece.vertices.size(); ++i) {
    out.vertices[i] = position + rotation * piece.vertices[i];
    out.min = out.min.cwiseMin(out.vertices[i]);
    out.max = out.max.cwiseMax(out.vertices[i]);
  }
  out.normals.resize(piece.normals.size());
  out.offsets.resize(piece.normals.size());
  for (std::size_t f = 0; f < piece.normals.size(); ++f) {
    out.normals[f] = rotation * piece.normals[f];
    out.offsets[f] = piece.offsets[f] + out.normals[f].dot(position);
  }
  out.edge_directions.resize(piece.edge_directions.size());
  for (std::size_t e = 0; e < piece.edge_directions.size(); ++e)
    out.edge_directions[e] = rotation * piece.edge_directions[e];
}

void grow_box(const ConvexPiece& piece, const Vec3& position, const Mat3& rotation, Vec3& min,
              Vec3& max) {
  for (const Vec3& v : piece.vertices) {
    const Vec3 w = position + rotation * v;
    min = min.cwiseMin(w);
    max = max.cwiseMax(w);
  }
}

namespace {

void extent(const std::vector<Vec3>& vertices, const Vec3& axis, double& low, double& high) {
  low = INFINITY;
  high = -INFINITY;
  for (const Vec3& v : vertices) {
    const double d = axis.dot(v);
    low = std::min(low, d);
    high = std::max(high, d);
  }
}

// How far `other` lies beyond face f of `reference` (negative: into it), m, and which of its
// vertices lies least far (`nearest`).
double face_gap(const PlacedPiece& reference, const PlacedPiece& other, std::size_t f,
                std::uint8_t& nearest) {
  const Vec3& normal = reference.normals[f];
  double low = INFINITY;
  std::size_t index = 0;
  for (std::size_t i = 0; i < other.vertices.size(); ++i) {
    const double d = normal.dot(other.vertices[i]);
    if (d < low) {
      low = d;
      index = i;
    }
  }
  nearest = static_cast<std::uint8_t>(index);
  return low - reference.offsets[f];
}

// The unit axis across edge directions ea and eb, unless they are (nearly) parallel.
bool cross_axis(const Vec3& ea, const Vec3& eb, Vec3& axis) {
  axis = ea.cross(eb);
  const double length = axis.norm();
  if (length < 1e-6) return false;
  axis /= length;
  return true;
}

// Closest points of segments p0-p1 and q0-q1 (clamped), returned as their midpoint.
Vec3 closest_midpoint(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                      double& distance_squared) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2);
  const double denominator = a * e - b * b;
  double s = denominator > 1e-18 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  const Vec3 x = p0 + s * d1, y = q0 + t * d2;
  distance_squared = (x - y).squaredNorm();
  return 0.5 * (x + y);
}

// A point of a clipped polygon and the feature it comes from (for warm starting).
struct ClipPoint {
  Vec3 point;
  std::uint32_t feature;
};

// Sutherland-Hodgman: the part of `polygon` with normal . x <= offset, into `out`.
void clip(const std::vector<ClipPoint>& polygon, const Vec3& normal, double offset,
          std::uint32_t side, std::vector<ClipPoint>& out) {
  out.clear();
  const std::size_t n = polygon.size();
  for (std::size_t k = 0; k < n; ++k) {
    const ClipPoint& p = polygon[k];
    const ClipPoint& q = polygon[(k + 1) % n];
    const double dp = normal.dot(p.point) - offset;
    const double dq = normal.dot(q.point) - offset;
    if (dp <= 0.0) out.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) {
      // Where the incident edge p-q crosses the side: tagged by the side and the edge.
      const std::uint32_t edge = (p.feature * 7u + q.feature * 13u) & 0xFu;
      out.push_back(
          ClipPoint{p.point + (dp / (dp - dq)) * (q.point - p.point), ((side & 0x7u) << 4) | edge});
    }
  }
}

// The contact points of a face contact: `incident`'s face most opposed to `reference`'s face
// `face`, clipped to the planes through the reference face's edges (square to it), and kept
// where within the margin of the reference plane, each midway between the surfaces. The
// normal (from a to b) is the reference face's, reversed when the reference is b.
void face_manifold(const PlacedPiece& reference, const PlacedPiece& incident, std::size_t face,
                   bool reference_is_b, double margin_m, double side_margin_m,
                   std::uint32_t feature_base, Manifold& out) {
  const Vec3& n = reference.normals[face];
  const double offset = reference.offsets[face];
  std::size_t opposed = 0;
  for (std::size_t f = 1; f < incident.normals.size(); ++f)
    if (incident.normals[f].dot(n) < incident.normals[opposed].dot(n)) opposed = f;
  thread_local std::vector<ClipPoint> polygon, clipped;
  polygon.clear();
  // Incident vertices: 128 + their index (64 apart for either reference side).
  const std::uint32_t vertex_tag = reference_is_b ? 192u : 128u;
  for (std::uint8_t i : incident.piece->faces[opposed])
    polygon.push_back(ClipPoint{incident.vertices[i], vertex_tag + (i & 0x3Fu)});
  const std::vector<std::uint8_t>& sides = reference.piece->faces[face];
  Vec3 centre = Vec3::Zero();
  for (std::uint8_t i : sides)
    centre += reference.vertices[i];
  centre /= static_cast<double>(std::max<std::size_t>(sides.size(), 1));
  for (std::size_t k = 0; k < sides.size() && !polygon.empty(); ++k) {
    const Vec3& p = reference.vertices[sides[k]];
    const Vec3& q = reference.vertices[sides[(k + 1) % sides.size()]];
    Vec3 outward = (q - p).cross(n);
    const double length = outward.norm();
    if (length <= 0.0) continue;
    outward /= length;
    if (outward.dot(centre - p) > 0.0) outward = -outward;
    // Clipped a little outside the side (the margin): a vertex of an equal brick stacked on
    // another stays a vertex, with the same feature from step to step (for warm starting),
    // instead of becoming a crossing of edges whenever the bricks turn by a hair.
    clip(polygon, outward, outward.dot(p) + side_margin_m, static_cast<std::uint32_t>(k), clipped);
    std::swap(polygon, clipped);
  }
  // And to the reference piece's box grown by sqrt(2) times as much: sides moved out by the
  // margin d meet d / sin(angle / 2) beyond a corner, at most sqrt(2) d where no corner is
  // acute (a box's faces: for bricks this clips nothing), but 20 m at a sliver's 1 degree tip
  // with d = 17 cm, and a sliver before a wall took points at the wall's edges, 2 m away, as
  // its own.
  const double grown = std::sqrt(2.0) * side_margin_m;
  for (int k = 0; k < 3 && !polygon.empty(); ++k)
    for (const double sign : {1.0, -1.0}) {
      const Vec3 outward = sign * Vec3::Unit(k);
      const double bound = sign > 0.0 ? reference.max[k] + grown : -(reference.min[k] - grown);
      bool outside = false;
      for (const ClipPoint& c : polygon)
        outside = outside || outward.dot(c.point) > bound;
      if (!outside) continue;
      clip(polygon, outward, bound, static_cast<std::uint32_t>(2 * k + (sign > 0.0 ? 0 : 1)),
           clipped);
      std::swap(polygon, clipped);
    }
  out.normal = reference_is_b ? Vec3(-n) : n;
  for (const ClipPoint& c : polygon) {
    const double depth = offset - n.dot(c.point);
    if (depth < -margin_m) continue;
    out.points.push_back(ContactPoint{c.point + 0.5 * depth * n, depth, feature_base + c.feature});
  }
}

// What the rounding of projections onto an axis can move them by, for pieces a and b: 1e-14 of
// their coordinates' size (a bound computed another way must give that much room to agree
// with them).
double projection_rounding(const PlacedPiece& a, const PlacedPiece& b) {
  return 1e-14 * std::max({a.min.cwiseAbs().maxCoeff(), a.max.cwiseAbs().maxCoeff(),
                           b.min.cwiseAbs().maxCoeff(), b.max.cwiseAbs().maxCoeff()});
}

// The separations of two pieces along their face axes, as collide and separated measure them:
// along each of a's face normals, then each of b's reversed (from a to b), with the vertex of
// the other piece least far along it.
struct FaceAxes {
  std::vector<double> separations;
  std::vector<std::uint8_t> nearest;
  void clear() {
    separations.clear();
    nearest.clear();
  }
  double add(const PlacedPiece& reference, const PlacedPiece& other, std::size_t f) {
    std::uint8_t vertex;
    separations.push_back(face_gap(reference, other, f, vertex));
    nearest.push_back(vertex);
    return separations.back();
  }
};

// Upper bounds on the separation of two pieces along an axis, for skipping the edge axes of
// the separating-axis test that cannot matter. For pieces of many sides the edge axes are most
// of the test: a fragment's 9 edge directions against another's make 81 axes, each two
// projections of all vertices, and pieces in touch (or overlapping, as a pane's pieces do
// before they part) project every one; on window.json with "on", 8.6 M edge axes against
// 2.8 M face axes. For any vertex x of a and y of b, the separation of b beyond a along an
// axis c is at most c . (y - x). With x and y the supports of a face axis (a vertex of the face
// and the other piece's vertex least far along its normal, both found by the face axis's own
// test) that bound is tight for axes near it, and a pane's pieces side by side have most of
// their edge axes near one of their face normals: the cross products of two outlines' edges
// are near-copies of the plate's normal, along which the pieces overlap by its thickness. The
// face axis that bounded the last axis is tried first (at the start the deepest), then the
// others in order. Boxes (3 x 3 edge axes) are left to the projections.
class SeparationBound {
 public:
  void start(const PlacedPiece& a, const PlacedPiece& b, const FaceAxes& faces) {
    gaps_.clear();
    if (a.edge_directions.size() * b.edge_directions.size() <= 16) return;
    const std::size_t faces_a = a.normals.size();
    double deepest = INFINITY;
    last_ = 0;
    for (std::size_t f = 0; f < faces.separations.size(); ++f) {
      const bool of_a = f < faces_a;
      const auto& own = of_a ? a.piece->faces[f] : b.piece->faces[f - faces_a];
      if (own.empty()) continue;  // (a face without vertices: none of a degenerate hull)
      const std::size_t x = of_a ? own.front() : faces.nearest[f];
      const std::size_t y = of_a ? faces.nearest[f] : own.front();
      if (faces.separations[f] < deepest) {
        deepest = faces.separations[f];
        last_ = gaps_.size();
      }
      gaps_.push_back(b.vertices[y] - a.vertices[x]);
    }
    slack_ = projection_rounding(a, b) + 1e-15;
  }
  bool active() const { return !gaps_.empty(); }
  // Whether the separation of b beyond a along `axis` is surely at most `limit` (by `slack_`).
  bool at_most(const Vec3& axis, double limit) {
    limit -= slack_;
    if (!(axis.dot(gaps_[last_]) > limit)) return true;
    for (std::size_t k = 0; k < gaps_.size(); ++k)
      if (k != last_ && !(axis.dot(gaps_[k]) > limit)) {
        last_ = k;
        return true;
      }
    return false;
  }

 private:
  std::vector<Vec3> gaps_;  // y - x, a face axis each (a's, then b's)
  std::size_t last_ = 0;
  double slack_ = 0.0;
};

}  // namespace

bool collide(const PlacedPiece& a, const PlacedPiece& b, double margin_m,
             std::uint32_t feature_base, Manifold& out, bool all_points, double side_margin_m,
             const StepMotion& step) {
  out.points.clear();
  if ((a.min.array() > b.max.array() + margin_m).any() ||
      (b.min.array() > a.max.array() + margin_m).any())
    return false;
  // Separating axes. Face axes first; an edge axis must separate clearly better to be chosen
  // (by 0.1 margin), so resting faces keep a face normal.
  struct FaceAxis {
    double separation = -INFINITY;
    Vec3 normal = Vec3::UnitY();
    std::size_t face = 0;  // of a, or of b if of_b
    bool of_b = false;
  };
  // The face axis of least overlap, and the one through which the pieces came into overlap
  // last in the step (the latest entry), judged by the separation at the start of the step
  // along each: b moved back by its displacement, the turns (not followed) may have moved it
  // by up to turned_m either way.
  FaceAxis least, entry;
  double least_before = 0.0, latest_entry = -INFINITY;
  // And the step swept linearly: along every axis the part of the step in which the pieces
  // overlap whatever the turns did (by more than turned_m); they surely met within the step if
  // those parts have a time in common, first at the latest of their starts, through the axis
  // that starts it (passed). (Counting a turn's worth of overlap as overlap, the pieces of a
  // pane flying side by side, specks among them spinning, were found to have met where they
  // had not, and with `on` five specks were thrown through the wall behind the window.) Its
  // entry is not the one above: there the pieces overlap at the end, and a face they were
  // possibly apart along at the start is an entry; one entry for both, judged surely,
  // let 23 spinning fragments through the wall with `on` instead of none or one.
  struct Sweep {
    double first = 0.0, last = 1.0;
    bool missed = false;
    FaceAxis passed;  // separation is the end's; face is none for an edge axis
    bool passed_edge = false;
    double turned = 0.0;
    void add(const FaceAxis& here, double before, bool edge) {
      const double end = here.separation + turned, start = before + turned;
      if (start > 0.0 && end > 0.0) missed = true;  // not surely overlapping at any time
      if (start > 0.0 && end <= 0.0) {
        const double entered = start / (start - end);
        if (entered > first) {
          first = entered;
          passed = here;
          passed_edge = edge;
        }
      } else if (start <= 0.0 && end > 0.0) {
        last = std::min(last, start / (start - end));
      }
    }
  } sweep;
  sweep.turned = step.turned_m;
  const auto face_axis = [&](const FaceAxis& here) {
    const double before = here.separation - step.moved.dot(here.normal);
    if (here.separation > least.separation) {
      least = here;
      least_before = before;
    }
    const double apart = before + step.turned_m;  // at most, at the start
    if (apart > 0.0 && here.separation < apart) {
      const double entered = apart / (apart - here.separation);  // fraction of the step
      if (entered > latest_entry) {
        latest_entry = entered;
        entry = here;
      }
    }
    sweep.add(here, before, false);
  };
  thread_local FaceAxes faces;
  faces.clear();
  for (std::size_t f = 0; f < a.normals.size(); ++f) {
    const double separation = faces.add(a, b, f);
    if (separation > margin_m) return false;
    face_axis({separation, a.normals[f], f, false});
  }
  for (std::size_t f = 0; f < b.normals.size(); ++f) {
    const double separation = faces.add(b, a, f);
    if (separation > margin_m) return false;
    face_axis({separation, -b.normals[f], f, true});
  }
  // Pieces that overlap at the end of the step, and along the axis of least overlap now were
  // deeper at its start by more than the turns can explain (the one piece moving out through
  // the other's far side), came in through the face they crossed last: a fragment at 14 m/s,
  // 12 cm into a 20 cm wall after one 9.5 ms step, overlaps it least towards its back face and
  // was pushed out through it (docs/simulator.md, Tunnelling). Where the pieces only slid
  // along the axis of least overlap, it stays (two fragments meeting side by side in a pile).
  const bool came_through = least.separation < 0.0 &&
                            least.separation - least_before > step.turned_m &&
                            latest_entry > -INFINITY;
  const FaceAxis& chosen = came_through ? entry : least;
  double best = chosen.separation;
  Vec3 axis = chosen.normal;
  std::size_t reference_face = chosen.face;
  bool reference_is_b = chosen.of_b;
  const Vec3 between = 0.5 * (b.min + b.max - a.min - a.max);
  bool edge_axis = false;
  // Edge axes that cannot matter are not projected (SeparationBound): those whose separation
  // is surely below all that could make it count — end the test (the margin), become the
  // chosen axis (best, beyond its 0.1 margin) or change the sweep (unless already missed: then
  // nothing changes it). The others are projected as before, so the result is the one
  // projecting every axis gives.
  thread_local SeparationBound bound;
  bound.start(a, b, faces);
  for (const Vec3& ea : a.edge_directions)
    for (const Vec3& eb : b.edge_directions) {
      Vec3 candidate;
      if (!cross_axis(ea, eb, candidate)) continue;
      if (candidate.dot(between) < 0.0) candidate = -candidate;
      if (bound.active()) {
        double limit = margin_m;
        if (!came_through) limit = std::min(limit, best + 0.1 * margin_m);
        if (!sweep.missed)
          limit = std::min(limit, -step.turned_m - std::max(0.0, -step.moved.dot(candidate)));
        if (bound.at_most(candidate, limit)) continue;
      }
      double a_low, a_high, b_low, b_high;
      extent(a.vertices, candidate, a_low, a_high);
      extent(b.vertices, candidate, b_low, b_high);
      const double separation = b_low - a_high;
      if (separation > margin_m) return false;
      sweep.add({separation, candidate, 0, false}, separation - step.moved.dot(candidate), true);
      if (!came_through && separation > best + 0.1 * margin_m) {
        best = separation;
        axis = candidate;
        edge_axis = true;
      }
    }
  // Pieces apart at the end of the step that met within it: the one passed right through the
  // other (a 10 cm block at 19 m/s moves 18 cm in a 9.5 ms step, through a 2 cm plate). The
  // contact is the axis they met through, as deep as the piece is now past it.
  if (best >= 0.0 && !sweep.missed && sweep.first > 0.0 && sweep.first <= sweep.last) {
    best = sweep.passed.separation;
    axis = sweep.passed.normal;
    edge_axis = sweep.passed_edge;
    reference_face = sweep.passed.face;
    reference_is_b = sweep.passed.of_b;
  }
  out.normal = axis;
  double a_low, a_high, b_low, b_high;
  extent(a.vertices, axis, a_low, a_high);
  extent(b.vertices, axis, b_low, b_high);
  // The manifold on a face axis: the most opposed face of the other piece, clipped to the
  // sides of the reference face, its points within the margin of the reference plane.
  if (!edge_axis)
    face_manifold(reference_is_b ? b : a, reference_is_b ? a : b, reference_face, reference_is_b,
                  margin_m, side_margin_m < 0.0 ? margin_m : side_margin_m, feature_base, out);
  if (out.points.size() > 4 && !all_points) {
    // Four points carry a face contact: the extremes along two directions across the normal
    // (a brick on two others has eight within the margin; the solve costs per point).
    // (Skewed from the plane's axes, so a rectangle's four corners are four distinct extremes.)
    const Vec3 x = std::abs(axis.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(axis).normalized())
                                             : Vec3(Vec3::UnitY().cross(axis).normalized());
    const Vec3 y = axis.cross(x);
    const Vec3 u = x + 0.37 * y, v = y - 0.37 * x;
    std::array<std::size_t, 4> keep = {0, 0, 0, 0};
    for (std::size_t i = 1; i < out.points.size(); ++i) {
      const Vec3& p = out.points[i].point;
      if (p.dot(u) < out.points[keep[0]].point.dot(u)) keep[0] = i;
      if (p.dot(u) > out.points[keep[1]].point.dot(u)) keep[1] = i;
      if (p.dot(v) < out.points[keep[2]].point.dot(v)) keep[2] = i;
      if (p.dot(v) > out.points[keep[3]].point.dot(v)) keep[3] = i;
    }
    std::sort(keep.begin(), keep.end());
    std::vector<ContactPoint> kept;
    for (std::size_t k = 0; k < 4; ++k)
      if (k == 0 || keep[k] != keep[k - 1]) kept.push_back(out.points[keep[k]]);
    out.points.swap(kept);
  }
  if (out.points.empty()) {
    // Edge against edge (or no vertex inside): one point, the closest points of the edges on
    // each piece's supporting side.
    const double band = std::max(margin_m, 1e-3 * (a.max - a.min).norm());
    double closest = INFINITY;
    Vec3 point = Vec3::Zero();
    std::uint32_t feature = feature_base + 255;
    const auto& a_edges = a.piece->edges;
    const auto& b_edges = b.piece->edges;
    // b's edges on its supporting side, found once (not once per edge of a), each with the
    // sphere around it. Two edges are at least as far apart as their spheres, less `slack`
    // for rounding: a pair whose spheres are farther apart than the closest pair so far cannot
    // be closer, and is passed over (the band takes nearly every edge of a fragment: its
    // margin grows with the pieces' motion; on window.json with "on" the 16 500 edge contacts
    // measured 590 pairs each).
    struct SideEdge {
      std::uint32_t index;
      Vec3 middle;
      double half_length;
    };
    thread_local std::vector<SideEdge> b_side;
    b_side.clear();
    for (std::size_t j = 0; j < b_edges.size(); ++j) {
      const Vec3& q0 = b.vertices[b_edges[j][0]];
      const Vec3& q1 = b.vertices[b_edges[j][1]];
      if (axis.dot(q0) > b_low + band || axis.dot(q1) > b_low + band) continue;
      b_side.push_back({static_cast<std::uint32_t>(j), 0.5 * (q0 + q1), 0.5 * (q1 - q0).norm()});
    }
    const double slack = 1e-9 + projection_rounding(a, b);
    for (std::size_t i = 0; i < a_edges.size(); ++i) {
      const Vec3& p0 = a.vertices[a_edges[i][0]];
      const Vec3& p1 = a.vertices[a_edges[i][1]];
      if (axis.dot(p0) < a_high - band || axis.dot(p1) < a_high - band) continue;
      const Vec3 middle = 0.5 * (p0 + p1);
      const double half_length = 0.5 * (p1 - p0).norm();
      for (const SideEdge& edge : b_side) {
        const double apart = (edge.middle - middle).norm() - half_length - edge.half_length - slack;
        if (apart > 0.0 && apart * apart > closest) continue;
        const std::uint32_t j = edge.index;
        const Vec3& q0 = b.vertices[b_edges[j][0]];
        const Vec3& q1 = b.vertices[b_edges[j][1]];
        double d2;
        const Vec3 mid = closest_midpoint(p0, p1, q0, q1, d2);
        if (d2 < closest) {
          closest = d2;
          point = mid;
          feature = feature_base + 192 + static_cast<std::uint32_t>((i * 7 + j) % 60);
        }
      }
    }
    if (closest == INFINITY) {
      // A vertex against a face seen only by its support: midway between the supports.
      std::size_t ia = 0, ib = 0;
      for (std::size_t i = 0; i < a.vertices.size(); ++i)
        if (axis.dot(a.vertices[i]) > axis.dot(a.vertices[ia])) ia = i;
      for (std::size_t i = 0; i < b.vertices.size(); ++i)
        if (axis.dot(b.vertices[i]) < axis.dot(b.vertices[ib])) ib = i;
      point = 0.5 * (a.vertices[ia] + b.vertices[ib]);
    }
    out.points.push_back(ContactPoint{point, -best, feature});
  }
  return true;
}

bool separated(const PlacedPiece& a, const PlacedPiece& b, double margin_m) {
  if ((a.min.array() > b.max.array() + margin_m).any() ||
      (b.min.array() > a.max.array() + margin_m).any())
    return true;
  thread_local FaceAxes faces;
  faces.clear();
  for (std::size_t f = 0; f < a.normals.size(); ++f)
    if (faces.add(a, b, f) > margin_m) return true;
  for (std::size_t f = 0; f < b.normals.size(); ++f)
    if (faces.add(b, a, f) > margin_m) return true;
  // (An edge axis along which neither piece can be beyond the other by the margin, judged by
  // SeparationBound both ways, is not projected.)
  thread_local SeparationBound bound;
  bound.start(a, b, faces);
  for (const Vec3& ea : a.edge_directions)
    for (const Vec3& eb : b.edge_directions) {
      Vec3 axis;
      if (!cross_axis(ea, eb, axis)) continue;
      if (bound.active() && bound.at_most(axis, margin_m) && bound.at_most(-axis, margin_m))
        continue;
      double a_low, a_high, b_low, b_high;
      extent(a.vertices, axis, a_low, a_high);
      extent(b.vertices, axis, b_low, b_high);
      if (b_low - a_high > margin_m || a_low - b_high > margin_m) return true;
    }
  return false;
}

}  // namespace brisance::dynamics
