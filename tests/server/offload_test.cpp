// Large request bodies are parsed and validated off the I/O threads (HttpOptions::
// offload_body_bytes): /healthz answers promptly while several large, valid and slow submissions
// are in flight, and a full request pool answers 503. Without the pool the one I/O thread here
// validates the scenes one after another and /healthz waits seconds behind them.
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using Clock = std::chrono::steady_clock;

// A closed sphere of radius 1 m, `rings` x `segments` (2 x rings x segments triangles, wound
// counter-clockwise seen from outside): valid, and slow to parse and check when large.
nlohmann::json sphere_scene(int rings, int segments) {
  nlohmann::json vertices = nlohmann::json::array();
  vertices.push_back({0, 1, 0});
  for (int i = 1; i < rings; ++i) {
    const double phi = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double theta = 2 * M_PI * j / segments;
      vertices.push_back(
          {std::sin(phi) * std::cos(theta), std::cos(phi), std::sin(phi) * std::sin(theta)});
    }
  }
  vertices.push_back({0, -1, 0});
  const int bottom = static_cast<int>(vertices.size()) - 1;
  const auto at = [&](int ring, int j) { return (ring - 1) * segments + (j % segments) + 1; };
  nlohmann::json triangles = nlohmann::json::array();
  for (int j = 0; j < segments; ++j)
    triangles.push_back({0, at(1, j + 1), at(1, j)});
  for (int i = 1; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  for (int j = 0; j < segments; ++j)
    triangles.push_back({bottom, at(rings - 1, j), at(rings - 1, j + 1)});
  return {{"charges", {{{"position", {0, 1, -10}}, {"mass", 1}}}},
          {"objects",
           {{{"name", "ball"},
             {"shape", {{"type", "mesh"}, {"vertices", vertices}, {"triangles", triangles}}},
             {"position", {0, 2, 0}},
             {"mass", 10}}}},
          {"simulation", {{"duration", 0.1}, {"frame_rate", 30}}}};
}

TEST(Offload, HealthzAnswersWhileLargeSubmissionsAreValidated) {
  TestServerOptions options = with_workers(0);
  options.io_threads = 1;  // the worst case: one thread for every connection
  options.body_limit_bytes = 32 << 20;
  TestServer server(options);
  const std::string body = job_body(sphere_scene(300, 500));  // 299 000 triangles, ~11 MB

  constexpr int kSubmissions = 4;
  std::atomic<int> pending{kSubmissions};
  std::atomic<int> accepted{0};
  std::vector<std::thread> submitters;
  for (int i = 0; i < kSubmissions; ++i) {
    submitters.emplace_back([&] {
      const ClientResponse r = server.request("POST", "/v1/jobs", body);
      accepted += r.status == 202;
      --pending;
    });
  }
  // Probe until every submission is answered: the early probes land while the bodies are still
  // being read, the later ones while they are parsed and validated.
  double slowest_s = 0.0;
  int answered_while_busy = 0;
  while (pending > 0) {
    const auto start = Clock::now();
    const ClientResponse health = server.request("GET", "/healthz");
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_EQ(health.status, 200);
    slowest_s = std::max(slowest_s, seconds);
    answered_while_busy += pending > 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (auto& t : submitters)
    t.join();
  EXPECT_EQ(accepted, kSubmissions);
  // The probes must have run while validations were in flight, or they prove nothing.
  ASSERT_GT(answered_while_busy, 0) << "the submissions finished before /healthz was asked";
  EXPECT_LT(slowest_s, 1.0) << "/healthz waited behind the validations";
}

TEST(Offload, AFullRequestPoolAnswers503) {
  TestServerOptions options = with_workers(0);
  options.body_limit_bytes = 32 << 20;
  options.request_threads = 1;
  options.request_queue = 0;  // one large request at a time, none waiting
  TestServer server(options);
  const std::string body = job_body(sphere_scene(300, 500));
  constexpr int kSubmissions = 4;
  std::atomic<int> accepted{0}, overloaded{0};
  std::vector<std::thread> submitters;
  for (int i = 0; i < kSubmissions; ++i) {
    submitters.emplace_back([&] {
      const ClientResponse r = server.request("POST", "/v1/jobs", body);
      if (r.status == 202) ++accepted;
      if (r.status == 503 && r.body.find("urn:brisance:problem:overloaded") != std::string::npos &&
          r.header("retry-after") == "1") {
        ++overloaded;
      }
    });
  }
  for (auto& t : submitters)
    t.join();
  EXPECT_EQ(accepted + overloaded, kSubmissions);
  EXPECT_GE(accepted, 1);
  EXPECT_GE(overloaded, 1);
  // Small requests never wait for the pool.
  EXPECT_EQ(server.request("GET", "/healthz").status, 200);
}

}  // namespace
}  // namespace brisance::testing
