// tests/server/test_server: a real server in-process — SQLite file in a fresh temporary folder
// (or a fresh PostgreSQL database, see TestServerOptions::postgres), worker pool, Beast transport
// on an ephemeral port — and the scenes the server tests submit.
#pragma once

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/api.hpp"
#include "server/blob_store.hpp"
#include "server/callbacks.hpp"
#include "server/http_server.hpp"
#include "server/job_service.hpp"
#include "server/metrics.hpp"
#include "server/pg_storage.hpp"
#include "server/sqlite_storage.hpp"
#include "server/worker_pool.hpp"
#include "tests/server/http_client.hpp"
#include "tests/server/postgres_fixture.hpp"
#include "tests/server/temp_dir.hpp"

namespace brisance::testing {

inline bool test_store_is_postgres() {
  const char* store = std::getenv("BRISANCE_TEST_STORE");
  return store && std::string_view(store) == "postgres";
}

struct TestServerOptions {
  int workers = 1;
  std::int64_t max_queue = 1000;
  std::size_t body_limit_bytes = 1 << 20;
  std::size_t max_asset_bytes = 512 * 1024;  // POST /v1/assets above it: 413
  std::string api_keys;                      // keys-file text; empty: no keys
  std::chrono::milliseconds lease{15000};
  std::size_t max_connections = 1024;
  std::int64_t max_db_bytes = 0;  // 0: no limit (see SqliteOptions::max_size_bytes)
  std::chrono::milliseconds store_failure_pause{5000};
  std::uint64_t min_free_bytes = 0;  // the data folder's free-space floor; 0: not checked
  double job_timeout_s = 600.0;      // serve --job-timeout-s
  std::uint64_t job_memory_bytes = std::uint64_t{2048} << 20;  // serve --job-memory-mb
  // The store: SQLite unless BRISANCE_TEST_STORE=postgres (CTest runs the API suite both ways),
  // then a new database on the test program's PostgreSQL server, or `postgres_url` when given
  // (several servers on one database stand for several nodes).
  bool postgres = test_store_is_postgres();
  std::string postgres_url;
  // A callback sender (server/callbacks) with these options, and the default URL; none unset.
  std::optional<server::CallbackOptions> callbacks;
  std::string default_callback_url;
  // Results in a blob store (serve --blobs) in this folder; empty: in the database, unless
  // BRISANCE_TEST_BLOBS=1 (CTest runs the API suite once so), which puts them in the test's own.
  std::filesystem::path blobs_dir;
  int io_threads = 4;
  std::size_t offload_body_bytes = 64 * 1024;  // HttpOptions::offload_body_bytes
  int request_threads = 2;
  std::size_t request_queue = 16;
  std::int64_t max_glb_frame_samples = 2000000;
};

inline TestServerOptions with_workers(int workers) {
  TestServerOptions options;
  options.workers = workers;
  return options;
}

class TestServer {
 public:
  explicit TestServer(TestServerOptions options = {}) {
    if (options.postgres || !options.postgres_url.empty()) {
      server::PostgresOptions store;
      store.conninfo =
          options.postgres_url.empty() ? shared_postgres().create_database() : options.postgres_url;
      storage_ = server::open_postgres_storage(store);
    } else {
      server::SqliteOptions store;
      store.file = dir_.path() / "brisance.sqlite3";
      store.max_size_bytes = options.max_db_bytes;
      storage_ = server::open_sqlite_storage(store);
    }
    std::unique_ptr<server::BlobStore> blobs;
    if (options.blobs_dir.empty() && std::getenv("BRISANCE_TEST_BLOBS"))
      options.blobs_dir = dir_.path() / "blobs";
    if (!options.blobs_dir.empty()) {
      server::BlobOptions blob_options;
      blob_options.dir = options.blobs_dir;
      blobs = std::make_unique<server::BlobStore>(blob_options);
    }
    blobs_dir_ = options.blobs_dir;
    storage_ = server::with_blob_store(std::move(storage_), std::move(blobs));
    server::ServiceOptions service_options;
    service_options.max_queue = options.max_queue;
    service_options.default_callback_url = options.default_callback_url;
    service_options.max_asset_bytes = options.max_asset_bytes;
    service_options.max_glb_frame_samples = options.max_glb_frame_samples;
    service_options.job_memory_bytes = options.job_memory_bytes;
    service_ = std::make_unique<server::JobService>(*storage_, service_options);
    if (options.callbacks)
      callbacks_ = std::make_unique<server::CallbackSender>(*service_, *options.callbacks);
    server::WorkerOptions worker_options;
    worker_options.workers = options.workers;
    worker_options.lease = options.lease;
    worker_options.store_failure_pause = options.store_failure_pause;
    worker_options.job_timeout_s = options.job_timeout_s;
    worker_options.job_memory_bytes = options.job_memory_bytes;
    pool_ = std::make_unique<server::WorkerPool>(*service_, metrics_, worker_options);
    if (!options.api_keys.empty()) keys_ = server::ApiKeys::parse(options.api_keys, "test");
    server::ApiOptions api_options;
    api_options.body_limit_bytes = options.body_limit_bytes;
    if (options.min_free_bytes > 0)
      api_options.free_space =
          std::make_shared<server::FreeSpace>(dir_.path(), options.min_free_bytes);
    api_ = std::make_unique<server::Api>(
        *service_, metrics_, keys_,
        [this] {
          return server::WorkerGauges{pool_->busy(), pool_->size()};
        },
        api_options);
    server::HttpOptions http;
    http.port = 0;
    http.body_limit_bytes = options.body_limit_bytes;
    http.max_connections = options.max_connections;
    http.io_threads = options.io_threads;
    http.offload_body_bytes = options.offload_body_bytes;
    http.request_threads = options.request_threads;
    http.request_queue = options.request_queue;
    http_ = std::make_unique<server::HttpServer>(*api_, *service_, metrics_, http);
    http_->listen();
    pool_->start();
    http_->start();
  }
  ~TestServer() { stop(); }

  void stop() {
    if (http_) http_->stop(std::chrono::seconds(5));
    if (pool_) pool_->stop(std::chrono::milliseconds(0));
    callbacks_.reset();
  }

  std::uint16_t port() const { return http_->port(); }
  server::JobService& service() { return *service_; }
  // The store itself, for tests that look behind the service (the server reaches it only through
  // the service).
  server::Storage& storage() { return *storage_; }
  server::WorkerPool& pool() { return *pool_; }
  const std::filesystem::path& blobs_dir() const { return blobs_dir_; }

  ClientResponse request(const std::string& method, const std::string& target,
                         const std::string& body = {}, const Headers& headers = {}) {
    return http_request(port(), method, target, body, headers);
  }
  nlohmann::json get_json(const std::string& target, const Headers& headers = {}) {
    return nlohmann::json::parse(request("GET", target, {}, headers).body);
  }
  // /metrics once it holds `line`, or as it is after 10 s. A worker counts a job after the store
  // has taken its result, so a client that sees "succeeded" can scrape before the counts move
  // (seen with PostgreSQL, whose commit is visible before the worker's call returns); a scraper
  // sees them on its next pass, and so does this.
  std::string scrape_metrics_until(const std::string& line) {
    std::string text = request("GET", "/metrics").body;
    for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
         text.find(line) == std::string::npos && std::chrono::steady_clock::now() < deadline;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      text = request("GET", "/metrics").body;
    }
    return text;
  }

 private:
  TempDir dir_;
  std::filesystem::path blobs_dir_;
  std::unique_ptr<server::Storage> storage_;
  std::unique_ptr<server::JobService> service_;
  std::unique_ptr<server::CallbackSender> callbacks_;
  server::Metrics metrics_;
  std::unique_ptr<server::WorkerPool> pool_;
  server::ApiKeys keys_;
  std::unique_ptr<server::Api> api_;
  std::unique_ptr<server::HttpServer> http_;
};

// Three wooden blocks and a 10 kg charge (scenes/three_blocks.json): a run of a few ms.
inline nlohmann::json quick_scene() {
  return {{"charges", {{{"position", {0, 0.25, 0}}, {"mass", 10}}}},
          {"objects",
           {{{"name", "near"},
             {"shape", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
             {"position", {0.5, 0.25, 6}},
             {"material", "wood"}},
            {{"name", "far"},
             {"shape", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
             {"position", {3.0, 0.25, 6}},
             {"material", "wood"}}}},
          {"simulation", {{"duration", 1}, {"frame_rate", 30}}}};
}

// Boxes falling forever (no ground, no air) with a tiny fixed step: a run of minutes, never at
// rest, so it is still running whenever a test cancels it or stops the server.
inline nlohmann::json slow_scene() {
  nlohmann::json objects = nlohmann::json::array();
  for (int i = 0; i < 40; ++i) {
    objects.push_back({{"name", "box" + std::to_string(i)},
                       {"shape", {{"type", "box"}, {"size", {0.2, 0.2, 0.2}}}},
                       {"position", {0.3 * i, 1.0, 20}},
                       {"mass", 1}});
  }
  return {{"charges", {{{"position", {0, 1, 0}}, {"mass", 1}}}},
          {"environment", {{"ground", nullptr}, {"air_density", 0}}},
          {"objects", objects},
          {"simulation", {{"duration", 600}, {"frame_rate", 10}, {"time_step", 1e-5}}}};
}

inline std::string job_body(const nlohmann::json& scene, int priority = 0) {
  return nlohmann::json{{"scene", scene}, {"priority", priority}}.dump();
}

}  // namespace brisance::testing
