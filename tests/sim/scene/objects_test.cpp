// Tests of sim/scene/parse_objects: object shapes, materials, mass or density, flags, breakable
// panes and windows, and the cross-checks on objects (names, the ground).
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

// `file` and `asset` shapes: the parser asks the resolver of their kind and checks what it gets.
TEST(SceneObjects, FileAndAssetShapesTakeTheirMeshFromTheResolver) {
  geometry::TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::vector<MeshReference> asked;
  ResolvedMesh answer{tetrahedron, {}};
  MeshSources sources;
  sources.file = [&](const MeshReference& reference) {
    asked.push_back(reference);
    return answer;
  };
  json doc = minimal_scene();
  doc["objects"][0]["shape"] = {{"type", "file"}, {"path", "props/crate.glb"}, {"node", "Crate"}};
  doc["objects"][0]["position"] = {0, 0, 0};
  doc["objects"][0].erase("mass");
  doc["objects"][0]["density"] = 600;
  ParseResult parsed = parse_scene(doc, {}, sources);
  ASSERT_TRUE(parsed.scene) << dump_errors(parsed);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0].reference, "props/crate.glb");
  EXPECT_EQ(asked[0].node, std::optional<std::string>("Crate"));
  EXPECT_EQ(parsed.scene->objects[0].shape, ShapeType::mesh);
  EXPECT_EQ(parsed.scene->objects[0].mesh.vertices.size(), 4u);
  EXPECT_NEAR(parsed.scene->objects[0].mass_kg, 600.0 / 6.0, 1e-9);  // density x volume

  // The resolver's error and the closedness check are reported at the shape.
  answer = {std::nullopt, "no node named 'Crate'"};
  parsed = parse_scene(doc, {}, sources);
  ASSERT_EQ(parsed.errors.size(), 1u) << dump_errors(parsed);
  EXPECT_EQ(parsed.errors[0].pointer, "/objects/0/shape");
  EXPECT_TRUE(contains(parsed.errors[0].message, "no node named 'Crate'"));
  geometry::TriangleMesh open = tetrahedron;
  open.triangles.pop_back();
  answer = {open, {}};
  parsed = parse_scene(doc, {}, sources);
  ASSERT_EQ(parsed.errors.size(), 1u) << dump_errors(parsed);
  EXPECT_EQ(parsed.errors[0].pointer, "/objects/0/shape");
  EXPECT_TRUE(contains(parsed.errors[0].message, "the mesh is open (3 edges open)"))
      << parsed.errors[0].message;

  // Without a resolver for the kind (the service has no files, the CLI no assets).
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/type"), "POST /v1/assets"));
  doc["objects"][0]["shape"] = {{"type", "asset"}, {"asset", "c0ffee"}};
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/shape/type"), "uploaded to the HTTP service"));
  // Malformed references are reported at their field, and the resolver is not asked.
  asked.clear();
  doc["objects"][0]["shape"] = {{"type", "file"}, {"node", 3}};
  parsed = parse_scene(doc, {}, sources);
  EXPECT_TRUE(find_error(parsed, "/objects/0/shape/path")) << dump_errors(parsed);
  EXPECT_TRUE(find_error(parsed, "/objects/0/shape/node")) << dump_errors(parsed);
  EXPECT_TRUE(asked.empty());
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

TEST(SceneObjects, ShelteredDirectionsAreBitsOfTheObjectsOwnAxes) {
  json doc = minimal_scene();
  EXPECT_EQ(parse_ok(doc).objects[0].sheltered, 0u);
  doc["objects"][0]["sheltered"] = {"-z", "+x"};
  const std::uint8_t mask = parse_ok(doc).objects[0].sheltered;
  EXPECT_EQ(mask, kShelteredBack | 1u);
  EXPECT_TRUE(is_sheltered(mask, Eigen::Vector3d(0, 0, -1)));
  EXPECT_TRUE(is_sheltered(mask, Eigen::Vector3d(0.8, 0, 0.6)));   // 37° from +x
  EXPECT_FALSE(is_sheltered(mask, Eigen::Vector3d(0.6, 0, 0.8)));  // 53° from +x
  EXPECT_FALSE(is_sheltered(mask, Eigen::Vector3d(0, 0, 1)));
  EXPECT_FALSE(is_sheltered(mask, Eigen::Vector3d(0, -1, 0)));
  doc["objects"][0]["sheltered"] = {"back"};
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/sheltered/0"), "\"-z\""));
  doc["objects"][0]["sheltered"] = "-z";
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/sheltered"), "array"));
  doc["objects"][0]["sheltered"] = {"-z", "-z"};
  EXPECT_TRUE(contains(single_error(doc, "/objects/0/sheltered/1"), "twice"));
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
  doc["objects"][0]["fracture"] = {{"break", "always"},
                                   {"growth_length", 0.01},
                                   {"pattern_scale", 100},
                                   {"branch_angle", 15},
                                   {"angle_variance", 0},
                                   {"wiggle_probability", 0},
                                   {"wiggle_variance", 10},
                                   {"grid", 256},
                                   {"seed", 9},
                                   {"framed", true},
                                   {"bond_strength", 5},
                                   {"frame_strength", 6},
                                   {"frame_bite", 0.02},
                                   {"clearing", "pane"},
                                   {"strength", 1e8},
                                   {"toughness", 1e6},
                                   {"youngs_modulus", 6e10},
                                   {"breakage", "static"}};
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
  EXPECT_EQ(spec.breakage, FractureSpec::Breakage::static_plate);
  EXPECT_EQ(spec.strength_pa, 1e8);
  EXPECT_EQ(spec.fracture_toughness_pa_sqrt_m, 1e6);
  EXPECT_EQ(spec.youngs_modulus_pa, 6e10);
  doc["objects"][0]["material"] = "tempered_glass";
  doc["objects"][0]["fracture"] = json::object();
  EXPECT_EQ(parse_ok(doc).objects[0].fracture->strength_pa, 120e6);
  EXPECT_EQ(parse_ok(doc).objects[0].fracture->breakage, FractureSpec::Breakage::dynamic);
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
      {"/objects/0/fracture/breakage",
       [](json& d) { d["objects"][0]["fracture"]["breakage"] = "wobbly"; }, "dynamic, static"},
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
      {"/objects/0/shape/size",
       [](json& d) {
         d["objects"][0]["shape"]["size"] = {1e200, 0.9, 0.006};
       },
       "at most 100 m"},
      {"/objects/0/shape/size/2",
       [](json& d) {
         d["objects"][0]["shape"]["size"] = {1.2, 0.9, 1e-200};
       },
       "at least 0.0001 m"},
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

TEST(SceneWindow, APaneOverAHundredMetresIsAnError) {
  json doc = window_scene();
  doc["generators"][0]["size"] = {101, 0.9};
  EXPECT_TRUE(contains(single_error(doc, "/generators/0/size/0"), "100"));
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
  EXPECT_EQ(pane.sheltered, kShelteredBack);  // a room behind the window, by default
  EXPECT_EQ(pane.fracture->clearing, FractureSpec::Clearing::pane);
  EXPECT_EQ(scene.objects[1].name, "w/frame/bottom");
  // The frame's inner edges meet the pane's edges.
  EXPECT_NEAR(scene.objects[1].position.y() + 0.5 * scene.objects[1].box_size_m.y(), 1.5 - 0.45,
              1e-12);
  json doc = window_scene();
  doc["generators"][0]["frame"] = false;
  doc["generators"][0]["material"] = "tempered_glass";
  doc["generators"][0]["fracture"] = {{"growth_length", 0.02}};
  doc["generators"][0]["sheltered_back"] = false;
  const Scene unframed = parse_ok(doc);
  ASSERT_EQ(unframed.objects.size(), 1u);
  EXPECT_EQ(unframed.objects[0].sheltered, 0u);
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
      {"/generators/0/size/1", [](json& d) { d["generators"][0]["size"][1] = -1; }, "(0, 100]"},
      {"/generators/0/material", [](json& d) { d["generators"][0]["material"] = "brick"; },
       "breakable material"},
      {"/generators/0/thickness", [](json& d) { d["generators"][0]["thickness"] = 0; },
       "[0.0001, 0.1]"},
      {"/generators/0/thickness", [](json& d) { d["generators"][0]["thickness"] = 1e-200; },
       "[0.0001, 0.1]"},
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

}  // namespace
}  // namespace brisance::scene
