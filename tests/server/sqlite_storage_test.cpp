// The SQLite job store: migrations, idempotency, the claim order, leases and their recovery,
// attempts, cancellation, deletion and retention.
#include "server/sqlite_storage.hpp"

#include <mutex>
#include <set>
#include <thread>

#include <gtest/gtest.h>

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

class SqliteStorage : public ::testing::Test {
 protected:
  std::unique_ptr<server::Storage> open() {
    server::SqliteOptions options;
    options.file = dir_.path() / "sub" / "jobs.sqlite3";
    return server::open_sqlite_storage(options);
  }
  TempDir dir_;
};

TEST_F(SqliteStorage, MigratesOnceAndKeepsJobsAcrossReopen) {
  {
    auto storage = open();
    storage->create_job(new_job("a"));
  }
  auto storage = open();  // the migrations do not run twice
  const auto job = storage->get_job("a");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, JobStatus::queued);
  EXPECT_EQ(job->version, 1);
  EXPECT_GE(server::sqlite_schema_version(), 1);
}

TEST_F(SqliteStorage, IdempotencyKeyFindsTheFirstJobAndFlagsAnotherBody) {
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

TEST_F(SqliteStorage, ClaimsByPriorityThenAgeAndCountsAttempts) {
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

TEST_F(SqliteStorage, ConcurrentClaimsNeverHandOutAJobTwice) {
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

TEST_F(SqliteStorage, WorkerWritesNeedTheLease) {
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

TEST_F(SqliteStorage, ExpiredLeasesRequeueUntilTheAttemptsRunOut) {
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

TEST_F(SqliteStorage, ReleaseDoesNotCountTheAttemptAndRenewKeepsTheLease) {
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

TEST_F(SqliteStorage, CancelQueuedAtOnceRunningByRequest) {
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

TEST_F(SqliteStorage, ResultsAreStoredOnceAndGoWithTheirJob) {
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

TEST_F(SqliteStorage, PruneDeletesOnlyFinishedJobsPastRetention) {
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

TEST_F(SqliteStorage, AnUnwritableLocationIsAStorageError) {
  server::SqliteOptions options;
  options.file = "/proc/brisance/jobs.sqlite3";
  EXPECT_THROW(server::open_sqlite_storage(options), server::StorageError);
}

}  // namespace
}  // namespace brisance::testing
