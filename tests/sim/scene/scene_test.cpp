// Tests of sim/scene: scene JSON parsing and validation, the generators and the materials table.
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

namespace brisance::scene {
namespace {

using json = nlohmann::json;

// A valid scene to start from: one charge 5 m in front of a 1 m cube resting on the ground.
json minimal_scene() {
  return json::parse(R"({
    "charges": [{"position": [0, 1, -5], "mass": 1}],
    "objects": [{"name": "cube", "shape": {"type": "box", "size": [1, 1, 1]},
                 "position": [0, 0.5, 0], "mass": 10}]
  })");
}

std::string dump_errors(const ParseResult& result) {
  std::string text;
  for (const ValidationError& error : result.errors)
    text += "  " + (error.pointer.empty() ? std::string("\"\"") : error.pointer) + ": " +
            error.message + "\n";
  return text;
}

const ValidationError* find_error(const ParseResult& result, const std::string& pointer) {
  for (const ValidationError& error : result.errors)
    if (error.pointer == pointer) return &error;
  return nullptr;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Parses and expects success.
Scene parse_ok(const json& document, const Limits& limits = {}) {
  ParseResult result = parse_scene(document, limits);
  EXPECT_TRUE(result.errors.empty()) << dump_errors(result);
  EXPECT_TRUE(result.scene.has_value());
  return result.scene.value_or(Scene{});
}

// Parses and expects exactly one error, at `pointer`; returns its message.
std::string single_error(const json& document, const std::string& pointer,
                         const Limits& limits = {}) {
  const ParseResult result = parse_scene(document, limits);
  EXPECT_FALSE(result.scene.has_value());
  EXPECT_EQ(result.errors.size(), 1u) << dump_errors(result);
  const ValidationError* error = find_error(result, pointer);
  EXPECT_NE(error, nullptr) << "no error at " << pointer << ", got:\n" << dump_errors(result);
  return error ? error->message : std::string();
}

// A unit tetrahedron (volume 1/6), wound counter-clockwise seen from outside.
json tetrahedron_shape() {
  return json::parse(R"({"type": "mesh",
    "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "triangles": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]})");
}

json brick_wall_generator() {
  return json::parse(R"({"type": "brick_wall", "name": "wall", "rows": 6, "columns": 5,
                         "brick_size": [0.4, 0.15, 0.1], "brick_mass": 10})");
}

// Lowest y of an object's vertices in the world.
double lowest_y(const ObjectSpec& object) {
  double lowest = INFINITY;
  for (const Vec3& v : object.mesh.vertices)
    lowest = std::min(lowest, (object.position + object.orientation * v).y());
  return lowest;
}

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
// Charges

TEST(SceneCharges, AtLeastOneChargeIsRequired) {
  json doc = minimal_scene();
  doc.erase("charges");
  EXPECT_TRUE(contains(single_error(doc, "/charges"), "required"));
  doc["charges"] = json::array();
  EXPECT_TRUE(contains(single_error(doc, "/charges"), "at least one charge"));
  doc["charges"] = json::object();
  single_error(doc, "/charges");
}

TEST(SceneCharges, PositionAndMassAreRequiredAndMassPositive) {
  json doc = minimal_scene();
  doc["charges"][0].erase("position");
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/position"), "required"));
  doc = minimal_scene();
  doc["charges"][0].erase("mass");
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/mass"), "required"));
  for (double mass : {0.0, -2.0}) {
    doc = minimal_scene();
    doc["charges"][0]["mass"] = mass;
    EXPECT_TRUE(contains(single_error(doc, "/charges/0/mass"), "> 0"));
  }
}

TEST(SceneCharges, ExplosiveNamesAreLookedUp) {
  json doc = minimal_scene();
  doc["charges"][0]["explosive"] = "comp-b";
  const Scene scene = parse_ok(doc);
  EXPECT_EQ(scene.charges[0].explosive, "Composition B");
  EXPECT_DOUBLE_EQ(scene.charges[0].tnt_factor, 1.148);
}

TEST(SceneCharges, UnknownExplosiveListsTheKnownOnes) {
  json doc = minimal_scene();
  doc["charges"][0]["explosive"] = "semtex-9000";
  const std::string message = single_error(doc, "/charges/0/explosive");
  EXPECT_TRUE(contains(message, "semtex-9000")) << message;
  EXPECT_TRUE(contains(message, "TNT")) << message;
  EXPECT_TRUE(contains(message, "RDX")) << message;
  EXPECT_TRUE(contains(message, "tnt_factor")) << message;
}

TEST(SceneCharges, CustomTntFactor) {
  json doc = minimal_scene();
  doc["charges"][0]["explosive"] = {{"tnt_factor", 1.3}};
  const Scene scene = parse_ok(doc);
  EXPECT_EQ(scene.charges[0].explosive, "custom");
  EXPECT_EQ(scene.charges[0].tnt_factor, 1.3);

  doc["charges"][0]["explosive"] = {{"tnt_factor", 0}};
  single_error(doc, "/charges/0/explosive/tnt_factor");
  doc["charges"][0]["explosive"] = json::object();
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/explosive/tnt_factor"), "required"));
}

TEST(SceneCharges, ChargeInsideAnObjectIsAnError) {
  json doc = minimal_scene();
  doc["charges"][0]["position"] = {0.1, 0.6, -0.2};
  const std::string message = single_error(doc, "/charges/0/position");
  EXPECT_TRUE(contains(message, "inside object 'cube'")) << message;
}

TEST(SceneCharges, ChargeOnTheSurfaceOrJustOutsideIsAllowed) {
  json doc = minimal_scene();
  doc["charges"][0]["position"] = {0, 1.0, 0};  // on the top face: a contact charge
  parse_ok(doc);
  doc["charges"][0]["position"] = {0.49, 0.99, -0.501};  // just in front of the front face
  parse_ok(doc);
}

TEST(SceneCharges, ChargesAnywhereOnTheSurfaceAreAllowed) {
  // Points on faces, edges and corners of a cube (turned, so nothing is axis-aligned), where the
  // winding number alone is ill-defined.
  json doc = minimal_scene();
  doc["objects"][0]["position"] = {0, 1, 0};
  const Quat turn(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  doc["objects"][0]["orientation"] = {turn.x(), turn.y(), turn.z(), turn.w()};
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-0.5, 0.5}) {
      for (double u : {-0.5, -0.3, 0.0, 0.1, 0.5}) {
        for (double v : {-0.5, -0.2, 0.0, 0.25, 0.5}) {
          Vec3 local;
          local[axis] = side;
          local[(axis + 1) % 3] = u;
          local[(axis + 2) % 3] = v;
          const Vec3 world = Vec3(0, 1, 0) + turn * local;
          doc["charges"][0]["position"] = {world.x(), world.y(), world.z()};
          const ParseResult result = parse_scene(doc);
          EXPECT_TRUE(result.errors.empty()) << local.transpose() << "\n" << dump_errors(result);
          // A millimetre inwards is inside.
          const Vec3 inner = Vec3(0, 1, 0) + turn * (0.998 * local);
          doc["charges"][0]["position"] = {inner.x(), inner.y(), inner.z()};
          EXPECT_EQ(parse_scene(doc).errors.size(), 1u) << local.transpose();
        }
      }
    }
  }
}

TEST(SceneCharges, InsideTestUsesTheObjectsOrientation) {
  // A 4 x 0.2 x 0.2 bar turned 90 degrees about y lies along z.
  json doc = minimal_scene();
  doc["objects"][0]["shape"]["size"] = {4, 0.2, 0.2};
  doc["objects"][0]["position"] = {0, 0.1, 0};
  const double s = std::sqrt(0.5);
  doc["objects"][0]["orientation"] = {0, s, 0, s};
  doc["charges"][0]["position"] = {1.5, 0.1, 0};  // inside the unrotated bar only
  parse_ok(doc);
  doc["charges"][0]["position"] = {0, 0.1, 1.5};  // inside the turned bar
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/position"), "'cube'"));
}

TEST(SceneCharges, InsideTestWorksForMeshes) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["charges"][0]["position"] = {0.1, 0.1, 0.1};
  single_error(doc, "/charges/0/position");
  // Inside the tetrahedron's bounding box but outside the tetrahedron.
  doc["charges"][0]["position"] = {0.6, 0.6, 0.6};
  parse_ok(doc);
}

TEST(SceneCharges, ChargeInsideAGeneratedBrick) {
  json doc = minimal_scene();
  doc["objects"] = json::array();
  doc["generators"] = {brick_wall_generator()};
  doc["charges"][0]["position"] = {0.0, 0.05, 0.0};
  const std::string message = single_error(doc, "/charges/0/position");
  EXPECT_TRUE(contains(message, "'wall/r0/b2'")) << message;
}

TEST(SceneCharges, BuriedChargeIsAnError) {
  json doc = minimal_scene();
  doc["charges"][0]["position"] = {0, -0.5, -5};
  const std::string message = single_error(doc, "/charges/0/position");
  EXPECT_TRUE(contains(message, "below the ground")) << message;
  doc["charges"][0]["position"] = {0, -0.0005, -5};  // within the 1 mm tolerance
  parse_ok(doc);
  doc["environment"]["ground"] = nullptr;
  doc["charges"][0]["position"] = {0, -0.5, -5};
  doc["objects"][0]["position"] = {0, -2, 0};
  parse_ok(doc);
}

// ---------------------------------------------------------------------------------------------
// Environment

TEST(SceneEnvironment, GroundNullMeansNoGround) {
  json doc = minimal_scene();
  doc["environment"]["ground"] = nullptr;
  EXPECT_FALSE(parse_ok(doc).environment.ground.has_value());
  doc["environment"]["ground"] = json::object();
  const Scene scene = parse_ok(doc);
  ASSERT_TRUE(scene.environment.ground.has_value());
  EXPECT_EQ(scene.environment.ground->friction, 0.5);
  EXPECT_EQ(scene.environment.ground->restitution, 0.2);
}

TEST(SceneEnvironment, RangesAreChecked) {
  const std::pair<const char*, std::function<void(json&)>> cases[] = {
      {"/environment/air_density", [](json& d) { d["environment"]["air_density"] = -0.1; }},
      {"/environment/ambient_pressure", [](json& d) { d["environment"]["ambient_pressure"] = 0; }},
      {"/environment/ground/friction",
       [](json& d) { d["environment"]["ground"]["friction"] = -0.1; }},
      {"/environment/ground/restitution",
       [](json& d) { d["environment"]["ground"]["restitution"] = 1.01; }},
      {"/environment/ground/restitution",
       [](json& d) { d["environment"]["ground"]["restitution"] = -0.01; }},
      {"/environment/ground/height", [](json& d) { d["environment"]["ground"]["height"] = "low"; }},
      {"/environment/gravity/2",
       [](json& d) {
         d["environment"]["gravity"] = {0, -9.81, "z"};
       }},
  };
  for (const auto& [pointer, edit] : cases) {
    json doc = minimal_scene();
    edit(doc);
    single_error(doc, pointer);
  }
  json doc = minimal_scene();
  doc["environment"]["ground"]["restitution"] = 1;
  doc["environment"]["ground"]["friction"] = 0;
  parse_ok(doc);
}

// ---------------------------------------------------------------------------------------------
// Objects

TEST(SceneObjects, NameAndShapeAreRequired) {
  json doc = minimal_scene();
  doc["objects"][0].erase("name");
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/name"), "required"));
  doc = minimal_scene();
  doc["objects"][0].erase("shape");
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape"), "required"));
  doc = minimal_scene();
  doc["objects"][0]["shape"].erase("type");
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/type"), "required"));
  doc = minimal_scene();
  doc["objects"][0]["shape"]["type"] = "sphere";
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/type"), "box, mesh"));
  doc = minimal_scene();
  doc["objects"][0]["shape"].erase("size");
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/size"), "required"));
}

TEST(SceneObjects, BoxSizesMustBePositive) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    json doc = minimal_scene();
    doc["objects"][0]["shape"]["size"][axis] = -1;
    single_error(doc, "/objects/0/shape/size/" + std::to_string(axis));
  }
}

TEST(SceneObjects, MeshShapeIsStoredAndItsDensityGivesTheMass) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["objects"][0].erase("mass");
  doc["objects"][0]["density"] = 600;
  const Scene scene = parse_ok(doc);
  const ObjectSpec& tetra = scene.objects.at(0);
  EXPECT_EQ(tetra.shape, ShapeType::mesh);
  EXPECT_EQ(tetra.mesh.vertices.size(), 4u);
  EXPECT_EQ(tetra.mesh.triangles.size(), 4u);
  EXPECT_NEAR(tetra.mass_kg, 100.0, 1e-9);  // 600 kg/m^3 * 1/6 m^3
}

TEST(SceneObjects, MeshValuesAreCheckedElementByElement) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["objects"][0]["shape"]["triangles"][1][2] = -1;
  single_error(doc, "/objects/0/shape/triangles/1/2");
  doc["objects"][0]["shape"]["triangles"][1][2] = 1.5;
  single_error(doc, "/objects/0/shape/triangles/1/2");
  doc["objects"][0]["shape"]["triangles"][1][2] = 3.0;  // an integral number is an integer
  parse_ok(doc);
  doc["objects"][0]["shape"]["triangles"][1] = {0, 1};
  single_error(doc, "/objects/0/shape/triangles/1");
  doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["objects"][0]["shape"]["vertices"][2][0] = "x";
  single_error(doc, "/objects/0/shape/vertices/2/0");
  doc["objects"][0]["shape"].erase("vertices");
  single_error(doc, "/objects/0/shape/vertices");
}

TEST(SceneObjects, OpenOrInvertedMeshesAreRejectedWithTheGeometryMessage) {
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = tetrahedron_shape();
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["objects"][0]["shape"]["triangles"].erase(3);  // open: three triangles
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/triangles"), "at least 4 triangles"));

  // The geometry's own diagnosis is passed on.
  const auto expect_geometry_message = [&](const json& shape) {
    geometry::TriangleMesh mesh;
    for (const auto& v : shape["vertices"])
      mesh.vertices.emplace_back(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    for (const auto& t : shape["triangles"])
      mesh.triangles.push_back(
          {t[0].get<std::uint32_t>(), t[1].get<std::uint32_t>(), t[2].get<std::uint32_t>()});
    const auto problem = geometry::check_closed_mesh(mesh);
    ASSERT_TRUE(problem.has_value());
    json broken = minimal_scene();
    broken["objects"][0]["shape"] = shape;
    broken["objects"][0]["position"] = {0, 0, 0};
    const std::string message = single_error(broken, "/objects/0/shape");
    EXPECT_TRUE(contains(message, *problem)) << message;
    EXPECT_TRUE(contains(message, "cannot be simulated")) << message;
  };
  // Five triangles: one face doubled, so an edge is shared by three.
  json shape = tetrahedron_shape();
  shape["triangles"].push_back({1, 2, 3});
  expect_geometry_message(shape);
  // Every triangle wound inward: negative volume.
  shape = tetrahedron_shape();
  for (auto& triangle : shape["triangles"])
    std::swap(triangle[1], triangle[2]);
  expect_geometry_message(shape);
  // An index past the vertices.
  shape = tetrahedron_shape();
  shape["triangles"][0][0] = 9;
  expect_geometry_message(shape);
  // A degenerate triangle: all four vertices in one plane.
  shape = tetrahedron_shape();
  shape["vertices"][3] = {0.5, 0.5, 0};
  expect_geometry_message(shape);
}

TEST(SceneObjects, OrientationIsXyzwAndMustBeUnit) {
  json doc = minimal_scene();
  const double s = std::sqrt(0.5);
  doc["objects"][0]["orientation"] = {0, 0, s, s};  // 90 degrees about z
  Scene scene = parse_ok(doc);
  const Quat& q = scene.objects[0].orientation;
  EXPECT_NEAR(q.w(), s, 1e-12);
  EXPECT_NEAR(q.z(), s, 1e-12);
  EXPECT_TRUE((q * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));

  doc["objects"][0]["orientation"] = {0, 0, 0, 1.0005};  // rounding: normalised
  scene = parse_ok(doc);
  EXPECT_NEAR(scene.objects[0].orientation.norm(), 1.0, 1e-15);

  for (const json& bad : {json{0, 0, 0, 2}, json{0, 0, 0, 0}, json{0, 0, 0, 1.002}}) {
    doc["objects"][0]["orientation"] = bad;
    const std::string message = single_error(doc, "/objects/0/orientation");
    EXPECT_TRUE(contains(message, "orientation must be a unit quaternion [x, y, z, w]")) << message;
  }
  doc["objects"][0]["orientation"] = {0, 0, 1};
  single_error(doc, "/objects/0/orientation");
  doc["objects"][0]["orientation"] = {0, 0, "z", 1};
  single_error(doc, "/objects/0/orientation/2");
}

TEST(SceneObjects, MassOrDensityExactlyOne) {
  json doc = minimal_scene();
  doc["objects"][0]["density"] = 100;
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/density"), "not both"));
  doc["objects"][0].erase("mass");
  doc["objects"][0].erase("density");
  const std::string message = single_error(doc, "/objects/0/mass");
  EXPECT_TRUE(contains(message, "density")) << message;
  EXPECT_TRUE(contains(message, "material")) << message;
  doc["objects"][0]["density"] = 0;
  single_error(doc, "/objects/0/density");
  doc["objects"][0]["density"] = 250;
  EXPECT_NEAR(parse_ok(doc).objects[0].mass_kg, 250.0, 1e-9);
  doc["objects"][0].erase("density");
  doc["objects"][0]["mass"] = 0;
  single_error(doc, "/objects/0/mass");
}

TEST(SceneObjects, MaterialGivesDensityAndFriction) {
  json doc = minimal_scene();
  doc["objects"][0].erase("mass");
  doc["objects"][0]["material"] = "Concrete";  // names are case-insensitive
  doc["objects"][0]["shape"]["size"] = {1, 1, 0.5};
  doc["objects"][0]["position"] = {0, 0.5, 0};
  Scene scene = parse_ok(doc);
  EXPECT_EQ(scene.objects[0].material, "concrete");
  EXPECT_NEAR(scene.objects[0].mass_kg, 1200.0, 1e-9);  // 2400 kg/m^3 * 0.5 m^3
  EXPECT_EQ(scene.objects[0].friction, 0.6);

  doc["objects"][0]["friction"] = 0.9;    // an explicit friction wins
  doc["objects"][0]["density"] = 1000.0;  // and so does an explicit density
  scene = parse_ok(doc);
  EXPECT_EQ(scene.objects[0].friction, 0.9);
  EXPECT_NEAR(scene.objects[0].mass_kg, 500.0, 1e-9);

  doc["objects"][0].erase("density");
  doc["objects"][0]["mass"] = 3.0;
  scene = parse_ok(doc);
  EXPECT_EQ(scene.objects[0].mass_kg, 3.0);
}

TEST(SceneObjects, UnknownMaterialListsTheKnownOnes) {
  json doc = minimal_scene();
  doc["objects"][0]["material"] = "unobtainium";
  const std::string message = single_error(doc, "/objects/0/material");
  for (const Material& material : known_materials())
    EXPECT_TRUE(contains(message, std::string(material.name))) << message;
  // With no mass either, the material error stands alone.
  doc["objects"][0].erase("mass");
  single_error(doc, "/objects/0/material");
}

TEST(SceneObjects, FrictionDragAndFlags) {
  json doc = minimal_scene();
  doc["objects"][0]["friction"] = -0.1;
  single_error(doc, "/objects/0/friction");
  doc["objects"][0]["friction"] = 0;
  EXPECT_EQ(parse_ok(doc).objects[0].friction, 0.0);
  doc["objects"][0]["drag_coefficient"] = 0;
  single_error(doc, "/objects/0/drag_coefficient");
}

// A breakable pane: a glass box, thickness along z.
json pane_scene() {
  json doc = minimal_scene();
  doc["objects"][0] = {{"name", "pane"},
                       {"shape", {{"type", "box"}, {"size", {1.2, 0.9, 0.006}}}},
                       {"position", {0, 1.5, 0}},
                       {"material", "annealed_glass"},
                       {"fracture", json::object()}};
  return doc;
}

TEST(SceneFracture, PaneGetsTheMaterialsValuesAndDefaults) {
  const Scene scene = parse_ok(pane_scene());
  ASSERT_TRUE(scene.objects[0].fracture.has_value());
  const FractureSpec& spec = *scene.objects[0].fracture;
  EXPECT_EQ(spec.strength_pa, 45e6);
  EXPECT_EQ(spec.fracture_toughness_pa_sqrt_m, 0.75e6);
  EXPECT_EQ(spec.youngs_modulus_pa, 70e9);
  EXPECT_EQ(spec.trigger, FractureSpec::Trigger::automatic);
  EXPECT_FALSE(spec.growth_length_m.has_value());
  EXPECT_FALSE(spec.framed);
  EXPECT_NEAR(scene.objects[0].mass_kg, 2500.0 * 1.2 * 0.9 * 0.006, 1e-9);
}

TEST(SceneFracture, EveryFieldIsRead) {
  json doc = pane_scene();
  doc["objects"][0]["material"] = "tempered_glass";
  doc["objects"][0]["fracture"] = {
      {"break", "always"},     {"growth_length", 0.01}, {"pattern_scale", 100},
      {"branch_angle", 15},    {"angle_variance", 0},   {"wiggle_probability", 0},
      {"wiggle_variance", 10}, {"grid", 256},           {"seed", 9},
      {"framed", true},        {"bond_strength", 5},    {"frame_strength", 6},
      {"frame_bite", 0.02},    {"clearing", "pane"},    {"strength", 1e8},
      {"toughness", 1e6},      {"youngs_modulus", 6e10}};
  const FractureSpec spec = *parse_ok(doc).objects[0].fracture;
  EXPECT_EQ(spec.trigger, FractureSpec::Trigger::always);
  EXPECT_EQ(spec.growth_length_m, 0.01);
  EXPECT_EQ(spec.pattern_scale, 100.0);
  EXPECT_EQ(spec.branch_angle_deg, 15.0);
  EXPECT_EQ(spec.grid, 256);
  EXPECT_EQ(spec.seed, 9u);
  EXPECT_TRUE(spec.framed);
  EXPECT_EQ(spec.bond_strength_pa, 5.0);
  EXPECT_EQ(spec.frame_strength_pa, 6.0);
  EXPECT_EQ(spec.frame_bite_m, 0.02);
  EXPECT_EQ(spec.clearing, FractureSpec::Clearing::pane);
  EXPECT_EQ(spec.strength_pa, 1e8);
  EXPECT_EQ(spec.fracture_toughness_pa_sqrt_m, 1e6);
  EXPECT_EQ(spec.youngs_modulus_pa, 6e10);
  doc["objects"][0]["material"] = "tempered_glass";
  doc["objects"][0]["fracture"] = json::object();
  EXPECT_EQ(parse_ok(doc).objects[0].fracture->strength_pa, 120e6);
}

TEST(SceneFracture, ErrorsPointAtTheFieldAndNameTheFix) {
  const std::tuple<const char*, std::function<void(json&)>, const char*> cases[] = {
      {"/objects/0/fracture/colour", [](json& d) { d["objects"][0]["fracture"]["colour"] = 1; },
       "known fields"},
      {"/objects/0/fracture/break", [](json& d) { d["objects"][0]["fracture"]["break"] = "now"; },
       "auto, always"},
      {"/objects/0/fracture/grid", [](json& d) { d["objects"][0]["fracture"]["grid"] = 8; },
       "integer in [16, 4096]"},
      {"/objects/0/fracture/growth_length",
       [](json& d) { d["objects"][0]["fracture"]["growth_length"] = 0; }, "(0, 10]"},
      {"/objects/0/fracture/clearing",
       [](json& d) { d["objects"][0]["fracture"]["clearing"] = "edge"; }, "fragment, pane"},
      {"/objects/0/fracture", [](json& d) { d["objects"][0]["fracture"] = 3; }, "JSON object"},
      {"/objects/0/fracture",
       [](json& d) {
         d["objects"][0].erase("material");
         d["objects"][0]["density"] = 2500;
       },
       "breakable 'material'"},
      {"/objects/0/shape/size/2",
       [](json& d) {
         d["objects"][0]["shape"]["size"] = {0.006, 0.9, 1.2};
       },
       "smallest edge"},
      {"/objects/0/anchored", [](json& d) { d["objects"][0]["anchored"] = true; }, "framed"},
  };
  for (const auto& [pointer, edit, part] : cases) {
    json doc = pane_scene();
    edit(doc);
    const std::string message = single_error(doc, pointer);
    EXPECT_TRUE(contains(message, part)) << pointer << ": " << message;
  }
  json doc = pane_scene();
  doc["objects"][0]["shape"] = {{"type", "mesh"},
                                {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
                                {"triangles", {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}}};
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape"), "must be a box pane"));
}

json window_scene() {
  json doc = minimal_scene();
  doc.erase("objects");
  doc["generators"] = {{{"type", "window"},
                        {"name", "w"},
                        {"position", {0, 1.5, 0}},
                        {"size", {1.2, 0.9}},
                        {"thickness", 0.006}}};
  return doc;
}

TEST(SceneWindow, GeneratesAPaneAndAnAnchoredFrame) {
  const Scene scene = parse_ok(window_scene());
  ASSERT_EQ(scene.objects.size(), 5u);
  const ObjectSpec& pane = scene.objects[0];
  EXPECT_EQ(pane.name, "w/pane");
  EXPECT_EQ(pane.material, "annealed_glass");
  ASSERT_TRUE(pane.fracture.has_value());
  EXPECT_TRUE(pane.fracture->framed);
  EXPECT_EQ(pane.fracture->strength_pa, 45e6);
  EXPECT_TRUE(pane.box_size_m.isApprox(Eigen::Vector3d(1.2, 0.9, 0.006)));
  for (std::size_t i = 1; i < 5; ++i) {
    EXPECT_TRUE(scene.objects[i].anchored) << scene.objects[i].name;
    EXPECT_FALSE(scene.objects[i].fracture.has_value());
  }
  EXPECT_EQ(scene.objects[1].name, "w/frame/bottom");
  // The frame's inner edges meet the pane's edges.
  EXPECT_NEAR(scene.objects[1].position.y() + 0.5 * scene.objects[1].box_size_m.y(), 1.5 - 0.45,
              1e-12);
  json doc = window_scene();
  doc["generators"][0]["frame"] = false;
  doc["generators"][0]["material"] = "tempered_glass";
  doc["generators"][0]["fracture"] = {{"growth_length", 0.02}};
  const Scene unframed = parse_ok(doc);
  ASSERT_EQ(unframed.objects.size(), 1u);
  EXPECT_FALSE(unframed.objects[0].fracture->framed);
  EXPECT_EQ(unframed.objects[0].fracture->strength_pa, 120e6);
  EXPECT_EQ(unframed.objects[0].fracture->growth_length_m, 0.02);
}

TEST(SceneWindow, ErrorsPointAtTheFieldAndNameTheFix) {
  const std::tuple<const char*, std::function<void(json&)>, const char*> cases[] = {
      {"/generators/0/glass", [](json& d) { d["generators"][0]["glass"] = 1; }, "known fields"},
      {"/generators/0/size",
       [](json& d) {
         d["generators"][0]["size"] = {1, 2, 3};
       },
       "[width, height]"},
      {"/generators/0/size", [](json& d) { d["generators"][0].erase("size"); }, "is required"},
      {"/generators/0/size/1", [](json& d) { d["generators"][0]["size"][1] = -1; }, "> 0"},
      {"/generators/0/material", [](json& d) { d["generators"][0]["material"] = "brick"; },
       "breakable material"},
      {"/generators/0/thickness", [](json& d) { d["generators"][0]["thickness"] = 0; }, "(0, 0.1]"},
      {"/generators/0/frame_depth", [](json& d) { d["generators"][0]["frame_depth"] = 0.001; },
       "deeper"},
      {"/generators/0/fracture/framed",
       [](json& d) {
         d["generators"][0]["fracture"] = {{"framed", true}};
       },
       "'frame'"},
      {"/generators/0/fracture/pattern_scale",
       [](json& d) {
         d["generators"][0]["fracture"] = {{"pattern_scale", -1}};
       },
       "> 0"},
  };
  for (const auto& [pointer, edit, part] : cases) {
    json doc = window_scene();
    edit(doc);
    const std::string message = single_error(doc, pointer);
    EXPECT_TRUE(contains(message, part)) << pointer << ": " << message;
  }
}

TEST(SceneObjects, AtLeastOneObjectIsRequired) {
  json doc = minimal_scene();
  doc.erase("objects");
  EXPECT_TRUE(contains(single_error(doc, "/objects"), "at least one object"));
  doc["objects"] = json::array();
  doc["generators"] = json::array();
  single_error(doc, "/objects");
  // A generator alone is enough.
  json g = brick_wall_generator();
  g["position"] = {0, 0, 3};
  doc["generators"] = {g};
  EXPECT_EQ(parse_ok(doc).objects.size(), 33u);
}

TEST(SceneObjects, DuplicateNamesPointAtTheSecond) {
  json doc = minimal_scene();
  json second = doc["objects"][0];
  second["position"] = {3, 0.5, 0};
  doc["objects"].push_back(second);
  const std::string message = single_error(doc, "/objects/1/name");
  EXPECT_TRUE(contains(message, "'cube'")) << message;
  EXPECT_TRUE(contains(message, "/objects/0/name")) << message;
}

TEST(SceneObjects, GeneratedNamesMustNotClash) {
  json doc = minimal_scene();
  doc["objects"][0]["name"] = "wall/r0/b0";
  doc["objects"][0]["position"] = {0, 0.5, 5};
  doc["generators"] = {brick_wall_generator()};
  const std::string message = single_error(doc, "/generators/0/name");
  EXPECT_TRUE(contains(message, "'wall/r0/b0'")) << message;

  // Two generators with the same prefix: one error for the second, not one per brick.
  doc = minimal_scene();
  json a = brick_wall_generator();
  a["position"] = {0, 0, 3};
  json b = a;
  b["position"] = {0, 0, 6};
  doc["generators"] = {a, b};
  single_error(doc, "/generators/1/name");
}

TEST(SceneObjects, BelowTheGroundIsAnError) {
  json doc = minimal_scene();
  doc["objects"][0]["position"] = {0, 0, 0};  // bottom face at y = -0.5
  const std::string message = single_error(doc, "/objects/0/position");
  EXPECT_TRUE(contains(message, "raise")) << message;
  EXPECT_TRUE(contains(message, "'cube'")) << message;

  doc["objects"][0]["position"] = {0, 0.4995, 0};  // 0.5 mm low: tolerated
  parse_ok(doc);
  doc["objects"][0]["position"] = {0, 0.498, 0};  // 2 mm low: not
  single_error(doc, "/objects/0/position");

  doc["environment"]["ground"]["height"] = 1.0;  // the ground moved up
  doc["objects"][0]["position"] = {0, 0.5, 0};
  doc["charges"][0]["position"] = {0, 2, -5};
  single_error(doc, "/objects/0/position");

  doc["environment"]["ground"] = nullptr;  // no ground, nothing to be below
  parse_ok(doc);
}

TEST(SceneObjects, BelowTheGroundCountsRotatedCorners) {
  json doc = minimal_scene();
  // A unit cube balanced on an edge: turned 45 degrees about z, its lowest edge is at
  // y = 0.5 - sqrt(0.5) < 0.
  const double angle = std::numbers::pi / 8.0;
  doc["objects"][0]["orientation"] = {0, 0, std::sin(angle), std::cos(angle)};
  single_error(doc, "/objects/0/position");
  doc["objects"][0]["position"] = {0, std::sqrt(0.5), 0};
  parse_ok(doc);
}

TEST(SceneObjects, GeneratorBelowTheGroundIsOneError) {
  json doc = minimal_scene();
  json g = brick_wall_generator();
  g["position"] = {0, -0.1, 3};
  doc["generators"] = {g};
  const std::string message = single_error(doc, "/generators/0/position");
  EXPECT_TRUE(contains(message, "5 generated objects")) << message;  // the bottom row
}

// ---------------------------------------------------------------------------------------------
// Simulation

TEST(SceneSimulation, RangesAndLimits) {
  const std::pair<const char*, json> cases[] = {
      {"duration", 0},        {"duration", 601},       {"frame_rate", 0},
      {"frame_rate", 1001},   {"time_step", 0},        {"time_step", 0.2},
      {"tolerance", 0},       {"tolerance", 1},        {"seed", -1},
      {"seed", 1.5},          {"seed", "1"},           {"max_panel_area", 0},
      {"linear_damping", -1}, {"angular_damping", -1}, {"rotation_factor", -0.5},
  };
  for (const auto& [field, value] : cases) {
    json doc = minimal_scene();
    doc["simulation"][field] = value;
    single_error(doc, std::string("/simulation/") + field);
  }
  json doc = minimal_scene();
  doc["simulation"]["duration"] = 601;
  EXPECT_TRUE(contains(single_error(doc, "/simulation/duration"), "max_duration_s"));
  doc["simulation"]["duration"] = 600;
  parse_ok(doc);
  Limits limits;
  limits.max_duration_s = 10;
  doc["simulation"]["duration"] = 11;
  EXPECT_TRUE(contains(single_error(doc, "/simulation/duration", limits), "10"));
  doc = minimal_scene();
  doc["simulation"]["frame_rate"] = 1001;
  EXPECT_TRUE(contains(single_error(doc, "/simulation/frame_rate"), "max_frame_rate_hz"));
}

TEST(SceneSimulation, TimeStepOrToleranceNotBoth) {
  json doc = minimal_scene();
  doc["simulation"]["time_step"] = 0.01;
  EXPECT_EQ(parse_ok(doc).simulation.time_step_s, 0.01);
  doc["simulation"]["tolerance"] = 1e-4;
  EXPECT_TRUE(contains(single_error(doc, "/simulation/tolerance"), "not both"));
  doc["simulation"].erase("time_step");
  EXPECT_EQ(parse_ok(doc).simulation.tolerance, 1e-4);
}

TEST(SceneSimulation, SeedTakesTheWholeUnsignedRange) {
  json doc = minimal_scene();
  doc["simulation"]["seed"] = std::numeric_limits<std::uint64_t>::max();
  EXPECT_EQ(parse_ok(doc).simulation.seed, std::numeric_limits<std::uint64_t>::max());
  const ParseResult result = parse_scene_text(R"({"charges": [{"position": [0, 1, -5], "mass": 1}],
        "objects": [{"name": "c", "shape": {"type": "box", "size": [1, 1, 1]},
                     "position": [0, 0.5, 0], "mass": 1}],
        "simulation": {"seed": 18446744073709551615}})");
  ASSERT_TRUE(result.scene.has_value()) << dump_errors(result);
  EXPECT_EQ(result.scene->simulation.seed, 18446744073709551615u);
}

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

// ---------------------------------------------------------------------------------------------
// Generators

// Per row of a generated wall: the x range covered, the bricks and the half bricks.
struct RowSummary {
  double left = INFINITY;
  double right = -INFINITY;
  int full = 0;
  int half = 0;
  double bottom = 0.0;
};

std::map<int, RowSummary> summarise_rows(const std::vector<ObjectSpec>& bricks, double length) {
  std::map<int, RowSummary> rows;
  for (const ObjectSpec& brick : bricks) {
    const int row = std::stoi(brick.name.substr(brick.name.find("/r") + 2));
    RowSummary& summary = rows[row];
    summary.left = std::min(summary.left, brick.position.x() - 0.5 * brick.box_size_m.x());
    summary.right = std::max(summary.right, brick.position.x() + 0.5 * brick.box_size_m.x());
    summary.bottom = brick.position.y() - 0.5 * brick.box_size_m.y();
    if (brick.box_size_m.x() < 0.75 * length) {
      ++summary.half;
    } else {
      ++summary.full;
    }
  }
  return rows;
}

TEST(BrickWall, ThesisWallHas27FullAnd6HalfBricks) {
  BrickWallParams params;
  params.name = "wall";
  params.rows = 6;
  params.columns = 5;
  params.brick_size_m = Vec3(0.4, 0.15, 0.1);
  params.brick_mass_kg = 10.0;
  const std::vector<ObjectSpec> bricks = brick_wall(params);
  ASSERT_EQ(bricks.size(), 33u);
  EXPECT_EQ(brick_wall_count(6, 5), 33u);
  int full = 0;
  int half = 0;
  for (const ObjectSpec& brick : bricks) {
    if (brick.mass_kg == 10.0) {
      ++full;
      EXPECT_EQ(brick.box_size_m, Vec3(0.4, 0.15, 0.1)) << brick.name;
    } else {
      ++half;
      EXPECT_EQ(brick.mass_kg, 5.0) << brick.name;
      EXPECT_EQ(brick.box_size_m, Vec3(0.2, 0.15, 0.1)) << brick.name;
    }
    EXPECT_EQ(brick.shape, ShapeType::box);
    EXPECT_EQ(brick.mesh.vertices.size(), 8u);
    EXPECT_EQ(brick.friction, 0.6);
    EXPECT_EQ(brick.material, "brick");
  }
  EXPECT_EQ(full, 27);
  EXPECT_EQ(half, 6);
  EXPECT_EQ(bricks.front().name, "wall/r0/b0");
  EXPECT_EQ(bricks.back().name, "wall/r5/b5");
}

TEST(BrickWall, RunningBondRowsSpanTheSameWidthWithHalfBricksAtTheEnds) {
  for (double gap : {0.0, 0.01}) {
    BrickWallParams params;
    params.name = "w";
    params.rows = 5;
    params.columns = 4;
    params.brick_size_m = Vec3(0.4, 0.2, 0.1);
    params.mortar_gap_m = gap;
    const std::vector<ObjectSpec> bricks = brick_wall(params);
    EXPECT_EQ(bricks.size(), brick_wall_count(5, 4));
    const double width = 4 * 0.4 + 3 * gap;
    const auto rows = summarise_rows(bricks, 0.4);
    ASSERT_EQ(rows.size(), 5u);
    for (const auto& [row, summary] : rows) {
      EXPECT_NEAR(summary.left, -0.5 * width, 1e-12) << "row " << row << " gap " << gap;
      EXPECT_NEAR(summary.right, 0.5 * width, 1e-12) << "row " << row << " gap " << gap;
      EXPECT_NEAR(summary.bottom, row * (0.2 + gap), 1e-12) << "row " << row;
      EXPECT_EQ(summary.full, row % 2 == 0 ? 4 : 3) << "row " << row;
      EXPECT_EQ(summary.half, row % 2 == 0 ? 0 : 2) << "row " << row;
    }
    // The half bricks are the first and last of each odd row.
    for (const ObjectSpec& brick : bricks) {
      const bool is_half = brick.box_size_m.x() < 0.3;
      const bool at_end =
          std::abs(std::abs(brick.position.x()) - 0.5 * width) < 0.5 * brick.box_size_m.x() + 1e-9;
      if (is_half) {
        EXPECT_TRUE(at_end) << brick.name;
      }
    }
    // Neighbours in a row are separated by exactly the gap, and odd-row joints sit over the
    // middle of a brick below.
    for (std::size_t i = 0; i + 1 < bricks.size(); ++i) {
      const ObjectSpec& a = bricks[i];
      const ObjectSpec& b = bricks[i + 1];
      if (a.position.y() != b.position.y()) continue;
      const double joint_left = a.position.x() + 0.5 * a.box_size_m.x();
      const double joint_right = b.position.x() - 0.5 * b.box_size_m.x();
      EXPECT_NEAR(joint_right - joint_left, gap, 1e-12);
    }
    const auto row_of = [&](int r) {
      std::vector<const ObjectSpec*> out;
      for (const ObjectSpec& brick : bricks)
        if (brick.name.find("/r" + std::to_string(r) + "/") != std::string::npos)
          out.push_back(&brick);
      return out;
    };
    const auto row0 = row_of(0);
    const auto row1 = row_of(1);
    for (std::size_t j = 0; j + 1 < row1.size(); ++j) {
      const double joint = row1[j]->position.x() + 0.5 * row1[j]->box_size_m.x() + 0.5 * gap;
      EXPECT_NEAR(joint, row0[j]->position.x(), 1e-12);
    }
  }
}

TEST(BrickWall, PositionAndOrientationPlaceTheWholeWall) {
  BrickWallParams params;
  params.name = "w";
  params.rows = 2;
  params.columns = 2;
  params.brick_size_m = Vec3(0.4, 0.2, 0.1);
  const std::vector<ObjectSpec> local = brick_wall(params);
  params.position = Vec3(3, 1, -2);
  params.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const std::vector<ObjectSpec> placed = brick_wall(params);
  ASSERT_EQ(local.size(), placed.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    EXPECT_TRUE(placed[i].position.isApprox(
        params.position + params.orientation * local[i].position, 1e-12));
    EXPECT_TRUE(placed[i].orientation.isApprox(params.orientation));
  }
  // The base stands on the given position: the lowest brick face is at y = 1.
  double lowest = INFINITY;
  for (const ObjectSpec& brick : placed)
    lowest = std::min(lowest, lowest_y(brick));
  EXPECT_NEAR(lowest, 1.0, 1e-12);
  // Turned 90 degrees about y, the wall runs along z: the first brick is at +z.
  EXPECT_NEAR(placed.front().position.x(), 3.0, 1e-12);
  EXPECT_GT(placed.front().position.z(), -2.0);
}

TEST(BrickWall, FromJsonWithErrors) {
  const std::pair<const char*, std::function<void(json&)>> cases[] = {
      {"/generators/0/rows", [](json& g) { g["rows"] = 0; }},
      {"/generators/0/rows", [](json& g) { g.erase("rows"); }},
      {"/generators/0/columns", [](json& g) { g["columns"] = 2.5; }},
      {"/generators/0/columns", [](json& g) { g["columns"] = "5"; }},
      {"/generators/0/brick_size/1", [](json& g) { g["brick_size"][1] = 0; }},
      {"/generators/0/brick_size",
       [](json& g) {
         g["brick_size"] = {0.4, 0.2};
       }},
      {"/generators/0/brick_mass", [](json& g) { g["brick_mass"] = -10; }},
      {"/generators/0/name", [](json& g) { g.erase("name"); }},
      {"/generators/0/friction", [](json& g) { g["friction"] = -1; }},
      {"/generators/0/mortar_gap", [](json& g) { g["mortar_gap"] = -0.01; }},
      {"/generators/0/mortar_gap", [](json& g) { g["mortar_gap"] = 0.4; }},
      {"/generators/0/orientation",
       [](json& g) {
         g["orientation"] = {1, 1, 1, 1};
       }},
      {"/generators/0/type", [](json& g) { g["type"] = "brickwall"; }},
      {"/generators/0/type", [](json& g) { g.erase("type"); }},
  };
  for (const auto& [pointer, edit] : cases) {
    json doc = minimal_scene();
    json g = brick_wall_generator();
    g["position"] = {0, 0, 3};
    edit(g);
    doc["generators"] = {g};
    single_error(doc, pointer);
  }
}

TEST(BrickWall, FromJsonAppendsAfterExplicitObjects) {
  json doc = minimal_scene();
  json g = brick_wall_generator();
  g["position"] = {1, 0, 3};
  g["friction"] = 1.2;
  g["mortar_gap"] = 0.005;
  doc["generators"] = {g};
  const Scene scene = parse_ok(doc);
  ASSERT_EQ(scene.objects.size(), 34u);
  EXPECT_EQ(scene.objects[0].name, "cube");
  EXPECT_EQ(scene.objects[1].name, "wall/r0/b0");
  for (std::size_t i = 1; i < scene.objects.size(); ++i) {
    EXPECT_EQ(scene.objects[i].friction, 1.2);
    EXPECT_NEAR(scene.objects[i].position.z(), 3.0, 1e-12);
  }
  EXPECT_NEAR(lowest_y(scene.objects[1]), 0.0, 1e-12);
}

TEST(BrickWall, JsonDefaults) {
  json doc = minimal_scene();
  doc["objects"] = json::array();
  doc["generators"] = {brick_wall_generator()};  // no position, orientation, friction, gap
  const Scene scene = parse_ok(doc);
  ASSERT_EQ(scene.objects.size(), 33u);
  double left = INFINITY;
  double right = -INFINITY;
  for (const ObjectSpec& brick : scene.objects) {
    EXPECT_EQ(brick.friction, 0.6) << brick.name;
    EXPECT_TRUE(brick.orientation.isApprox(Quat::Identity())) << brick.name;
    EXPECT_NEAR(brick.position.z(), 0.0, 1e-12) << brick.name;
    left = std::min(left, brick.position.x() - 0.5 * brick.box_size_m.x());
    right = std::max(right, brick.position.x() + 0.5 * brick.box_size_m.x());
    // No mortar gap: half bricks are exactly half as long.
    EXPECT_TRUE(brick.box_size_m.x() == 0.4 || brick.box_size_m.x() == 0.2) << brick.name;
  }
  // Centred on the origin, standing on y = 0.
  EXPECT_NEAR(left, -1.0, 1e-12);
  EXPECT_NEAR(right, 1.0, 1e-12);
  EXPECT_NEAR(lowest_y(scene.objects.front()), 0.0, 1e-12);
}

TEST(Blocks, JsonDefaults) {
  json doc = minimal_scene();
  doc["objects"] = json::array();
  doc["generators"] = json::parse(R"([{"type": "blocks", "name": "b", "counts": [2, 1, 1],
                                       "size": [1, 1, 1], "mass": 3}])");
  const Scene scene = parse_ok(doc);
  ASSERT_EQ(scene.objects.size(), 2u);
  for (const ObjectSpec& box : scene.objects) {
    EXPECT_EQ(box.friction, 0.5);
    EXPECT_EQ(box.mass_kg, 3.0);
    EXPECT_NEAR(box.position.y(), 0.5, 1e-12);
  }
  // No spacing: the two boxes touch at x = 0.
  EXPECT_NEAR(scene.objects[0].position.x(), -0.5, 1e-12);
  EXPECT_NEAR(scene.objects[1].position.x(), 0.5, 1e-12);
}

TEST(Blocks, GridPositionsAndMasses) {
  BlocksParams params;
  params.name = "b";
  params.counts = {3, 2, 2};
  params.size_m = Vec3(1, 0.5, 2);
  params.spacing_m = Vec3(0.5, 0.1, 1);
  params.position = Vec3(10, 0, 0);
  params.mass_kg = 7;
  const std::vector<ObjectSpec> boxes = blocks(params);
  ASSERT_EQ(boxes.size(), 12u);
  EXPECT_EQ(blocks_count({3, 2, 2}), 12u);
  double min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY, min_z = INFINITY, max_z = -INFINITY;
  std::set<std::string> names;
  for (const ObjectSpec& box : boxes) {
    EXPECT_EQ(box.mass_kg, 7.0);
    EXPECT_EQ(box.box_size_m, Vec3(1, 0.5, 2));
    min_x = std::min(min_x, box.position.x() - 0.5);
    max_x = std::max(max_x, box.position.x() + 0.5);
    min_y = std::min(min_y, box.position.y() - 0.25);
    min_z = std::min(min_z, box.position.z() - 1.0);
    max_z = std::max(max_z, box.position.z() + 1.0);
    names.insert(box.name);
  }
  EXPECT_EQ(names.size(), 12u);
  EXPECT_TRUE(names.contains("b/x2/y1/z1"));
  // Extent along x: 3 * 1 + 2 * 0.5 = 4, centred on x = 10; along z: 2 * 2 + 1 = 5.
  EXPECT_NEAR(min_x, 8.0, 1e-12);
  EXPECT_NEAR(max_x, 12.0, 1e-12);
  EXPECT_NEAR(min_y, 0.0, 1e-12);
  EXPECT_NEAR(min_z, -2.5, 1e-12);
  EXPECT_NEAR(max_z, 2.5, 1e-12);
  // The second layer stands on the first with the y spacing between.
  EXPECT_NEAR(boxes.back().position.y(), 0.5 + 0.1 + 0.25, 1e-12);
}

TEST(Blocks, OrientationTurnsTheGridAboutItsBaseCentre) {
  BlocksParams params;
  params.name = "b";
  params.counts = {2, 1, 1};
  params.size_m = Vec3(1, 1, 1);
  params.spacing_m = Vec3(1, 0, 0);
  const std::vector<ObjectSpec> local = blocks(params);
  params.position = Vec3(0, 2, 5);
  params.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const std::vector<ObjectSpec> placed = blocks(params);
  ASSERT_EQ(placed.size(), 2u);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    EXPECT_TRUE(placed[i].position.isApprox(
        params.position + params.orientation * local[i].position, 1e-12));
    EXPECT_TRUE(placed[i].orientation.isApprox(params.orientation));
  }
  // The row along local x now runs along world z: x = -1 maps to z = 5 + 1.
  EXPECT_NEAR(placed[0].position.x(), 0.0, 1e-12);
  EXPECT_NEAR(placed[0].position.z(), 6.0, 1e-12);
  EXPECT_NEAR(placed[0].position.y(), 2.5, 1e-12);
}

TEST(Blocks, FromJson) {
  json doc = minimal_scene();
  doc["generators"] = json::parse(R"([{"type": "blocks", "name": "crates", "position": [0, 0, 4],
      "counts": [3, 1, 1], "size": [0.5, 0.5, 0.5], "spacing": [0.25, 0, 0], "density": 800,
      "friction": 0.7}])");
  const Scene scene = parse_ok(doc);
  ASSERT_EQ(scene.objects.size(), 4u);
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_NEAR(scene.objects[i].mass_kg, 100.0, 1e-9);  // 800 * 0.125
    EXPECT_EQ(scene.objects[i].friction, 0.7);
  }
  EXPECT_NEAR(scene.objects[1].position.x(), -0.75, 1e-12);
  EXPECT_NEAR(scene.objects[3].position.x(), 0.75, 1e-12);

  const std::pair<const char*, std::function<void(json&)>> cases[] = {
      {"/generators/0/counts/2", [](json& g) { g["counts"][2] = 0; }},
      {"/generators/0/counts",
       [](json& g) {
         g["counts"] = {3, 1};
       }},
      {"/generators/0/counts", [](json& g) { g.erase("counts"); }},
      {"/generators/0/size/0", [](json& g) { g["size"][0] = -1; }},
      {"/generators/0/spacing/1", [](json& g) { g["spacing"][1] = -0.1; }},
      {"/generators/0/density", [](json& g) { g["mass"] = 5; }},
      {"/generators/0/mass", [](json& g) { g.erase("density"); }},
      {"/generators/0/friction", [](json& g) { g["friction"] = "rough"; }},
      {"/generators/0/rows", [](json& g) { g["rows"] = 2; }},
  };
  for (const auto& [pointer, edit] : cases) {
    json broken = doc;
    edit(broken["generators"][0]);
    single_error(broken, pointer);
  }
}

// ---------------------------------------------------------------------------------------------
// Materials

TEST(Materials, TableIsSaneAndSourced) {
  std::set<std::string> names;
  for (const Material& material : known_materials()) {
    EXPECT_TRUE(names.insert(std::string(material.name)).second) << material.name;
    EXPECT_GT(material.density_kg_m3, 300.0) << material.name;
    EXPECT_LT(material.density_kg_m3, 9000.0) << material.name;
    EXPECT_GE(material.friction, 0.2) << material.name;
    EXPECT_LE(material.friction, 1.5) << material.name;
    EXPECT_FALSE(material.source.empty()) << material.name;
    EXPECT_EQ(std::string(material.name), [&] {
      std::string lower(material.name);
      for (char& c : lower)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return lower;
    }()) << "names are lower case";
  }
  for (const char* name : {"brick", "concrete", "steel", "wood", "glass", "aluminium", "granite"})
    EXPECT_TRUE(names.contains(name)) << name;
  for (const Material& material : known_materials()) {
    if (material.name == "brick") {
      EXPECT_GE(material.density_kg_m3, 1250.0);
      EXPECT_LE(material.density_kg_m3, 2100.0);
      EXPECT_EQ(material.friction, 0.6);
    }
    if (material.name == "steel") {
      EXPECT_EQ(material.density_kg_m3, 7850.0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The example scenes in scenes/

std::filesystem::path repository_root() {
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path().parent_path();
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
