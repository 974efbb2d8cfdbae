// Tests of the scene limits (sim/scene/checks and the section parsers): object, charge, vertex,
// panel and frame-sample counts.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/scene/generators.hpp"
#include "sim/scene/scene.hpp"
#include "tests/sim/scene/scene_test_support.hpp"

namespace brisance::scene {
namespace {

using namespace test_support;
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Limits

TEST(SceneLimits, ObjectAndChargeCounts) {
  Limits limits;
  limits.max_objects = 2;
  limits.max_charges = 1;
  json doc = minimal_scene();
  for (int i = 1; i < 3; ++i) {
    json object = doc["objects"][0];
    object["name"] = "cube" + std::to_string(i);
    object["position"] = {2.0 * i, 0.5, 0};
    doc["objects"].push_back(object);
  }
  doc["charges"].push_back(doc["charges"][0]);
  const ParseResult result = parse_scene(doc, limits);
  ASSERT_EQ(result.errors.size(), 2u) << dump_errors(result);
  ASSERT_NE(find_error(result, "/objects"), nullptr);
  EXPECT_TRUE(contains(find_error(result, "/objects")->message, "max_objects = 2"));
  EXPECT_TRUE(contains(find_error(result, "/objects")->message, "3 objects"));
  ASSERT_NE(find_error(result, "/charges"), nullptr);
  EXPECT_TRUE(contains(find_error(result, "/charges")->message, "max_charges = 1"));
}

TEST(SceneLimits, GeneratorsAreCheckedBeforeTheyGenerate) {
  json doc = minimal_scene();
  json g = brick_wall_generator();
  g["position"] = {0, 0, 3};
  g["rows"] = 100000;
  g["columns"] = 100000;  // 10^10 bricks: must be refused without allocating them
  doc["generators"] = {g};
  const std::string message = single_error(doc, "/generators/0");
  EXPECT_TRUE(contains(message, "max_objects = 20000")) << message;

  // The explicit objects count towards the limit.
  Limits limits;
  limits.max_objects = 33;
  g["rows"] = 6;
  g["columns"] = 5;
  doc["generators"] = {g};
  single_error(doc, "/generators/0", limits);
  limits.max_objects = 34;
  EXPECT_EQ(parse_ok(doc, limits).objects.size(), 34u);
}

TEST(SceneLimits, MeshVertices) {
  Limits limits;
  limits.max_mesh_vertices = 3;
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  const std::string message = single_error(doc, "/objects/0/shape/vertices", limits);
  EXPECT_TRUE(contains(message, "max_mesh_vertices = 3")) << message;
  limits.max_mesh_vertices = 4;
  parse_ok(doc, limits);
}

TEST(SceneLimits, PanelsAreCountedAsTheEngineCutsThem) {
  json doc = minimal_scene();
  doc["simulation"]["max_panel_area"] = 10;  // every face of the cube is one panel
  Limits limits;
  limits.max_panels = 6;
  parse_ok(doc, limits);
  limits.max_panels = 5;
  EXPECT_TRUE(contains(single_error(doc, "", limits), "max_panels"));

  // Finer panels: the count is make_panels' own.
  doc["simulation"]["max_panel_area"] = 0.05;
  const std::size_t panels = geometry::make_panels(geometry::make_box(Vec3::Ones()), 0.05).size();
  ASSERT_GT(panels, 6u);
  limits.max_panels = panels;
  parse_ok(doc, limits);
  limits.max_panels = panels - 1;
  single_error(doc, "", limits);

  // Panels of all objects add up (two equal cubes: twice the panels).
  json second = doc["objects"][0];
  second["name"] = "cube2";
  second["position"] = {3, 0.5, 0};
  doc["objects"].push_back(second);
  limits.max_panels = 2 * panels;
  parse_ok(doc, limits);
  limits.max_panels = 2 * panels - 1;
  single_error(doc, "", limits);
}

TEST(SceneLimits, TooManyPanelsIsOneErrorAndStopsCounting) {
  // Forty large boxes of different sizes cut into panels of 1 mm^2: each face hits make_panels'
  // subdivision cap, and the count passes the default limit after a few boxes.
  json doc = minimal_scene();
  for (int i = 0; i < 40; ++i) {
    doc["objects"].push_back({{"name", "slab" + std::to_string(i)},
                              {"shape", {{"type", "box"}, {"size", {10.0 + i, 1, 10}}}},
                              {"position", {0, 0.5, 20.0 + 12.0 * i}},
                              {"mass", 100}});
  }
  doc["simulation"]["max_panel_area"] = 1e-6;
  EXPECT_TRUE(contains(single_error(doc, ""), "max_panels"));
}

TEST(SceneLimits, FrameSamples) {
  json doc = minimal_scene();  // 2 s at 30 frames/s: 61 frames of 1 body
  Limits limits;
  limits.max_frame_samples = 61;
  parse_ok(doc, limits);
  limits.max_frame_samples = 60;
  const std::string message = single_error(doc, "/simulation", limits);
  EXPECT_TRUE(contains(message, "max_frame_samples = 60")) << message;
  EXPECT_TRUE(contains(message, "61 frames")) << message;
}

}  // namespace
}  // namespace brisance::scene
