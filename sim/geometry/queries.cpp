// sim/geometry/queries: distances to triangles and mesh surfaces, winding numbers and bounding
// spheres (see queries.hpp).
#include "sim/geometry/queries.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

namespace brisance::geometry {

double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a);
  const double twice_area = normal.norm();
  if (twice_area > 0.0) {
    const Vec3 n = normal / twice_area;
    const double height = (p - a).dot(n);
    const Vec3 q = p - height * n;
    // q is inside if it is on the inner side of all three edges.
    if ((b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
        (a - c).cross(q - c).dot(n) >= 0.0)
      return std::abs(height);
  }
  return std::min(
      {distance_to_segment(p, a, b), distance_to_segment(p, b, c), distance_to_segment(p, c, a)});
}

double distance_to_surface(const TriangleMesh& mesh, const Vec3& p) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& triangle : mesh.triangles) {
    nearest = std::min(
        nearest, distance_to_triangle(p, mesh.vertices[triangle[0]], mesh.vertices[triangle[1]],
                                      mesh.vertices[triangle[2]]));
  }
  return nearest;
}

double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm();
  const double lb = b.norm();
  const double lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(numerator, denominator);
}

double winding_number(const TriangleMesh& mesh, const Vec3& point) {
  double total = 0.0;
  for (const auto& triangle : mesh.triangles) {
    total += solid_angle(mesh.vertices[triangle[0]] - point, mesh.vertices[triangle[1]] - point,
                         mesh.vertices[triangle[2]] - point);
  }
  return total / (4.0 * std::numbers::pi);
}

BoundingSphere bounding_sphere(const TriangleMesh& mesh) {
  BoundingSphere sphere;
  if (mesh.vertices.empty()) return sphere;
  Vec3 low = mesh.vertices.front();
  Vec3 high = low;
  for (const Vec3& vertex : mesh.vertices) {
    low = low.cwiseMin(vertex);
    high = high.cwiseMax(vertex);
  }
  sphere.centre = 0.5 * (low + high);
  for (const Vec3& vertex : mesh.vertices)
    sphere.radius_m = std::max(sphere.radius_m, (vertex - sphere.centre).norm());
  return sphere;
}

}  // namespace brisance::geometry
