// Tests of sim/geometry/polygon: area and centroid, simplicity, point location, ear clipping of
// concave polygons with collinear runs, prism extrusion, closed-form prism mass properties
// against the mesh integrator, and front-face panels.
#include "sim/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace brisance::geometry {
namespace {

Polygon rectangle(double w, double h, const Vec2& origin = Vec2::Zero()) {
  return {origin, origin + Vec2(w, 0), origin + Vec2(w, h), origin + Vec2(0, h)};
}

// An L: the 2 × 2 square minus its upper-right unit square, area 3.
Polygon l_shape() {
  return {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
}

// A comb of `teeth` teeth with every edge cut into half-unit steps, as crack polylines on a grid
// produce: long collinear runs and deep concavities. Tooth t spans x in [2t + 1, 2t + 2] up to
// y = 6; the gaps between teeth go down to y = 2.
Polygon staircase_comb(int teeth) {
  std::vector<Vec2> corners = {{0, 0}, {2.0 * teeth, 0}};
  for (int t = teeth; t-- > 0;) {
    corners.emplace_back(2.0 * t + 2, 6);
    corners.emplace_back(2.0 * t + 1, 6);
    corners.emplace_back(2.0 * t + 1, 2);
    corners.emplace_back(2.0 * t, 2);
  }
  Polygon p;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec2 from = corners[i];
    const Vec2 d = corners[(i + 1) % corners.size()] - from;
    const int steps = static_cast<int>(std::lround(2.0 * d.norm()));
    for (int k = 0; k < steps; ++k)
      p.push_back(from + d * (static_cast<double>(k) / steps));
  }
  return p;
}

// A random star-shaped polygon around the origin with n vertices, radii in [0.3, 1].
Polygon random_star(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  Polygon p;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.3 + 0.7 * static_cast<double>(engine() >> 11) * 0x1.0p-53;
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    p.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return p;
}

double triangle_area(const Polygon& p, const std::array<std::uint32_t, 3>& t) {
  const Vec2 u = p[t[1]] - p[t[0]];
  const Vec2 v = p[t[2]] - p[t[0]];
  return 0.5 * (u.x() * v.y() - u.y() * v.x());
}

// Triangles are CCW, cover exactly the polygon's area and each lies inside it.
void expect_valid_triangulation(const Polygon& p) {
  const auto triangles = triangulate(p);
  ASSERT_FALSE(triangles.empty());
  double sum = 0.0;
  for (const auto& t : triangles) {
    const double a = triangle_area(p, t);
    EXPECT_GT(a, 0.0);
    sum += a;
    const Vec2 c = (p[t[0]] + p[t[1]] + p[t[2]]) / 3.0;
    EXPECT_TRUE(contains(p, c)) << c.transpose();
  }
  EXPECT_NEAR(sum, std::abs(signed_area(p)), 1e-12 * std::abs(signed_area(p)));
}

TEST(Polygon, AreaAndCentroid) {
  EXPECT_DOUBLE_EQ(signed_area(l_shape()), 3.0);
  Polygon cw = l_shape();
  std::reverse(cw.begin(), cw.end());
  EXPECT_DOUBLE_EQ(signed_area(cw), -3.0);
  // Two unit squares at x ∈ [0, 2] × [0, 1] (centre (1, 0.5)) and one at [0, 1] × [1, 2].
  const Vec2 expected((2.0 * Vec2(1.0, 0.5) + Vec2(0.5, 1.5)) / 3.0);
  EXPECT_NEAR((centroid(l_shape()) - expected).norm(), 0.0, 1e-15);
  EXPECT_NEAR((centroid(cw) - expected).norm(), 0.0, 1e-15);
}

TEST(Polygon, SimpleAcceptsCollinearRunsAndRejectsTouchingOrFolding) {
  EXPECT_TRUE(is_simple(l_shape()));
  EXPECT_TRUE(is_simple(staircase_comb(5)));
  EXPECT_TRUE(is_simple(Polygon{{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}));
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {2, 2}, {2, 0}, {0, 2}}));          // bow tie
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {2, 0}, {1, 0}, {1, 1}}));          // folds back
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {1, 0}, {1, 0}, {1, 1}}));          // zero-length edge
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {4, 0}, {4, 4}, {2, 0}, {0, 4}}));  // touches an edge
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {1, 0}}));
  EXPECT_FALSE(is_simple(Polygon{{0, 0}, {1, 0}, {2, 0}}));  // no area
}

TEST(Polygon, ContainsFollowsTheOutline) {
  EXPECT_TRUE(contains(l_shape(), {0.5, 1.5}));
  EXPECT_TRUE(contains(l_shape(), {1.5, 0.5}));
  EXPECT_FALSE(contains(l_shape(), {1.5, 1.5}));  // the missing corner
  EXPECT_FALSE(contains(l_shape(), {-0.1, 0.5}));
}

TEST(Polygon, RemoveCollinearKeepsTheCorners) {
  const Polygon comb = staircase_comb(3);
  const Polygon reduced = remove_collinear(comb);
  EXPECT_LT(reduced.size(), comb.size());
  EXPECT_EQ(reduced.size(), 2u + 4u * 3u);  // two base corners, four per tooth
  EXPECT_DOUBLE_EQ(signed_area(reduced), signed_area(comb));
}

TEST(Triangulate, ConvexConcaveAndCollinear) {
  expect_valid_triangulation(rectangle(2, 1));
  expect_valid_triangulation(l_shape());
  Polygon cw = l_shape();
  std::reverse(cw.begin(), cw.end());
  expect_valid_triangulation(cw);
  expect_valid_triangulation(staircase_comb(10));  // hundreds of mostly collinear vertices
  EXPECT_GT(staircase_comb(10).size(), 150u);
}

TEST(Triangulate, RandomStarsUpToSeveralHundredVertices) {
  for (std::uint64_t seed = 0; seed < 40; ++seed)
    expect_valid_triangulation(random_star(3 + seed * 10, seed));
}

TEST(Extrude, ClosedOutwardPrisms) {
  for (const Polygon& p : {rectangle(1, 2), l_shape(), staircase_comb(4), random_star(300, 7)}) {
    const TriangleMesh mesh = extrude(p, 0.01);
    EXPECT_EQ(check_closed_mesh(mesh), std::nullopt);
  }
  Polygon cw = l_shape();
  std::reverse(cw.begin(), cw.end());
  EXPECT_EQ(check_closed_mesh(extrude(cw, 0.5)), std::nullopt);
}

TEST(PrismMassProperties, BoxInClosedForm) {
  const double w = 0.6, h = 0.4, t = 0.01, rho = 2500.0;
  const MassProperties props = prism_mass_properties(rectangle(w, h, {1.0, 2.0}), t, rho);
  const double m = rho * w * h * t;
  EXPECT_NEAR(props.mass_kg, m, 1e-12 * m);
  EXPECT_NEAR((props.centre_of_mass - Vec3(1.3, 2.2, 0.0)).norm(), 0.0, 1e-14);
  EXPECT_NEAR(props.inertia_kg_m2(0, 0), m * (h * h + t * t) / 12.0, 1e-12);
  EXPECT_NEAR(props.inertia_kg_m2(1, 1), m * (w * w + t * t) / 12.0, 1e-12);
  EXPECT_NEAR(props.inertia_kg_m2(2, 2), m * (w * w + h * h) / 12.0, 1e-12);
  EXPECT_NEAR(props.inertia_kg_m2(0, 1), 0.0, 1e-15);
}

TEST(PrismMassProperties, MatchTheMeshIntegrator) {
  std::vector<Polygon> polygons = {l_shape(), staircase_comb(6), random_star(250, 3)};
  for (Polygon& p : polygons)  // far from the origin and rotated
    for (Vec2& v : p)
      v = Eigen::Rotation2Dd(0.3) * v + Vec2(5.0, -3.0);
  polygons.push_back(random_star(40, 11));
  for (const Polygon& p : polygons) {
    for (double t : {0.004, 0.5}) {
      const MassProperties closed = prism_mass_properties(p, t, 2500.0);
      const MassProperties mesh = mass_properties(extrude(p, t), 2500.0);
      EXPECT_NEAR(closed.mass_kg, mesh.mass_kg, 1e-9 * mesh.mass_kg);
      EXPECT_NEAR((closed.centre_of_mass - mesh.centre_of_mass).norm(), 0.0,
                  1e-9 * mesh.centre_of_mass.norm());
      const double scale = mesh.inertia_kg_m2.norm();
      EXPECT_NEAR((closed.inertia_kg_m2 - mesh.inertia_kg_m2).norm(), 0.0, 1e-9 * scale)
          << "thickness " << t;
    }
  }
}

TEST(FrontPanels, AtLeastFiveSummingToTheArea) {
  for (const Polygon& p : {Polygon{{0, 0}, {1, 0}, {0, 1}}, rectangle(2, 1), l_shape(),
                           staircase_comb(8), random_star(300, 5)}) {
    const auto panels = front_panels(p, 0.02);
    EXPECT_GE(panels.size(), 5u);
    EXPECT_LE(panels.size(), 16u);
    double sum = 0.0;
    Vec2 moment = Vec2::Zero();
    for (const Panel& panel : panels) {
      EXPECT_GT(panel.area_m2, 0.0);
      EXPECT_EQ(panel.outward_normal, Vec3::UnitZ());
      EXPECT_DOUBLE_EQ(panel.centre.z(), 0.01);
      sum += panel.area_m2;
      moment += panel.area_m2 * panel.centre.head<2>();
    }
    const double area = std::abs(signed_area(p));
    EXPECT_NEAR(sum, area, 1e-12 * area);
    // Uniform pressure on the panels has the torque of uniform pressure on the face.
    EXPECT_NEAR((moment / sum - centroid(p)).norm(), 0.0, 1e-12);
  }
  const auto triangle = front_panels(Polygon{{0, 0}, {1, 0}, {0, 1}}, 0.02);
  EXPECT_EQ(triangle.size(), 5u);
  EXPECT_NEAR(triangle.front().face_half_size_m, 0.5 * std::sqrt(0.5), 1e-15);
}

TEST(MinimalWidth, OfRectanglesAndTriangles) {
  EXPECT_NEAR(minimal_width(rectangle(3, 1)), 1.0, 1e-15);
  EXPECT_NEAR(minimal_width(l_shape()), 2.0, 1e-15);
}

}  // namespace
}  // namespace brisance::geometry
