// The blob store (server/blob_store, serve --blobs) on both job stores: results round-trip
// byte-identical with and without blobs, a blob is in place before its job reads succeeded, a
// missing or corrupt blob is an error (a 500 problem through the API), and collection removes
// exactly the blobs no job names, also against a writer committing while it runs.
#include "server/blob_store.hpp"

#include <cstring>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <unistd.h>

#include "server/compact_result.hpp"
#include "server/forwarding_storage.hpp"
#include "server/pg_storage.hpp"
#include "server/sqlite_storage.hpp"
#include "tests/server/postgres_fixture.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using server::JobStatus;
namespace fs = std::filesystem;

enum class Store { sqlite, postgres };

std::string store_name(const ::testing::TestParamInfo<Store>& info) {
  return info.param == Store::sqlite ? "Sqlite" : "Postgres";
}

server::StoredResult sample_result(float shift = 0.0f) {
  server::StoredResult result;
  result.summary_json = "{\"x\":1}";
  result.stats_json = "{\"steps\":3}";
  server::StoredBody body;
  body.name = "pane \xe2\x80\x94 fragment";
  body.mass_kg = 2.5;
  body.animated = true;
  body.initial_pose = {1, 2, 3, 0, 0, 0, 1};
  // Float bits that a text round trip would change: a NaN payload, -0, a denormal.
  body.vertices = {0, -0.0f, 1e-40f, 1, 0, 0, 0, 1, 0.1f + shift, 0, 0, 1};
  body.triangles = {0, 1, 2, 0xffffffffu, 7, 3};
  server::StoredBody still;
  still.name = "ground";
  result.bodies = {body, still};
  for (int f = 0; f < 5; ++f)
    result.frames.push_back({0.25 * f, {static_cast<float>(f), 2, 3, 0, 0, 0, 1}});
  return result;
}

void expect_same(const std::vector<server::StoredBody>& a,
                 const std::vector<server::StoredBody>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].mass_kg, b[i].mass_kg);
    EXPECT_EQ(a[i].animated, b[i].animated);
    EXPECT_EQ(a[i].initial_pose, b[i].initial_pose);
    ASSERT_EQ(a[i].vertices.size(), b[i].vertices.size());
    if (!a[i].vertices.empty()) {  // bit for bit: -0 and denormals included
      EXPECT_EQ(0, std::memcmp(a[i].vertices.data(), b[i].vertices.data(),
                               a[i].vertices.size() * sizeof(float)));
    }
    EXPECT_EQ(a[i].triangles, b[i].triangles);
  }
}

void expect_same(const std::vector<server::StoredFrame>& a,
                 const std::vector<server::StoredFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t f = 0; f < a.size(); ++f) {
    EXPECT_EQ(a[f].time_s, b[f].time_s);
    EXPECT_EQ(a[f].poses, b[f].poses);
  }
}

// Checks at every complete() that the blob the row is about to name is in place.
class CheckingStorage final : public server::ForwardingStorage {
 public:
  CheckingStorage(std::unique_ptr<server::Storage> inner, fs::path blobs)
      : ForwardingStorage(std::move(inner)), blobs_(std::move(blobs)) {}
  bool complete(std::string_view id, std::string_view owner, const server::StoredResult& result,
                std::int64_t now_ms) override {
    const std::string& d = result.blob_digest;
    EXPECT_FALSE(d.empty());
    EXPECT_TRUE(fs::exists(blobs_ / d.substr(0, 2) / d)) << "row names a blob not yet written";
    ++completed;
    return inner_->complete(id, owner, result, now_ms);
  }
  int completed = 0;

 private:
  fs::path blobs_;
};

class BlobStoreTest : public ::testing::TestWithParam<Store> {
 protected:
  // The test's store (each call another connection to the same database), with results in
  // `blobs` when given.
  std::unique_ptr<server::Storage> open(std::unique_ptr<server::BlobStore> blobs = {}) {
    return server::with_blob_store(open_plain(), std::move(blobs));
  }
  std::unique_ptr<server::Storage> open_plain() {
    if (GetParam() == Store::sqlite) {
      server::SqliteOptions options;
      options.file = dir_.path() / "jobs.sqlite3";
      return server::open_sqlite_storage(options);
    }
    if (url_.empty()) url_ = shared_postgres().create_database();
    server::PostgresOptions options;
    options.conninfo = url_;
    return server::open_postgres_storage(options);
  }
  std::unique_ptr<server::BlobStore> blob_store(std::chrono::seconds grace = {}) {
    server::BlobOptions options;
    options.dir = blobs_dir();
    options.grace = grace;
    return std::make_unique<server::BlobStore>(options);
  }
  fs::path blobs_dir() const { return dir_.path() / "blobs"; }
  // Creates, claims and completes job `id` with `result`.
  static void run(server::Storage& storage, const std::string& id,
                  const server::StoredResult& result) {
    server::NewJob job;
    job.id = id;
    job.scene_json = "{}";
    job.now_ms = 1000;
    storage.create_job(job);
    ASSERT_EQ(storage.claim_next("w", 2000, 100000)->job.id, id);
    ASSERT_TRUE(storage.complete(id, "w", result, 3000));
  }
  static std::size_t blob_count(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
      n += entry.is_regular_file() && server::is_blob_digest(entry.path().filename().string());
    return n;
  }

  TempDir dir_;
  std::string url_;
};

INSTANTIATE_TEST_SUITE_P(Stores, BlobStoreTest, ::testing::Values(Store::sqlite, Store::postgres),
                         store_name);

TEST_P(BlobStoreTest, ResultsRoundTripByteIdenticalWithAndWithoutBlobs) {
  const server::StoredResult result = sample_result();
  auto in_database = open();
  run(*in_database, "db", result);
  auto with_blobs = open(blob_store());
  run(*with_blobs, "blob", result);

  // The row names the blob; the database holds no bodies or frames for it.
  const std::string digest = with_blobs->result_blob("blob").value_or("");
  ASSERT_TRUE(server::is_blob_digest(digest)) << digest;
  EXPECT_EQ(in_database->result_blob("db"), "");
  EXPECT_TRUE(fs::exists(blobs_dir() / digest.substr(0, 2) / digest));
  EXPECT_TRUE(open_plain()->result_bodies("blob").empty());
  EXPECT_EQ(with_blobs->blob_references(), std::vector<std::string>{digest});

  // A node with blobs reads both kinds of row; the one without reads the database's.
  expect_same(in_database->result_bodies("db"), result.bodies);
  expect_same(with_blobs->result_bodies("db"), result.bodies);
  expect_same(with_blobs->result_bodies("blob"), result.bodies);
  expect_same(with_blobs->result_frames("blob", 1, 4), in_database->result_frames("db", 1, 4));
  expect_same(with_blobs->result_frames("blob", 0, INT64_MAX), result.frames);
  expect_same(in_database->result_frames("db", 0, INT64_MAX), result.frames);
  EXPECT_TRUE(with_blobs->result_frames("blob", 7, 9).empty());
  EXPECT_EQ(with_blobs->result_summary("blob"), "{\"x\":1}");
  // The stats gain the encoded size; the same result is the same bytes in a row or a blob.
  const std::string encoded = in_database->result_encoded("db").value_or("");
  ASSERT_TRUE(server::is_compact_result(encoded));
  EXPECT_EQ(server::BlobStore({blobs_dir()}).get(digest), encoded);
  const std::string stats = "{\"steps\":3,\"stored_bytes\":" + std::to_string(encoded.size()) + "}";
  EXPECT_EQ(nlohmann::json::parse(with_blobs->get_job("blob")->stats_json),
            nlohmann::json::parse(stats));
  EXPECT_EQ(nlohmann::json::parse(in_database->get_job("db")->stats_json),
            nlohmann::json::parse(stats));
  // Compact: one job_results row, no job_bodies or job_frames rows.
  EXPECT_TRUE(open_plain()->result_bodies("db").empty());
  EXPECT_TRUE(open_plain()->result_frames("db", 0, INT64_MAX).empty());
}

// Results stored before the compact encoding (job_bodies and job_frames rows, and blobs in the
// older uncompressed layout) still read, through every path, page by page too.
TEST_P(BlobStoreTest, OlderUncompressedResultsStillRead) {
  const server::StoredResult result = sample_result();
  run(*open_plain(), "rows", result);  // the store alone writes rows, as before 007
  server::StoredResult old_blob;
  old_blob.summary_json = result.summary_json;
  old_blob.stats_json = result.stats_json;
  old_blob.blob_digest =
      blob_store()->put(server::encode_result_blob(result.bodies, result.frames));
  run(*open_plain(), "blob", old_blob);

  auto storage = open(blob_store());
  for (const std::string id : {"rows", "blob"}) {
    EXPECT_FALSE(storage->result_encoded(id).has_value()) << id;
    expect_same(storage->result_bodies(id), result.bodies);
    expect_same(storage->result_frames(id, 0, INT64_MAX), result.frames);
    expect_same(
        storage->result_frames(id, 1, 4),
        std::vector<server::StoredFrame>(result.frames.begin() + 1, result.frames.begin() + 4));
    const server::Storage::FrameReader reader = storage->frame_reader(id);
    expect_same(reader(2, 5),
                std::vector<server::StoredFrame>(result.frames.begin() + 2, result.frames.end()));
    EXPECT_EQ(storage->get_job(id)->stats_json, "{\"steps\":3}");
  }
}

TEST_P(BlobStoreTest, TheBlobIsInPlaceBeforeTheRowSaysSucceeded) {
  auto checking = std::make_unique<CheckingStorage>(open_plain(), blobs_dir());
  CheckingStorage& spy = *checking;
  auto storage = server::with_blob_store(std::move(checking), blob_store());
  run(*storage, "a", sample_result());
  run(*storage, "b", sample_result());  // the same content: one blob, found and touched
  EXPECT_EQ(spy.completed, 2);
  EXPECT_EQ(blob_count(blobs_dir()), 1u);
  EXPECT_EQ(storage->result_blob("a"), storage->result_blob("b"));
  // Nothing left behind in the temporary names.
  for (const auto& entry : fs::recursive_directory_iterator(blobs_dir()))
    EXPECT_FALSE(entry.path().filename().string().starts_with(".")) << entry.path();
}

TEST_P(BlobStoreTest, AMissingOrCorruptBlobIsAnErrorNotAWrongResult) {
  auto storage = open(blob_store());
  run(*storage, "a", sample_result());
  const std::string digest = *storage->result_blob("a");
  const fs::path path = blobs_dir() / digest.substr(0, 2) / digest;

  // One byte flipped in a float: the digest no longer matches.
  std::string bytes = server::BlobStore({blobs_dir()}).get(digest);
  bytes[bytes.size() - 5] ^= 0x01;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_THROW(storage->result_bodies("a"), server::BlobError);
  EXPECT_THROW(storage->result_frames("a", 0, 5), server::BlobError);

  fs::remove(path);
  EXPECT_THROW(storage->result_frames("a", 0, 5), server::BlobError);

  // A node without --blobs reading a row that names a blob: an error, not an empty result.
  EXPECT_THROW(open()->result_bodies("a"), server::BlobError);
  // Putting the same result again (a new job) writes the blob back.
  run(*storage, "b", sample_result());
  expect_same(storage->result_bodies("a"), sample_result().bodies);
}

TEST_P(BlobStoreTest, CollectionRemovesOnlyBlobsNoJobNames) {
  auto storage = open(blob_store());
  run(*storage, "a", sample_result());
  run(*storage, "b", sample_result());  // shares a's blob
  run(*storage, "c", sample_result(1.0f));
  EXPECT_EQ(blob_count(blobs_dir()), 2u);
  EXPECT_EQ(storage->collect_blobs(0), 0);

  EXPECT_TRUE(storage->delete_job("a"));
  EXPECT_EQ(storage->collect_blobs(0), 0);  // b still names it
  expect_same(storage->result_bodies("b"), sample_result().bodies);

  EXPECT_TRUE(storage->delete_job("b"));
  EXPECT_EQ(storage->collect_blobs(0), 1);
  EXPECT_EQ(blob_count(blobs_dir()), 1u);
  expect_same(storage->result_bodies("c"), sample_result(1.0f).bodies);

  // Retention: a pruned job's blob goes at the next collection.
  EXPECT_EQ(storage->prune_finished(4000), 1);
  EXPECT_EQ(storage->collect_blobs(0), 1);
  EXPECT_EQ(blob_count(blobs_dir()), 0u);
}

TEST_P(BlobStoreTest, CollectionSparesYoungBlobsAndOnesNamedWhileItRuns) {
  // A blob written for a job that has not committed yet is younger than the grace period.
  auto patient = blob_store(std::chrono::seconds(600));
  const std::string young = patient->put("result of a job about to commit");
  EXPECT_EQ(
      patient->collect([] { return std::vector<std::string>{}; }, fs::file_time_type::clock::now()),
      0);
  EXPECT_TRUE(patient->contains(young));

  // Without the grace period: named between the collector's two questions, the blob is put back,
  // and readable meanwhile.
  auto store = blob_store();
  const auto now = fs::file_time_type::clock::now() + std::chrono::seconds(1);
  int asked = 0;
  const auto removed = store->collect(
      [&] {
        if (++asked == 1) return std::vector<std::string>{};
        EXPECT_FALSE(store->contains(young));  // set aside
        EXPECT_EQ(store->get(young), "result of a job about to commit");
        return std::vector<std::string>{young};
      },
      now);
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(removed, 0);
  EXPECT_TRUE(store->contains(young));
  EXPECT_EQ(store->get(young), "result of a job about to commit");

  // Named by nobody both times: gone.
  EXPECT_EQ(store->collect([] { return std::vector<std::string>{}; }, now), 1);
  EXPECT_FALSE(store->contains(young));
  EXPECT_THROW(store->get(young), server::BlobError);
}

TEST(BlobApi, ResultsFromBlobsAndA500ForACorruptOne) {
  TempDir blobs;
  TestServerOptions options;
  options.blobs_dir = blobs.path();
  TestServer server(options);
  const ClientResponse posted = server.request("POST", "/v1/jobs", job_body(quick_scene()));
  ASSERT_EQ(posted.status, 202) << posted.body;
  const std::string id = nlohmann::json::parse(posted.body).at("id");
  nlohmann::json job = server.get_json("/v1/jobs/" + id);
  for (int i = 0; i < 60 && job.at("status") != "succeeded"; ++i)
    job = server.get_json("/v1/jobs/" + id + "?wait=5");
  ASSERT_EQ(job.at("status"), "succeeded");
  const std::string digest = server.storage().result_blob(id).value_or("");
  ASSERT_TRUE(server::is_blob_digest(digest));
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id + "/meshes").status, 200);
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id + "/result.glb").status, 200);

  std::ofstream(blobs.path() / digest.substr(0, 2) / digest, std::ios::binary | std::ios::app)
      << "x";
  for (const std::string form : {"/meshes", "/frames", "/result.glb"}) {
    const ClientResponse r = server.request("GET", "/v1/jobs/" + id + form);
    EXPECT_EQ(r.status, 500) << form;
    EXPECT_NE(r.body.find("result-unavailable"), std::string::npos) << r.body;
  }
  EXPECT_EQ(server.request("GET", "/v1/jobs/" + id).status, 200);  // the job itself is fine
}

// A blob folder that cannot take a result is a storage failure, not the job's: back to the queue.
TEST(BlobApi, AResultTheBlobFolderCannotTakeSendsTheJobBackToTheQueue) {
  TempDir data;
  const fs::path blobs = data.path() / "blobs";
  TestServerOptions options;
  options.blobs_dir = blobs;
  options.store_failure_pause = std::chrono::milliseconds(100);
  TestServer server(options);
  // The folder gone and a file in its place (a read-only folder would not stop root).
  fs::remove_all(blobs);
  std::ofstream(blobs) << "not a folder";
  const ClientResponse posted = server.request("POST", "/v1/jobs", job_body(quick_scene()));
  const std::string id = nlohmann::json::parse(posted.body).at("id");
  bool ran = false, requeued = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline && !requeued) {
    const nlohmann::json job = server.get_json("/v1/jobs/" + id);
    ASSERT_NE(job.at("status"), "succeeded") << job.dump();
    ASSERT_NE(job.at("status"), "failed") << job.dump();
    if (job.at("status") == "running") ran = true;
    if (ran && job.at("status") == "queued") requeued = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(requeued);
  fs::remove(blobs);  // and once it can take it, the job succeeds
  fs::create_directory(blobs);
  nlohmann::json job = server.get_json("/v1/jobs/" + id);
  for (int i = 0; i < 60 && job.at("status") != "succeeded"; ++i)
    job = server.get_json("/v1/jobs/" + id + "?wait=5");
  EXPECT_EQ(job.at("status"), "succeeded");
}

}  // namespace
}  // namespace brisance::testing
