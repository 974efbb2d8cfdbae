// Parsing and validation of the scene JSON (DESIGN.md "Contracts"), in three layers: the reader
// (reader.hpp: pointers, bounds, typed values, did-you-mean), the parsers of each section
// (sections.hpp) and the checks across sections (checks.hpp). This file runs them in order. The
// parser never stops at the first problem: each value is checked where it is, and an invalid value
// is reported and skipped (its object or charge drops out of the cross-checks) so one run lists
// everything the user has to fix. The order of the errors is part of the contract.
#include "sim/scene/scene.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/scene/checks.hpp"
#include "sim/scene/reader.hpp"
#include "sim/scene/sections.hpp"

namespace brisance::scene {

ParseResult parse_scene(const json& document, const Limits& limits, const MeshSources& meshes) {
  Errors errors;
  ParseResult result;
  if (!document.is_object()) {
    errors.add("",
               "a scene must be a JSON object {\"charges\": [...], \"objects\": [...], ...}; "
               "got " +
                   describe(document));
    result.errors = errors.take();
    return result;
  }
  const Fields top(document, "", errors, "the scene",
                   {"charges", "environment", "objects", "generators", "simulation"});
  Scene scene;

  // Charges (invalid ones stay as nullopt so their indices still match for later checks).
  std::vector<std::optional<ChargeSpec>> charges;
  if (const json* list = top.require("charges",
                                     "an array of at least one charge {\"position\": "
                                     "[x, y, z], \"mass\": kg}")) {
    const std::string at = top.at("charges");
    if (expect_array(*list, at, "'charges'", errors)) {
      if (list->empty()) {
        errors.add(at,
                   "the scene needs at least one charge; add {\"position\": [x, y, z], "
                   "\"mass\": kg}");
      } else if (list->size() > limits.max_charges) {
        errors.add(at, "the scene has " + std::to_string(list->size()) +
                           " charges, more than the limit max_charges = " +
                           std::to_string(limits.max_charges));
      } else {
        for (std::size_t i = 0; i < list->size(); ++i)
          charges.push_back(parse_charge((*list)[i], child(at, i), errors));
      }
    }
  }

  if (const json* environment = top.get("environment"))
    scene.environment = parse_environment(*environment, top.at("environment"), errors);

  std::vector<SceneObject> objects;
  if (const json* list = top.get("objects")) {
    const std::string at = top.at("objects");
    if (expect_array(*list, at, "'objects'", errors)) {
      if (list->size() > limits.max_objects) {
        errors.add(at, "the scene has " + std::to_string(list->size()) +
                           " objects, more than the limit max_objects = " +
                           std::to_string(limits.max_objects));
      } else {
        for (std::size_t i = 0; i < list->size(); ++i) {
          if (auto object = parse_object((*list)[i], child(at, i), limits, meshes, errors))
            objects.push_back(std::move(*object));
        }
      }
    }
  }
  const json* explicit_objects = top.get("objects");
  const std::size_t explicit_count =
      explicit_objects && explicit_objects->is_array() ? explicit_objects->size() : 0;

  bool generators_ok = true;
  if (const json* list = top.get("generators")) {
    const std::string at = top.at("generators");
    if (expect_array(*list, at, "'generators'", errors)) {
      std::size_t before = explicit_count;
      for (std::size_t i = 0; i < list->size(); ++i) {
        const ErrorScope scope(errors);
        auto generated = parse_generator((*list)[i], child(at, i), i, before, limits, errors);
        generators_ok = generators_ok && scope.ok();
        before += generated.size();
        for (SceneObject& object : generated)
          objects.push_back(std::move(object));
      }
    } else {
      generators_ok = false;
    }
  }

  bool simulation_ok = true;
  if (const json* simulation = top.get("simulation")) {
    const ErrorScope scope(errors);
    scene.simulation = parse_simulation(*simulation, top.at("simulation"), limits, errors);
    simulation_ok = scope.ok();
  }

  // The scene as a whole. An empty scene is only reported when nothing else explains it.
  if (objects.empty() && explicit_count == 0 && generators_ok &&
      (!explicit_objects || explicit_objects->is_array())) {
    errors.add("/objects",
               "the scene needs at least one object: add one to 'objects' or add a "
               "generator to 'generators'");
  }
  check_unique_names(objects, errors);
  check_charges_above_ground(scene.environment.ground, charges, errors);
  check_objects_above_ground(scene.environment.ground, objects, errors);
  check_charges_outside_objects(charges, objects, errors);
  check_limits(objects, scene.simulation, simulation_ok, limits, errors);

  result.errors = errors.take();
  if (!result.errors.empty()) return result;
  for (auto& charge : charges)
    scene.charges.push_back(std::move(*charge));
  scene.objects.reserve(objects.size());
  for (SceneObject& object : objects)
    scene.objects.push_back(std::move(object.spec));
  result.scene = std::move(scene);
  return result;
}

ParseResult parse_scene_text(std::string_view text, const Limits& limits,
                             const MeshSources& meshes) {
  json document;
  try {
    document = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& error) {
    // what() reads "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string detail = error.what();
    if (const auto bracket = detail.find("] ");
        detail.starts_with("[json.exception") && bracket != std::string::npos)
      detail = detail.substr(bracket + 2);
    ParseResult result;
    result.errors.push_back({"", "malformed JSON at byte " + std::to_string(error.byte) + ": " +
                                     detail + "; fix the JSON syntax"});
    return result;
  } catch (const json::out_of_range&) {
    // A number beyond a double's range (1e400) is well-formed JSON that the parser cannot hold
    // (found by tests/fuzz: it escaped as an exception, so `brisance validate` exited 1).
    ParseResult result;
    result.errors.push_back(
        {"", "a number in the JSON is too large for a double (about 1.8e308 at most); fix it"});
    return result;
  }
  return parse_scene(document, limits, meshes);
}

bool is_sheltered(std::uint8_t mask, const Vec3& normal) {
  constexpr double kCos45 = 0.70710678118654752;
  for (int axis = 0; axis < 3; ++axis) {
    if ((mask & (1u << (2 * axis))) && normal[axis] > kCos45) return true;
    if ((mask & (1u << (2 * axis + 1))) && -normal[axis] > kCos45) return true;
  }
  return false;
}

}  // namespace brisance::scene
