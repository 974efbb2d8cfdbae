#include "server/pg_storage.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "server/embedded.hpp"
#include "server/group_commit.hpp"
#include "server/pg.hpp"
#include "server/pg_pool.hpp"

namespace brisance::server {

bool is_postgres_url(std::string_view text) {
  return text.starts_with("postgres://") || text.starts_with("postgresql://");
}

namespace {

// pg_advisory_lock key of the migrations: "brisance" in ASCII.
constexpr const char* kMigrationLock = "SELECT pg_advisory_lock(7093015238034759269)";
constexpr const char* kMigrationUnlock = "SELECT pg_advisory_unlock(7093015238034759269)";

// Idle connections kept for reuse; more are opened when more threads need one at once.
constexpr std::size_t kMaxIdleConnections = 16;
// Frames inserted per statement when a result is stored (4 parameters each).
constexpr std::size_t kFramesPerInsert = 1000;

#define JOB_COLUMNS                                                                        \
  "id, seq, status, priority, progress, version, attempts, cancel_requested, created_ms, " \
  "updated_ms, started_ms, finished_ms, error_type, error, stats, owner, name, labels, "   \
  "callback_url, callback_state, callback_deliveries"
constexpr int kJobColumnCount = 21;

using pg::storable;
using pg::storable_key;

JobRecord read_job(const pg::Result& r, int row) {
  JobRecord j;
  j.id = std::string(r.text(row, 0));
  j.seq = r.int64(row, 1);
  j.status = parse_job_status(r.text(row, 2)).value_or(JobStatus::queued);
  j.priority = static_cast<int>(r.int64(row, 3));
  j.progress = r.real(row, 4);
  j.version = r.int64(row, 5);
  j.attempts = static_cast<int>(r.int64(row, 6));
  j.cancel_requested = r.boolean(row, 7);
  j.created_ms = r.int64(row, 8);
  j.updated_ms = r.int64(row, 9);
  j.started_ms = r.optional_int64(row, 10);
  j.finished_ms = r.optional_int64(row, 11);
  j.error_type = std::string(r.text(row, 12));
  j.error = std::string(r.text(row, 13));
  j.stats_json = std::string(r.text(row, 14));
  j.owner = std::string(r.text(row, 15));
  j.name = std::string(r.text(row, 16));
  j.labels_json = std::string(r.text(row, 17));
  j.callback_url = std::string(r.text(row, 18));
  j.callback_state = std::string(r.text(row, 19));
  j.callback_deliveries_json = std::string(r.text(row, 20));
  return j;
}

class PgStorage final : public Storage {
 public:
  explicit PgStorage(PostgresOptions options)
      : options_(std::move(options)),
        pool_({options_.conninfo, options_.first_backoff, options_.max_backoff,
               kMaxIdleConnections}) {
    pool_.with_connection([&](pg::Connection& c) {
      migrate(c);
      return 0;
    });
  }

  ~PgStorage() override { listener_.reset(); }

  // Group commit (server/group_commit.hpp): concurrent submissions share one transaction.
  CreateResult create_job(const NewJob& job) override {
    return group_.submit(job,
                         [this](const std::vector<PendingCreate*>& batch) { run_batch(batch); });
  }

  std::optional<JobRecord> get_job(std::string_view id) override {
    if (!storable(id)) return std::nullopt;
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<JobRecord> {
      const pg::Result r =
          c.exec("SELECT " JOB_COLUMNS " FROM jobs WHERE id = $1", pg::Params().add(id));
      if (r.rows() == 0) return std::nullopt;
      return read_job(r, 0);
    });
  }

  JobPage list_jobs(const JobFilter& filter, std::int64_t before_seq, int limit) override {
    if (filter.owner && !storable(*filter.owner)) return {};
    pg::Params params;
    const auto next = [&](std::string_view value) {
      params.add(value);
      return "$" + std::to_string(params.size());
    };
    params.add(before_seq > 0 ? before_seq : INT64_MAX);
    std::string sql = "SELECT " JOB_COLUMNS " FROM jobs WHERE seq < $1";
    if (filter.owner) sql += " AND owner = " + next(*filter.owner);
    if (filter.status) sql += " AND status = " + next(to_string(*filter.status));
    for (const LabelSelector& label : filter.labels) {
      if (label.value && !storable(*label.value)) return {};
      sql += label.value ? " AND labels::jsonb ->> " + next(label.key) + " = " + next(*label.value)
                         : " AND labels::jsonb ? " + next(label.key);
    }
    if (!filter.name_contains.empty()) {
      if (!storable(filter.name_contains)) return {};
      sql += " AND strpos(lower(name), lower(" + next(filter.name_contains) + ")) > 0";
    }
    params.add(limit + 1);
    sql += " ORDER BY seq DESC LIMIT $" + std::to_string(params.size());
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r = c.exec(sql.c_str(), params);
      JobPage page;
      for (int row = 0; row < r.rows(); ++row)
        page.jobs.push_back(read_job(r, row));
      if (static_cast<int>(page.jobs.size()) > limit) {
        page.jobs.pop_back();
        page.cursor = page.jobs.back().seq;
      }
      return page;
    });
  }

  std::int64_t count_queued() override {
    return pool_.with_connection([&](pg::Connection& c) {
      return c.exec("SELECT count(*) FROM jobs WHERE status = 'queued'").int64(0, 0);
    });
  }

  QueueCounts queue_counts(std::int64_t now_ms) override {
    return pool_.with_connection([&](pg::Connection& c) {
      // One statement, so one snapshot.
      const pg::Result r = c.exec(
          "SELECT count(*) FILTER (WHERE status = 'queued'), "
          "count(*) FILTER (WHERE status = 'running'), "
          "count(*) FILTER (WHERE status = 'succeeded'), "
          "count(*) FILTER (WHERE status = 'failed'), "
          "count(*) FILTER (WHERE status = 'cancelled'), "
          "min(created_ms) FILTER (WHERE status = 'queued'), "
          "count(*) FILTER (WHERE finished_ms >= $1 AND status IN ('succeeded', 'failed')) "
          "FROM jobs",
          pg::Params().add(now_ms - 60000));
      QueueCounts counts;
      for (int s = 0; s < 5; ++s)
        counts.by_status[static_cast<std::size_t>(s)] = r.int64(0, s);
      counts.oldest_queued_created_ms = r.optional_int64(0, 5);
      counts.finished_last_minute = r.int64(0, 6);
      return counts;
    });
  }

  std::optional<ClaimedJob> claim_next(std::string_view owner, std::int64_t now_ms,
                                       std::int64_t lease_ms) override {
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<ClaimedJob> {
      // SKIP LOCKED: a row another node is claiming right now is passed over, not waited on.
      const pg::Result r = c.exec(
          "WITH next AS (SELECT seq AS next_seq FROM jobs WHERE status = 'queued' "
          "ORDER BY priority DESC, seq LIMIT 1 FOR UPDATE SKIP LOCKED) "
          "UPDATE jobs SET status = 'running', lease_owner = $1, lease_expires_ms = $2, "
          "attempts = attempts + 1, started_ms = $3, updated_ms = $3, progress = 0, "
          "version = version + 1 FROM next WHERE seq = next_seq "
          "RETURNING " JOB_COLUMNS ", scene, pg_notify('brisance_jobs', id)",
          pg::Params().add(owner).add(now_ms + lease_ms).add(now_ms));
      if (r.rows() == 0) return std::nullopt;
      return ClaimedJob{read_job(r, 0), std::string(r.text(0, kJobColumnCount))};
    });
  }

  bool renew_lease(std::string_view id, std::string_view owner, std::int64_t until_ms) override {
    return owned_update(id, owner,
                        "UPDATE jobs SET lease_expires_ms = $3 WHERE id = $1 AND lease_owner = $2 "
                        "AND status = 'running'",
                        pg::Params().add(id).add(owner).add(until_ms));
  }

  bool set_progress(std::string_view id, std::string_view owner, double progress,
                    std::int64_t now_ms) override {
    return owned_update(id, owner,
                        "UPDATE jobs SET progress = $3, updated_ms = $4, version = version + 1 "
                        "WHERE id = $1 AND lease_owner = $2 AND status = 'running' "
                        "RETURNING pg_notify('brisance_jobs', id)",
                        pg::Params().add(id).add(owner).add(progress).add(now_ms));
  }

  bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                std::int64_t now_ms) override {
    if (!storable(id) || !storable(owner)) return false;
    return pool_.with_connection([&](pg::Connection& c) {
      pg::Transaction tx(c);
      std::int64_t seq = 0;
      {
        // The row lock holds off a concurrent requeue or delete until this commits.
        const pg::Result r = c.exec(
            "SELECT seq FROM jobs WHERE id = $1 AND lease_owner = $2 AND status = 'running' "
            "FOR UPDATE",
            pg::Params().add(id).add(owner));
        if (r.rows() == 0) return false;
        seq = r.int64(0, 0);
      }
      for (std::size_t i = 0; i < result.bodies.size(); ++i) {
        const StoredBody& b = result.bodies[i];
        pg::Params params;
        params.add(seq).add(static_cast<std::int64_t>(i)).add(b.name).add(b.mass_kg);
        params.add(b.animated);
        params.add_bytes(std::span<const double>(b.initial_pose));
        params.add_bytes(std::span<const float>(b.vertices));
        params.add_bytes(std::span<const std::uint32_t>(b.triangles));
        c.exec(
            "INSERT INTO job_bodies (job_seq, body_index, name, mass_kg, animated, "
            "initial_pose, vertices, triangles) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
            params);
      }
      if (!result.encoded.empty()) {
        c.exec("INSERT INTO job_results (job_seq, data) VALUES ($1, $2)",
               pg::Params().add(seq).add_bytes(std::span<const char>(result.encoded)));
      }
      for (std::size_t first = 0; first < result.frames.size(); first += kFramesPerInsert) {
        const std::size_t last = std::min(result.frames.size(), first + kFramesPerInsert);
        pg::Params params;
        std::string sql = "INSERT INTO job_frames (job_seq, frame, time_s, poses) VALUES ";
        for (std::size_t f = first; f < last; ++f) {
          const int base = params.size();
          params.add(seq).add(static_cast<std::int64_t>(f)).add(result.frames[f].time_s);
          params.add_bytes(std::span<const float>(result.frames[f].poses));
          sql += (f == first ? "($" : ", ($") + std::to_string(base + 1) + ", $" +
                 std::to_string(base + 2) + ", $" + std::to_string(base + 3) + ", $" +
                 std::to_string(base + 4) + ")";
        }
        c.exec(sql.c_str(), params);
      }
      c.exec(
          "UPDATE jobs SET status = 'succeeded', progress = 1, finished_ms = $2, "
          "updated_ms = $2, version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, "
          "stats = $3, result_summary = $4, result_blob = NULLIF($5, '') WHERE seq = $1 "
          "RETURNING pg_notify('brisance_jobs', id)",
          pg::Params()
              .add(seq)
              .add(now_ms)
              .add(result.stats_json)
              .add(result.summary_json)
              .add(result.blob_digest));
      tx.commit();
      return true;
    });
  }

  bool fail(std::string_view id, std::string_view owner, std::string_view error_type,
            std::string_view message, std::int64_t now_ms) override {
    return owned_update(
        id, owner,
        "UPDATE jobs SET status = 'failed', finished_ms = $3, updated_ms = $3, "
        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, error_type = $4, "
        "error = $5 WHERE id = $1 AND lease_owner = $2 AND status = 'running' "
        "RETURNING pg_notify('brisance_jobs', id)",
        pg::Params().add(id).add(owner).add(now_ms).add(error_type).add(message));
  }

  bool finish_cancelled(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return owned_update(id, owner,
                        "UPDATE jobs SET status = 'cancelled', finished_ms = $3, updated_ms = $3, "
                        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL "
                        "WHERE id = $1 AND lease_owner = $2 AND status = 'running' "
                        "RETURNING pg_notify('brisance_jobs', id)",
                        pg::Params().add(id).add(owner).add(now_ms));
  }

  bool release(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return owned_update(
        id, owner,
        "UPDATE jobs SET status = 'queued', progress = 0, started_ms = NULL, updated_ms = $3, "
        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, "
        "attempts = greatest(attempts - 1, 0) "
        "WHERE id = $1 AND lease_owner = $2 AND status = 'running' "
        "RETURNING pg_notify('brisance_jobs', id), pg_notify('brisance_queue', '')",
        pg::Params().add(id).add(owner).add(now_ms));
  }

  bool cancel_requested(std::string_view id) override {
    if (!storable(id)) return true;  // no such job: as deleted
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r =
          c.exec("SELECT cancel_requested FROM jobs WHERE id = $1", pg::Params().add(id));
      return r.rows() == 0 || r.boolean(0, 0);  // a deleted job counts as cancelled
    });
  }

  CancelOutcome request_cancel(std::string_view id, std::int64_t now_ms) override {
    if (!storable(id)) return CancelOutcome::not_found;
    return pool_.with_connection([&](pg::Connection& c) {
      pg::Transaction tx(c);
      JobStatus status;
      {
        const pg::Result r =
            c.exec("SELECT status FROM jobs WHERE id = $1 FOR UPDATE", pg::Params().add(id));
        if (r.rows() == 0) return CancelOutcome::not_found;
        status = parse_job_status(r.text(0, 0)).value_or(JobStatus::queued);
      }
      CancelOutcome outcome = CancelOutcome::already_final;
      if (status == JobStatus::queued) {
        c.exec(
            "UPDATE jobs SET status = 'cancelled', cancel_requested = true, finished_ms = $2, "
            "updated_ms = $2, version = version + 1 WHERE id = $1 "
            "RETURNING pg_notify('brisance_jobs', id)",
            pg::Params().add(id).add(now_ms));
        outcome = CancelOutcome::cancelled;
      } else if (status == JobStatus::running) {
        c.exec(
            "UPDATE jobs SET cancel_requested = true, updated_ms = $2, version = version + 1 "
            "WHERE id = $1 AND NOT cancel_requested RETURNING pg_notify('brisance_jobs', id)",
            pg::Params().add(id).add(now_ms));
        outcome = CancelOutcome::requested;
      }
      tx.commit();
      return outcome;
    });
  }

  bool delete_job(std::string_view id) override {
    return owned_update(id, "",
                        "DELETE FROM jobs WHERE id = $1 RETURNING pg_notify('brisance_jobs', id)",
                        pg::Params().add(id));
  }

  PutAsset put_asset(const AssetRecord& asset, std::string_view bytes) override {
    const bool created = pool_.with_connection([&](pg::Connection& c) {
      return c.exec(
                  "INSERT INTO assets (owner, id, format, size_bytes, nodes, created_ms, bytes) "
                  "VALUES ($1, $2, $3, $4, $5, $6, $7) ON CONFLICT (owner, id) DO NOTHING",
                  pg::Params()
                      .add(asset.owner)
                      .add(asset.id)
                      .add(asset.format)
                      .add(asset.size_bytes)
                      .add(asset.nodes_json)
                      .add(asset.created_ms)
                      .add_bytes(std::span<const char>(bytes.data(), bytes.size())))
                 .affected() > 0;
    });
    auto stored = get_asset(asset.id, std::string_view(asset.owner));
    if (!stored) throw StorageError("postgres: asset " + asset.id + " vanished after its insert");
    return {std::move(*stored), created};
  }

  std::optional<AssetRecord> get_asset(std::string_view id,
                                       std::optional<std::string_view> owner) override {
    if (!storable(id) || (owner && !storable(*owner))) return std::nullopt;
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<AssetRecord> {
      const pg::Result r = c.exec(
          "SELECT id, owner, format, size_bytes, nodes, created_ms FROM assets "
          "WHERE id = $1 AND ($2 = 0 OR owner = $3) ORDER BY created_ms, owner LIMIT 1",
          pg::Params().add(id).add(owner ? 1 : 0).add(owner.value_or("")));
      if (r.rows() == 0) return std::nullopt;
      return AssetRecord{std::string(r.text(0, 0)), std::string(r.text(0, 1)),
                         std::string(r.text(0, 2)), r.int64(0, 3),
                         std::string(r.text(0, 4)), r.int64(0, 5)};
    });
  }

  std::optional<std::string> asset_bytes(std::string_view id,
                                         std::optional<std::string_view> owner) override {
    if (!storable(id) || (owner && !storable(*owner))) return std::nullopt;
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<std::string> {
      const pg::Result r = c.exec(
          "SELECT bytes FROM assets WHERE id = $1 AND ($2 = 0 OR owner = $3) "
          "ORDER BY created_ms, owner LIMIT 1",
          pg::Params().add(id).add(owner ? 1 : 0).add(owner.value_or("")));
      if (r.rows() == 0) return std::nullopt;
      const std::vector<char> bytes = r.bytes<char>(0, 0);
      return std::string(bytes.begin(), bytes.end());
    });
  }

  std::optional<std::string> scene(std::string_view id) override {
    return text_column("SELECT scene FROM jobs WHERE id = $1", id);
  }

  std::optional<std::string> result_summary(std::string_view id) override {
    return text_column("SELECT result_summary FROM jobs WHERE id = $1 AND status = 'succeeded'",
                       id);
  }

  std::optional<std::string> result_blob(std::string_view id) override {
    return text_column(
        "SELECT coalesce(result_blob, '') FROM jobs WHERE id = $1 AND status = 'succeeded'", id);
  }

  std::vector<std::string> blob_references() override {
    return pool_.with_connection([](pg::Connection& c) {
      const pg::Result r =
          c.exec("SELECT DISTINCT result_blob FROM jobs WHERE result_blob IS NOT NULL");
      std::vector<std::string> digests;
      for (int row = 0; row < r.rows(); ++row)
        digests.emplace_back(r.text(row, 0));
      return digests;
    });
  }

  std::vector<StoredBody> result_bodies(std::string_view id) override {
    if (!storable(id)) return {};
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r = c.exec(
          "SELECT b.name, b.mass_kg, b.animated, b.initial_pose, b.vertices, b.triangles "
          "FROM job_bodies b JOIN jobs j ON j.seq = b.job_seq WHERE j.id = $1 "
          "ORDER BY b.body_index",
          pg::Params().add(id));
      std::vector<StoredBody> bodies;
      for (int row = 0; row < r.rows(); ++row) {
        StoredBody b;
        b.name = std::string(r.text(row, 0));
        b.mass_kg = r.real(row, 1);
        b.animated = r.boolean(row, 2);
        const auto pose = r.bytes<double>(row, 3);
        std::copy_n(pose.begin(), std::min<std::size_t>(pose.size(), 7), b.initial_pose.begin());
        b.vertices = r.bytes<float>(row, 4);
        b.triangles = r.bytes<std::uint32_t>(row, 5);
        bodies.push_back(std::move(b));
      }
      return bodies;
    });
  }

  std::optional<std::string> result_encoded(std::string_view id) override {
    if (!storable(id)) return std::nullopt;
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<std::string> {
      const pg::Result r = c.exec(
          "SELECT r.data FROM job_results r JOIN jobs j ON j.seq = r.job_seq "
          "WHERE j.id = $1 AND j.status = 'succeeded'",
          pg::Params().add(id));
      if (r.rows() == 0) return std::nullopt;
      const std::vector<char> bytes = r.bytes<char>(0, 0);
      return std::string(bytes.begin(), bytes.end());
    });
  }

  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                         std::int64_t to) override {
    if (!storable(id)) return {};
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r = c.exec(
          "SELECT f.time_s, f.poses FROM job_frames f JOIN jobs j ON j.seq = f.job_seq "
          "WHERE j.id = $1 AND f.frame >= $2 AND f.frame < $3 ORDER BY f.frame",
          pg::Params()
              .add(id)
              .add(std::clamp<std::int64_t>(from, 0, INT32_MAX))
              .add(std::clamp<std::int64_t>(to, 0, INT32_MAX)));
      std::vector<StoredFrame> frames;
      frames.reserve(static_cast<std::size_t>(r.rows()));
      for (int row = 0; row < r.rows(); ++row)
        frames.push_back({r.real(row, 0), r.bytes<float>(row, 1)});
      return frames;
    });
  }

  // Every node's keeper runs this every few seconds: rows another keeper (or a worker finishing
  // its job) holds are skipped, not waited on, so keepers never wait on or deadlock with each
  // other; the next tick takes what was skipped.
  RecoveryReport recover_expired(std::int64_t now_ms, int max_attempts) override {
    return pool_.with_connection([&](pg::Connection& c) {
      pg::Transaction tx(c);
      RecoveryReport report;
      report.failed =
          c.exec(
               "UPDATE jobs SET status = 'failed', finished_ms = $1, updated_ms = $1, "
               "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, "
               "error_type = 'worker_lost', error = 'the worker running this job stopped "
               "(crashed or was killed) ' || attempts || ' times; the job is not retried again' "
               "WHERE status = 'running' AND seq IN (SELECT seq FROM jobs "
               "WHERE status = 'running' AND lease_expires_ms < $1 AND attempts >= $2 "
               "FOR UPDATE SKIP LOCKED) "
               "RETURNING pg_notify('brisance_jobs', id)",
               pg::Params().add(now_ms).add(max_attempts))
              .rows();
      // A job whose cancel was requested is not run again.
      report.requeued =
          c.exec(
               "UPDATE jobs SET status = CASE WHEN cancel_requested THEN 'cancelled' ELSE "
               "'queued' END, finished_ms = CASE WHEN cancel_requested THEN $1::bigint END, "
               "progress = 0, started_ms = NULL, updated_ms = $1, version = version + 1, "
               "lease_owner = NULL, lease_expires_ms = NULL "
               "WHERE status = 'running' AND seq IN (SELECT seq FROM jobs "
               "WHERE status = 'running' AND lease_expires_ms < $1 FOR UPDATE SKIP LOCKED) "
               "RETURNING pg_notify('brisance_jobs', id), pg_notify('brisance_queue', '')",
               pg::Params().add(now_ms))
              .rows();
      tx.commit();
      return report;
    });
  }

  std::vector<std::string> running_owners() override {
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r = c.exec(
          "SELECT DISTINCT lease_owner FROM jobs WHERE status = 'running' "
          "AND lease_owner IS NOT NULL ORDER BY lease_owner");
      std::vector<std::string> owners;
      for (int row = 0; row < r.rows(); ++row)
        owners.emplace_back(r.text(row, 0));
      return owners;
    });
  }

  std::int64_t expire_leases(std::string_view owner) override {
    if (!storable(owner)) return 0;
    return pool_.with_connection([&](pg::Connection& c) {
      return c
          .exec(
              "UPDATE jobs SET lease_expires_ms = 0 WHERE status = 'running' AND lease_owner = $1",
              pg::Params().add(owner))
          .affected();
    });
  }

  std::optional<JobRecord> claim_callback(std::int64_t now_ms, std::int64_t lease_ms) override {
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<JobRecord> {
      // SKIP LOCKED: senders on other nodes take other deliveries instead of waiting.
      const pg::Result r = c.exec(
          "UPDATE jobs SET callback_next_ms = $2 WHERE seq = (SELECT seq FROM jobs WHERE "
          "callback_state = 'pending' AND status IN ('succeeded', 'failed', 'cancelled') AND "
          "callback_next_ms <= $1 ORDER BY callback_next_ms LIMIT 1 FOR UPDATE SKIP LOCKED) "
          "RETURNING " JOB_COLUMNS,
          pg::Params().add(now_ms).add(now_ms + lease_ms));
      if (r.rows() == 0) return std::nullopt;
      return read_job(r, 0);
    });
  }

  bool record_callback(std::string_view id, std::string_view deliveries_json,
                       std::string_view state, std::int64_t next_ms, std::int64_t now_ms) override {
    if (!storable(id)) return false;
    return pool_.with_connection([&](pg::Connection& c) {
      return c.exec(
                  "UPDATE jobs SET callback_deliveries = $2, callback_state = $3, "
                  "callback_next_ms = $4, version = version + 1, updated_ms = $5 WHERE id = $1 "
                  "RETURNING pg_notify('brisance_jobs', id)",
                  pg::Params().add(id).add(deliveries_json).add(state).add(next_ms).add(now_ms))
                 .rows() > 0;
    });
  }

  std::int64_t prune_finished(std::int64_t before_ms) override {
    return pool_.with_connection([&](pg::Connection& c) {
      return c
          .exec(
              "DELETE FROM jobs WHERE finished_ms < $1 AND status IN ('succeeded', 'failed', "
              "'cancelled')",
              pg::Params().add(before_ms))
          .affected();
    });
  }

  bool ping() override {
    try {
      return pool_.with_connection(
          [](pg::Connection& c) { return c.exec("SELECT 1").int64(0, 0) == 1; });
    } catch (const StorageError&) {
      return false;
    }
  }

  void watch(JobChanged job_changed, WorkQueued work_queued) override {
    // Waits for a dispatch in progress, so the old callbacks are not called after this returns.
    std::lock_guard dispatching(dispatch_mutex_);
    job_changed_ = std::move(job_changed);
    work_queued_ = std::move(work_queued);
    if (!listener_ && (job_changed_ || work_queued_)) {
      listener_ = std::make_unique<pg::Listener>(
          pg::PoolOptions{options_.conninfo, options_.first_backoff, options_.max_backoff},
          std::vector<std::string>{"brisance_jobs", "brisance_queue"},
          [this](const pg::Notification& n) { dispatch(n); },
          [this] {
            dispatch({"brisance_queue", ""});
          });
    }
  }

 private:
  void run_batch(const std::vector<PendingCreate*>& batch) {
    if (batch.size() > 1) {
      try {
        std::vector<CreateResult> results;
        pool_.with_connection([&](pg::Connection& c) {
          results.clear();
          pg::Transaction tx(c);
          for (const PendingCreate* p : batch)
            results.push_back(create_one(c, *p->job));
          tx.commit();
          return 0;
        });
        for (std::size_t i = 0; i < batch.size(); ++i)
          batch[i]->result = std::move(results[i]);
        return;
      } catch (const StorageError&) {
        // A failed statement aborts PostgreSQL's whole transaction (unlike SQLite's): nothing
        // of the batch was committed, so each job runs alone and only its own failure is its.
      }
    }
    for (PendingCreate* p : batch) {
      try {
        p->result =
            pool_.with_connection([&](pg::Connection& c) { return create_one(c, *p->job); });
      } catch (const StorageError&) {
        p->error = std::current_exception();
      }
    }
  }

  // One submission on `c` (in the batch's transaction, or alone).
  static CreateResult create_one(pg::Connection& c, const NewJob& job) {
    // Idempotency keys are the owner's own (as on SQLite): the owner's name prefixes the key.
    const std::string scoped_key = storable_key(
        job.owner.empty() ? job.idempotency_key : job.owner + "\n" + job.idempotency_key);
    auto existing = [&]() -> std::optional<CreateResult> {
      const pg::Result r =
          c.exec("SELECT " JOB_COLUMNS ", request_hash FROM jobs WHERE idempotency_key = $1",
                 pg::Params().add(scoped_key));
      if (r.rows() == 0) return std::nullopt;
      CreateResult found{CreateOutcome::existing, read_job(r, 0)};
      if (r.text(0, kJobColumnCount) != job.request_hash) {
        found.outcome = CreateOutcome::key_conflict;
      }
      return found;
    };
    if (!job.idempotency_key.empty()) {
      if (auto found = existing()) return *found;
    }
    if (!job.create_if_missing) return {CreateOutcome::not_created, {}};
    pg::Params params;
    params.add(job.id).add(job.priority).add(job.scene_json).add(job.now_ms);
    if (job.idempotency_key.empty()) {
      params.add_null().add_null();
    } else {
      params.add(scoped_key).add(job.request_hash);
    }
    params.add(job.owner).add(job.name).add(job.labels_json).add(job.callback_url);
    params.add(initial_callback_state(job));
    // Another node may insert the same key between the look-up and here: ON CONFLICT waits
    // for its commit and inserts nothing, and the look-up then finds that job.
    const pg::Result r = c.exec(
        "WITH inserted AS (INSERT INTO jobs (id, status, priority, scene, created_ms, "
        "updated_ms, idempotency_key, request_hash, owner, name, labels, callback_url, "
        "callback_state) VALUES ($1, 'queued', $2, $3, $4, $4, $5, $6, $7, $8, $9, $10, $11) "
        "ON CONFLICT (idempotency_key) DO NOTHING RETURNING seq) "
        "SELECT seq, pg_notify('brisance_queue', '') FROM inserted",
        params);
    if (r.rows() == 0) {
      if (auto found = existing()) return *found;
      throw StorageError("postgres: idempotency key conflict on a job that vanished");
    }
    return {CreateOutcome::created, created_record(job, r.int64(0, 0))};
  }

  // One conditional UPDATE/DELETE of job `id` (held by `owner`): true when it touched a row.
  bool owned_update(std::string_view id, std::string_view owner, const char* sql,
                    const pg::Params& params) {
    if (!storable(id) || !storable(owner)) return false;
    return pool_.with_connection([&](pg::Connection& c) {
      const pg::Result r = c.exec(sql, params);
      return r.affected() > 0;
    });
  }

  std::optional<std::string> text_column(const char* sql, std::string_view id) {
    if (!storable(id)) return std::nullopt;
    return pool_.with_connection([&](pg::Connection& c) -> std::optional<std::string> {
      const pg::Result r = c.exec(sql, pg::Params().add(id));
      if (r.rows() == 0) return std::nullopt;
      return std::string(r.text(0, 0));
    });
  }

  // Under a session advisory lock: the first node to start migrates, the others wait for it.
  static void migrate(pg::Connection& c) {
    c.exec(kMigrationLock);
    try {
      c.exec(
          "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, "
          "name TEXT NOT NULL, applied_ms BIGINT NOT NULL)");
      for (const EmbeddedFile& m : embedded_pg_migrations()) {
        const int version = std::stoi(std::string(m.name.substr(0, 3)));
        pg::Transaction tx(c);
        if (c.exec("SELECT 1 FROM schema_migrations WHERE version = $1", pg::Params().add(version))
                .rows() > 0) {
          continue;
        }
        c.exec(std::string(m.data).c_str());
        c.exec(
            "INSERT INTO schema_migrations (version, name, applied_ms) VALUES ($1, $2, "
            "(extract(epoch FROM clock_timestamp()) * 1000)::bigint)",
            pg::Params().add(version).add(m.name));
        tx.commit();
      }
    } catch (const StorageError&) {
      if (c.ok()) c.exec(kMigrationUnlock);
      throw;
    }
    c.exec(kMigrationUnlock);
  }

  void dispatch(const pg::Notification& n) {
    std::lock_guard dispatching(dispatch_mutex_);
    if (n.channel == "brisance_jobs" && job_changed_) {
      job_changed_(n.payload);
    } else if (n.channel == "brisance_queue" && work_queued_) {
      work_queued_();
    }
  }

  PostgresOptions options_;
  pg::Pool pool_;
  GroupCommit group_;

  std::mutex dispatch_mutex_;  // held while the callbacks run, and while they are replaced
  JobChanged job_changed_;
  WorkQueued work_queued_;
  std::unique_ptr<pg::Listener> listener_;  // started by the first watch() with a callback
};

}  // namespace

std::unique_ptr<Storage> open_postgres_storage(const PostgresOptions& options) {
  return std::make_unique<PgStorage>(options);
}

int postgres_schema_version() {
  int version = 0;
  for (const EmbeddedFile& m : embedded_pg_migrations())
    version = std::max(version, std::stoi(std::string(m.name.substr(0, 3))));
  return version;
}

}  // namespace brisance::server
