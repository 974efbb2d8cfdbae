// Tests of sim/io/result_json: the documented structure, every Stats field, and the streamed
// writer producing exactly the text of the DOM.
#include "sim/io/result_json.hpp"

#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace brisance::io {
namespace {

using nlohmann::json;

// A box of half extents (hx, hy, hz).
geometry::TriangleMesh box(double hx, double hy, double hz) {
  return geometry::make_box(geometry::Vec3(2.0 * hx, 2.0 * hy, 2.0 * hz));
}

engine::Pose pose_at(std::size_t frame, std::size_t k) {
  const double angle = 0.3 * static_cast<double>(frame) * static_cast<double>(k + 1);
  engine::Pose pose;
  pose.position = {1.0 * static_cast<double>(frame) + static_cast<double>(k), 2.0,
                   -0.5 * static_cast<double>(frame)};
  pose.orientation = {0.0, std::sin(angle / 2), 0.0, std::cos(angle / 2)};
  return pose;
}

// Two static bodies (0, 2) and two animated ones listed out of body order (3, 1), 3 frames.
engine::Result synthetic_result() {
  engine::Result result;
  const char* names[] = {"ground", "door", "wall", "window"};
  for (std::size_t i = 0; i < 4; ++i) {
    engine::BodyInfo body;
    body.name = names[i];
    body.mass_kg = 10.0 * static_cast<double>(i + 1) + 0.25;
    body.mesh = box(0.5 + 0.1 * static_cast<double>(i), 1.0, 0.05);
    body.initial_pose.position = {static_cast<double>(i), 0.0, -1.5};
    body.initial_pose.orientation = {0.0, 0.0, std::sin(0.1), std::cos(0.1)};
    result.bodies.push_back(body);
  }
  result.animated = {3, 1};
  result.frame_times_s = {0.0, 1.0 / 60.0, 2.0 / 60.0};
  for (std::size_t f = 0; f < 3; ++f)
    for (std::size_t k = 0; k < 2; ++k)
      result.poses.push_back(pose_at(f, k));
  for (std::size_t i = 0; i < 4; ++i) {
    engine::FinalState state;
    state.name = result.bodies[i].name;
    state.pose = pose_at(2, i);
    state.linear_velocity_m_s = {0.5 * static_cast<double>(i), -1.0, 2.0};
    state.angular_velocity_rad_s = {0.0, 3.0, -0.125 * static_cast<double>(i)};
    result.final_state.push_back(state);
  }
  // Every field off its default so a field written from the wrong member shows.
  result.stats = {.steps = 1200,
                  .simulated_time_s = 0.04,
                  .wall_time_s = 0.7,
                  .ended_early = true,
                  .bodies = 4,
                  .bodies_anchored = 1,
                  .bodies_never_released = 2,
                  .fragments_held_by_frame = 1,
                  .bodies_slept = 3,
                  .bodies_static_in_frames = 5,
                  .panels = 48,
                  .panels_loaded = 30,
                  .panels_back_facing = 12,
                  .panels_not_reached = 6,
                  .body_steps = 2400,
                  .occlusion_skipped = false,
                  .panels_shielded = 9,
                  .panes_broken = 1,
                  .panes_not_broken = 7,
                  .fragments = 2,
                  .panels_merged = 16,
                  .collision_pairs = 90,
                  .collision_pairs_skipped = 8,
                  .contact_points = 150};
  result.warnings.push_back({"blast_out_of_range", "scaled distance above the fit", 7});
  engine::PaneReport pane;
  pane.name = "window/pane";
  pane.broken = true;
  pane.peak_pressure_pa = 8.1e4;
  pane.stress_pa = 7.8e8;
  pane.strength_pa = 4.5e7;
  pane.deflection_m = 0.25;
  pane.small_deflection = false;
  pane.critical_crack_length_m = 3e-7;
  pane.growth_length_m = 1.5e-3;
  pane.growth_length_clamped = true;
  pane.first_body = 2;
  pane.fragment_count = 2;
  pane.frontal_area_m2 = {
      .count = 2, .mean = 0.5, .min = 0.25, .p10 = 0.25, .p50 = 0.25, .p90 = 0.75, .max = 0.75};
  pane.launch_speed_m_s = {.count = 1, .mean = 3, .min = 3, .p10 = 3, .p50 = 3, .p90 = 3, .max = 3};
  pane.launch_speed_larger_half_m_s = 3;
  pane.launch_speed_mass_weighted_m_s = 2.5;
  pane.cracks_start_s = 0.0125;
  pane.crack_origin_m = {0.75, 0.5};
  pane.released = 1;
  pane.release_times_s = {0.0173, -1.0};
  pane.release_time_s = {.count = 1,
                         .mean = 0.0173,
                         .min = 0.0173,
                         .p10 = 0.0173,
                         .p50 = 0.0173,
                         .p90 = 0.0173,
                         .max = 0.0173};
  pane.empirical_mean_area_m2 = 1.9e-5;
  pane.empirical_mean_speed_m_s = 46.3;
  pane.hazard.condition = "3b";
  pane.hazard.protection_level = "high";
  pane.hazard.hazard_level = "low";
  pane.hazard.floor_height_m = -0.5;
  pane.hazard.fragments_in_room = 1;
  pane.hazard.fragments_on_floor = 1;
  pane.hazard.max_floor_distance_m = 2.25;
  result.fracture.push_back(pane);
  return result;
}

void expect_vec3(const json& j, const std::array<double, 3>& v) {
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_EQ(j[i].get<double>(), v[i]) << i;
}

void expect_quat(const json& j, const std::array<double, 4>& q) {
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(j[i].get<double>(), q[i]) << i;
}

// Parsed back from the streamed text, so the test covers what a client reads.
json round_trip(const engine::Result& result) {
  std::ostringstream out;
  write_result_json(result, out);
  return json::parse(out.str());
}

TEST(ResultJson, HasExactlyTheDocumentedTopLevelMembers) {
  const json j = round_trip(synthetic_result());
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items())
    keys.insert(key);
  EXPECT_EQ(keys, (std::set<std::string>{"bodies", "frames", "final_state", "fracture", "shielding",
                                         "stats", "warnings"}));
}

TEST(ResultJson, ShieldingNamesEachShieldedBodyPerCharge) {
  engine::Result result = synthetic_result();
  EXPECT_EQ(round_trip(result)["shielding"], json::array());
  result.shielding.push_back({0, {{1, 0.0}, {2, 0.25}}});
  result.shielding.push_back({1, {}});
  const json j = round_trip(result)["shielding"];
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["charge"], 0);
  EXPECT_EQ(j[0]["bodies"][0],
            (json{{"body", 1}, {"name", result.bodies[1].name}, {"attenuation", 0.0}}));
  EXPECT_EQ(j[0]["bodies"][1]["attenuation"], 0.25);
  EXPECT_EQ(j[1], (json{{"charge", 1}, {"bodies", json::array()}}));
  EXPECT_EQ(j, round_trip(result)["shielding"]);
  EXPECT_EQ(result_to_json(result)["shielding"], j);  // the DOM and the streamed text agree
}

TEST(ResultJson, BodiesCarryNameMassMeshPoseAndAnimatedFlag) {
  const engine::Result result = synthetic_result();
  const json j = round_trip(result);
  ASSERT_EQ(j["bodies"].size(), 4u);
  const bool expected_animated[] = {false, true, false, true};
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    const json& body = j["bodies"][i];
    const engine::BodyInfo& info = result.bodies[i];
    EXPECT_EQ(body["name"], info.name);
    EXPECT_EQ(body["mass"].get<double>(), info.mass_kg);
    EXPECT_EQ(body["animated"], expected_animated[i]);
    expect_vec3(body["position"], info.initial_pose.position);
    expect_quat(body["orientation"], info.initial_pose.orientation);
    ASSERT_EQ(body["mesh"]["vertices"].size(), info.mesh.vertices.size());
    for (std::size_t v = 0; v < info.mesh.vertices.size(); ++v) {
      const geometry::Vec3& vertex = info.mesh.vertices[v];
      expect_vec3(body["mesh"]["vertices"][v], {vertex.x(), vertex.y(), vertex.z()});
    }
    ASSERT_EQ(body["mesh"]["triangles"].size(), info.mesh.triangles.size());
    for (std::size_t t = 0; t < info.mesh.triangles.size(); ++t)
      EXPECT_EQ(body["mesh"]["triangles"][t].get<std::vector<std::uint32_t>>(),
                (std::vector<std::uint32_t>(info.mesh.triangles[t].begin(),
                                            info.mesh.triangles[t].end())));
  }
}

TEST(ResultJson, FramesListOnlyTheAnimatedBodiesByIndex) {
  const engine::Result result = synthetic_result();
  const json j = round_trip(result);
  ASSERT_EQ(j["frames"].size(), 3u);
  for (std::size_t f = 0; f < 3; ++f) {
    SCOPED_TRACE(f);
    const json& frame = j["frames"][f];
    EXPECT_EQ(frame.size(), 3u) << frame.dump();
    EXPECT_EQ(frame["index"].get<std::size_t>(), f);
    EXPECT_EQ(frame["time"].get<double>(), result.frame_times_s[f]);
    ASSERT_EQ(frame["poses"].size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const json& entry = frame["poses"][k];
      EXPECT_EQ(entry.size(), 3u) << entry.dump();
      EXPECT_EQ(entry["body"].get<std::uint32_t>(), result.animated[k]);
      expect_vec3(entry["position"], pose_at(f, k).position);
      expect_quat(entry["orientation"], pose_at(f, k).orientation);
    }
  }
}

TEST(ResultJson, FinalStateAndWarnings) {
  const engine::Result result = synthetic_result();
  const json j = round_trip(result);
  ASSERT_EQ(j["final_state"].size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    const json& state = j["final_state"][i];
    const engine::FinalState& expected = result.final_state[i];
    EXPECT_EQ(state.size(), 5u);
    EXPECT_EQ(state["name"], expected.name);
    expect_vec3(state["position"], expected.pose.position);
    expect_quat(state["orientation"], expected.pose.orientation);
    expect_vec3(state["linear_velocity"], expected.linear_velocity_m_s);
    expect_vec3(state["angular_velocity"], expected.angular_velocity_rad_s);
  }
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_EQ(j["warnings"][0], (json{{"code", "blast_out_of_range"},
                                    {"message", "scaled distance above the fit"},
                                    {"count", 7}}));
}

TEST(ResultJson, StatsHoldEveryFieldUnderItsMemberName) {
  const engine::Result result = synthetic_result();
  const json stats = round_trip(result)["stats"];
  const json expected = {{"steps", 1200},
                         {"simulated_time_s", 0.04},
                         {"wall_time_s", 0.7},
                         {"ended_early", true},
                         {"bodies", 4},
                         {"bodies_anchored", 1},
                         {"bodies_never_released", 2},
                         {"fragments_held_by_frame", 1},
                         {"bodies_slept", 3},
                         {"bodies_static_in_frames", 5},
                         {"panels", 48},
                         {"panels_loaded", 30},
                         {"panels_back_facing", 12},
                         {"panels_not_reached", 6},
                         {"body_steps", 2400},
                         {"occlusion_skipped", false},
                         {"panels_shielded", 9},
                         {"panes_broken", 1},
                         {"panes_not_broken", 7},
                         {"fragments", 2},
                         {"panels_merged", 16},
                         {"collision_pairs", 90},
                         {"collision_pairs_skipped", 8},
                         {"contact_points", 150}};
  EXPECT_EQ(stats, expected) << stats.dump();
  EXPECT_EQ(stats_to_json(result.stats), expected);
}

TEST(ResultJson, FractureHoldsEveryPaneField) {
  const json fracture = round_trip(synthetic_result())["fracture"];
  ASSERT_EQ(fracture.size(), 1u);
  const json& pane = fracture[0];
  EXPECT_EQ(pane.size(), 27u) << pane.dump();
  EXPECT_EQ(pane["name"], "window/pane");
  EXPECT_EQ(pane["broken"], true);
  EXPECT_EQ(pane["forced"], false);
  EXPECT_EQ(pane["peak_pressure_pa"], 8.1e4);
  EXPECT_EQ(pane["stress_pa"], 7.8e8);
  EXPECT_EQ(pane["strength_pa"], 4.5e7);
  EXPECT_EQ(pane["deflection_m"], 0.25);
  EXPECT_EQ(pane["small_deflection"], false);
  EXPECT_EQ(pane["critical_crack_length_m"], 3e-7);
  EXPECT_EQ(pane["growth_length_m"], 1.5e-3);
  EXPECT_EQ(pane["growth_length_given"], false);
  EXPECT_EQ(pane["growth_length_clamped"], true);
  EXPECT_EQ(pane["first_body"], 2);
  EXPECT_EQ(pane["fragment_count"], 2);
  EXPECT_EQ(pane["frontal_area_m2"], (json{{"count", 2},
                                           {"mean", 0.5},
                                           {"min", 0.25},
                                           {"p10", 0.25},
                                           {"p50", 0.25},
                                           {"p90", 0.75},
                                           {"max", 0.75}}));
  EXPECT_EQ(pane["launch_speed_m_s"]["mean"], 3.0);
  EXPECT_EQ(pane["launch_speed_larger_half_m_s"], 3.0);
  EXPECT_EQ(pane["launch_speed_mass_weighted_m_s"], 2.5);
  EXPECT_EQ(pane["cracks_start_s"], 0.0125);
  EXPECT_EQ(pane["crack_origin_m"], json::array({0.75, 0.5}));
  EXPECT_EQ(pane["launch_speed_smaller_half_m_s"], 0.0);
  EXPECT_EQ(pane["released"], 1);
  // A fragment that never broke free is null.
  EXPECT_EQ(pane["release_times_s"], (json::array({0.0173, nullptr})));
  EXPECT_EQ(pane["release_time_s"]["max"], 0.0173);
  EXPECT_EQ(pane["empirical_mean_area_m2"], 1.9e-5);
  EXPECT_EQ(pane["empirical_mean_speed_m_s"], 46.3);
  EXPECT_EQ(pane["hazard"], (json{{"condition", "3b"},
                                  {"protection_level", "high"},
                                  {"hazard_level", "low"},
                                  {"floor_height_m", -0.5},
                                  {"fragments_in_room", 1},
                                  {"fragments_outside", 0},
                                  {"fragments_on_floor", 1},
                                  {"witness_impacts", 0},
                                  {"fragments_extrapolated", 0},
                                  {"max_floor_distance_m", 2.25},
                                  {"max_witness_height_m", 0.0}}));
  EXPECT_EQ(round_trip(engine::Result{})["fracture"], json::array());
}

TEST(ResultJson, StreamedTextIsTheCompactDumpAndANewline) {
  // Frames are streamed without a DOM, so the numbers nlohmann formats specially must match too:
  // NaN (null), negative zero, integral values, extremes.
  engine::Result odd_numbers = synthetic_result();
  odd_numbers.poses[0].position = {std::nan(""), -0.0, 3.0};
  odd_numbers.poses[1].position = {1e-300, -1.7976931348623157e308, 0.1 + 0.2};
  odd_numbers.poses[2].orientation = {5e-324, 1e21, -1e-7, 123456789.0};
  // Frames but no animated body: every frame lists no bodies.
  engine::Result still = synthetic_result();
  still.animated.clear();
  still.poses.clear();
  for (const engine::Result& result : {synthetic_result(), odd_numbers, still, engine::Result{}}) {
    std::ostringstream out;
    write_result_json(result, out);
    EXPECT_EQ(out.str(), result_to_json(result).dump() + "\n");
  }
}

TEST(ResultJson, EmptyResultHasEmptyArrays) {
  const json j = round_trip(engine::Result{});
  EXPECT_EQ(j["bodies"], json::array());
  EXPECT_EQ(j["frames"], json::array());
  EXPECT_EQ(j["final_state"], json::array());
  EXPECT_EQ(j["warnings"], json::array());
  EXPECT_EQ(j["stats"]["steps"], 0);
}

// 10 000 animated bodies x 60 frames (the size DESIGN.md targets): the streamed writer handles it
// in one pass; its text is checked piecewise rather than parsed whole to keep the test fast.
TEST(ResultJson, TenThousandBodiesBySixtyFramesStream) {
  constexpr std::size_t kBodies = 10000;
  constexpr std::size_t kFrames = 60;
  engine::Result result;
  result.bodies.resize(kBodies);
  for (std::size_t i = 0; i < kBodies; ++i) {
    result.bodies[i].name = "b" + std::to_string(i);
    result.animated.push_back(static_cast<std::uint32_t>(i));
  }
  for (std::size_t f = 0; f < kFrames; ++f)
    result.frame_times_s.push_back(static_cast<double>(f) / 60.0);
  result.poses.resize(kBodies * kFrames);
  for (std::size_t p = 0; p < result.poses.size(); ++p)
    result.poses[p].position = {static_cast<double>(p), 0.0, 0.0};

  std::ostringstream out;
  write_result_json(result, out);
  const std::string text = out.str();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  // Every pose appears once, and the last one is the last frame's last body.
  std::size_t entries = 0;
  for (std::size_t at = text.find("{\"body\":"); at != std::string::npos;
       at = text.find("{\"body\":", at + 1))
    ++entries;
  EXPECT_EQ(entries, kBodies * kFrames);
  const std::string last_pose = "{\"body\":9999,\"orientation\":[0.0,0.0,0.0,1.0],\"position\":[" +
                                json(static_cast<double>(kBodies * kFrames - 1)).dump() +
                                ",0.0,0.0]}],\"time\":";
  EXPECT_NE(text.find(last_pose), std::string::npos);
}

}  // namespace
}  // namespace brisance::io
