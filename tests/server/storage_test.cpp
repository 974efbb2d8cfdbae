// The job stores, SQLite and PostgreSQL, through one suite: migrations, idempotency, the claim
// order, leases and their recovery, attempts, cancellation, deletion, retention, the owner filter
// and the queue counts. Then what only one store has: SQLite's file errors; PostgreSQL's
// notifications across nodes, claims from several nodes, and an unreachable server.
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>

#include "server/embedded.hpp"
#include "server/pg_storage.hpp"
#include "server/sqlite_storage.hpp"
#include "tests/server/postgres_fixture.hpp"
#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using server::JobStatus;

server::NewJob new_job(std::string id, int priority = 0, std::int64_t now = 1000) {
  server::NewJob job;
  job.id = std::move(id);
  job.scene_json = "{}";
  job.priority = priority;
  job.now_ms = now;
  return job;
}

enum class Store { sqlite, postgres };

std::string store_name(const ::testing::TestParamInfo<Store>& info) {
  return info.param == Store::sqlite ? "Sqlite" : "Postgres";
}

// open() gives the store of the test's parameter; every call in one test opens the same
// database (another connection, or another node).
class StorageTest : public ::testing::TestWithParam<Store> {
 protected:
  std::unique_ptr<server::Storage> open() {
    if (GetParam() == Store::sqlite) {
      server::SqliteOptions options;
      options.file = dir_.path() / "sub" / "jobs.sqlite3";
      return server::open_sqlite_storage(options);
    }
    if (url_.empty()) url_ = shared_postgres().create_database();
    server::PostgresOptions options;
    options.conninfo = url_;
    return server::open_postgres_storage(options);
  }
  int schema_version() const {
    return GetParam() == Store::sqlite ? server::sqlite_schema_version()
                                       : server::postgres_schema_version();
  }
  TempDir dir_;
  std::string url_;
};

INSTANTIATE_TEST_SUITE_P(Stores, StorageTest, ::testing::Values(Store::sqlite, Store::postgres),
                         store_name);

TEST_P(StorageTest, MigratesOnceAndKeepsJobsAcrossReopen) {
  {
    auto storage = open();
    storage->create_job(new_job("a"));
  }
  auto storage = open();  // the migrations do not run twice
  const auto job = storage->get_job("a");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, JobStatus::queued);
  EXPECT_EQ(job->version, 1);
  EXPECT_GE(schema_version(), 2);
}

TEST_P(StorageTest, AssetsAreStoredOncePerOwnerWithTheirBytes) {
  auto storage = open();
  // Bytes with a NUL and high bytes, as a GLB has.
  const std::string bytes("glTF\0\x02\xff\x80 mesh", 14);
  server::AssetRecord asset{"a1", "alice", "glb", 14, "[\"Crate\"]", 1000};
  const auto first = storage->put_asset(asset, bytes);
  EXPECT_TRUE(first.created);
  EXPECT_EQ(first.asset.id, "a1");
  EXPECT_EQ(first.asset.nodes_json, "[\"Crate\"]");

  asset.created_ms = 2000;  // the same file again: the stored asset, not a new one
  const auto again = storage->put_asset(asset, bytes);
  EXPECT_FALSE(again.created);
  EXPECT_EQ(again.asset.created_ms, 1000);

  EXPECT_EQ(storage->asset_bytes("a1", std::string_view("alice")), bytes);
  EXPECT_EQ(storage->asset_bytes("a1", std::nullopt), bytes);  // admin or worker
  EXPECT_FALSE(storage->get_asset("a1", std::string_view("bob")));
  EXPECT_FALSE(storage->asset_bytes("a1", std::string_view("bob")));
  EXPECT_FALSE(storage->get_asset("a2", std::nullopt));

  asset.owner = "bob";  // another key uploading the same file owns its own copy
  EXPECT_TRUE(storage->put_asset(asset, bytes).created);
  const auto bobs = storage->get_asset("a1", std::string_view("bob"));
  ASSERT_TRUE(bobs);
  EXPECT_EQ(bobs->owner, "bob");
  EXPECT_EQ(bobs->format, "glb");
  EXPECT_EQ(bobs->size_bytes, 14);
}

TEST_P(StorageTest, IdempotencyKeyFindsTheFirstJobAndFlagsAnotherBody) {
  auto storage = open();
  auto job = new_job("a");
  job.idempotency_key = "k";
  job.request_hash = "h1";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::created);
  job.id = "b";
  const auto again = storage->create_job(job);
  EXPECT_EQ(again.outcome, server::CreateOutcome::existing);
  EXPECT_EQ(again.job.id, "a");
  job.request_hash = "h2";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::key_conflict);
  EXPECT_FALSE(storage->get_job("b"));
}

TEST_P(StorageTest, ClaimsByPriorityThenAgeAndCountsAttempts) {
  auto storage = open();
  storage->create_job(new_job("old-low", 0));
  storage->create_job(new_job("new-high", 5));
  storage->create_job(new_job("new-low", 0));
  std::vector<std::string> order;
  while (auto claimed = storage->claim_next("w", 2000, 1000)) {
    order.push_back(claimed->job.id);
    EXPECT_EQ(claimed->job.status, JobStatus::running);
    EXPECT_EQ(claimed->job.attempts, 1);
    EXPECT_EQ(claimed->scene_json, "{}");
  }
  EXPECT_EQ(order, (std::vector<std::string>{"new-high", "old-low", "new-low"}));
}

TEST_P(StorageTest, ConcurrentClaimsNeverHandOutAJobTwice) {
  auto storage = open();
  for (int i = 0; i < 200; ++i)
    storage->create_job(new_job("j" + std::to_string(i)));
  std::mutex mutex;
  std::multiset<std::string> claimed;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      while (auto job = storage->claim_next("w" + std::to_string(t), 2000, 60000)) {
        std::lock_guard lock(mutex);
        claimed.insert(job->job.id);
      }
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_EQ(claimed.size(), 200u);
  EXPECT_EQ(std::set<std::string>(claimed.begin(), claimed.end()).size(), 200u);
}

TEST_P(StorageTest, WorkerWritesNeedTheLease) {
  auto storage = open();
  storage->create_job(new_job("a"));
  ASSERT_TRUE(storage->claim_next("w1", 2000, 1000));
  EXPECT_FALSE(storage->set_progress("a", "w2", 0.5, 2100));
  EXPECT_TRUE(storage->set_progress("a", "w1", 0.5, 2100));
  EXPECT_FALSE(storage->complete("a", "w2", {}, 2200));
  EXPECT_TRUE(storage->complete("a", "w1", {}, 2200));
  EXPECT_FALSE(storage->complete("a", "w1", {}, 2300));  // exactly once
  EXPECT_EQ(storage->get_job("a")->status, JobStatus::succeeded);
}

TEST_P(StorageTest, ExpiredLeasesRequeueUntilTheAttemptsRunOut) {
  auto storage = open();
  storage->create_job(new_job("a"));
  std::int64_t now = 2000;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    auto claimed = storage->claim_next("dead", now, 1000);
    ASSERT_TRUE(claimed);
    EXPECT_EQ(claimed->job.attempts, attempt);
    now += 500;
    EXPECT_EQ(storage->recover_expired(now, 3).requeued, 0);  // lease still valid
    now += 1000;
    const auto report = storage->recover_expired(now, 3);
    if (attempt < 3) {
      EXPECT_EQ(report.requeued, 1);
      EXPECT_EQ(storage->get_job("a")->status, JobStatus::queued);
    } else {
      EXPECT_EQ(report.failed, 1);
    }
  }
  const auto job = storage->get_job("a");
  EXPECT_EQ(job->status, JobStatus::failed);
  EXPECT_EQ(job->error_type, "worker_lost");
  EXPECT_NE(job->error.find("3 times"), std::string::npos);
  EXPECT_FALSE(storage->claim_next("w", now, 1000));
}

TEST_P(StorageTest, ReleaseDoesNotCountTheAttemptAndRenewKeepsTheLease) {
  auto storage = open();
  storage->create_job(new_job("a"));
  ASSERT_TRUE(storage->claim_next("w", 2000, 1000));
  EXPECT_TRUE(storage->renew_lease("a", "w", 10000));
  EXPECT_EQ(storage->recover_expired(5000, 3).requeued, 0);
  EXPECT_EQ(storage->running_owners(), std::vector<std::string>{"w"});
  EXPECT_EQ(storage->expire_leases("w"), 1);
  EXPECT_EQ(storage->recover_expired(5000, 3).requeued, 1);
  ASSERT_TRUE(storage->claim_next("w", 6000, 1000));
  EXPECT_TRUE(storage->release("a", "w", 6100));
  const auto job = storage->get_job("a");
  EXPECT_EQ(job->status, JobStatus::queued);
  EXPECT_EQ(job->attempts, 1);
}

TEST_P(StorageTest, CancelQueuedAtOnceRunningByRequest) {
  auto storage = open();
  storage->create_job(new_job("q"));
  storage->create_job(new_job("r", 9));
  ASSERT_EQ(storage->claim_next("w", 2000, 1000)->job.id, "r");
  EXPECT_EQ(storage->request_cancel("q", 2100), server::CancelOutcome::cancelled);
  EXPECT_EQ(storage->get_job("q")->status, JobStatus::cancelled);
  EXPECT_EQ(storage->request_cancel("r", 2100), server::CancelOutcome::requested);
  EXPECT_TRUE(storage->cancel_requested("r"));
  EXPECT_TRUE(storage->finish_cancelled("r", "w", 2200));
  EXPECT_EQ(storage->request_cancel("r", 2300), server::CancelOutcome::already_final);
  EXPECT_EQ(storage->request_cancel("nope", 2300), server::CancelOutcome::not_found);
}

TEST_P(StorageTest, ResultsAreStoredOnceAndGoWithTheirJob) {
  auto storage = open();
  storage->create_job(new_job("a"));
  ASSERT_TRUE(storage->claim_next("w", 2000, 1000));
  server::StoredResult result;
  result.summary_json = "{\"x\":1}";
  result.stats_json = "{\"steps\":3}";
  server::StoredBody body;
  body.name = "b";
  body.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  body.triangles = {0, 1, 2};
  result.bodies = {body};
  result.frames = {{0.0, {1, 2, 3, 0, 0, 0, 1}}, {0.5, {4, 5, 6, 0, 0, 0, 1}}};
  ASSERT_TRUE(storage->complete("a", "w", result, 3000));
  EXPECT_EQ(storage->get_job("a")->stats_json, "{\"steps\":3}");
  EXPECT_EQ(storage->result_summary("a"), "{\"x\":1}");
  const auto frames = storage->result_frames("a", 1, 5);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].time_s, 0.5);
  EXPECT_EQ(frames[0].poses[0], 4.0f);
  EXPECT_EQ(storage->result_bodies("a")[0].vertices.size(), 12u);
  EXPECT_TRUE(storage->delete_job("a"));
  EXPECT_TRUE(storage->result_bodies("a").empty());
  EXPECT_TRUE(storage->result_frames("a", 0, 5).empty());
}

TEST_P(StorageTest, PruneDeletesOnlyFinishedJobsPastRetention) {
  auto storage = open();
  storage->create_job(new_job("old", 0, 1000));
  storage->create_job(new_job("waiting", 0, 1000));
  ASSERT_EQ(storage->claim_next("w", 1000, 1000)->job.id, "old");
  ASSERT_TRUE(storage->fail("old", "w", "x", "y", 1500));
  EXPECT_EQ(storage->prune_finished(1400), 0);
  EXPECT_EQ(storage->prune_finished(2000), 1);
  EXPECT_FALSE(storage->get_job("old"));
  EXPECT_TRUE(storage->get_job("waiting"));
}

server::JobFilter by(std::optional<JobStatus> status, std::optional<std::string> owner = {}) {
  server::JobFilter filter;
  filter.status = status;
  filter.owner = std::move(owner);
  return filter;
}

TEST_P(StorageTest, CallbacksAreClaimedOnceDueAndRecorded) {
  auto storage = open();
  auto job = new_job("cb");
  job.callback_url = "http://127.0.0.1:9/done";
  EXPECT_EQ(storage->create_job(job).job.callback_state, "pending");
  storage->create_job(new_job("plain"));
  // Not finished yet: nothing to send.
  EXPECT_FALSE(storage->claim_callback(2000, 1000));
  ASSERT_EQ(storage->claim_next("w", 2000, 10000)->job.id, "cb");
  ASSERT_TRUE(storage->fail("cb", "w", "simulation-error", "boom", 2100));
  // Finished: claimed once, then held until the lease runs out.
  const auto claimed = storage->claim_callback(3000, 1000);
  ASSERT_TRUE(claimed);
  EXPECT_EQ(claimed->id, "cb");
  EXPECT_EQ(claimed->callback_url, "http://127.0.0.1:9/done");
  EXPECT_FALSE(storage->claim_callback(3500, 1000));
  const std::int64_t version = storage->get_job("cb")->version;
  ASSERT_TRUE(
      storage->record_callback("cb", R"([{"attempt":1,"status":503}])", "pending", 5000, 3600));
  const auto recorded = storage->get_job("cb");
  EXPECT_EQ(recorded->callback_deliveries_json, R"([{"attempt":1,"status":503}])");
  EXPECT_EQ(recorded->version, version + 1);
  EXPECT_FALSE(storage->claim_callback(4999, 1000));  // not due before the backoff
  ASSERT_TRUE(storage->claim_callback(5000, 1000));
  ASSERT_TRUE(storage->record_callback("cb", "[]", "delivered", 0, 5100));
  EXPECT_FALSE(storage->claim_callback(99999, 1000));
  EXPECT_EQ(storage->get_job("cb")->callback_state, "delivered");
  EXPECT_EQ(storage->get_job("plain")->callback_state, "");
  EXPECT_FALSE(storage->record_callback("gone", "[]", "failed", 0, 6000));
}

TEST_P(StorageTest, KeepsNamesAndLabelsAndListsByThem) {
  auto storage = open();
  const std::vector<std::tuple<std::string, std::string, std::string>> jobs = {
      {"j1", "Facade shot 12", R"({"artist":"kim","shot":"sq010"})"},
      {"j2", "facade test", R"({"shot":"sq020"})"},
      {"j3", "", "{}"},
      {"j4", "Crate", R"({"artist":"lee","shot":"sq010","take":"2"})"},
  };
  for (const auto& [id, name, labels] : jobs) {
    auto job = new_job(id);
    job.name = name;
    job.labels_json = labels;
    EXPECT_EQ(storage->create_job(job).job.labels_json, labels);
  }
  const auto stored = storage->get_job("j1");
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->name, "Facade shot 12");
  EXPECT_EQ(stored->labels_json, R"({"artist":"kim","shot":"sq010"})");
  EXPECT_EQ(storage->get_job("j3")->labels_json, "{}");

  const auto ids = [&](server::JobFilter filter) {
    std::vector<std::string> out;
    for (const auto& job : storage->list_jobs(filter, 0, 10).jobs)
      out.push_back(job.id);
    return out;
  };
  server::JobFilter filter;
  filter.labels = {{"shot", "sq010"}};
  EXPECT_EQ(ids(filter), (std::vector<std::string>{"j4", "j1"}));
  filter.labels = {{"shot", "sq010"}, {"artist", "kim"}};
  EXPECT_EQ(ids(filter), (std::vector<std::string>{"j1"}));
  filter.labels = {{"take", std::nullopt}};
  EXPECT_EQ(ids(filter), (std::vector<std::string>{"j4"}));
  filter.labels = {{"shot", "sq01"}};  // values match whole, not as prefixes
  EXPECT_TRUE(ids(filter).empty());
  filter.labels = {};
  filter.name_contains = "FACADE";
  EXPECT_EQ(ids(filter), (std::vector<std::string>{"j2", "j1"}));
  filter.labels = {{"shot", "sq020"}};
  EXPECT_EQ(ids(filter), (std::vector<std::string>{"j2"}));
  filter.status = JobStatus::running;
  EXPECT_TRUE(ids(filter).empty());
}

TEST_P(StorageTest, ListsNewestFirstByOwnerAndStatusWithACursor) {
  auto storage = open();
  for (int i = 0; i < 5; ++i) {
    auto job = new_job("a" + std::to_string(i));
    job.owner = "alice";
    storage->create_job(job);
    job = new_job("b" + std::to_string(i));
    job.owner = "bob";
    storage->create_job(job);
  }
  ASSERT_EQ(storage->claim_next("w", 2000, 1000)->job.id, "a0");
  auto page = storage->list_jobs(by({}, "alice"), 0, 3);
  ASSERT_EQ(page.jobs.size(), 3u);
  EXPECT_EQ(page.jobs[0].id, "a4");
  EXPECT_EQ(page.jobs[2].id, "a2");
  EXPECT_EQ(page.jobs[0].owner, "alice");
  ASSERT_TRUE(page.cursor);
  page = storage->list_jobs(by({}, "alice"), *page.cursor, 3);
  ASSERT_EQ(page.jobs.size(), 2u);
  EXPECT_EQ(page.jobs[1].id, "a0");
  EXPECT_FALSE(page.cursor);
  page = storage->list_jobs(by(JobStatus::running), 0, 10);
  ASSERT_EQ(page.jobs.size(), 1u);
  EXPECT_EQ(page.jobs[0].id, "a0");
  EXPECT_TRUE(storage->list_jobs(by(JobStatus::running, "bob"), 0, 10).jobs.empty());
  EXPECT_EQ(storage->list_jobs(by(JobStatus::queued), 0, 100).jobs.size(), 9u);
  EXPECT_EQ(storage->list_jobs({}, 0, 100).jobs.size(), 10u);
}

TEST_P(StorageTest, IdempotencyKeysAreScopedToTheirOwner) {
  auto storage = open();
  auto job = new_job("a");
  job.owner = "alice";
  job.idempotency_key = "k";
  job.request_hash = "h";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::created);
  job.id = "b";
  job.owner = "bob";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::created);
  job.id = "c";
  job.create_if_missing = false;  // a full queue: only the look-up
  EXPECT_EQ(storage->create_job(job).job.id, "b");
  job.owner = "carol";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::not_created);
  EXPECT_FALSE(storage->get_job("c"));
}

TEST_P(StorageTest, QueueCountsByStatusOldestAndLastMinute) {
  auto storage = open();
  storage->create_job(new_job("a", 0, 1000));
  storage->create_job(new_job("b", 0, 2000));
  storage->create_job(new_job("c", 0, 3000));
  storage->create_job(new_job("d", 0, 4000));
  ASSERT_EQ(storage->claim_next("w", 70000, 1000)->job.id, "a");
  ASSERT_TRUE(storage->complete("a", "w", {}, 70000));
  ASSERT_EQ(storage->claim_next("w", 70000, 100000)->job.id, "b");
  ASSERT_TRUE(storage->fail("b", "w", "x", "y", 5000));  // finished long before the last minute
  ASSERT_EQ(storage->claim_next("w", 70000, 100000)->job.id, "c");
  EXPECT_EQ(storage->count_queued(), 1);
  const server::QueueCounts counts = storage->queue_counts(100000);
  EXPECT_EQ(counts.by_status, (std::array<std::int64_t, 5>{1, 1, 1, 1, 0}));
  EXPECT_EQ(counts.oldest_queued_created_ms, 4000);
  EXPECT_EQ(counts.finished_last_minute, 1);
  EXPECT_EQ(storage->queue_counts(200000).finished_last_minute, 0);
}

TEST_P(StorageTest, RecoveryCancelsAJobWhoseCancelWasRequested) {
  auto storage = open();
  storage->create_job(new_job("a"));
  ASSERT_TRUE(storage->claim_next("dead", 2000, 1000));
  EXPECT_EQ(storage->request_cancel("a", 2100), server::CancelOutcome::requested);
  EXPECT_EQ(storage->recover_expired(5000, 3).requeued, 1);
  const auto job = storage->get_job("a");
  EXPECT_EQ(job->status, JobStatus::cancelled);
  EXPECT_EQ(job->finished_ms, 5000);
  EXPECT_FALSE(storage->claim_next("w", 6000, 1000));
}

TEST_P(StorageTest, VersionCountsEveryVisibleChange) {
  auto storage = open();
  storage->create_job(new_job("a"));
  EXPECT_EQ(storage->claim_next("w", 2000, 1000)->job.version, 2);
  ASSERT_TRUE(storage->set_progress("a", "w", 0.25, 2100));
  ASSERT_TRUE(storage->renew_lease("a", "w", 9000));  // not visible to clients
  auto job = storage->get_job("a");
  EXPECT_EQ(job->version, 3);
  EXPECT_EQ(job->progress, 0.25);
  EXPECT_EQ(job->started_ms, 2000);
  EXPECT_FALSE(job->finished_ms);
  ASSERT_TRUE(storage->fail("a", "w", "timeout", "too long", 3000));
  job = storage->get_job("a");
  EXPECT_EQ(job->version, 4);
  EXPECT_EQ(job->error_type, "timeout");
  EXPECT_EQ(job->error, "too long");
  EXPECT_EQ(job->finished_ms, 3000);
}

TEST_P(StorageTest, AnotherConnectionSeesTheSameJobs) {
  auto first = open();
  auto second = open();
  first->create_job(new_job("a"));
  ASSERT_TRUE(second->claim_next("w2", 2000, 1000));
  EXPECT_FALSE(first->claim_next("w1", 2000, 1000));
  EXPECT_EQ(first->get_job("a")->status, JobStatus::running);
  EXPECT_TRUE(first->ping());
}

// Submissions arriving together share a commit (group commit on both stores): each still gets
// its own outcome — one that fails (a duplicate id) fails alone — and a key submitted from many
// threads at once names one job.
TEST_P(StorageTest, ConcurrentSubmissionsGetTheirOwnOutcomes) {
  auto storage = open();
  storage->create_job(new_job("dup"));
  std::mutex mutex;
  std::multiset<std::string> created, found;
  int failed = 0;
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 25; ++i) {
        auto job =
            new_job(t == 3 && i == 12 ? "dup" : "t" + std::to_string(t) + "-" + std::to_string(i));
        if (i % 5 == 0) {  // keys k0..k4, each sent by every thread
          job.idempotency_key = "k" + std::to_string(i / 5);
          job.request_hash = "h";
        }
        server::CreateResult result;
        try {
          result = storage->create_job(job);
        } catch (const server::StorageError&) {
          std::lock_guard lock(mutex);
          ++failed;
          continue;
        }
        std::lock_guard lock(mutex);
        if (result.outcome == server::CreateOutcome::created) {
          created.insert(result.job.id);
          EXPECT_EQ(result.job.id, job.id);
        } else {
          EXPECT_EQ(result.outcome, server::CreateOutcome::existing);
          found.insert(job.idempotency_key);
        }
      }
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_EQ(failed, 1);
  EXPECT_EQ(created.size(), 8u * 20u - 1u + 5u);  // every unkeyed job but "dup", one per key
  EXPECT_EQ(found.size(), 8u * 5u - 5u);
  EXPECT_EQ(storage->count_queued(), static_cast<std::int64_t>(created.size()) + 1);
}

// Clients send any bytes (ids in paths, keys in headers): those that are not UTF-8, or hold a
// NUL, name no job and work as keys, on both stores.
TEST_P(StorageTest, AnyBytesNameNoJobAndServeAsKeys) {
  auto storage = open();
  storage->create_job(new_job("a"));
  for (const std::string& id : {std::string("\xff\xfe"), std::string("a\0b", 3),
                                std::string("\xc3\x28"), std::string("\xed\xa0\x80")}) {
    EXPECT_FALSE(storage->get_job(id));
    EXPECT_FALSE(storage->scene(id));
    EXPECT_EQ(storage->request_cancel(id, 2000), server::CancelOutcome::not_found);
    EXPECT_FALSE(storage->delete_job(id));
    EXPECT_TRUE(storage->result_frames(id, 0, 10).empty());
  }
  EXPECT_TRUE(storage->list_jobs(by({}, "\xff"), 0, 10).jobs.empty());
  auto job = new_job("b");
  job.idempotency_key = "\xff";
  job.request_hash = "h";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::created);
  job.id = "c";
  EXPECT_EQ(storage->create_job(job).job.id, "b");
  job.idempotency_key = "\xfe";
  EXPECT_EQ(storage->create_job(job).outcome, server::CreateOutcome::created);
  EXPECT_TRUE(storage->get_job("a"));
}

TEST(SqliteStorage, AnUnwritableLocationIsAStorageError) {
  server::SqliteOptions options;
  options.file = "/proc/brisance/jobs.sqlite3";
  EXPECT_THROW(server::open_sqlite_storage(options), server::StorageError);
}

// Several stores on one PostgreSQL database stand for several nodes.
class PostgresStorage : public ::testing::Test {
 protected:
  std::unique_ptr<server::Storage> open_node() {
    server::PostgresOptions options;
    options.conninfo = url_;
    return server::open_postgres_storage(options);
  }
  std::string url_ = shared_postgres().create_database();
};

TEST_F(PostgresStorage, MigrationsRunOnceWhenNodesStartTogether) {
  std::vector<std::thread> threads;
  std::atomic<int> opened{0};
  for (int i = 0; i < 4; ++i) {
    threads.emplace_back([&] {
      if (open_node()) ++opened;
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_EQ(opened, 4);
  server::pg::Connection c(url_);
  const auto r = c.exec("SELECT version FROM schema_migrations ORDER BY version");
  // One row per migration, in order (numbers may have gaps while branches merge).
  const auto migrations = embedded_pg_migrations();
  ASSERT_EQ(r.rows(), static_cast<int>(migrations.size()));
  for (int row = 0; row < r.rows(); ++row)
    EXPECT_EQ(r.int64(row, 0),
              std::stoi(std::string(migrations[static_cast<std::size_t>(row)].name.substr(0, 3))));
  EXPECT_EQ(r.int64(r.rows() - 1, 0), server::postgres_schema_version());
}

TEST_F(PostgresStorage, NodesClaimingAtOnceNeverTakeAJobTwice) {
  auto first = open_node();
  for (int i = 0; i < 300; ++i)
    first->create_job(new_job("j" + std::to_string(i), i % 7));
  std::vector<std::unique_ptr<server::Storage>> nodes;
  for (int n = 0; n < 3; ++n)
    nodes.push_back(open_node());
  std::mutex mutex;
  std::multiset<std::string> claimed;
  std::vector<std::thread> threads;
  for (int t = 0; t < 6; ++t) {
    threads.emplace_back([&, t] {
      server::Storage& node = *nodes[static_cast<std::size_t>(t % 3)];
      while (auto job = node.claim_next("w" + std::to_string(t), 2000, 60000)) {
        std::lock_guard lock(mutex);
        claimed.insert(job->job.id);
      }
    });
  }
  for (auto& thread : threads)
    thread.join();
  EXPECT_EQ(claimed.size(), 300u);
  EXPECT_EQ(std::set<std::string>(claimed.begin(), claimed.end()).size(), 300u);
  EXPECT_EQ(first->queue_counts(3000).by_status[1], 300);
}

// What another node does reaches this node's listener: a queued job wakes its workers, a
// finished one its long-polls.
TEST_F(PostgresStorage, ChangesOnOneNodeAreHeardOnAnother) {
  auto here = open_node();
  auto there = open_node();
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::string> ids;
  int queued = 0;
  here->watch(
      [&](const std::string& id) {
        std::lock_guard lock(mutex);
        ids.push_back(id);
        changed.notify_all();
      },
      [&] {
        std::lock_guard lock(mutex);
        ++queued;
        changed.notify_all();
      });
  auto wait_for = [&](auto predicate) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(20), predicate);
  };
  // The listener reports work once connected (notifications sent before are lost).
  ASSERT_TRUE(wait_for([&] { return queued >= 1; }));
  const int before = queued;
  there->create_job(new_job("a"));
  EXPECT_TRUE(wait_for([&] { return queued > before; }));
  ASSERT_TRUE(there->claim_next("w", 2000, 1000));
  ASSERT_TRUE(there->complete("a", "w", {}, 3000));
  EXPECT_TRUE(wait_for([&] { return std::count(ids.begin(), ids.end(), "a") >= 2; }));
  here->watch({}, {});
}

TEST_F(PostgresStorage, AnUnreachableServerIsAStorageErrorAndPingSaysSo) {
  server::PostgresOptions options;
  options.conninfo = "postgresql://brisance@127.0.0.1:1/none?connect_timeout=2";
  EXPECT_THROW(server::open_postgres_storage(options), server::StorageError);
}

TEST(PostgresRestart, ADatabaseRestartIsSurvived) {
  PostgresServer own;  // stopped and started here: not the shared one
  server::PostgresOptions options;
  options.conninfo = own.create_database();
  auto storage = server::open_postgres_storage(options);
  storage->create_job(new_job("a"));
  EXPECT_TRUE(storage->ping());
  own.stop();
  EXPECT_FALSE(storage->ping());
  EXPECT_THROW(storage->get_job("a"), server::StorageError);
  own.start();
  // Reconnection waits out the backoff; the store answers again within it.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!storage->ping() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(storage->ping());
  ASSERT_TRUE(storage->get_job("a"));
  EXPECT_EQ(storage->claim_next("w", 2000, 1000)->job.id, "a");
}

}  // namespace
}  // namespace brisance::testing
