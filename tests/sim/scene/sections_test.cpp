// Tests of sim/scene/parse_sections: charges (and the checks on where they sit), the
// environment and the simulation section.
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
  EXPECT_EQ(scene.charges[0].impulse_tnt_factor, 1.3);  // one factor unless two are given

  doc["charges"][0]["explosive"] = {{"tnt_factor", 1.37}, {"impulse_tnt_factor", 1.19}};
  EXPECT_EQ(parse_ok(doc).charges[0].impulse_tnt_factor, 1.19);
  doc["charges"][0]["explosive"] = {{"tnt_factor", 1.37}, {"impulse_tnt_factor", -1}};
  single_error(doc, "/charges/0/explosive/impulse_tnt_factor");
  doc["charges"][0]["explosive"] = "c4";  // UFC 3-340-02 table 2-1 gives C-4 two factors
  EXPECT_EQ(parse_ok(doc).charges[0].tnt_factor, 1.37);
  EXPECT_EQ(parse_ok(doc).charges[0].impulse_tnt_factor, 1.19);

  // A TNT equivalent the curves cannot take: mass times factor overflows.
  doc["charges"][0]["explosive"] = {{"tnt_factor", 1e200}};
  doc["charges"][0]["mass"] = 1e200;
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/mass"), "not a finite mass")) << doc;
  doc["charges"][0]["explosive"] = {{"tnt_factor", 1e-200}, {"impulse_tnt_factor", 1e300}};
  EXPECT_TRUE(contains(single_error(doc, "/charges/0/mass"), "not a finite mass")) << doc;
  doc["charges"][0]["mass"] = 1;

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

TEST(SceneSimulation, ShieldingParametersAreReadAndChecked) {
  json doc = minimal_scene();
  EXPECT_EQ(parse_ok(doc).simulation.shielding.resolution, 32);
  doc["simulation"]["shielding"] = {
      {"resolution", 64}, {"blocking_offset", 2}, {"separation_slope", 0}, {"per_panel", false}};
  const ShieldingSpec spec = parse_ok(doc).simulation.shielding;
  EXPECT_EQ(spec.resolution, 64);
  EXPECT_EQ(spec.blocking_offset, 2.0);
  EXPECT_EQ(spec.separation_slope, 0.0);
  EXPECT_FALSE(spec.per_panel);
  const std::pair<const char*, json> cases[] = {
      {"resolution", 3},        {"resolution", 129},  {"resolution", 32.5}, {"blocking_offset", 0},
      {"separation_slope", -1}, {"per_panel", "yes"}, {"pixels", 32},
  };
  for (const auto& [field, value] : cases) {
    doc = minimal_scene();
    doc["simulation"]["shielding"] = {{field, value}};
    single_error(doc, std::string("/simulation/shielding/") + field);
  }
  doc = minimal_scene();
  doc["simulation"]["shielding"] = 32;
  single_error(doc, "/simulation/shielding");
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

TEST(SceneSimulation, BodySubstepsNeedSemiImplicitEulerAndNoCollisions) {
  json doc = minimal_scene();
  EXPECT_FALSE(parse_ok(doc).simulation.body_substeps.has_value());  // unset: on where it applies
  doc["simulation"] = {{"body_substeps", false}};
  EXPECT_EQ(parse_ok(doc).simulation.body_substeps, false);
  doc["simulation"] = {{"integrator", "rk4"}};  // unset: no error where it does not apply
  EXPECT_FALSE(parse_ok(doc).simulation.body_substeps.has_value());
  doc["simulation"] = {{"collisions", "auto"}};
  EXPECT_FALSE(parse_ok(doc).simulation.body_substeps.has_value());
  doc["simulation"] = {{"body_substeps", true}};
  EXPECT_EQ(parse_ok(doc).simulation.body_substeps, true);
  doc["simulation"] = {{"body_substeps", true}, {"integrator", "rk4"}};
  EXPECT_TRUE(contains(single_error(doc, "/simulation/body_substeps"), "semi_implicit_euler"));
  doc["simulation"] = {{"body_substeps", true}, {"collisions", "auto"}};
  EXPECT_TRUE(contains(single_error(doc, "/simulation/body_substeps"), "collisions"));
  doc["simulation"] = {{"body_substeps", 1}};
  single_error(doc, "/simulation/body_substeps");
}

}  // namespace
}  // namespace brisance::scene
