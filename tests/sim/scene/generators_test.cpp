// Tests of sim/scene/generators and parse_generators (brick walls, block grids) and the
// materials table.
#include "sim/scene/generators.hpp"

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

#include "sim/scene/scene.hpp"
#include "tests/sim/scene/scene_test_support.hpp"

namespace brisance::scene {
namespace {

using namespace test_support;
using json = nlohmann::json;

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

// ---------------------------------------------------------------------------------------------
// Openings in a brick wall

// The thesis wall (6 rows x 5 columns of 0.4 x 0.15 x 0.1 m bricks, 2.0 x 0.9 m) with openings.
BrickWallParams thesis_wall(std::vector<WallOpening> openings) {
  BrickWallParams wall;
  wall.name = "wall";
  wall.rows = 6;
  wall.columns = 5;
  wall.brick_size_m = Vec3(0.4, 0.15, 0.1);
  wall.brick_mass_kg = 10.0;
  wall.openings = std::move(openings);
  return wall;
}

WallOpening hole(double x, double y, double width, double height) {
  WallOpening opening;
  opening.centre_m = {x, y};
  opening.size_m = {width, height};
  return opening;
}

// How many bricks cover the point (x, y) of the wall's frame (the wall stands at the origin).
int bricks_covering(const std::vector<ObjectSpec>& bricks, double x, double y) {
  int count = 0;
  for (const ObjectSpec& brick : bricks) {
    if (std::abs(x - brick.position.x()) < 0.5 * brick.box_size_m.x() &&
        std::abs(y - brick.position.y()) < 0.5 * brick.box_size_m.y())
      ++count;
  }
  return count;
}

double total_mass(const std::vector<ObjectSpec>& objects) {
  double mass = 0.0;
  for (const ObjectSpec& object : objects)
    mass += object.mass_kg;
  return mass;
}

TEST(BrickWallOpenings, ABrickSizedHoleDropsExactlyThatBrick) {
  // Row 2 (even) holds five full bricks; its middle one spans x -0.2..0.2, y 0.3..0.45.
  const auto bricks = brick_wall(thesis_wall({hole(0.0, 0.375, 0.4, 0.15)}));
  EXPECT_EQ(bricks.size(), brick_wall_count(6, 5) - 1);
  EXPECT_NEAR(total_mass(bricks), 300.0 - 10.0, 1e-9);
  EXPECT_EQ(bricks_covering(bricks, 0.0, 0.375), 0);
  // The row's remaining bricks are numbered on, left to right.
  std::set<std::string> names;
  for (const ObjectSpec& brick : bricks)
    names.insert(brick.name);
  EXPECT_TRUE(names.count("wall/r2/b3"));
  EXPECT_FALSE(names.count("wall/r2/b4"));
}

TEST(BrickWallOpenings, NeighboursAreShortenedToTheEdgeWithTheirShareOfMass) {
  // 0.5 m wide: the middle brick goes, each neighbour loses 0.05 of its 0.4 m (1.25 kg).
  const auto bricks = brick_wall(thesis_wall({hole(0.0, 0.375, 0.5, 0.15)}));
  EXPECT_EQ(bricks.size(), brick_wall_count(6, 5) - 1);
  EXPECT_NEAR(total_mass(bricks), 300.0 - 10.0 - 2.0 * 1.25, 1e-9);
  int shortened = 0;
  for (const ObjectSpec& brick : bricks) {
    if (std::abs(brick.box_size_m.x() - 0.35) < 1e-12) {
      ++shortened;
      EXPECT_NEAR(brick.mass_kg, 8.75, 1e-12);
      EXPECT_NEAR(std::abs(brick.position.x()) - 0.175, 0.25, 1e-12);  // its inner end at 0.25
    }
  }
  EXPECT_EQ(shortened, 2);
}

TEST(BrickWallOpenings, NoBrickOverlapsAHoleAndTheRestOfTheWallIsCovered) {
  // Two holes off the brick grid, touching each other: bricks are cut across courses.
  const std::vector<WallOpening> openings = {hole(-0.35, 0.42, 0.62, 0.41),
                                             hole(0.31, 0.5, 0.7, 0.5)};
  BrickWallParams wall = thesis_wall(openings);
  wall.rows = 12;  // 4.0 x 1.8 m: room around the holes
  wall.columns = 10;
  const auto bricks = brick_wall(wall);
  for (const ObjectSpec& brick : bricks) {
    for (const WallOpening& opening : openings) {
      const double dx = 0.5 * (brick.box_size_m.x() + opening.size_m[0]) -
                        std::abs(brick.position.x() - opening.centre_m[0]);
      const double dy = 0.5 * (brick.box_size_m.y() + opening.size_m[1]) -
                        std::abs(brick.position.y() - opening.centre_m[1]);
      EXPECT_FALSE(dx > 1e-12 && dy > 1e-12) << brick.name << " overlaps an opening";
    }
    // No slivers.
    EXPECT_GE(brick.box_size_m.x(), kMinBrickPartFraction * 0.4 - 1e-12) << brick.name;
    EXPECT_GE(brick.box_size_m.y(), kMinBrickPartFraction * 0.15 - 1e-12) << brick.name;
  }
  // Every point of the wall farther from the holes than a brick (where dropped slivers may leave
  // gaps) is covered exactly once.
  int sampled = 0;
  for (double x = -1.995; x < 2.0; x += 0.01) {
    for (double y = 0.005; y < 1.8; y += 0.01) {
      bool near_a_hole = false;
      for (const WallOpening& opening : openings) {
        near_a_hole =
            near_a_hole || (std::abs(x - opening.centre_m[0]) < 0.5 * opening.size_m[0] + 0.4 &&
                            std::abs(y - opening.centre_m[1]) < 0.5 * opening.size_m[1] + 0.15);
      }
      if (!near_a_hole) {
        EXPECT_EQ(bricks_covering(bricks, x, y), 1) << x << ", " << y;
        ++sampled;
      }
    }
  }
  EXPECT_GT(sampled, 40000);
}

// A scene with the thesis wall at [3, 0, 2], turned a quarter about y, with the given openings.
json wall_with_openings(const json& openings) {
  json doc = minimal_scene();
  json g = brick_wall_generator();
  g["position"] = {3, 0, 2};
  g["orientation"] = {0, std::sin(std::numbers::pi / 4), 0, std::cos(std::numbers::pi / 4)};
  g["openings"] = openings;
  doc["generators"] = {g};
  return doc;
}

TEST(BrickWallOpenings, AWindowSitsInItsOpeningWithASheltheredBack) {
  const Scene scene = parse_ok(wall_with_openings(json::parse(R"([
      {"position": [0.2, 0.45], "size": [0.8, 0.5],
       "window": {"thickness": 0.005, "frame_width": 0.06}}])")));
  const Quat turn(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const Vec3 origin(3, 0, 2);
  std::map<std::string, const ObjectSpec*> by_name;
  for (const ObjectSpec& object : scene.objects)
    by_name[object.name] = &object;
  ASSERT_TRUE(by_name.count("wall/opening0/pane"));
  const ObjectSpec& pane = *by_name["wall/opening0/pane"];
  EXPECT_TRUE((pane.position - (origin + turn * Vec3(0.2, 0.45, 0.0))).norm() < 1e-12);
  EXPECT_TRUE(pane.orientation.isApprox(turn, 1e-12));
  // The frame lies outside the pane, inside the opening.
  EXPECT_NEAR(pane.box_size_m.x(), 0.8 - 2 * 0.06, 1e-12);
  EXPECT_NEAR(pane.box_size_m.y(), 0.5 - 2 * 0.06, 1e-12);
  EXPECT_NEAR(pane.box_size_m.z(), 0.005, 1e-12);
  EXPECT_EQ(pane.sheltered, kShelteredBack);
  ASSERT_TRUE(pane.fracture.has_value());
  EXPECT_TRUE(pane.fracture->framed);
  // The frame's outer edges are the opening's, in the wall's frame.
  double left = INFINITY, right = -INFINITY, bottom = INFINITY, top = -INFINITY;
  for (const char* bar : {"bottom", "top", "left", "right"}) {
    const std::string name = std::string("wall/opening0/frame/") + bar;
    ASSERT_TRUE(by_name.count(name)) << name;
    const ObjectSpec& frame = *by_name[name];
    EXPECT_TRUE(frame.anchored);
    const Vec3 local = turn.inverse() * (frame.position - origin);
    left = std::min(left, local.x() - 0.5 * frame.box_size_m.x());
    right = std::max(right, local.x() + 0.5 * frame.box_size_m.x());
    bottom = std::min(bottom, local.y() - 0.5 * frame.box_size_m.y());
    top = std::max(top, local.y() + 0.5 * frame.box_size_m.y());
  }
  EXPECT_NEAR(left, -0.2, 1e-12);
  EXPECT_NEAR(right, 0.6, 1e-12);
  EXPECT_NEAR(bottom, 0.2, 1e-12);
  EXPECT_NEAR(top, 0.7, 1e-12);
  // No brick overlaps the window (checked in the wall's frame).
  for (const ObjectSpec& object : scene.objects) {
    if (object.name.find("/opening") != std::string::npos) continue;
    const Vec3 local = turn.inverse() * (object.position - origin);
    EXPECT_FALSE(std::abs(local.x() - 0.2) < 0.5 * (object.box_size_m.x() + 0.8) - 1e-9 &&
                 std::abs(local.y() - 0.45) < 0.5 * (object.box_size_m.y() + 0.5) - 1e-9)
        << object.name;
  }
}

TEST(BrickWallOpenings, AnEmptyOpeningHasNoWindowAndNoFrameTheOpeningHasNoFrame) {
  const Scene empty = parse_ok(wall_with_openings(json::parse(R"([
      {"position": [0, 0.45], "size": [0.8, 0.3]}])")));
  for (const ObjectSpec& object : empty.objects)
    EXPECT_EQ(object.name.find("opening"), std::string::npos) << object.name;
  const Scene frameless = parse_ok(wall_with_openings(json::parse(R"([
      {"position": [0, 0.45], "size": [0.8, 0.3], "window": {"frame": false}}])")));
  int windows = 0;
  for (const ObjectSpec& object : frameless.objects) {
    if (object.name.find("opening") == std::string::npos) continue;
    ++windows;
    EXPECT_EQ(object.name, "wall/opening0/pane");
    EXPECT_NEAR(object.box_size_m.x(), 0.8, 1e-12);  // the whole opening
  }
  EXPECT_EQ(windows, 1);
}

TEST(BrickWallOpenings, BadOpeningsAreErrorsWithPointers) {
  const std::pair<const char*, const char*> cases[] = {
      {"/generators/0/openings", R"({"position": [0, 0.4], "size": [0.5, 0.3]})"},
      {"/generators/0/openings/0", R"([5])"},
      {"/generators/0/openings/0/size", R"([{"position": [0, 0.4]}])"},
      {"/generators/0/openings/0/size/0", R"([{"position": [0, 0.4], "size": [0, 0.3]}])"},
      {"/generators/0/openings/0/position", R"([{"position": [0], "size": [0.5, 0.3]}])"},
      {"/generators/0/openings/0/door", R"([{"position": [0, 0.4], "size": [0.5, 0.3],
                                             "door": true}])"},
      // Outside the wall's outline (x -1..1, y 0..0.9): past an end, above, below.
      {"/generators/0/openings/0/position", R"([{"position": [0.9, 0.4], "size": [0.5, 0.3]}])"},
      {"/generators/0/openings/0/position", R"([{"position": [0, 0.8], "size": [0.5, 0.3]}])"},
      {"/generators/0/openings/0/position", R"([{"position": [0, 0.1], "size": [0.5, 0.3]}])"},
      {"/generators/0/openings/1", R"([{"position": [-0.3, 0.4], "size": [0.5, 0.3]},
                                       {"position": [0.1, 0.5], "size": [0.5, 0.3]}])"},
      {"/generators/0/openings/0/window/frame_width",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"frame_width": 0.15}}])"},
      {"/generators/0/openings/0/window/material",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"material": "brick"}}])"},
      {"/generators/0/openings/0/window/name",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"name": "w"}}])"},
      {"/generators/0/openings/0/window/size",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"size": [0.4, 0.2]}}])"},
      {"/generators/0/openings/0/window/thickness",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"thickness": 0.3}}])"},
      // Thinner than 0.1 mm: the plate model's mass and stiffness would underflow.
      {"/generators/0/openings/0/window/thickness",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3], "window": {"thickness": 1e-200}}])"},
      {"/generators/0/openings/0/window/frame_depth",
       R"([{"position": [0, 0.4], "size": [0.5, 0.3],
            "window": {"thickness": 0.05, "frame_depth": 0.01}}])"},
  };
  for (const auto& [pointer, openings] : cases) {
    SCOPED_TRACE(openings);
    single_error(wall_with_openings(json::parse(openings)), pointer);
  }
  // Touching openings, and one flush with the wall's ends and base (a door), are fine.
  parse_ok(wall_with_openings(json::parse(R"([
      {"position": [-0.75, 0.3], "size": [0.5, 0.6]},
      {"position": [-0.25, 0.45], "size": [0.5, 0.3]},
      {"position": [0.75, 0.45], "size": [0.5, 0.9]}])")));
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

}  // namespace
}  // namespace brisance::scene
