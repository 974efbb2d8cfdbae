// Helpers shared by the tests of sim/scene: a valid scene to start from, and parsing that expects
// success or exactly one error at a given pointer.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/scene/scene.hpp"

namespace brisance::scene::test_support {

using json = nlohmann::json;

// A valid scene to start from: one charge 5 m in front of a 1 m cube resting on the ground.
inline json minimal_scene() {
  return json::parse(R"({
    "charges": [{"position": [0, 1, -5], "mass": 1}],
    "objects": [{"name": "cube", "shape": {"type": "box", "size": [1, 1, 1]},
                 "position": [0, 0.5, 0], "mass": 10}]
  })");
}

inline std::string dump_errors(const ParseResult& result) {
  std::string text;
  for (const ValidationError& error : result.errors)
    text += "  " + (error.pointer.empty() ? std::string("\"\"") : error.pointer) + ": " +
            error.message + "\n";
  return text;
}

inline const ValidationError* find_error(const ParseResult& result, const std::string& pointer) {
  for (const ValidationError& error : result.errors)
    if (error.pointer == pointer) return &error;
  return nullptr;
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Parses and expects success.
inline Scene parse_ok(const json& document, const Limits& limits = {}) {
  ParseResult result = parse_scene(document, limits);
  EXPECT_TRUE(result.errors.empty()) << dump_errors(result);
  EXPECT_TRUE(result.scene.has_value());
  return result.scene.value_or(Scene{});
}

// Parses and expects exactly one error, at `pointer`; returns its message.
inline std::string single_error(const json& document, const std::string& pointer,
                                const Limits& limits = {}) {
  const ParseResult result = parse_scene(document, limits);
  EXPECT_FALSE(result.scene.has_value());
  EXPECT_EQ(result.errors.size(), 1u) << dump_errors(result);
  const ValidationError* error = find_error(result, pointer);
  EXPECT_NE(error, nullptr) << "no error at " << pointer << ", got:\n" << dump_errors(result);
  return error ? error->message : std::string();
}

// A unit tetrahedron (volume 1/6), wound counter-clockwise seen from outside.
inline json tetrahedron_shape() {
  return json::parse(R"({"type": "mesh",
    "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "triangles": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]})");
}

inline json brick_wall_generator() {
  return json::parse(R"({"type": "brick_wall", "name": "wall", "rows": 6, "columns": 5,
                         "brick_size": [0.4, 0.15, 0.1], "brick_mass": 10})");
}

// Lowest y of an object's vertices in the world.
inline double lowest_y(const ObjectSpec& object) {
  double lowest = INFINITY;
  for (const Vec3& v : object.mesh.vertices)
    lowest = std::min(lowest, (object.position + object.orientation * v).y());
  return lowest;
}

}  // namespace brisance::scene::test_support
