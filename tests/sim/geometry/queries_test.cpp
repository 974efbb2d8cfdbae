// Tests of sim/geometry/queries against closed forms: nearest points of segments (2D and 3D),
// distances to triangles and mesh surfaces, solid angles, winding numbers and bounding spheres.
#include "sim/geometry/queries.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <gtest/gtest.h>

namespace brisance::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(NearestOnSegment, InteriorEndsAndZeroLength2D) {
  const Vec2 a(0, 0);
  const Vec2 b(4, 0);
  SegmentNearest nearest = nearest_on_segment(Vec2(1, 3), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 3.0);
  EXPECT_DOUBLE_EQ(nearest.t, 0.25);
  // Beyond b the nearest point is b; before a it is a (a 3-4-5 triangle each).
  nearest = nearest_on_segment(Vec2(7, 4), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 5.0);
  EXPECT_EQ(nearest.t, 1.0);
  nearest = nearest_on_segment(Vec2(-3, -4), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 5.0);
  EXPECT_EQ(nearest.t, 0.0);
  // A zero-length segment is its point, t = 0.
  nearest = nearest_on_segment(Vec2(4, 3), a, a);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 5.0);
  EXPECT_EQ(nearest.t, 0.0);
  EXPECT_EQ(distance_to_segment(Vec2(1, 3), a, b), 3.0);
}

TEST(NearestOnSegment, InteriorEndsAndZeroLength3D) {
  const Vec3 a(1, 1, 1);
  const Vec3 b(1, 1, 7);
  // Off the middle by (2, 2, 0): distance √8 at t = 1/2.
  SegmentNearest nearest = nearest_on_segment(Vec3(3, 3, 4), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, std::sqrt(8.0));
  EXPECT_DOUBLE_EQ(nearest.t, 0.5);
  nearest = nearest_on_segment(Vec3(1, 1, 10), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 3.0);
  EXPECT_EQ(nearest.t, 1.0);
  nearest = nearest_on_segment(Vec3(1, 4, -3), a, b);
  EXPECT_DOUBLE_EQ(nearest.distance_m, 5.0);
  EXPECT_EQ(nearest.t, 0.0);
  EXPECT_DOUBLE_EQ(distance_to_segment(Vec3(2, 1, 1), b, b), std::sqrt(37.0));
}

TEST(NearestOnSegment, TwoAndThreeDimensionsAgreeBitForBit) {
  // The same segment in the plane z = 0 must round alike in both overloads.
  const Vec2 p(0.3, 0.7), a(-0.1, 0.2), b(1.3, -0.4);
  const SegmentNearest flat = nearest_on_segment(p, a, b);
  const SegmentNearest space =
      nearest_on_segment(Vec3(p.x(), p.y(), 0.0), Vec3(a.x(), a.y(), 0.0), Vec3(b.x(), b.y(), 0.0));
  EXPECT_EQ(flat.distance_m, space.distance_m);
  EXPECT_EQ(flat.t, space.t);
}

TEST(DistanceToTriangle, PlaneEdgesAndCorners) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(0.25, 0.25, 2), a, b, c), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(0.25, 0.25, -3), a, b, c), 3.0);      // either side
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(0.5, -1, 0), a, b, c), 1.0);          // edge ab
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(1, 1, 0), a, b, c), std::sqrt(0.5));  // edge bc
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(4, 0, 4), a, b, c), 5.0);             // corner b
  // The winding does not matter.
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(0.25, 0.25, 2), a, c, b), 2.0);
}

TEST(DistanceToTriangle, DegenerateTriangleIsItsEdges) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear: no plane
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(1.5, 2, 0), a, b, c), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_triangle(Vec3(5, 0, 4), a, b, c), 5.0);
}

TEST(DistanceToSurface, BoxFromInsideOutsideAndEmpty) {
  const TriangleMesh box = make_box(Vec3(2, 4, 6));
  EXPECT_DOUBLE_EQ(distance_to_surface(box, Vec3::Zero()), 1.0);  // the nearest faces are ±x
  EXPECT_DOUBLE_EQ(distance_to_surface(box, Vec3(0.5, 1.5, 0)), 0.5);
  EXPECT_DOUBLE_EQ(distance_to_surface(box, Vec3(4, 0, 0)), 3.0);
  EXPECT_DOUBLE_EQ(distance_to_surface(box, Vec3(2, 3, 0)), std::sqrt(2.0));  // edge
  EXPECT_DOUBLE_EQ(distance_to_surface(box, Vec3(1, 2, 3)), 0.0);             // corner
  EXPECT_EQ(distance_to_surface(TriangleMesh{}, Vec3::Zero()),
            std::numeric_limits<double>::infinity());
}

TEST(SolidAngle, OctantTriangleIsAnEighthOfTheSphere) {
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  EXPECT_NEAR(solid_angle(x, y, z), kPi / 2, 1e-15);
  EXPECT_NEAR(solid_angle(x, z, y), -kPi / 2, 1e-15);  // reversed winding
  // Scaling the triangle away from the origin along its rays changes nothing.
  EXPECT_NEAR(solid_angle(3 * x, 3 * y, 3 * z), kPi / 2, 1e-15);
  // A triangle whose plane holds the origin subtends nothing.
  EXPECT_EQ(solid_angle(x, y, Vec3(1, 1, 0)), 0.0);
}

TEST(WindingNumber, OneInsideZeroOutsideMinusOneReversed) {
  const TriangleMesh box = make_box(Vec3(1, 2, 3));
  EXPECT_NEAR(winding_number(box, Vec3::Zero()), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(box, Vec3(0.49, 0.99, -1.49)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(box, Vec3(0.51, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(box, Vec3(100, -50, 3)), 0.0, 1e-12);
  TriangleMesh inverted = box;
  for (auto& triangle : inverted.triangles)
    std::swap(triangle[1], triangle[2]);
  EXPECT_NEAR(winding_number(inverted, Vec3::Zero()), -1.0, 1e-12);

  // A tetrahedron: its centroid is inside, the reflection of it through a face is outside.
  TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_NEAR(winding_number(tetrahedron, Vec3::Constant(0.25)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(tetrahedron, Vec3(0.25, 0.25, -0.25)), 0.0, 1e-12);
}

TEST(BoundingSphere, CentredOnTheBoxReachingTheFarthestVertex) {
  TriangleMesh box = make_box(Vec3(2, 4, 4));
  BoundingSphere sphere = bounding_sphere(box);
  EXPECT_EQ(sphere.centre, Vec3::Zero());
  EXPECT_DOUBLE_EQ(sphere.radius_m, 3.0);  // √(1 + 4 + 4)
  for (Vec3& vertex : box.vertices)
    vertex += Vec3(10, -20, 5);
  sphere = bounding_sphere(box);
  EXPECT_TRUE(sphere.centre.isApprox(Vec3(10, -20, 5), 1e-15));
  EXPECT_DOUBLE_EQ(sphere.radius_m, 3.0);
  EXPECT_EQ(bounding_sphere(TriangleMesh{}).radius_m, 0.0);
}

}  // namespace
}  // namespace brisance::geometry
