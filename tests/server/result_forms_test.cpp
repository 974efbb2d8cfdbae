// The result forms the API serves equal what JobService builds through the sim/io codec from the
// same stored rows: frames (JSON and BRF1, with and without `from`, `to` and `bodies=`), meshes
// and result.glb, byte for byte (long pages streamed in blocks too), and the stored size in the
// stats and /metrics. A real server, a real client, a real SQLite file.
#include <gtest/gtest.h>

#include "sim/io/frames.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;

// The quick scene plus an anchored wall, so frames include a body that never moves.
json scene_with_a_static_body() {
  json scene = quick_scene();
  scene["objects"].push_back({{"name", "wall"},
                              {"shape", {{"type", "box"}, {"size", {2.0, 1.0, 0.2}}}},
                              {"position", {-3.0, 1.5, 4.0}},
                              {"orientation", {0.0, 0.0, 0.3826834323650898, 0.9238795325112867}},
                              {"material", "concrete"},
                              {"anchored", true}});
  return scene;
}

std::string succeeded_job(TestServer& server, const json& scene) {
  const ClientResponse posted = server.request("POST", "/v1/jobs", job_body(scene));
  EXPECT_EQ(posted.status, 202) << posted.body;
  const std::string id = json::parse(posted.body).at("id");
  json job = server.get_json("/v1/jobs/" + id);
  for (int i = 0; i < 60 && job.at("status") != "succeeded"; ++i)
    job = server.get_json("/v1/jobs/" + id + "?wait=5");
  EXPECT_EQ(job.at("status"), "succeeded") << job.dump();
  return id;
}

TEST(ResultForms, ServedFramesMeshesAndGlbEqualTheCodecOnStoredRows) {
  TestServer server;
  const std::string id = succeeded_job(server, scene_with_a_static_body());
  server::JobService& service = server.service();
  const std::optional<server::ResultLayout> layout = service.result_layout(id);
  ASSERT_TRUE(layout);
  ASSERT_EQ(layout->body_count(), 3u);
  ASSERT_EQ(layout->frame_count, 31);
  // The wall never moves; at least one block does.
  ASSERT_FALSE(layout->animated.empty());
  for (const std::uint32_t body : layout->animated)
    EXPECT_NE(body, 2u);

  struct Case {
    std::string query;
    std::int64_t from, to;
    std::vector<std::uint32_t> bodies;
  };
  const std::vector<Case> cases = {
      {"", 0, 31, layout->animated},
      {"?from=3&to=9&bodies=2,0", 3, 9, {2, 0}},
      {"?from=30&bodies=0,1,2", 30, 31, {0, 1, 2}},
      {"?from=31", 31, 31, layout->animated},
      {"?bodies=", 0, 31, {}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.query);
    const std::string target = "/v1/jobs/" + id + "/frames" + c.query;
    const io::FrameSet frames = service.result_frame_set(id, *layout, c.from, c.to, c.bodies);
    const ClientResponse served_json = server.request("GET", target);
    ASSERT_EQ(served_json.status, 200) << served_json.body;
    EXPECT_EQ(served_json.body, io::frames_document_json(frames, 31));
    const ClientResponse served_binary =
        server.request("GET", target, {}, {{"Accept", "application/octet-stream"}});
    ASSERT_EQ(served_binary.status, 200);
    EXPECT_EQ(served_binary.body, io::frames_to_brf1(frames));
  }

  // With velocities, any page's frames equal the same frames of the whole run's.
  const io::FrameSet everything =
      io::with_velocities(service.result_frame_set(id, *layout, 0, 31, layout->animated));
  const json whole = json::parse(io::frames_document_json(everything, 31));
  for (const auto& [from, to] :
       std::vector<std::pair<int, int>>{{0, 31}, {0, 1}, {7, 12}, {30, 31}}) {
    SCOPED_TRACE(std::to_string(from) + ".." + std::to_string(to));
    const json page =
        server.get_json("/v1/jobs/" + id + "/frames?velocities=true&from=" + std::to_string(from) +
                        "&to=" + std::to_string(to));
    ASSERT_EQ(page.at("frames").size(), static_cast<std::size_t>(to - from));
    for (int f = from; f < to; ++f)
      EXPECT_EQ(page.at("frames")[f - from], whole.at("frames")[f]);
    EXPECT_TRUE(page.at("frames")[0].at("poses")[0].contains("angular_velocity"));
  }
  EXPECT_EQ(server
                .request("GET", "/v1/jobs/" + id + "/frames?velocities=true", {},
                         {{"Accept", "application/octet-stream"}})
                .status,
            400);
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id + "/frames?velocities=yes").status, 400);

  const ClientResponse meshes = server.request("GET", "/v1/jobs/" + id + "/meshes");
  ASSERT_EQ(meshes.status, 200);
  EXPECT_EQ(meshes.body, service.result_meshes_json(id));

  const ClientResponse glb = server.request("GET", "/v1/jobs/" + id + "/result.glb");
  ASSERT_EQ(glb.status, 200);
  const std::optional<std::vector<std::uint8_t>> codec_glb = service.result_glb(id);
  ASSERT_TRUE(codec_glb);
  EXPECT_EQ(glb.body, std::string(codec_glb->begin(), codec_glb->end()));

  EXPECT_FALSE(service.result_layout("j000000000000000000000000"));
  EXPECT_FALSE(service.result_glb("j000000000000000000000000"));
}

// A page of many blocks (40 moving bodies, 1 001 frames: about 200 frames a block) streams the
// same bytes as the page built whole, chunked, and a glb above the server's bound is a 422.
TEST(ResultForms, LongPagesStreamTheSameBytesInBlocks) {
  TestServerOptions options;
  options.max_glb_frame_samples = 40000;
  TestServer server(options);
  json scene = slow_scene();  // falling freely: every body moves in every frame
  scene["simulation"] = {{"duration", 1}, {"frame_rate", 1000}};
  const std::string id = succeeded_job(server, scene);
  server::JobService& service = server.service();
  const std::optional<server::ResultLayout> layout = service.result_layout(id);
  ASSERT_TRUE(layout);
  ASSERT_EQ(layout->frame_count, 1001);
  ASSERT_EQ(layout->animated.size(), 40u);

  for (const auto& [from, to] : std::vector<std::pair<int, int>>{{0, 1001}, {150, 700}}) {
    SCOPED_TRACE(std::to_string(from) + ".." + std::to_string(to));
    const std::string target =
        "/v1/jobs/" + id + "/frames?from=" + std::to_string(from) + "&to=" + std::to_string(to);
    const io::FrameSet frames = service.result_frame_set(id, *layout, from, to, layout->animated);
    const ClientResponse served_json = server.request("GET", target);
    ASSERT_EQ(served_json.status, 200);
    EXPECT_EQ(served_json.header("transfer-encoding"), "chunked");
    EXPECT_EQ(served_json.body, io::frames_document_json(frames, 1001));
    const ClientResponse served_binary =
        server.request("GET", target, {}, {{"Accept", "application/octet-stream"}});
    EXPECT_EQ(served_binary.body, io::frames_to_brf1(frames));
    // Velocities across block boundaries equal the whole run's.
    const json page = server.get_json(target + "&velocities=true");
    const json whole = json::parse(io::frames_document_json(
        io::with_velocities(service.result_frame_set(id, *layout, 0, 1001, layout->animated)),
        1001));
    ASSERT_EQ(page.at("frames").size(), static_cast<std::size_t>(to - from));
    for (int f = from; f < to; f += 37)
      EXPECT_EQ(page.at("frames")[f - from], whole.at("frames")[f]);
  }

  // 1 001 x 40 = 40 040 samples, above the bound of 40 000 this server has.
  const ClientResponse glb = server.request("GET", "/v1/jobs/" + id + "/result.glb");
  EXPECT_EQ(glb.status, 422);
  EXPECT_NE(glb.body.find("urn:brisance:problem:result-too-large"), std::string::npos);
}

// The stored size is in the job's stats and the result's, and /metrics counts it.
TEST(ResultForms, StoredBytesInTheStatsAndTheMetrics) {
  TestServer server;
  const std::string id = succeeded_job(server, quick_scene());
  if (!server.blobs_dir().empty()) GTEST_SKIP() << "with blobs the bytes are in a file";
  const std::optional<std::string> encoded = server.storage().result_encoded(id);
  const std::int64_t stored = encoded ? static_cast<std::int64_t>(encoded->size()) : 0;
  ASSERT_GT(stored, 0);
  EXPECT_EQ(server.get_json("/v1/jobs/" + id).at("stats").at("stored_bytes"), stored);
  EXPECT_EQ(server.get_json("/v1/jobs/" + id + "/result").at("stats").at("stored_bytes"), stored);
  const std::string metrics = server.scrape_metrics_until("\nbrisance_results_stored_total 1\n");
  EXPECT_NE(metrics.find("\nbrisance_results_stored_total 1\n"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\nbrisance_result_stored_bytes_total " + std::to_string(stored) + "\n"),
            std::string::npos);
}

}  // namespace
}  // namespace brisance::testing
