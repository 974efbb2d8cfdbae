// Tests of sim/geometry/mesh: boxes, the closed-mesh check, exact mass properties against closed
// forms, and load panels (faces, subdivision, clearing half sizes).
#include "sim/geometry/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace brisance::geometry {
namespace {

using Vec2 = Eigen::Vector2d;
using Triangle = std::array<std::uint32_t, 3>;

// --- Meshes ----------------------------------------------------------------------------------

TriangleMesh transformed(TriangleMesh mesh, const Mat3& rotation, const Vec3& translation_m) {
  for (Vec3& v : mesh.vertices)
    v = rotation * v + translation_m;
  return mesh;
}

TriangleMesh translated(TriangleMesh mesh, const Vec3& translation_m) {
  return transformed(std::move(mesh), Mat3::Identity(), translation_m);
}

Triangle reversed(const Triangle& tri) {
  return {tri[0], tri[2], tri[1]};
}

Mat3 arbitrary_rotation() {
  return (Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()) *
          Eigen::AngleAxisd(-1.9, Vec3(-0.4, 0.1, 0.8).normalized()))
      .toRotationMatrix();
}

// The right tetrahedron with vertices 0, a e_x, b e_y, c e_z, wound outward.
TriangleMesh right_tetrahedron(double a, double b, double c) {
  TriangleMesh mesh;
  mesh.vertices = {Vec3::Zero(), Vec3(a, 0, 0), Vec3(0, b, 0), Vec3(0, 0, c)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

// The regular octahedron |x| + |y| + |z| <= r, one triangle per octant, wound outward.
TriangleMesh octahedron(double r) {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(r, 0, 0),  Vec3(-r, 0, 0), Vec3(0, r, 0),
                   Vec3(0, -r, 0), Vec3(0, 0, r),  Vec3(0, 0, -r)};
  for (int sx : {1, -1}) {
    for (int sy : {1, -1}) {
      for (int sz : {1, -1}) {
        const std::uint32_t x = sx > 0 ? 0 : 1;
        const std::uint32_t y = sy > 0 ? 2 : 3;
        const std::uint32_t z = sz > 0 ? 4 : 5;
        // (x, y, z) winds around (+, +, +); each negative axis mirrors the winding.
        if (sx * sy * sz > 0) {
          mesh.triangles.push_back({x, y, z});
        } else {
          mesh.triangles.push_back({x, z, y});
        }
      }
    }
  }
  return mesh;
}

// A prism: the counter-clockwise polygon (triangulated by `cap`) in the xy plane, extruded from
// z = 0 to z = height.
TriangleMesh extrude(const std::vector<Vec2>& polygon, const std::vector<Triangle>& cap,
                     double height_m) {
  TriangleMesh mesh;
  const auto n = static_cast<std::uint32_t>(polygon.size());
  for (const Vec2& p : polygon)
    mesh.vertices.emplace_back(p.x(), p.y(), 0.0);
  for (const Vec2& p : polygon)
    mesh.vertices.emplace_back(p.x(), p.y(), height_m);
  for (const Triangle& t : cap) {
    mesh.triangles.push_back(reversed(t));                     // bottom, facing −z
    mesh.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});  // top, facing +z
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({i, j, j + n});
    mesh.triangles.push_back({i, j + n, i + n});
  }
  return mesh;
}

// An L: the square [0,2]², less [1,2]², fanned from its reflex corner (1, 1).
TriangleMesh l_prism(double height_m) {
  return extrude({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}},
                 {{3, 4, 5}, {3, 5, 0}, {3, 0, 1}, {3, 1, 2}}, height_m);
}

// A U: [0,3]×[0,2] less the notch [1,2]×[1,2]. Its two arm ends both face +y at y = 2.
TriangleMesh u_prism(double height_m) {
  return extrude({{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}},
                 {{0, 1, 4}, {0, 4, 5}, {1, 2, 3}, {1, 3, 4}, {0, 5, 6}, {0, 6, 7}}, height_m);
}

// A box of edge `side` centred on the origin, every face a grid of n × n squares of two triangles,
// vertices shared along the box's edges.
TriangleMesh grid_box(double side_m, int n) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::uint32_t> index_of;
  const auto vertex = [&](const std::array<int, 3>& lattice) {
    const auto [it, inserted] =
        index_of.try_emplace(lattice, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) {
      const double cells = static_cast<double>(n);
      mesh.vertices.emplace_back(side_m * (lattice[0] / cells - 0.5),
                                 side_m * (lattice[1] / cells - 0.5),
                                 side_m * (lattice[2] / cells - 0.5));
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {-1, 1}) {
      // (u, v) in-plane with u × v along sign × axis, so quads (i,j) → (i+1,j) → … wind outward.
      int u = (axis + 1) % 3;
      int v = (axis + 2) % 3;
      if (sign < 0) std::swap(u, v);
      const auto at = [&](int i, int j) {
        std::array<int, 3> lattice{};
        lattice[axis] = sign > 0 ? n : 0;
        lattice[u] = i;
        lattice[v] = j;
        return vertex(lattice);
      };
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1),
                              d = at(i, j + 1);
          mesh.triangles.push_back({a, b, c});
          mesh.triangles.push_back({a, c, d});
        }
      }
    }
  }
  return mesh;
}

// --- Closed forms ----------------------------------------------------------------------------

// Solid cuboid of full edges (a, b, c) about its centre: I = m/12 diag(b²+c², a²+c², a²+b²)
// (any table of moments of inertia, e.g. Wikipedia "List of moments of inertia").
Mat3 box_inertia(double mass_kg, const Vec3& size_m) {
  const Vec3 sq = size_m.cwiseProduct(size_m);
  return (mass_kg / 12.0 * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y())).asDiagonal();
}

// Union of disjoint boxes (centre, size) of one density, combined with the parallel-axis
// (Steiner) theorem I = Σ I_i + m_i (d·d E − d dᵀ), d = c_i − com.
MassProperties union_of_boxes(const std::vector<std::pair<Vec3, Vec3>>& boxes, double density) {
  MassProperties total;
  for (const auto& [centre, size] : boxes) {
    total.volume_m3 += size.prod();
    total.centre_of_mass += size.prod() * centre;
  }
  total.mass_kg = density * total.volume_m3;
  total.centre_of_mass /= total.volume_m3;
  for (const auto& [centre, size] : boxes) {
    const double mass = density * size.prod();
    const Vec3 d = centre - total.centre_of_mass;
    total.inertia_kg_m2 +=
        box_inertia(mass, size) + mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  }
  return total;
}

::testing::AssertionResult matrices_near(const Mat3& actual, const Mat3& expected,
                                         double relative_tolerance) {
  const double error = (actual - expected).norm();
  if (error <= relative_tolerance * expected.norm()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "relative error " << error / expected.norm() << "\nactual:\n"
         << actual << "\nexpected:\n"
         << expected;
}

::testing::AssertionResult vectors_near(const Vec3& actual, const Vec3& expected,
                                        double tolerance) {
  if ((actual - expected).norm() <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

void expect_same_mass_properties(const MassProperties& actual, const MassProperties& expected,
                                 double relative_tolerance) {
  EXPECT_NEAR(actual.volume_m3, expected.volume_m3, relative_tolerance * expected.volume_m3);
  EXPECT_NEAR(actual.mass_kg, expected.mass_kg, relative_tolerance * expected.mass_kg);
  EXPECT_TRUE(vectors_near(actual.centre_of_mass, expected.centre_of_mass,
                           relative_tolerance * std::cbrt(expected.volume_m3)));
  EXPECT_TRUE(matrices_near(actual.inertia_kg_m2, expected.inertia_kg_m2, relative_tolerance));
}

// --- make_box --------------------------------------------------------------------------------

TEST(MakeBox, HasEightCornersAndTwelveOutwardTriangles) {
  const Vec3 size(1.0, 2.0, 3.0);
  const TriangleMesh box = make_box(size);
  ASSERT_EQ(box.vertices.size(), 8u);
  ASSERT_EQ(box.triangles.size(), 12u);
  std::set<std::tuple<double, double, double>> corners;
  for (const Vec3& v : box.vertices) {
    EXPECT_DOUBLE_EQ(std::abs(v.x()), 0.5);
    EXPECT_DOUBLE_EQ(std::abs(v.y()), 1.0);
    EXPECT_DOUBLE_EQ(std::abs(v.z()), 1.5);
    corners.emplace(v.x(), v.y(), v.z());
  }
  EXPECT_EQ(corners.size(), 8u);
  // Each triangle lies on a face: its normal is that face's axis and points away from the centre.
  for (const Triangle& t : box.triangles) {
    const Vec3& a = box.vertices[t[0]];
    const Vec3 normal = (box.vertices[t[1]] - a).cross(box.vertices[t[2]] - a).normalized();
    const Vec3 centroid = (a + box.vertices[t[1]] + box.vertices[t[2]]) / 3.0;
    Eigen::Index axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(std::abs(normal[axis]), 1.0, 1e-15);
    EXPECT_NEAR(std::abs(centroid[axis]), 0.5 * size[axis], 1e-15);
    EXPECT_GT(normal[axis] * centroid[axis], 0.0);
  }
  EXPECT_EQ(check_closed_mesh(box), std::nullopt);
}

// --- check_closed_mesh -----------------------------------------------------------------------

// The check's message, or a failure if it accepted the mesh.
std::string rejection(const TriangleMesh& mesh) {
  const auto message = check_closed_mesh(mesh);
  EXPECT_TRUE(message.has_value()) << "the mesh was accepted";
  return message.value_or("");
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CheckClosedMesh, AcceptsClosedOutwardMeshes) {
  EXPECT_EQ(check_closed_mesh(make_box(Vec3(1, 2, 3))), std::nullopt);
  EXPECT_EQ(check_closed_mesh(make_box(Vec3(1e-4, 2e-4, 1e-4))), std::nullopt);  // millimetric
  EXPECT_EQ(check_closed_mesh(translated(make_box(Vec3(1, 1, 1)), Vec3(1e4, -2e4, 3e4))),
            std::nullopt);
  EXPECT_EQ(check_closed_mesh(right_tetrahedron(1, 2, 3)), std::nullopt);
  EXPECT_EQ(check_closed_mesh(octahedron(0.5)), std::nullopt);
  EXPECT_EQ(check_closed_mesh(l_prism(0.5)), std::nullopt);
  EXPECT_EQ(check_closed_mesh(u_prism(0.5)), std::nullopt);
  EXPECT_EQ(check_closed_mesh(grid_box(1.0, 4)), std::nullopt);
}

TEST(CheckClosedMesh, AcceptsTwoSeparateClosedPieces) {
  TriangleMesh two = make_box(Vec3(1, 1, 1));
  const TriangleMesh other = translated(make_box(Vec3(1, 1, 1)), Vec3(3, 0, 0));
  const auto offset = static_cast<std::uint32_t>(two.vertices.size());
  two.vertices.insert(two.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Triangle& t : other.triangles)
    two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  EXPECT_EQ(check_closed_mesh(two), std::nullopt);
}

TEST(CheckClosedMesh, RejectsAnEmptyMesh) {
  TriangleMesh empty;
  EXPECT_TRUE(contains(rejection(empty), "no triangles"));
  empty.vertices = make_box(Vec3(1, 1, 1)).vertices;
  EXPECT_TRUE(contains(rejection(empty), "no triangles"));
}

TEST(CheckClosedMesh, RejectsAnIndexOutOfRange) {
  TriangleMesh box = make_box(Vec3(1, 1, 1));
  box.triangles[3][1] = 99;
  const std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "triangle 3 uses vertex 99")) << message;
  EXPECT_TRUE(contains(message, "8 vertices")) << message;
}

TEST(CheckClosedMesh, RejectsNonFiniteVertices) {
  TriangleMesh box = make_box(Vec3(1, 1, 1));
  box.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "vertex 2 is not finite")) << message;

  box = make_box(Vec3(1, 1, 1));
  box.vertices[5].z() = std::numeric_limits<double>::infinity();
  message = rejection(box);
  EXPECT_TRUE(contains(message, "vertex 5 is not finite")) << message;

  // Even a vertex no triangle uses: NaN input is never silently carried along.
  box = make_box(Vec3(1, 1, 1));
  box.vertices.emplace_back(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0);
  message = rejection(box);
  EXPECT_TRUE(contains(message, "vertex 8 is not finite")) << message;
}

TEST(CheckClosedMesh, RejectsDegenerateTriangles) {
  // Two corners moved onto each other: the first triangle using both collapses.
  TriangleMesh box = make_box(Vec3(1, 1, 1));
  box.vertices[7] = box.vertices[6];
  std::size_t first = 0;
  while (std::count(box.triangles[first].begin(), box.triangles[first].end(), 6u) == 0 ||
         std::count(box.triangles[first].begin(), box.triangles[first].end(), 7u) == 0)
    ++first;
  std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "triangle " + std::to_string(first) + " is degenerate")) << message;

  // A repeated index.
  box = make_box(Vec3(1, 1, 1));
  box.triangles[4] = {0, 0, 1};
  message = rejection(box);
  EXPECT_TRUE(contains(message, "triangle 4 is degenerate")) << message;

  // A sliver far thinner than 1e-12 of the squared size (3 m²).
  box = make_box(Vec3(1, 1, 1));
  box.vertices[7] = box.vertices[6] + Vec3(1e-14, 0, 0);
  message = rejection(box);
  EXPECT_TRUE(contains(message, "degenerate")) << message;
}

TEST(CheckClosedMesh, RejectsAnOpenMesh) {
  TriangleMesh box = make_box(Vec3(1, 1, 1));
  box.triangles.pop_back();
  std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "open")) << message;
  EXPECT_TRUE(contains(message, "3 edges open")) << message;  // the missing triangle's rim

  TriangleMesh single;
  single.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  single.triangles = {{0, 1, 2}};
  message = rejection(single);
  EXPECT_TRUE(contains(message, "edge (0, 1) of triangle 0")) << message;
  EXPECT_TRUE(contains(message, "open")) << message;
}

TEST(CheckClosedMesh, RejectsADuplicatedTriangleAsNonManifold) {
  TriangleMesh box = make_box(Vec3(1, 1, 1));
  box.triangles.push_back(box.triangles[3]);
  const std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "not manifold")) << message;
  EXPECT_TRUE(contains(message, "3 edges shared by more than two triangles")) << message;
  EXPECT_TRUE(contains(message, "3 triangles")) << message;
  EXPECT_TRUE(contains(message, "triangle 3")) << message;
  EXPECT_TRUE(contains(message, "triangle 12")) << message;
}

TEST(CheckClosedMesh, RejectsOneFlippedTriangleAsInconsistent) {
  for (std::size_t flipped : {0u, 5u, 11u}) {
    TriangleMesh box = make_box(Vec3(1, 2, 3));
    box.triangles[flipped] = reversed(box.triangles[flipped]);
    const std::string message = rejection(box);
    EXPECT_TRUE(contains(message, "inconsistent")) << message;
    EXPECT_TRUE(contains(message, "triangle " + std::to_string(flipped))) << message;
  }
}

TEST(CheckClosedMesh, RejectsInwardWinding) {
  TriangleMesh box = make_box(Vec3(1, 2, 3));
  for (Triangle& t : box.triangles)
    t = reversed(t);
  const std::string message = rejection(box);
  EXPECT_TRUE(contains(message, "inward")) << message;
  EXPECT_TRUE(contains(message, "-6")) << message;  // the signed volume
}

TEST(CheckClosedMesh, RejectsAClosedSurfaceWithoutVolume) {
  // Two triangles back to back: every edge used once each way, nothing inside.
  TriangleMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}, {0, 2, 1}};
  const std::string message = rejection(flat);
  EXPECT_TRUE(contains(message, "no volume")) << message;
}

// --- mass_properties -------------------------------------------------------------------------

TEST(MassProperties, BoxMatchesTheCuboidFormulas) {
  const Vec3 size(0.4, 1.0, 2.5);
  const double density = 2500.0;
  const MassProperties props = mass_properties(make_box(size), density);
  const double volume = 0.4 * 1.0 * 2.5;
  EXPECT_NEAR(props.volume_m3, volume, 1e-15);
  EXPECT_NEAR(props.mass_kg, density * volume, 1e-11);
  EXPECT_TRUE(vectors_near(props.centre_of_mass, Vec3::Zero(), 1e-15));
  EXPECT_TRUE(matrices_near(props.inertia_kg_m2, box_inertia(density * volume, size), 1e-14));
  // Principal axes are the mesh axes: no products of inertia.
  EXPECT_NEAR(props.inertia_kg_m2(0, 1), 0.0, 1e-12);
  EXPECT_NEAR(props.inertia_kg_m2(0, 2), 0.0, 1e-12);
  EXPECT_NEAR(props.inertia_kg_m2(1, 2), 0.0, 1e-12);
}

TEST(MassProperties, GridTriangulatedBoxIsStillTheBox) {
  const MassProperties props = mass_properties(grid_box(2.0, 4), 1000.0);
  expect_same_mass_properties(props, union_of_boxes({{Vec3::Zero(), Vec3(2, 2, 2)}}, 1000.0),
                              1e-13);
}

TEST(MassProperties, TranslationShiftsTheCentreAndKeepsTheInertia) {
  const TriangleMesh near = l_prism(0.3);
  const MassProperties at_origin = mass_properties(near, 7800.0);
  for (const Vec3& offset : {Vec3(1000.0, -2000.0, 1500.0), Vec3(-1e5, 3e4, 2e5)}) {
    const MassProperties far = mass_properties(translated(near, offset), 7800.0);
    EXPECT_NEAR(far.volume_m3, at_origin.volume_m3, 1e-9 * at_origin.volume_m3);
    EXPECT_TRUE(
        vectors_near(far.centre_of_mass, at_origin.centre_of_mass + offset, 1e-9 * offset.norm()));
    EXPECT_TRUE(matrices_near(far.inertia_kg_m2, at_origin.inertia_kg_m2, 1e-9));
  }
}

TEST(MassProperties, RotationTurnsTheInertiaTensor) {
  // Rigid-body transformation of the inertia tensor: I' = R I Rᵀ, com' = R com + t.
  const Vec3 size(1.0, 2.0, 3.0);
  const Mat3 rotation = arbitrary_rotation();
  const Vec3 translation(0.3, -4.0, 2.0);
  const MassProperties props =
      mass_properties(transformed(make_box(size), rotation, translation), 500.0);
  const double mass = 500.0 * 6.0;
  EXPECT_NEAR(props.volume_m3, 6.0, 1e-13);
  EXPECT_TRUE(vectors_near(props.centre_of_mass, translation, 1e-13));
  const Mat3 expected = rotation * box_inertia(mass, size) * rotation.transpose();
  EXPECT_TRUE(matrices_near(props.inertia_kg_m2, expected, 1e-13));
  EXPECT_TRUE(props.inertia_kg_m2.isApprox(props.inertia_kg_m2.transpose(), 1e-15));
  EXPECT_GT(std::abs(props.inertia_kg_m2(0, 1)), 1.0);  // the test does exercise products
}

TEST(MassProperties, RightTetrahedronMatchesDirichletIntegrals) {
  // Over the simplex x/a + y/b + z/c <= 1 Dirichlet's formula ∫ x^p y^q z^r = p! q! r! / (p+q+r+3)!
  // (scaled by a^(p+1) b^(q+1) c^(r+1)) gives V = abc/6, com = (a, b, c)/4, ∫x² = V a²/10,
  // ∫xy = V ab/20; about the centre of mass ∫x'² = 3 V a²/80 and ∫x'y' = −V ab/80, so
  // I_xx = 3 m (b² + c²)/80 and I_xy = −∫ρ x'y' = m ab/80.
  const double a = 1.0, b = 2.0, c = 3.0, density = 10.0;
  const MassProperties props = mass_properties(right_tetrahedron(a, b, c), density);
  const double volume = a * b * c / 6.0;
  const double m = density * volume;
  EXPECT_NEAR(props.volume_m3, volume, 1e-15);
  EXPECT_NEAR(props.mass_kg, m, 1e-13);
  EXPECT_TRUE(vectors_near(props.centre_of_mass, Vec3(a, b, c) / 4.0, 1e-15));
  Mat3 expected;
  expected << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,          //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  EXPECT_TRUE(matrices_near(props.inertia_kg_m2, expected, 1e-14));
  // A physical inertia tensor is positive definite.
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat3>(props.inertia_kg_m2).eigenvalues().minCoeff(), 0.0);
}

TEST(MassProperties, RegularOctahedronIsIsotropic) {
  // |x|+|y|+|z| <= r: V = 4r³/3 and, by cubic symmetry, I = m r²/5 about every axis
  // (8 simplices of ∫x² = r⁵/60 each: ∫(y² + z²) = 4r⁵/15).
  const double r = 0.7, density = 3.0;
  const MassProperties props = mass_properties(octahedron(r), density);
  const double volume = 4.0 * r * r * r / 3.0;
  EXPECT_NEAR(props.volume_m3, volume, 1e-15);
  EXPECT_TRUE(vectors_near(props.centre_of_mass, Vec3::Zero(), 1e-15));
  const Mat3 expected = density * volume * r * r / 5.0 * Mat3::Identity();
  EXPECT_TRUE(matrices_near(props.inertia_kg_m2, expected, 1e-14));
}

TEST(MassProperties, RightTriangularPrismMatchesTheLaminaFormulas) {
  // Right triangle legs a (x), b (y) extruded by h (z). Triangle lamina about its centroid:
  // ∫x'² dm = m a²/18, ∫x'y' dm = −m ab/36 (from ∫xy dA = a²b²/24); along z a rod, m h²/12.
  const double a = 0.6, b = 1.5, h = 0.25, density = 2.0;
  const MassProperties props =
      mass_properties(extrude({{0, 0}, {a, 0}, {0, b}}, {{0, 1, 2}}, h), density);
  const double m = density * a * b * h / 2.0;
  EXPECT_NEAR(props.volume_m3, a * b * h / 2.0, 1e-15);
  EXPECT_TRUE(vectors_near(props.centre_of_mass, Vec3(a / 3, b / 3, h / 2), 1e-15));
  Mat3 expected;
  expected << m * (b * b / 18 + h * h / 12), m * a * b / 36, 0.0,  //
      m * a * b / 36, m * (a * a / 18 + h * h / 12), 0.0,          //
      0.0, 0.0, m * (a * a + b * b) / 18;
  EXPECT_TRUE(matrices_near(props.inertia_kg_m2, expected, 1e-14));
}

TEST(MassProperties, ConcavePrismsEqualTheirBoxParts) {
  const double h = 0.4, density = 1200.0;
  // L = [0,2]×[0,1] + [0,1]×[1,2].
  expect_same_mass_properties(mass_properties(l_prism(h), density),
                              union_of_boxes({{Vec3(1.0, 0.5, h / 2), Vec3(2, 1, h)},
                                              {Vec3(0.5, 1.5, h / 2), Vec3(1, 1, h)}},
                                             density),
                              1e-13);
  // U = [0,3]×[0,1] + [0,1]×[1,2] + [2,3]×[1,2].
  expect_same_mass_properties(mass_properties(u_prism(h), density),
                              union_of_boxes({{Vec3(1.5, 0.5, h / 2), Vec3(3, 1, h)},
                                              {Vec3(0.5, 1.5, h / 2), Vec3(1, 1, h)},
                                              {Vec3(2.5, 1.5, h / 2), Vec3(1, 1, h)}},
                                             density),
                              1e-13);
}

TEST(MassProperties, ScalesLinearlyWithDensity) {
  const TriangleMesh mesh = u_prism(0.2);
  const MassProperties light = mass_properties(mesh, 1.0);
  const MassProperties heavy = mass_properties(mesh, 2700.0);
  EXPECT_EQ(light.volume_m3, heavy.volume_m3);
  EXPECT_EQ(light.centre_of_mass, heavy.centre_of_mass);
  EXPECT_TRUE(matrices_near(heavy.inertia_kg_m2, 2700.0 * light.inertia_kg_m2, 1e-15));
}

// --- surface_area ----------------------------------------------------------------------------

TEST(SurfaceArea, MatchesClosedForms) {
  EXPECT_NEAR(surface_area(make_box(Vec3(1, 2, 3))), 2 * (2 + 6 + 3), 1e-14);
  EXPECT_NEAR(surface_area(grid_box(1.0, 4)), 6.0, 1e-14);
  // Three right triangles and an equilateral one of side √2 for the unit right tetrahedron.
  EXPECT_NEAR(surface_area(right_tetrahedron(1, 1, 1)), 1.5 + std::sqrt(3.0) / 2, 1e-15);
  // L: two caps of 3 plus a perimeter of 8 times the height.
  EXPECT_NEAR(surface_area(l_prism(0.5)), 2 * 3 + 8 * 0.5, 1e-14);
}

// --- make_panels -----------------------------------------------------------------------------

double total_area(const std::vector<Panel>& panels) {
  double sum = 0.0;
  for (const Panel& p : panels)
    sum += p.area_m2;
  return sum;
}

// The panels whose normal is `normal`.
std::vector<Panel> facing(const std::vector<Panel>& panels, const Vec3& normal) {
  std::vector<Panel> out;
  for (const Panel& p : panels)
    if ((p.outward_normal - normal).norm() < 1e-9) out.push_back(p);
  return out;
}

const std::array<Vec3, 6> kAxes = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                                   -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};

TEST(MakePanels, UnitBoxGivesOnePanelPerFace) {
  const std::vector<Panel> panels = make_panels(make_box(Vec3(1, 1, 1)), 10.0);
  ASSERT_EQ(panels.size(), 6u);
  for (const Vec3& axis : kAxes) {
    const std::vector<Panel> face = facing(panels, axis);
    ASSERT_EQ(face.size(), 1u) << axis.transpose();
    EXPECT_NEAR(face[0].area_m2, 1.0, 1e-15);
    EXPECT_TRUE(vectors_near(face[0].centre, 0.5 * axis, 1e-15));
    EXPECT_NEAR(face[0].outward_normal.norm(), 1.0, 1e-15);
    EXPECT_NEAR(face[0].face_half_size_m, 0.5, 1e-15);
  }
}

TEST(MakePanels, HalfSizeIsHalfTheSmallerSideOfEachFace) {
  for (const Panel& p : make_panels(make_box(Vec3(0.1, 0.1, 0.1)), 1.0))
    EXPECT_NEAR(p.face_half_size_m, 0.05, 1e-15);

  // 1 × 2 × 3: the ±x faces are 2 × 3, the ±y faces 1 × 3, the ±z faces 1 × 2.
  const Mat3 rotation = arbitrary_rotation();
  for (const Mat3& r : {Mat3(Mat3::Identity()), rotation}) {
    const std::vector<Panel> panels =
        make_panels(transformed(make_box(Vec3(1, 2, 3)), r, Vec3(5, 6, 7)), 100.0);
    ASSERT_EQ(panels.size(), 6u);
    const std::array<double, 3> half_size = {1.0, 0.5, 0.5};
    const std::array<double, 3> area = {6.0, 3.0, 2.0};
    for (int axis = 0; axis < 3; ++axis) {
      for (double sign : {1.0, -1.0}) {
        const std::vector<Panel> face = facing(panels, sign * (r * Vec3::Unit(axis)));
        ASSERT_EQ(face.size(), 1u);
        EXPECT_NEAR(face[0].face_half_size_m, half_size[axis], 1e-12);
        EXPECT_NEAR(face[0].area_m2, area[axis], 1e-12);
        EXPECT_TRUE(vectors_near(face[0].centre,
                                 Vec3(5, 6, 7) + r * (sign * 0.5 * (axis + 1) * Vec3::Unit(axis)),
                                 1e-12));
      }
    }
  }
}

TEST(MakePanels, TriangularFacesUseTheirSmallestAltitude) {
  // Unit right tetrahedron: three right isosceles faces (smallest altitude 1/√2, onto the
  // hypotenuse) and one equilateral face of side √2 (altitude √6/2).
  const std::vector<Panel> panels = make_panels(right_tetrahedron(1, 1, 1), 10.0);
  ASSERT_EQ(panels.size(), 4u);
  for (const Vec3& axis : {Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)}) {
    const std::vector<Panel> face = facing(panels, axis);
    ASSERT_EQ(face.size(), 1u);
    EXPECT_NEAR(face[0].face_half_size_m, 0.5 / std::sqrt(2.0), 1e-15);
    EXPECT_NEAR(face[0].area_m2, 0.5, 1e-15);
  }
  const std::vector<Panel> slanted = facing(panels, Vec3(1, 1, 1).normalized());
  ASSERT_EQ(slanted.size(), 1u);
  EXPECT_NEAR(slanted[0].face_half_size_m, std::sqrt(6.0) / 4.0, 1e-15);
  EXPECT_TRUE(vectors_near(slanted[0].centre, Vec3(1, 1, 1) / 3.0, 1e-15));
}

TEST(MakePanels, LargeFacesAreCutByAGridCentredOnTheFace) {
  // A unit face below 0.1 m²: cells of side at most sqrt(0.1) = 0.316 m, so 4 × 4 cells of
  // 0.0625 m² per face.
  const TriangleMesh box = make_box(Vec3(1, 1, 1));
  const std::vector<Panel> panels = make_panels(box, 0.1);
  ASSERT_EQ(panels.size(), 96u);
  EXPECT_NEAR(total_area(panels), surface_area(box), 1e-12);
  for (const Vec3& axis : kAxes) {
    const std::vector<Panel> face = facing(panels, axis);
    ASSERT_EQ(face.size(), 16u);
    Vec3 area_moment = Vec3::Zero();
    std::set<std::tuple<double, double, double>> centres;
    for (const Panel& p : face) {
      EXPECT_NEAR(p.area_m2, 0.0625, 1e-15);
      EXPECT_NEAR(p.face_half_size_m, 0.5, 1e-15);
      EXPECT_NEAR(p.centre.dot(axis), 0.5, 1e-15);  // on the face plane
      // Cell centres at ±0.125 and ±0.375 across the face.
      for (int k = 0; k < 3; ++k) {
        if (std::abs(axis[k]) > 0.5) continue;
        const double c = std::abs(p.centre[k]);
        EXPECT_TRUE(std::abs(c - 0.125) < 1e-12 || std::abs(c - 0.375) < 1e-12) << c;
      }
      area_moment += p.area_m2 * p.centre;
      centres.emplace(p.centre.x(), p.centre.y(), p.centre.z());
    }
    EXPECT_EQ(centres.size(), 16u);  // no cell twice
    // The cells tile the face, so their area centroid is the face's.
    EXPECT_TRUE(vectors_near(area_moment, 0.5 * axis, 1e-15));
  }
}

TEST(MakePanels, GridCellsAreTheLargestThatFit) {
  const TriangleMesh box = make_box(Vec3(1, 1, 1));
  EXPECT_EQ(make_panels(box, 1.0).size(), 6u);     // a face of exactly the limit stays whole
  EXPECT_EQ(make_panels(box, 0.5).size(), 24u);    // side sqrt(0.5) = 0.71: 2 × 2 cells
  EXPECT_EQ(make_panels(box, 0.25).size(), 24u);   // side 0.5 exactly: still 2 × 2
  EXPECT_EQ(make_panels(box, 0.249).size(), 54u);  // 3 × 3
  for (double limit : {1.0, 0.5, 0.25, 0.124, 0.01}) {
    const std::vector<Panel> panels = make_panels(box, limit);
    EXPECT_NEAR(total_area(panels), 6.0, 1e-12) << limit;
    for (const Panel& p : panels)
      EXPECT_LE(p.area_m2, limit * (1 + 1e-12));
  }
}

TEST(MakePanels, PanelsDoNotDependOnTheTriangulation) {
  // The same box as 2 and as 32 triangles a face: the same panels, to rounding.
  const double limit = 0.07;
  std::vector<Panel> coarse = make_panels(make_box(Vec3(1, 1, 1)), limit);
  std::vector<Panel> fine = make_panels(grid_box(1.0, 4), limit);
  ASSERT_EQ(coarse.size(), fine.size());
  const auto order = [](const Panel& p, const Panel& q) {
    const auto key = [](const Panel& x) {
      return std::make_tuple(std::round(x.outward_normal.x() * 1e6),
                             std::round(x.outward_normal.y() * 1e6),
                             std::round(x.outward_normal.z() * 1e6), std::round(x.centre.x() * 1e9),
                             std::round(x.centre.y() * 1e9), std::round(x.centre.z() * 1e9));
    };
    return key(p) < key(q);
  };
  std::sort(coarse.begin(), coarse.end(), order);
  std::sort(fine.begin(), fine.end(), order);
  for (std::size_t i = 0; i < coarse.size(); ++i) {
    EXPECT_TRUE(vectors_near(coarse[i].centre, fine[i].centre, 1e-12)) << i;
    EXPECT_NEAR(coarse[i].area_m2, fine[i].area_m2, 1e-14) << i;
  }
  // A long plate face follows its principal axes: a 1 × 0.1 face in 0.01 m² cells is one row
  // of ten cells along its length, symmetric about its centre.
  const std::vector<Panel> plate = make_panels(make_box(Vec3(1.0, 0.1, 0.02)), 0.01);
  const std::vector<Panel> top = facing(plate, Vec3::UnitZ());
  ASSERT_EQ(top.size(), 10u);
  double first_moment_y = 0.0;
  for (const Panel& p : top) {
    EXPECT_NEAR(p.area_m2, 0.01, 1e-15);
    first_moment_y += p.area_m2 * p.centre.y();
  }
  EXPECT_NEAR(first_moment_y, 0.0, 1e-16);
}

TEST(MakePanels, CoplanarGridTrianglesFormOneFace) {
  const TriangleMesh box = grid_box(1.0, 4);  // 32 triangles per face
  std::vector<Panel> panels = make_panels(box, 2.0);
  ASSERT_EQ(panels.size(), 6u);
  for (const Vec3& axis : kAxes) {
    const std::vector<Panel> face = facing(panels, axis);
    ASSERT_EQ(face.size(), 1u);
    EXPECT_NEAR(face[0].area_m2, 1.0, 1e-14);
    EXPECT_TRUE(vectors_near(face[0].centre, 0.5 * axis, 1e-14));
    EXPECT_NEAR(face[0].face_half_size_m, 0.5, 1e-14);
  }
  // Too large for one panel: the grid of the face, not its triangles.
  panels = make_panels(box, 0.1);
  EXPECT_EQ(panels.size(), 96u);
  EXPECT_NEAR(total_area(panels), 6.0, 1e-12);
  for (const Panel& p : panels)
    EXPECT_NEAR(p.face_half_size_m, 0.5, 1e-14);
}

TEST(MakePanels, ConcaveFacesStayWholeAndDisconnectedCoplanarFacesStayApart) {
  const double h = 0.5;
  // L prism: 2 caps and 6 sides. The top L (area 3) has its centroid at (5/6, 5/6) and its
  // convex hull is 2 wide.
  const TriangleMesh l = l_prism(h);
  std::vector<Panel> panels = make_panels(l, 10.0);
  EXPECT_EQ(panels.size(), 8u);
  EXPECT_NEAR(total_area(panels), surface_area(l), 1e-13);
  const std::vector<Panel> top = facing(panels, Vec3::UnitZ());
  ASSERT_EQ(top.size(), 1u);
  EXPECT_NEAR(top[0].area_m2, 3.0, 1e-14);
  EXPECT_TRUE(vectors_near(top[0].centre, Vec3(5.0 / 6, 5.0 / 6, h), 1e-14));
  EXPECT_NEAR(top[0].face_half_size_m, 1.0, 1e-14);
  // The two +x sides (x = 2 and x = 1) are parallel but not coplanar.
  EXPECT_EQ(facing(panels, Vec3::UnitX()).size(), 2u);

  // U prism: the arm ends at y = 2 are coplanar but share no edge: two faces, 10 in all.
  const TriangleMesh u = u_prism(h);
  panels = make_panels(u, 10.0);
  EXPECT_EQ(panels.size(), 10u);
  std::vector<Panel> ends = facing(panels, Vec3::UnitY());
  ASSERT_EQ(ends.size(), 3u);  // the two arm ends and the bottom of the notch (y = 1)
  std::sort(ends.begin(), ends.end(),
            [](const Panel& p, const Panel& q) { return p.centre.x() < q.centre.x(); });
  EXPECT_TRUE(vectors_near(ends[0].centre, Vec3(0.5, 2.0, h / 2), 1e-14));
  EXPECT_TRUE(vectors_near(ends[1].centre, Vec3(1.5, 1.0, h / 2), 1e-14));
  EXPECT_TRUE(vectors_near(ends[2].centre, Vec3(2.5, 2.0, h / 2), 1e-14));
  for (const Panel& p : ends) {
    EXPECT_NEAR(p.area_m2, h, 1e-14);
    EXPECT_NEAR(p.face_half_size_m, h / 2, 1e-14);
  }
}

TEST(MakePanels, FoldedFacesAreSplitAndRoundingIsNot) {
  // Pushing the (+,+,+) corner outward along the diagonal folds the three faces around it along
  // their diagonals through that corner: 3 + 2 × 3 = 9 faces.
  const auto lifted_box = [](double lift_m) {
    TriangleMesh box = make_box(Vec3(1, 1, 1));
    box.vertices[7] += Vec3::Constant(lift_m);
    return box;
  };
  EXPECT_EQ(make_panels(lifted_box(1e-3), 10.0).size(), 9u);
  // 1e-8 m: normals agree within 1e-8 rad, but the fold is 10× the plane tolerance (1e-9 × √3 m).
  EXPECT_EQ(make_panels(lifted_box(1e-8), 10.0).size(), 9u);
  // 1e-11 m is rounding-sized: still one face per side.
  EXPECT_EQ(make_panels(lifted_box(1e-11), 10.0).size(), 6u);
}

TEST(MakePanels, FarFromTheOriginFacesAreStillFound) {
  const Mat3 rotation = arbitrary_rotation();
  const TriangleMesh far = transformed(grid_box(1.0, 4), rotation, Vec3(1000.0, -3000.0, 2000.0));
  const std::vector<Panel> panels = make_panels(far, 2.0);
  ASSERT_EQ(panels.size(), 6u);
  for (const Panel& p : panels) {
    EXPECT_NEAR(p.area_m2, 1.0, 1e-9);
    EXPECT_NEAR(p.face_half_size_m, 0.5, 1e-9);
    EXPECT_NEAR((p.centre - Vec3(1000.0, -3000.0, 2000.0)).norm(), 0.5, 1e-9);
  }
}

TEST(MakePanels, PathologicalLimitIsCappedPerFace) {
  // A 1e-30 m² limit would need ~1e30 cells per face; the grid is halved along both axes until
  // it has at most 65536 cells, and the panels still cover the surface exactly.
  const TriangleMesh tetrahedron = right_tetrahedron(1, 1, 1);
  const std::vector<Panel> panels = make_panels(tetrahedron, 1e-30);
  EXPECT_GT(panels.size(), 4u * 1000u);
  EXPECT_LE(panels.size(), 4u * 65536u);
  EXPECT_NEAR(total_area(panels), surface_area(tetrahedron), 1e-10);
}

TEST(MakePanels, IsDeterministic) {
  const TriangleMesh mesh = transformed(u_prism(0.3), arbitrary_rotation(), Vec3(1, 2, 3));
  const std::vector<Panel> first = make_panels(mesh, 0.05);
  const std::vector<Panel> second = make_panels(mesh, 0.05);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].centre, second[i].centre);
    EXPECT_EQ(first[i].outward_normal, second[i].outward_normal);
    EXPECT_EQ(first[i].area_m2, second[i].area_m2);
    EXPECT_EQ(first[i].face_half_size_m, second[i].face_half_size_m);
  }
}

}  // namespace
}  // namespace brisance::geometry
