// POST /v1/assets and GET /v1/assets/{id} end to end, and scenes that name an asset: the upload
// round trip, the 413 and 422 refusals, each key's own assets, and a crate from a GLB asset blown
// up by a job.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "server/api_keys.hpp"
#include "server/sha256.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string asset_file(const std::string& name) {
  std::ifstream in(std::filesystem::path(BRISANCE_SOURCE_DIR) / "tests/assets" / name,
                   std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

const Headers kGlb = {{"Content-Type", "model/gltf-binary"}};

json crate_scene(const json& shape) {
  return {{"charges", {{{"position", {0, 0.3, -3}}, {"mass", 2}}}},
          {"environment", {{"gravity", {0, 0, 0}}, {"ground", nullptr}, {"air_density", 0}}},
          {"objects",
           {{{"name", "crate"}, {"shape", shape}, {"position", {0, 0.3, 0}}, {"density", 500}}}},
          {"simulation", {{"duration", 0.05}, {"frame_rate", 100}}}};
}

TEST(Api, AssetUploadRoundTripAndAJobThatBlowsTheCrateUp) {
  TestServer server;
  const std::string glb = asset_file("crate.glb");
  const ClientResponse posted = server.request("POST", "/v1/assets", glb, kGlb);
  ASSERT_EQ(posted.status, 201) << posted.body;
  const json asset = json::parse(posted.body);
  EXPECT_EQ(asset.at("id"), server::sha256_hex(glb));  // the content's hash
  EXPECT_EQ(asset.at("format"), "glb");
  EXPECT_EQ(asset.at("size_bytes"), glb.size());
  EXPECT_EQ(asset.at("nodes"), json({"Crate", "Pallet"}));
  const std::string id = asset.at("id");
  EXPECT_EQ(posted.header("location"), "/v1/assets/" + id);

  // The same file again is the same asset.
  const ClientResponse again = server.request("POST", "/v1/assets", glb, kGlb);
  EXPECT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(json::parse(again.body).at("id"), id);
  EXPECT_EQ(server.get_json("/v1/assets/" + id), asset);
  EXPECT_EQ(server.request("GET", "/v1/assets/" + std::string(64, '0')).status, 404);

  // OBJ by the format parameter.
  const ClientResponse obj =
      server.request("POST", "/v1/assets?format=obj", asset_file("crate.obj"));
  ASSERT_EQ(obj.status, 201) << obj.body;
  EXPECT_EQ(json::parse(obj.body).at("nodes"), json({"Crate"}));

  const std::string job =
      json::parse(
          server
              .request("POST", "/v1/jobs",
                       job_body(crate_scene({{"type", "asset"}, {"asset", id}, {"node", "Crate"}})))
              .body)
          .value("id", "");
  ASSERT_FALSE(job.empty());
  json done = server.get_json("/v1/jobs/" + job);
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (done.at("status") != "succeeded" && done.at("status") != "failed" &&
         Clock::now() < deadline)
    done = server.get_json("/v1/jobs/" + job + "?wait=5");
  ASSERT_EQ(done.at("status"), "succeeded") << done.dump();
  const json result = server.get_json("/v1/jobs/" + job + "/result");
  EXPECT_NEAR(result.at("bodies")[0].at("mass").get<double>(), 240.0, 1e-4);
  EXPECT_GT(result.at("final_state")[0].at("linear_velocity")[2].get<double>(), 0.05);
}

TEST(Api, AssetsThatCannotBeSimulatedAreRefusedWithTheReason) {
  TestServerOptions options = with_workers(0);
  options.max_asset_bytes = 2000;  // crate.glb has 2 644 bytes
  TestServer server(options);

  const ClientResponse large = server.request("POST", "/v1/assets", asset_file("crate.glb"), kGlb);
  EXPECT_EQ(large.status, 413) << large.body;
  EXPECT_NE(large.body.find("more than the limit of 2000 bytes"), std::string::npos) << large.body;

  const ClientResponse open =
      server.request("POST", "/v1/assets?format=obj", asset_file("open_crate.obj"));
  EXPECT_EQ(open.status, 422) << open.body;
  EXPECT_NE(open.body.find("4 edges open"), std::string::npos) << open.body;

  const ClientResponse finned = server.request("POST", "/v1/assets", asset_file("finned_crate.obj"),
                                               {{"Content-Type", "model/obj"}});
  EXPECT_EQ(finned.status, 422) << finned.body;
  EXPECT_NE(finned.body.find("shared by 4 triangles"), std::string::npos) << finned.body;

  EXPECT_EQ(
      server.request("POST", "/v1/assets", "v 0 0 0\n", {{"Content-Type", "text/plain"}}).status,
      415);
  EXPECT_EQ(server.request("POST", "/v1/assets?format=fbx", "x").status, 400);

  // The server reads no files of its own, and an unknown asset is named.
  const ClientResponse file = server.request(
      "POST", "/v1/jobs", job_body(crate_scene({{"type", "file"}, {"path", "/etc/passwd"}})));
  EXPECT_EQ(file.status, 422) << file.body;
  EXPECT_NE(file.body.find("/scene/objects/0/shape/type"), std::string::npos) << file.body;
  const ClientResponse missing = server.request(
      "POST", "/v1/jobs", job_body(crate_scene({{"type", "asset"}, {"asset", "nope"}})));
  EXPECT_EQ(missing.status, 422) << missing.body;
  EXPECT_NE(missing.body.find("no such asset"), std::string::npos) << missing.body;
}

TEST(Api, AssetsBelongToTheKeyThatUploadedThem) {
  const std::string alice_key = "bk_alice_key_for_tests";
  const std::string bob_key = "bk_bob_key_for_tests";
  TestServerOptions options = with_workers(0);
  options.api_keys = server::api_key_line("alice", server::Scope::write, alice_key) + "\n" +
                     server::api_key_line("bob", server::Scope::write, bob_key);
  TestServer server(options);
  const Headers alice = {{"Authorization", "Bearer " + alice_key},
                         {"Content-Type", "model/gltf-binary"}};
  const Headers bob = {{"Authorization", "Bearer " + bob_key}};
  const ClientResponse posted =
      server.request("POST", "/v1/assets", asset_file("crate.glb"), alice);
  ASSERT_EQ(posted.status, 201) << posted.body;
  const std::string id = json::parse(posted.body).at("id");
  EXPECT_EQ(server.request("GET", "/v1/assets/" + id, {}, alice).status, 200);
  EXPECT_EQ(server.request("GET", "/v1/assets/" + id, {}, bob).status, 404);
  const json scene = crate_scene({{"type", "asset"}, {"asset", id}});
  const Headers alice_json = {{"Authorization", "Bearer " + alice_key}};
  EXPECT_EQ(server.request("POST", "/v1/jobs", job_body(scene), alice_json).status, 202);
  EXPECT_EQ(server.request("POST", "/v1/jobs", job_body(scene), bob).status, 422);
}

}  // namespace
}  // namespace brisance::testing
