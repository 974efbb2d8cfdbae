// Tests of `brisance run` in-process: every output form (.json, .brf, .glb) carries the same
// frames in the one frame shape, and an unknown extension is a usage error.
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli/commands.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/io/frames.hpp"
#include "sim/io/gltf.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::cli {
namespace {

using nlohmann::json;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("brisance_run_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Two wooden blocks, one pushed by a 10 kg charge, and an anchored slab that never moves:
// a run of a few ms with animated and static bodies.
const json& scene_json() {
  static const json scene = {{"charges", {{{"position", {0, 0.25, 0}}, {"mass", 10}}}},
                             {"objects",
                              {{{"name", "near"},
                                {"shape", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
                                {"position", {0.5, 0.25, 6}},
                                {"material", "wood"}},
                               {{"name", "slab"},
                                {"shape", {{"type", "box"}, {"size", {2, 0.2, 2}}}},
                                {"position", {-4, 0.1, 0}},
                                {"material", "concrete"},
                                {"anchored", true}},
                               {{"name", "far"},
                                {"shape", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
                                {"position", {3.0, 0.25, 6}},
                                {"material", "wood"}}}},
                             {"simulation", {{"duration", 0.5}, {"frame_rate", 20}}}};
  return scene;
}

class RunCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_path_ = temp_path("scene.json");
    std::ofstream(scene_path_) << scene_json().dump();
  }
  void TearDown() override {
    for (const std::string& path : written_)
      std::filesystem::remove(path);
    std::filesystem::remove(scene_path_);
  }
  std::string run_to(const std::string& name) {
    const std::string path = temp_path(name);
    written_.push_back(path);
    std::ostringstream out;
    EXPECT_EQ(run_simulation({scene_path_, "-o", path}, out), kExitOk);
    return read(path);
  }
  // The same scene simulated here: runs are deterministic, so its frames are the CLI's.
  static engine::Result simulate() {
    const scene::ParseResult parsed = scene::parse_scene(scene_json());
    EXPECT_TRUE(parsed.scene);
    return engine::simulate(*parsed.scene, {}).result;
  }

  std::string scene_path_;
  std::vector<std::string> written_;
};

TEST_F(RunCommand, JsonFramesHaveTheHttpShape) {
  const json result = json::parse(run_to("out.json"));
  const engine::Result expected = simulate();
  const json& frames = result.at("frames");
  ASSERT_EQ(frames.size(), expected.frame_times_s.size());
  ASSERT_FALSE(expected.animated.empty());
  ASSERT_LT(expected.animated.size(), expected.bodies.size());  // the slab is not in frames
  for (std::size_t f = 0; f < frames.size(); ++f) {
    SCOPED_TRACE(f);
    EXPECT_EQ(frames[f].size(), 3u);
    EXPECT_EQ(frames[f].at("index"), f);
    EXPECT_EQ(frames[f].at("time").get<double>(), expected.frame_times_s[f]);
    const json& poses = frames[f].at("poses");
    ASSERT_EQ(poses.size(), expected.animated.size());
    for (std::size_t k = 0; k < poses.size(); ++k) {
      EXPECT_EQ(poses[k].at("body"), expected.animated[k]);
      EXPECT_EQ(poses[k].at("position").get<std::vector<double>>(),
                std::vector<double>(expected.pose(f, k).position.begin(),
                                    expected.pose(f, k).position.end()));
      EXPECT_EQ(poses[k].at("orientation").get<std::vector<double>>(),
                std::vector<double>(expected.pose(f, k).orientation.begin(),
                                    expected.pose(f, k).orientation.end()));
    }
  }
}

TEST_F(RunCommand, EachPaneGetsALineWithItsHazard) {
  // A framed 1.2 x 0.9 m window 1.5 m up with 10 kg of TNT 10 m in front (scenes/window.json,
  // 0.5 s): its glass crosses the room, GSA condition 5; the same pane 200 m away stays whole.
  json scene = {
      {"charges", {{{"position", {0, 1.5, 10}}, {"mass", 10}}}},
      {"environment", {{"ground", nullptr}}},
      {"generators",
       {{{"type", "window"}, {"name", "near"}, {"position", {0, 1.5, 0}}, {"size", {1.2, 0.9}}},
        {{"type", "window"}, {"name", "far"}, {"position", {0, 1.5, -190}}, {"size", {1.2, 0.9}}}}},
      {"simulation", {{"duration", 0.5}}}};
  std::ofstream(scene_path_) << scene.dump();
  const std::string path = temp_path("window.json");
  written_.push_back(path);
  std::ostringstream out;
  ASSERT_EQ(run_simulation({scene_path_, "-o", path}, out), kExitOk);
  const json result = json::parse(read(path));
  const json& near = result.at("fracture").at(0);
  ASSERT_EQ(near.at("name"), "near/pane");
  EXPECT_NE(out.str().find(
                "  pane near/pane: " + std::to_string(near.at("fragment_count").get<int>()) +
                " fragments, " + std::to_string(near.at("released").get<int>()) + " released, " +
                std::to_string(near.at("hazard").at("fragments_in_room").get<int>()) +
                " into the room behind it; GSA P100 condition 5 (hazard high)\n"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("  pane far/pane: not broken; GSA P100 condition 1 (hazard none)\n"),
            std::string::npos)
      << out.str();
}

TEST_F(RunCommand, FrameVelocitiesAreCentralDifferencesOfThePoses) {
  const std::string path = temp_path("moving.json");
  written_.push_back(path);
  std::ostringstream out;
  ASSERT_EQ(run_simulation({scene_path_, "-o", path, "--frame-velocities"}, out), kExitOk);
  const json result = json::parse(read(path));
  const json& frames = result.at("frames");
  ASSERT_GE(frames.size(), 3u);
  // Inside the run: the central difference of the neighbouring positions, exactly.
  const std::size_t f = frames.size() / 2;
  const json& pose = frames[f].at("poses")[0];
  const double dt = frames[f + 1].at("time").get<double>() - frames[f - 1].at("time").get<double>();
  for (int c = 0; c < 3; ++c) {
    const double expected = (frames[f + 1].at("poses")[0].at("position")[c].get<double>() -
                             frames[f - 1].at("poses")[0].at("position")[c].get<double>()) /
                            dt;
    EXPECT_NEAR(pose.at("linear_velocity")[c].get<double>(), expected, 1e-12);
  }
  // Without the flag the poses have no velocities; with another format it is a usage error.
  EXPECT_FALSE(
      json::parse(run_to("plain.json")).at("frames")[f].at("poses")[0].contains("linear_velocity"));
  EXPECT_THROW(run_simulation({scene_path_, "-o", temp_path("x.brf"), "--frame-velocities"}, out),
               UsageError);
}

TEST_F(RunCommand, BrfHoldsTheFramesAsBrf1) {
  const std::string brf = run_to("out.brf");
  const engine::Result expected = simulate();
  EXPECT_EQ(brf, io::frames_to_brf1(io::frames_of(expected)));
  // The layout of api/openapi.yaml, read back field by field.
  const std::size_t bodies = expected.animated.size();
  const std::size_t frames = expected.frame_times_s.size();
  ASSERT_EQ(brf.size(), 16 + 4 * bodies + frames * (8 + 28 * bodies));
  EXPECT_EQ(brf.substr(0, 4), "BRF1");
  std::uint32_t header[3];
  std::memcpy(header, brf.data() + 4, sizeof header);
  EXPECT_EQ(header[0], 0u);
  EXPECT_EQ(header[1], frames);
  EXPECT_EQ(header[2], bodies);
  const std::size_t last = 16 + 4 * bodies + (frames - 1) * (8 + 28 * bodies);
  double time = 0.0;
  std::memcpy(&time, brf.data() + last, 8);
  EXPECT_EQ(time, expected.frame_times_s.back());
  float z = 0.0f;
  std::memcpy(&z, brf.data() + last + 8 + 2 * 4, 4);
  EXPECT_EQ(z, static_cast<float>(expected.pose(frames - 1, 0).position[2]));
}

TEST_F(RunCommand, GlbIsTheResultsGlb) {
  const std::string glb = run_to("out.glb");
  const std::vector<std::uint8_t> expected = io::result_to_glb(simulate());
  EXPECT_EQ(glb, std::string(expected.begin(), expected.end()));
}

TEST_F(RunCommand, AnUnknownExtensionIsAUsageErrorNamingTheForms) {
  std::ostringstream out;
  try {
    run_simulation({scene_path_, "-o", temp_path("out.txt")}, out);
    ADD_FAILURE() << "no usage error";
  } catch (const UsageError& error) {
    EXPECT_NE(error.message.find(".glb, .json or .brf"), std::string::npos) << error.message;
  }
}

}  // namespace
}  // namespace brisance::cli
