// Tests of sim/io/mesh_import on the crates of tests/assets (written by make_crates.py): nodes,
// frames, joining of split vertices, and the closedness diagnosis of broken files.
#include "sim/io/mesh_import.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "sim/geometry/mesh.hpp"

namespace brisance::io {
namespace {

const std::filesystem::path kAssets = std::filesystem::path(BRISANCE_SOURCE_DIR) / "tests/assets";

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

geometry::Vec3 lowest(const geometry::TriangleMesh& mesh) {
  geometry::Vec3 low = mesh.vertices.front();
  for (const auto& v : mesh.vertices)
    low = low.cwiseMin(v);
  return low;
}

geometry::Vec3 highest(const geometry::TriangleMesh& mesh) {
  geometry::Vec3 high = mesh.vertices.front();
  for (const auto& v : mesh.vertices)
    high = high.cwiseMax(v);
  return high;
}

TEST(MeshImport, GlbNodeIsTakenInItsOwnFrameWithSplitVerticesJoined) {
  const MeshImport crate = import_mesh_file(kAssets / "crate.glb", "Crate");
  ASSERT_TRUE(crate.mesh) << crate.error;
  EXPECT_EQ(crate.nodes, (std::vector<std::string>{"Crate", "Pallet"}));
  // 24 vertices in the file (four per face, each with the face's normal), 8 corners here.
  EXPECT_EQ(crate.mesh->vertices.size(), 8u);
  EXPECT_EQ(crate.mesh->triangles.size(), 12u);
  EXPECT_EQ(geometry::check_closed_mesh(*crate.mesh), std::nullopt);
  // The node's own translation (x = 5 m) is dropped: the crate is centred on its origin.
  EXPECT_TRUE(lowest(*crate.mesh).isApprox(geometry::Vec3(-0.5, -0.3, -0.4), 1e-6));
  EXPECT_TRUE(highest(*crate.mesh).isApprox(geometry::Vec3(0.5, 0.3, 0.4), 1e-6));
  EXPECT_NEAR(geometry::mass_properties(*crate.mesh, 1.0).volume_m3, 1.0 * 0.6 * 0.8, 1e-6);
}

TEST(MeshImport, WholeGlbKeepsTheNodesWhereTheFilePutsThem) {
  const MeshImport all = import_mesh_file(kAssets / "crate.glb");
  ASSERT_TRUE(all.mesh) << all.error;
  EXPECT_EQ(geometry::check_closed_mesh(*all.mesh), std::nullopt);
  EXPECT_NEAR(geometry::mass_properties(*all.mesh, 1.0).volume_m3, 0.48 + 1.2 * 0.1 * 1.0, 1e-6);
  EXPECT_NEAR(highest(*all.mesh).x(), 5.5, 1e-6);  // the crate, at x = 5 m
  EXPECT_NEAR(lowest(*all.mesh).y(), -0.5, 1e-6);  // the pallet, at y = -0.45 m
}

TEST(MeshImport, BytesGiveWhatTheFileGives) {
  const MeshImport from_file = import_mesh_file(kAssets / "crate.glb", "Pallet");
  const MeshImport from_bytes =
      import_mesh(read_bytes(kAssets / "crate.glb"), MeshFormat::glb, "Pallet");
  ASSERT_TRUE(from_file.mesh && from_bytes.mesh) << from_file.error << from_bytes.error;
  EXPECT_EQ(from_file.mesh->vertices, from_bytes.mesh->vertices);
  EXPECT_EQ(from_file.mesh->triangles, from_bytes.mesh->triangles);
}

TEST(MeshImport, UnknownNodeListsTheNodesThereAre) {
  const MeshImport missing = import_mesh_file(kAssets / "crate.glb", "Lid");
  EXPECT_FALSE(missing.mesh);
  EXPECT_TRUE(contains(missing.error, "no node named 'Lid'")) << missing.error;
  EXPECT_TRUE(contains(missing.error, "'Crate', 'Pallet'")) << missing.error;
}

TEST(MeshImport, ObjCrateInMetres) {
  const MeshImport crate = import_mesh(read_bytes(kAssets / "crate.obj"), MeshFormat::obj);
  ASSERT_TRUE(crate.mesh) << crate.error;
  EXPECT_EQ(crate.mesh->vertices.size(), 8u);
  EXPECT_EQ(geometry::check_closed_mesh(*crate.mesh), std::nullopt);
  EXPECT_NEAR(geometry::mass_properties(*crate.mesh, 1.0).volume_m3, 0.48, 1e-6);
  EXPECT_TRUE(crate.error.empty());
  const MeshImport node = import_mesh_file(kAssets / "crate.obj", "Crate");
  ASSERT_TRUE(node.mesh) << node.error;
  EXPECT_EQ(node.mesh->vertices, crate.mesh->vertices);
}

TEST(MeshImport, OpenAndNonManifoldCratesAreDiagnosed) {
  const MeshImport open = import_mesh_file(kAssets / "open_crate.obj");
  ASSERT_TRUE(open.mesh) << open.error;
  const auto open_problem = geometry::check_closed_mesh(*open.mesh);
  ASSERT_TRUE(open_problem);
  EXPECT_TRUE(contains(*open_problem, "the mesh is open (4 edges open)")) << *open_problem;

  const MeshImport finned = import_mesh_file(kAssets / "finned_crate.obj");
  ASSERT_TRUE(finned.mesh) << finned.error;
  const auto finned_problem = geometry::check_closed_mesh(*finned.mesh);
  ASSERT_TRUE(finned_problem);
  EXPECT_TRUE(contains(*finned_problem, "not manifold")) << *finned_problem;
  EXPECT_TRUE(contains(*finned_problem, "shared by 4 triangles")) << *finned_problem;
}

TEST(MeshImport, UnreadableInputIsAnErrorNotACrash) {
  EXPECT_TRUE(contains(import_mesh("glTF garbage", MeshFormat::glb).error, "cannot read"));
  EXPECT_TRUE(contains(import_mesh("", MeshFormat::obj).error, "empty"));
  EXPECT_TRUE(contains(import_mesh_file(kAssets / "missing.glb").error, "no such file"));
  EXPECT_TRUE(contains(import_mesh_file(kAssets / "make_crates.py").error, "unknown mesh format"));
  EXPECT_EQ(parse_mesh_format("GLB"), MeshFormat::glb);
  EXPECT_EQ(parse_mesh_format("fbx"), std::nullopt);
}

}  // namespace
}  // namespace brisance::io
