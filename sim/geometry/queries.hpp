// sim/geometry/queries: point queries against segments, triangles and closed meshes — the nearest
// point of a segment (2D and 3D), the distance to a triangle and to a mesh's surface, the winding
// number of a closed mesh about a point (point in mesh) and a bounding sphere for quick rejects.
// Units: metres; every point and mesh in one frame, whichever the caller chooses.
#pragma once

#include <algorithm>

#include <Eigen/Core>

#include "sim/geometry/mesh.hpp"

namespace brisance::geometry {

using Vec2 = Eigen::Vector2d;

// The point of the segment [a, b] nearest to p is a + t (b − a).
struct SegmentNearest {
  double distance_m = 0.0;  // from p to that point
  double t = 0.0;           // in [0, 1]; 0 for a zero-length segment
};

namespace detail {
// One body for both dimensions, so the 2D and 3D answers round alike.
template <typename Vector>
SegmentNearest nearest_on_segment(const Vector& p, const Vector& a, const Vector& b) {
  const Vector ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double t =
      length_squared > 0.0 ? std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0) : 0.0;
  return {(a + t * ab - p).norm(), t};
}
}  // namespace detail

inline SegmentNearest nearest_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return detail::nearest_on_segment(p, a, b);
}
inline SegmentNearest nearest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  return detail::nearest_on_segment(p, a, b);
}
inline double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return nearest_on_segment(p, a, b).distance_m;
}
inline double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  return nearest_on_segment(p, a, b).distance_m;
}

// Distance from p to the triangle (a, b, c): to its plane if p projects inside it, else to the
// nearest edge. A degenerate triangle is treated as its edges.
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Distance from p to the nearest triangle of the mesh; infinity for a mesh without triangles.
double distance_to_surface(const TriangleMesh& mesh, const Vec3& p);

// Solid angle, sr, that the triangle (a, b, c) subtends at the origin, signed by its winding:
// positive when its normal (b − a) × (c − a) points away from the origin, so the triangles of an
// outward-wound mesh around the origin add up to 4π (Van Oosterom & Strackee 1983, IEEE Trans.
// Biomed. Eng. 30(2)).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c);

// The winding number of a closed, outward-wound mesh about a point: 1 inside, 0 outside. Unlike
// ray casting it needs no care for rays through edges or vertices. On the surface it is not well
// defined (a triangle seen edge-on subtends ±2π or 0); ask distance_to_surface there.
double winding_number(const TriangleMesh& mesh, const Vec3& point);

// A sphere enclosing every vertex of a mesh: centred on the vertices' bounding box, radius to the
// farthest vertex. Not the smallest such sphere, but cheap and tight enough for quick rejects.
struct BoundingSphere {
  Vec3 centre = Vec3::Zero();
  double radius_m = 0.0;
};
BoundingSphere bounding_sphere(const TriangleMesh& mesh);

}  // namespace brisance::geometry
