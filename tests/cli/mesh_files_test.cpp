// Tests of `file` shapes through `brisance run` and `brisance validate`: a crate from a GLB and
// the same crate from an OBJ, both next to the scene file, blown up by one charge; broken mesh
// files are refused with the reason at the shape's pointer.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli/commands.hpp"

namespace brisance::cli {
namespace {

using nlohmann::json;

const std::filesystem::path kAssets = std::filesystem::path(BRISANCE_SOURCE_DIR) / "tests/assets";

class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("brisance_mesh_files_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_ / "meshes");
    for (const char* name : {"crate.glb", "crate.obj", "open_crate.obj", "finned_crate.obj"})
      std::filesystem::copy_file(kAssets / name, folder_ / "meshes" / name,
                                 std::filesystem::copy_options::overwrite_existing);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  std::string write_scene(const json& scene) {
    const std::string path = (folder_ / "scene.json").string();
    std::ofstream(path) << scene.dump();
    return path;
  }

  // The one-line error `validate` ends with (the last problem, with its pointer).
  std::string validate_error(const json& scene) {
    const std::string path = write_scene(scene);
    std::ostringstream out;
    try {
      run_validate({path}, out);
    } catch (const UsageError& error) {
      return error.message;
    }
    ADD_FAILURE() << "the scene was valid: " << out.str();
    return {};
  }

  std::filesystem::path folder_;
};

json crate(const std::string& name, const json& shape, double x) {
  return {{"name", name}, {"shape", shape}, {"position", {x, 0.3, 0}}, {"density", 500}};
}

// No gravity, no ground, no drag: only the blast moves the crates.
json blast_scene(json objects) {
  return {{"charges", {{{"position", {0, 0.3, -3}}, {"mass", 2}}}},
          {"environment", {{"gravity", {0, 0, 0}}, {"ground", nullptr}, {"air_density", 0}}},
          {"objects", std::move(objects)},
          {"simulation", {{"duration", 0.05}, {"frame_rate", 100}}}};
}

TEST_F(MeshFiles, GlbAndObjCratesAreBlownAwayFromTheChargeWithTheirMass) {
  // The two crates sit mirrored about the charge (x = -2 m and x = +2 m), so they must fly
  // mirrored: away from the charge (+z) and outwards.
  const json scene = blast_scene(
      {crate("from_glb", {{"type", "file"}, {"path", "meshes/crate.glb"}, {"node", "Crate"}}, -2),
       crate("from_obj", {{"type", "file"}, {"path", "meshes/crate.obj"}}, 2)});
  const std::string scene_path = write_scene(scene);
  const std::string output = (folder_ / "result.json").string();
  std::ostringstream out;
  ASSERT_EQ(run_simulation({scene_path, "-o", output}, out), kExitOk);
  std::ifstream in(output);
  const json result = json::parse(in);

  ASSERT_EQ(result["bodies"].size(), 2u);
  for (const json& body : result["bodies"]) {
    // Density times volume; the files hold float32 coordinates (0.3 is 0.30000001).
    EXPECT_NEAR(body["mass"].get<double>(), 500.0 * 1.0 * 0.6 * 0.8, 1e-4) << body["name"];
    EXPECT_EQ(body["mesh"]["vertices"].size(), 8u) << body["name"];
  }
  const json& glb = result["final_state"][0]["linear_velocity"];
  const json& obj = result["final_state"][1]["linear_velocity"];
  EXPECT_GT(glb[2].get<double>(), 0.05);  // pushed away from the charge, m/s
  EXPECT_LT(glb[0].get<double>(), 0.0);   // and outwards
  EXPECT_GT(obj[0].get<double>(), 0.0);
  EXPECT_NEAR(glb[2].get<double>(), obj[2].get<double>(), 1e-6 * std::abs(obj[2].get<double>()));
  EXPECT_NEAR(glb[0].get<double>(), -obj[0].get<double>(), 1e-6 * std::abs(obj[2].get<double>()));
}

TEST_F(MeshFiles, WholeFileIsEveryNode) {
  // Crate (0.48 m^3) and pallet (0.12 m^3) together.
  const std::string path = write_scene(
      blast_scene({crate("both", {{"type", "file"}, {"path", "meshes/crate.glb"}}, 0)}));
  std::ostringstream out;
  EXPECT_EQ(run_validate({path}, out), kExitOk);
  EXPECT_NE(out.str().find("valid (1 objects"), std::string::npos) << out.str();
}

TEST_F(MeshFiles, BrokenFilesAreRefusedAtTheShape) {
  std::string message = validate_error(
      blast_scene({crate("open", {{"type", "file"}, {"path", "meshes/open_crate.obj"}}, 0)}));
  EXPECT_NE(message.find("/objects/0/shape: the mesh cannot be simulated: the mesh is open "
                         "(4 edges open)"),
            std::string::npos)
      << message;

  message = validate_error(
      blast_scene({crate("finned", {{"type", "file"}, {"path", "meshes/finned_crate.obj"}}, 0)}));
  EXPECT_NE(
      message.find("/objects/0/shape: the mesh cannot be simulated: the mesh is not manifold"),
      std::string::npos)
      << message;
  EXPECT_NE(message.find("shared by 4 triangles"), std::string::npos) << message;

  message = validate_error(blast_scene(
      {crate("lid", {{"type", "file"}, {"path", "meshes/crate.glb"}, {"node", "Lid"}}, 0)}));
  EXPECT_NE(message.find("/objects/0/shape: cannot read the mesh file"), std::string::npos)
      << message;
  EXPECT_NE(message.find("'Crate', 'Pallet'"), std::string::npos) << message;

  // Relative to the scene file, not to the working folder.
  message =
      validate_error(blast_scene({crate("lost", {{"type", "file"}, {"path", "crate.glb"}}, 0)}));
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;

  // Assets live in the HTTP service.
  message = validate_error(blast_scene({crate("asset", {{"type", "asset"}, {"asset", "a1"}}, 0)}));
  EXPECT_NE(message.find("/objects/0/shape/type"), std::string::npos) << message;
}

}  // namespace
}  // namespace brisance::cli
