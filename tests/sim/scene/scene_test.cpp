// Tests of sim/scene/scene: whole scenes parsed with their defaults, the error list (pointers,
// collection, order, escaping, wrong types) and the example scenes in scenes/.
#include "sim/scene/scene.hpp"

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
#include "tests/sim/scene/scene_test_support.hpp"

namespace brisance::scene {
namespace {

using namespace test_support;
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Success and defaults

TEST(SceneParse, MinimalSceneGetsEveryDefault) {
  const Scene scene = parse_ok(minimal_scene());
  ASSERT_EQ(scene.charges.size(), 1u);
  const ChargeSpec& charge = scene.charges[0];
  EXPECT_EQ(charge.position, Vec3(0, 1, -5));
  EXPECT_EQ(charge.mass_kg, 1.0);
  EXPECT_EQ(charge.explosive, "TNT");
  EXPECT_EQ(charge.tnt_factor, 1.0);
  EXPECT_EQ(charge.burst, blast::Burst::air);
  EXPECT_EQ(charge.surface_model, blast::SurfaceBurstModel::hemispherical);

  EXPECT_EQ(scene.environment.gravity_m_s2, Vec3(0, -9.81, 0));
  EXPECT_EQ(scene.environment.air_density_kg_m3, 1.225);
  EXPECT_EQ(scene.environment.ambient_pressure_pa, 101325.0);
  ASSERT_TRUE(scene.environment.ground.has_value());
  EXPECT_EQ(scene.environment.ground->height_m, 0.0);
  EXPECT_EQ(scene.environment.ground->friction, 0.5);
  EXPECT_EQ(scene.environment.ground->restitution, 0.2);

  ASSERT_EQ(scene.objects.size(), 1u);
  const ObjectSpec& cube = scene.objects[0];
  EXPECT_EQ(cube.name, "cube");
  EXPECT_EQ(cube.shape, ShapeType::box);
  EXPECT_EQ(cube.box_size_m, Vec3(1, 1, 1));
  EXPECT_EQ(cube.mesh.vertices.size(), 8u);
  EXPECT_EQ(cube.mesh.triangles.size(), 12u);
  EXPECT_EQ(cube.position, Vec3(0, 0.5, 0));
  EXPECT_TRUE(cube.orientation.isApprox(Quat::Identity()));
  EXPECT_EQ(cube.mass_kg, 10.0);
  EXPECT_EQ(cube.friction, 0.5);
  EXPECT_EQ(cube.drag_coefficient, 1.0);
  EXPECT_FALSE(cube.anchored);
  EXPECT_TRUE(cube.blocks);
  EXPECT_TRUE(cube.rotates);
  EXPECT_EQ(cube.material, "");

  const SimulationSpec& sim = scene.simulation;
  EXPECT_EQ(sim.duration_s, 2.0);
  EXPECT_EQ(sim.frame_rate_hz, 30.0);
  EXPECT_FALSE(sim.time_step_s.has_value());
  EXPECT_EQ(sim.tolerance, 1e-3);
  EXPECT_EQ(sim.seed, 0u);
  EXPECT_TRUE(sim.clearing);
  EXPECT_EQ(sim.occlusion, OcclusionMode::automatic);
  EXPECT_EQ(sim.integrator, Integrator::semi_implicit_euler);
  EXPECT_EQ(sim.pulse_shape, blast::PulseShape::friedlander);
  EXPECT_EQ(sim.max_panel_area_m2, 0.05);
  EXPECT_EQ(sim.linear_damping, 0.0);
  EXPECT_EQ(sim.angular_damping, 0.0);
  EXPECT_EQ(sim.rotation_factor, 1.0);
  EXPECT_TRUE(sim.sleep);
}

TEST(SceneParse, EveryFieldIsRead) {
  json doc = json::parse(R"({
    "charges": [{"position": [1, 2, -3], "mass": 4, "explosive": "RDX", "burst": "surface",
                 "burst_model": "factor_1_8"}],
    "environment": {"gravity": [0, -1.62, 0], "air_density": 0, "ambient_pressure": 90000,
                    "ground": {"height": -1, "friction": 0.8, "restitution": 0.5}},
    "objects": [{"name": "slab", "shape": {"type": "box", "size": [2, 1, 0.5]},
                 "position": [0, 0.5, 0], "orientation": [0, 0, 0, 1], "density": 100,
                 "friction": 0.3, "drag_coefficient": 1.5, "anchored": true, "blocks": false,
                 "rotates": false}],
    "simulation": {"duration": 3, "frame_rate": 60, "time_step": 0.001, "seed": 42,
                   "clearing": false, "occlusion": "off", "integrator": "rk4",
                   "pulse": "triangle_same_impulse", "max_panel_area": 0.2,
                   "linear_damping": 0.1, "angular_damping": 0.2, "rotation_factor": 0.5,
                   "sleep": false}
  })");
  const Scene scene = parse_ok(doc);
  const ChargeSpec& charge = scene.charges.at(0);
  EXPECT_EQ(charge.explosive, "RDX");
  EXPECT_DOUBLE_EQ(charge.tnt_factor, 1.185);
  EXPECT_EQ(charge.burst, blast::Burst::surface);
  EXPECT_EQ(charge.surface_model, blast::SurfaceBurstModel::factor_1_8);
  EXPECT_EQ(scene.environment.gravity_m_s2, Vec3(0, -1.62, 0));
  EXPECT_EQ(scene.environment.air_density_kg_m3, 0.0);
  EXPECT_EQ(scene.environment.ambient_pressure_pa, 90000.0);
  EXPECT_EQ(scene.environment.ground->height_m, -1.0);
  EXPECT_EQ(scene.environment.ground->friction, 0.8);
  EXPECT_EQ(scene.environment.ground->restitution, 0.5);
  const ObjectSpec& slab = scene.objects.at(0);
  EXPECT_NEAR(slab.mass_kg, 100.0, 1e-9);  // 100 kg/m^3 * 1 m^3
  EXPECT_EQ(slab.friction, 0.3);
  EXPECT_EQ(slab.drag_coefficient, 1.5);
  EXPECT_TRUE(slab.anchored);
  EXPECT_FALSE(slab.blocks);
  EXPECT_FALSE(slab.rotates);
  const SimulationSpec& sim = scene.simulation;
  EXPECT_EQ(sim.duration_s, 3.0);
  EXPECT_EQ(sim.frame_rate_hz, 60.0);
  EXPECT_EQ(sim.time_step_s, 0.001);
  EXPECT_EQ(sim.seed, 42u);
  EXPECT_FALSE(sim.clearing);
  EXPECT_EQ(sim.occlusion, OcclusionMode::off);
  EXPECT_EQ(sim.integrator, Integrator::rk4);
  EXPECT_EQ(sim.pulse_shape, blast::PulseShape::triangle_same_impulse);
  EXPECT_EQ(sim.max_panel_area_m2, 0.2);
  EXPECT_EQ(sim.linear_damping, 0.1);
  EXPECT_EQ(sim.angular_damping, 0.2);
  EXPECT_EQ(sim.rotation_factor, 0.5);
  EXPECT_FALSE(sim.sleep);
}

TEST(SceneParse, EnumChoicesMapToTheirValues) {
  const std::map<std::string, OcclusionMode> occlusion = {
      {"auto", OcclusionMode::automatic}, {"on", OcclusionMode::on}, {"off", OcclusionMode::off}};
  for (const auto& [text, mode] : occlusion) {
    json doc = minimal_scene();
    doc["simulation"]["occlusion"] = text;
    EXPECT_EQ(parse_ok(doc).simulation.occlusion, mode) << text;
  }
  const std::map<std::string, Integrator> integrators = {
      {"explicit_euler", Integrator::explicit_euler},
      {"semi_implicit_euler", Integrator::semi_implicit_euler},
      {"rk4", Integrator::rk4}};
  for (const auto& [text, integrator] : integrators) {
    json doc = minimal_scene();
    doc["simulation"]["integrator"] = text;
    EXPECT_EQ(parse_ok(doc).simulation.integrator, integrator) << text;
  }
  const std::map<std::string, blast::PulseShape> pulses = {
      {"friedlander", blast::PulseShape::friedlander},
      {"triangle_same_impulse", blast::PulseShape::triangle_same_impulse},
      {"triangle_same_period", blast::PulseShape::triangle_same_period}};
  for (const auto& [text, shape] : pulses) {
    json doc = minimal_scene();
    doc["simulation"]["pulse"] = text;
    EXPECT_EQ(parse_ok(doc).simulation.pulse_shape, shape) << text;
  }
  json doc = minimal_scene();
  doc["charges"][0]["burst_model"] = "hemispherical";
  doc["charges"][0]["burst"] = "air";
  const Scene scene = parse_ok(doc);
  EXPECT_EQ(scene.charges[0].burst, blast::Burst::air);
  EXPECT_EQ(scene.charges[0].surface_model, blast::SurfaceBurstModel::hemispherical);
}

TEST(SceneParse, TextIsParsedLikeTheDocument) {
  const ParseResult result = parse_scene_text(minimal_scene().dump());
  ASSERT_TRUE(result.scene.has_value()) << dump_errors(result);
  EXPECT_EQ(result.scene->objects.at(0).name, "cube");
}

// ---------------------------------------------------------------------------------------------
// Malformed input and the shape of errors

TEST(SceneErrors, ScenewideChecksSeeChargesAndObjectsWithOtherErrors) {
  // A wrong explosive or mass must not hide that the charge is buried, the object sunk in the
  // ground or the charge inside an object: validation lists every problem in one pass.
  json doc = minimal_scene();
  doc["environment"] = {{"ground", {{"height", 0}}}};
  doc["charges"] = {{{"position", {0, -1, -5}}, {"mass", 1}, {"explosive", "TNTX"}},
                    {{"position", {0, 0.5, 0}}, {"mass", -2}}};
  doc["objects"][0]["mass"] = -3;
  doc["objects"].push_back({{"name", "sunk"},
                            {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}},
                            {"position", {5, -2, 0}},
                            {"friction", -1},
                            {"mass", 1}});
  const ParseResult result = parse_scene(doc);
  EXPECT_FALSE(result.scene);
  for (const char* pointer :
       {"/charges/0/explosive", "/charges/0/position", "/charges/1/mass", "/charges/1/position",
        "/objects/0/mass", "/objects/1/friction", "/objects/1/position"}) {
    EXPECT_NE(find_error(result, pointer), nullptr) << pointer << " missing in\n"
                                                    << dump_errors(result);
  }
  EXPECT_EQ(result.errors.size(), 7u) << dump_errors(result);
}

// 300 objects with a negative mass are 300 problems: the first 100 are listed, then one line
// (pointer "") says how many more there were, so a huge bad scene is not a huge answer.
TEST(SceneErrors, LongListsStopAtAHundredAndSayHowManyMore) {
  json doc = minimal_scene();
  doc["objects"] = json::array();
  for (int i = 0; i < 300; ++i) {
    doc["objects"].push_back({{"name", "o" + std::to_string(i)},
                              {"shape", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
                              {"position", {0.0, 0.25, 0.0}},
                              {"mass", -1.0}});
  }
  const ParseResult result = parse_scene_text(doc.dump());
  ASSERT_EQ(result.errors.size(), 101u) << dump_errors(result);
  EXPECT_EQ(result.errors[0].pointer, "/objects/0/mass");
  EXPECT_EQ(result.errors[99].pointer, "/objects/99/mass");
  EXPECT_EQ(result.errors[100].pointer, "");
  EXPECT_TRUE(contains(result.errors[100].message, "and 200 more problems"))
      << result.errors[100].message;

  json& objects = doc["objects"];
  objects.erase(objects.begin() + 100, objects.end());  // exactly 100: listed whole
  EXPECT_EQ(parse_scene_text(doc.dump()).errors.size(), 100u);
}

// Found by tests/fuzz/fuzz_scene: a number out of a double's range escaped parse_scene_text as
// an exception.
TEST(SceneErrors, NumberTooLargeForADoubleIsOneErrorNotAnException) {
  for (const char* text :
       {R"({"charges": [1e400]})", R"({"simulation": {"duration": -1e99999}})"}) {
    const ParseResult result = parse_scene_text(text);
    ASSERT_EQ(result.errors.size(), 1u) << dump_errors(result);
    EXPECT_FALSE(result.scene.has_value());
    EXPECT_EQ(result.errors[0].pointer, "");
    EXPECT_TRUE(contains(result.errors[0].message, "too large")) << result.errors[0].message;
  }
}

TEST(SceneErrors, MalformedJsonIsOneErrorWithTheBytePosition) {
  const ParseResult result = parse_scene_text(R"({"charges": [}")");
  ASSERT_EQ(result.errors.size(), 1u) << dump_errors(result);
  EXPECT_FALSE(result.scene.has_value());
  EXPECT_EQ(result.errors[0].pointer, "");
  EXPECT_TRUE(contains(result.errors[0].message, "byte 14")) << result.errors[0].message;
  EXPECT_TRUE(contains(result.errors[0].message, "malformed JSON"));

  const ParseResult empty = parse_scene_text("");
  ASSERT_EQ(empty.errors.size(), 1u);
  EXPECT_EQ(empty.errors[0].pointer, "");
  EXPECT_TRUE(contains(empty.errors[0].message, "byte"));
}

TEST(SceneErrors, TopLevelMustBeAnObject) {
  for (const char* text : {"[]", "3", "\"scene\"", "null", "true"}) {
    const ParseResult result = parse_scene_text(text);
    ASSERT_EQ(result.errors.size(), 1u) << text;
    EXPECT_EQ(result.errors[0].pointer, "") << text;
    EXPECT_TRUE(contains(result.errors[0].message, "JSON object")) << text;
  }
}

TEST(SceneErrors, UnknownFieldsAreErrorsAtEveryDepth) {
  const std::pair<const char*, std::function<void(json&)>> cases[] = {
      {"/colour", [](json& d) { d["colour"] = "red"; }},
      {"/charges/0/yield", [](json& d) { d["charges"][0]["yield"] = 1; }},
      {"/environment/wind", [](json& d) { d["environment"]["wind"] = 1; }},
      {"/environment/ground/slope", [](json& d) { d["environment"]["ground"]["slope"] = 1; }},
      {"/objects/0/colour", [](json& d) { d["objects"][0]["colour"] = "red"; }},
      {"/objects/0/shape/sizee", [](json& d) { d["objects"][0]["shape"]["sizee"] = 1; }},
      {"/simulation/fps", [](json& d) { d["simulation"]["fps"] = 30; }},
      {"/charges/0/explosive/factor",
       [](json& d) {
         d["charges"][0]["explosive"] = {{"tnt_factor", 1}, {"factor", 1}};
       }},
      {"/generators/0/height",
       [](json& d) {
         json g = brick_wall_generator();
         g["position"] = {0, 0, 5};
         g["height"] = 2;
         d["generators"] = {g};
       }},
  };
  for (const auto& [pointer, edit] : cases) {
    json doc = minimal_scene();
    edit(doc);
    const std::string message = single_error(doc, pointer);
    EXPECT_TRUE(contains(message, "unknown field")) << pointer << ": " << message;
  }
}

TEST(SceneErrors, UnknownFieldMessageSuggestsTheCloseName) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"]["sizee"] = doc["objects"][0]["shape"]["size"];
  const std::string message = single_error(doc, "/objects/0/shape/sizee");
  EXPECT_TRUE(contains(message, "did you mean 'size'")) << message;
}

TEST(SceneErrors, PointerTokensAreEscaped) {
  json doc = minimal_scene();
  doc["a/b"] = 1;
  doc["m~n"] = 1;
  const ParseResult result = parse_scene(doc);
  EXPECT_NE(find_error(result, "/a~1b"), nullptr) << dump_errors(result);
  EXPECT_NE(find_error(result, "/m~0n"), nullptr) << dump_errors(result);
}

TEST(SceneErrors, AllErrorsAreCollected) {
  json doc = minimal_scene();
  doc["charges"][0]["mass"] = -1;
  doc["objects"][0]["shape"]["size"] = {1, 0, 1};
  doc["objects"][0]["friction"] = "high";
  doc["environment"]["air_density"] = -1;
  doc["simulation"]["duration"] = 0;
  doc["simulation"]["frame_rate"] = nullptr;
  doc["bogus"] = true;
  const ParseResult result = parse_scene(doc);
  EXPECT_FALSE(result.scene.has_value());
  for (const char* pointer :
       {"/charges/0/mass", "/objects/0/shape/size/1", "/objects/0/friction",
        "/environment/air_density", "/simulation/duration", "/simulation/frame_rate", "/bogus"}) {
    EXPECT_NE(find_error(result, pointer), nullptr) << "missing " << pointer << " in\n"
                                                    << dump_errors(result);
  }
  EXPECT_EQ(result.errors.size(), 7u) << dump_errors(result);
}

TEST(SceneErrors, ElementErrorsPointAtTheElement) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"]["size"] = {1, 0, 1};
  const std::string message = single_error(doc, "/objects/0/shape/size/1");
  EXPECT_TRUE(contains(message, "> 0")) << message;
  EXPECT_TRUE(contains(message, "got 0")) << message;

  doc = minimal_scene();
  doc["charges"][0]["position"] = {0, "up", -5};
  single_error(doc, "/charges/0/position/1");
}

TEST(SceneErrors, WrongTypesAndNullsAreRejected) {
  const std::pair<const char*, std::function<void(json&)>> cases[] = {
      {"/charges/0/mass", [](json& d) { d["charges"][0]["mass"] = "10"; }},
      {"/charges/0/mass", [](json& d) { d["charges"][0]["mass"] = nullptr; }},
      {"/charges/0/mass", [](json& d) { d["charges"][0]["mass"] = true; }},
      {"/charges/0/position",
       [](json& d) {
         d["charges"][0]["position"] = {0, 1};
       }},
      {"/charges/0/position", [](json& d) { d["charges"][0]["position"] = nullptr; }},
      {"/charges/0/position", [](json& d) { d["charges"][0]["position"] = "0 1 -5"; }},
      {"/charges/0/burst", [](json& d) { d["charges"][0]["burst"] = "ground"; }},
      {"/charges/0/burst", [](json& d) { d["charges"][0]["burst"] = 1; }},
      {"/charges/0/burst_model", [](json& d) { d["charges"][0]["burst_model"] = "x1.8"; }},
      {"/charges/0/explosive", [](json& d) { d["charges"][0]["explosive"] = 1.2; }},
      {"/charges/0", [](json& d) { d["charges"][0] = "bomb"; }},
      {"/environment", [](json& d) { d["environment"] = nullptr; }},
      {"/environment/gravity", [](json& d) { d["environment"]["gravity"] = -9.81; }},
      {"/environment/ground", [](json& d) { d["environment"]["ground"] = false; }},
      {"/objects/0/name", [](json& d) { d["objects"][0]["name"] = 7; }},
      {"/objects/0/name", [](json& d) { d["objects"][0]["name"] = ""; }},
      {"/objects/0/shape", [](json& d) { d["objects"][0]["shape"] = "box"; }},
      {"/objects/0/anchored", [](json& d) { d["objects"][0]["anchored"] = "yes"; }},
      {"/objects/0/blocks", [](json& d) { d["objects"][0]["blocks"] = 1; }},
      {"/objects/0/rotates", [](json& d) { d["objects"][0]["rotates"] = nullptr; }},
      {"/objects/0/material", [](json& d) { d["objects"][0]["material"] = 3; }},
      {"/objects/0", [](json& d) { d["objects"][0] = nullptr; }},
      {"/simulation", [](json& d) { d["simulation"] = 5; }},
      {"/simulation/clearing", [](json& d) { d["simulation"]["clearing"] = "no"; }},
      {"/simulation/sleep", [](json& d) { d["simulation"]["sleep"] = 0; }},
      {"/simulation/occlusion", [](json& d) { d["simulation"]["occlusion"] = true; }},
      {"/simulation/integrator", [](json& d) { d["simulation"]["integrator"] = "verlet"; }},
      {"/simulation/pulse", [](json& d) { d["simulation"]["pulse"] = "square"; }},
      {"/generators", [](json& d) { d["generators"] = json::object(); }},
      {"/generators/0", [](json& d) { d["generators"] = {1}; }},
  };
  for (const auto& [pointer, edit] : cases) {
    json doc = minimal_scene();
    edit(doc);
    const std::string message = single_error(doc, pointer);
    EXPECT_FALSE(message.empty()) << pointer;
  }
}

TEST(SceneErrors, NonFiniteNumbersAreRejected) {
  // JSON text cannot hold them, but a document built in code can.
  json doc = minimal_scene();
  doc["charges"][0]["mass"] = std::nan("");
  single_error(doc, "/charges/0/mass");
  doc = minimal_scene();
  doc["objects"][0]["position"][0] = INFINITY;
  single_error(doc, "/objects/0/position/0");
}

TEST(SceneErrors, EnumMessagesListTheChoicesAndSuggest) {
  json doc = minimal_scene();
  doc["simulation"]["integrator"] = "rk5";
  const std::string message = single_error(doc, "/simulation/integrator");
  EXPECT_TRUE(contains(message, "explicit_euler, semi_implicit_euler, rk4")) << message;
  EXPECT_TRUE(contains(message, "did you mean 'rk4'")) << message;
}

// ---------------------------------------------------------------------------------------------
// The example scenes in scenes/

// The source tree, from the build (__FILE__ is relative when ccache's base_dir is set).
std::filesystem::path repository_root() {
  return std::filesystem::path(BRISANCE_SOURCE_DIR);
}

ParseResult parse_file(const std::string& name) {
  const std::filesystem::path path = repository_root() / "scenes" / name;
  std::ifstream file(path);
  EXPECT_TRUE(file.good()) << "cannot open " << path;
  std::stringstream text;
  text << file.rdbuf();
  return parse_scene_text(text.str());
}

TEST(ExampleScenes, BrickWallIsTheThesisWall) {
  const ParseResult result = parse_file("brick_wall.json");
  ASSERT_TRUE(result.scene.has_value()) << dump_errors(result);
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.objects.size(), 33u);
  int full = 0;
  int half = 0;
  for (const ObjectSpec& brick : scene.objects) {
    if (brick.mass_kg == 10.0) ++full;
    if (brick.mass_kg == 5.0) ++half;
    // A plausible brick density (solid or perforated clay brick).
    const double density = brick.mass_kg / brick.box_size_m.prod();
    EXPECT_GT(density, 1250.0) << brick.name;
    EXPECT_LT(density, 2100.0) << brick.name;
    EXPECT_GE(lowest_y(brick), -1e-9) << brick.name;
  }
  EXPECT_EQ(full, 27);
  EXPECT_EQ(half, 6);
  ASSERT_EQ(scene.charges.size(), 1u);
  EXPECT_EQ(scene.charges[0].mass_kg, 100.0);
  EXPECT_EQ(scene.charges[0].explosive, "TNT");
  EXPECT_EQ(scene.charges[0].position.x(), 0.0);    // horizontally centred
  EXPECT_EQ(scene.charges[0].position.z(), -15.0);  // 15 m behind the wall
  EXPECT_GT(scene.charges[0].position.y(), 0.0);    // slightly above the wall's base
  EXPECT_LT(scene.charges[0].position.y(), 1.0);
  EXPECT_EQ(scene.simulation.duration_s, 2.0);
  EXPECT_EQ(scene.simulation.frame_rate_hz, 30.0);
}

TEST(ExampleScenes, BrickWallStrongHasAWeakerChargeAndMoreFriction) {
  const ParseResult strong = parse_file("brick_wall_strong.json");
  const ParseResult normal = parse_file("brick_wall.json");
  ASSERT_TRUE(strong.scene.has_value()) << dump_errors(strong);
  ASSERT_TRUE(normal.scene.has_value());
  ASSERT_EQ(strong.scene->objects.size(), normal.scene->objects.size());
  EXPECT_LT(strong.scene->charges.at(0).mass_kg, normal.scene->charges.at(0).mass_kg);
  for (std::size_t i = 0; i < strong.scene->objects.size(); ++i) {
    EXPECT_GT(strong.scene->objects[i].friction, normal.scene->objects[i].friction);
    EXPECT_EQ(strong.scene->objects[i].position, normal.scene->objects[i].position);
  }
}

TEST(ExampleScenes, ThreeBlocksParse) {
  const ParseResult result = parse_file("three_blocks.json");
  ASSERT_TRUE(result.scene.has_value()) << dump_errors(result);
  EXPECT_EQ(result.scene->objects.size(), 3u);
  EXPECT_EQ(result.scene->charges.size(), 1u);
}

}  // namespace
}  // namespace brisance::scene
