// Tests of geometry::count_panels: it must give exactly make_panels(mesh, area).size() for every
// mesh and limit, including subdivided faces and the per-face cap of 4^8 pieces.
#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "sim/geometry/mesh.hpp"
#include "sim/geometry/polygon.hpp"

namespace brisance::geometry {
namespace {

// Meshes of every kind make_panels meets: boxes (a brick, a pane, a slab), a tetrahedron with a
// slanted face, prisms of convex and concave outlines (many coplanar triangles per face), a
// folded box, and a turned, far-away one.
std::vector<std::pair<std::string, TriangleMesh>> sample_meshes() {
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  meshes.emplace_back("unit box", make_box(Vec3(1, 1, 1)));
  meshes.emplace_back("brick", make_box(Vec3(0.4, 0.15, 0.1)));
  meshes.emplace_back("pane", make_box(Vec3(1.2, 0.9, 0.006)));
  meshes.emplace_back("slab", make_box(Vec3(20, 0.3, 8)));
  TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vec3::Zero(), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 3)};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  meshes.emplace_back("tetrahedron", tetrahedron);
  meshes.emplace_back(
      "hexagonal prism",
      extrude(Polygon{{1, 0}, {0.5, 0.866}, {-0.5, 0.866}, {-1, 0}, {-0.5, -0.866}, {0.5, -0.866}},
              0.2));
  meshes.emplace_back(
      "U prism",
      extrude(Polygon{{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0.5));
  TriangleMesh folded = make_box(Vec3(1, 1, 1));
  folded.vertices[7] += Vec3::Constant(1e-3);
  meshes.emplace_back("folded box", folded);
  TriangleMesh far = meshes[6].second;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  for (Vec3& vertex : far.vertices)
    vertex = rotation * vertex + Vec3(1000.0, -3000.0, 2000.0);
  meshes.emplace_back("turned far U prism", far);
  return meshes;
}

TEST(CountPanels, EqualsMakePanelsOverMeshesAndLimits) {
  std::mt19937_64 random(20261124);
  std::uniform_real_distribution<double> exponent(-5.0, 2.0);
  for (const auto& [name, mesh] : sample_meshes()) {
    // Round limits (a face exactly at the limit is one panel), the default, and random ones.
    std::vector<double> areas = {1e3, 20 * 8, 1.0, 0.5, 0.25, 0.05, 0.01, 1e-3};
    for (int i = 0; i < 12; ++i)
      areas.push_back(std::pow(10.0, exponent(random)));
    for (double area : areas) {
      EXPECT_EQ(count_panels(mesh, area), make_panels(mesh, area).size())
          << name << ", max_panel_area " << area;
    }
  }
}

TEST(CountPanels, FollowsTheCellCap) {
  // A 1e-30 m^2 limit stops at 65536 cells per face.
  TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_LE(count_panels(tetrahedron, 1e-30), 4u * 65536u);
  EXPECT_EQ(count_panels(tetrahedron, 1e-30), make_panels(tetrahedron, 1e-30).size());
  // A box's rectangular faces fill their grids: 256 × 256 cells each.
  const TriangleMesh box = make_box(Vec3(1, 2, 3));
  EXPECT_EQ(count_panels(box, 1e-30), 6u * 65536u);
  EXPECT_EQ(count_panels(box, 1e-30), make_panels(box, 1e-30).size());
  EXPECT_EQ(count_panels(box, 1e-300), 6u * 65536u);
}

TEST(CountPanels, EmptyMeshHasNoPanels) {
  EXPECT_EQ(count_panels(TriangleMesh{}, 0.05), 0u);
}

}  // namespace
}  // namespace brisance::geometry
