// `brisance serve` as a process: a failed bind, SIGTERM, and kill -9 with jobs queued and running
// (every accepted job must complete exactly once as clients see it).
#include <fstream>
#include <sstream>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <gtest/gtest.h>
#include <signal.h>

#include "tests/server/server_process.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string submit(std::uint16_t port, const json& scene, int priority = 0) {
  const auto r = http_request(port, "POST", "/v1/jobs", job_body(scene, priority));
  EXPECT_EQ(r.status, 202) << r.body;
  return json::parse(r.body).at("id");
}

// Long-polls with the ETag last seen, so a change between two polls answers at once: without
// it a poll waits for a change after its own arrival and can miss a short "running" (seen under
// load: the job went running while the first poll was answered, and the next waited for
// "succeeded").
json wait_status(std::uint16_t port, const std::string& id, std::string_view status,
                 std::chrono::seconds limit) {
  const auto deadline = Clock::now() + limit;
  ClientResponse r = http_request(port, "GET", "/v1/jobs/" + id);
  json job = json::parse(r.body);
  std::string etag = r.header("etag");
  while (job.at("status") != status && Clock::now() < deadline) {
    r = http_request(port, "GET", "/v1/jobs/" + id + "?wait=5", {}, {{"If-None-Match", etag}});
    if (r.status == 304) continue;
    job = json::parse(r.body);
    etag = r.header("etag");
  }
  return job;
}

// Long enough that it is still running when the test acts on it, short enough to finish.
json medium_scene() {
  json scene = slow_scene();
  scene["simulation"]["duration"] = 4;
  scene["simulation"]["time_step"] = 1e-4;
  return scene;
}

TEST(ServeProcess, ABusyPortExitsNonZeroWithTheAddressInTheMessage) {
  boost::asio::io_context ioc;
  boost::asio::ip::tcp::acceptor taken(ioc, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const auto port = taken.local_endpoint().port();
  TempDir dir;
  ServerProcess process(dir.path() / "data", {"--port", std::to_string(port)}, dir.path() / "log");
  EXPECT_EQ(process.wait_exit(std::chrono::seconds(30)), 1);
  EXPECT_NE(process.log().find("cannot listen on 127.0.0.1:" + std::to_string(port)),
            std::string::npos)
      << process.log();
}

TEST(ServeProcess, SigtermRequeuesTheRunningJobAndARestartFinishesIt) {
  TempDir dir;
  std::string id;
  {
    ServerProcess process(dir.path() / "data", {"--workers", "1", "--grace-s", "0.2"},
                          dir.path() / "log1");
    const auto port = process.wait_listening();
    ASSERT_NE(port, 0) << process.log();
    id = submit(port, slow_scene());
    ASSERT_EQ(wait_status(port, id, "running", std::chrono::seconds(30)).at("status"), "running");
    EXPECT_EQ(process.signal_and_wait(SIGTERM, std::chrono::seconds(30)), 0) << process.log();
    EXPECT_NE(process.log().find("requeued (shutting down)"), std::string::npos) << process.log();
  }
  ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log2");
  const auto port = process.wait_listening();
  ASSERT_NE(port, 0) << process.log();
  const json again = wait_status(port, id, "running", std::chrono::seconds(30));
  EXPECT_EQ(again.at("status"), "running");
  EXPECT_EQ(again.at("attempts"), 1);  // the interrupted run did not count
  EXPECT_EQ(http_request(port, "POST", "/v1/jobs/" + id + "/cancel").status, 202);
  EXPECT_EQ(wait_status(port, id, "cancelled", std::chrono::seconds(30)).at("status"), "cancelled");
  EXPECT_EQ(process.signal_and_wait(SIGINT, std::chrono::seconds(30)), 0);
}

TEST(ServeProcess, KillNineLosesNoAcceptedJobAndCompletesEachExactlyOnce) {
  TempDir dir;
  std::vector<std::string> ids;
  std::string running;
  {
    ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log1");
    const auto port = process.wait_listening();
    ASSERT_NE(port, 0) << process.log();
    running = submit(port, medium_scene(), 10);
    ASSERT_EQ(wait_status(port, running, "running", std::chrono::seconds(30)).at("status"),
              "running");
    for (int i = 0; i < 5; ++i)
      ids.push_back(submit(port, quick_scene()));
    EXPECT_EQ(process.signal_and_wait(SIGKILL, std::chrono::seconds(10)), 128 + SIGKILL);
  }
  ids.push_back(running);
  ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log2");
  const auto port = process.wait_listening();
  ASSERT_NE(port, 0) << process.log();
  for (const std::string& id : ids) {
    const json job = wait_status(port, id, "succeeded", std::chrono::seconds(180));
    EXPECT_EQ(job.at("status"), "succeeded") << job.dump();
    EXPECT_EQ(job.at("attempts"), id == running ? 2 : 1) << id;
    const auto result = http_request(port, "GET", "/v1/jobs/" + id + "/result");
    EXPECT_EQ(result.status, 200);
  }
  const json list = json::parse(http_request(port, "GET", "/v1/jobs?limit=100").body);
  EXPECT_EQ(list.at("jobs").size(), ids.size());
  EXPECT_NE(process.log().find("recovered jobs left running"), std::string::npos) << process.log();
  EXPECT_EQ(process.signal_and_wait(SIGTERM, std::chrono::seconds(30)), 0);
}

}  // namespace
}  // namespace brisance::testing
