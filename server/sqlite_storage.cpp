#include "server/sqlite_storage.hpp"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <span>
#include <utility>

#include "server/embedded.hpp"
#include "server/group_commit.hpp"
#include "server/sqlite.hpp"

namespace brisance::server {

namespace {

using sqlite::Connection;
using sqlite::Statement;
using sqlite::Transaction;

JobRecord read_job(const Statement& s) {
  JobRecord j;
  j.id = s.text(0);
  j.seq = s.int64(1);
  j.status = parse_job_status(s.text(2)).value_or(JobStatus::queued);
  j.priority = static_cast<int>(s.int64(3));
  j.progress = s.real(4);
  j.version = s.int64(5);
  j.attempts = static_cast<int>(s.int64(6));
  j.cancel_requested = s.int64(7) != 0;
  j.created_ms = s.int64(8);
  j.updated_ms = s.int64(9);
  if (!s.is_null(10)) j.started_ms = s.int64(10);
  if (!s.is_null(11)) j.finished_ms = s.int64(11);
  j.error_type = s.text(12);
  j.error = s.text(13);
  j.stats_json = s.text(14);
  j.owner = s.text(15);
  j.name = s.text(16);
  j.labels_json = s.text(17);
  j.callback_url = s.text(18);
  j.callback_state = s.text(19);
  j.callback_deliveries_json = s.text(20);
  return j;
}

#define JOB_COLUMNS                                                                        \
  "id, seq, status, priority, progress, version, attempts, cancel_requested, created_ms, " \
  "updated_ms, started_ms, finished_ms, error_type, error, stats, owner, name, labels, "   \
  "callback_url, callback_state, callback_deliveries"

constexpr int kJobColumnCount = 21;

class SqliteStorage final : public Storage {
 public:
  explicit SqliteStorage(SqliteOptions options) : options_(std::move(options)) {
    std::error_code ec;
    if (options_.file.has_parent_path()) {
      std::filesystem::create_directories(options_.file.parent_path(), ec);
      if (ec) {
        throw StorageError("cannot create directory " + options_.file.parent_path().string() +
                           ": " + ec.message());
      }
    }
    auto lease = acquire();
    migrate(*lease);
  }

  // Group commit (server/group_commit.hpp): concurrent submissions share one transaction.
  CreateResult create_job(const NewJob& job) override {
    return group_.submit(job,
                         [this](const std::vector<PendingCreate*>& batch) { run_batch(batch); });
  }

  std::optional<JobRecord> get_job(std::string_view id) override {
    auto c = acquire();
    return read_by_id(*c, id);
  }

  JobPage list_jobs(const JobFilter& filter, std::int64_t before_seq, int limit) override {
    auto c = acquire();
    // The owner's jobs use the (owner, seq) index, the others the primary key; labels and names
    // are checked on the rows walked in seq order.
    std::string sql = "SELECT " JOB_COLUMNS " FROM jobs WHERE seq < ?";
    if (filter.owner) sql += " AND owner = ?";
    if (filter.status) sql += " AND status = ?";
    // One text for either kind of selector, so the statements cached stay few.
    for (std::size_t i = 0; i < filter.labels.size(); ++i)
      sql += " AND json_type(labels, ?) IS NOT NULL AND (? IS NULL OR json_extract(labels, ?) = ?)";
    if (!filter.name_contains.empty()) sql += " AND instr(lower(name), lower(?)) > 0";
    sql += " ORDER BY seq DESC LIMIT ?";
    auto s = c->prepare(sql.c_str());
    int n = 0;
    s.bind(++n, before_seq > 0 ? before_seq : INT64_MAX);
    if (filter.owner) s.bind(++n, *filter.owner);
    if (filter.status) s.bind(++n, to_string(*filter.status));
    for (const LabelSelector& label : filter.labels) {
      const std::string path = "$.\"" + label.key + "\"";
      for (int twice = 0; twice < 2; ++twice) {
        s.bind(++n, path);
        if (label.value) {
          s.bind(++n, *label.value);
        } else {
          s.bind_null(++n);
        }
      }
    }
    if (!filter.name_contains.empty()) s.bind(++n, filter.name_contains);
    s.bind(++n, limit + 1);
    JobPage page;
    while (s.step())
      page.jobs.push_back(read_job(s));
    if (static_cast<int>(page.jobs.size()) > limit) {
      page.jobs.pop_back();
      page.cursor = page.jobs.back().seq;
    }
    return page;
  }

  std::int64_t count_queued() override {
    auto c = acquire();
    auto s = c->prepare("SELECT count(*) FROM jobs WHERE status = 'queued'");
    s.step();
    return s.int64(0);
  }

  QueueCounts queue_counts(std::int64_t now_ms) override {
    auto c = acquire();
    QueueCounts counts;
    Transaction tx(*c, false);
    {
      auto s = c->prepare("SELECT status, count(*) FROM jobs GROUP BY status");
      while (s.step()) {
        if (auto status = parse_job_status(s.text(0))) {
          counts.by_status[static_cast<std::size_t>(*status)] = s.int64(1);
        }
      }
    }
    {
      auto s = c->prepare("SELECT min(created_ms) FROM jobs WHERE status = 'queued'");
      if (s.step() && !s.is_null(0)) counts.oldest_queued_created_ms = s.int64(0);
    }
    {
      auto s = c->prepare(
          "SELECT count(*) FROM jobs WHERE finished_ms >= ? AND status IN ('succeeded', 'failed')");
      s.bind(1, now_ms - 60000);
      s.step();
      counts.finished_last_minute = s.int64(0);
    }
    tx.commit();
    return counts;
  }

  std::optional<ClaimedJob> claim_next(std::string_view owner, std::int64_t now_ms,
                                       std::int64_t lease_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    std::string id;
    {
      auto s = c->prepare(
          "SELECT id FROM jobs INDEXED BY jobs_queue WHERE status = 'queued' "
          "ORDER BY priority DESC, seq LIMIT 1");
      if (!s.step()) return std::nullopt;
      id = s.text(0);
    }
    {
      auto s = c->prepare(
          "UPDATE jobs SET status = 'running', lease_owner = ?, lease_expires_ms = ?, "
          "attempts = attempts + 1, started_ms = ?, updated_ms = ?, progress = 0, "
          "version = version + 1 WHERE id = ?");
      s.bind(1, owner).bind(2, now_ms + lease_ms).bind(3, now_ms).bind(4, now_ms).bind(5, id);
      s.run();
    }
    ClaimedJob claimed;
    {
      auto s = c->prepare("SELECT " JOB_COLUMNS ", scene FROM jobs WHERE id = ?");
      s.bind(1, id);
      s.step();
      claimed.job = read_job(s);
      claimed.scene_json = s.text(kJobColumnCount);
    }
    tx.commit();
    return claimed;
  }

  bool renew_lease(std::string_view id, std::string_view owner, std::int64_t until_ms) override {
    return owned_update(
        "UPDATE jobs SET lease_expires_ms = ? WHERE id = ? AND lease_owner = ? "
        "AND status = 'running'",
        [&](Statement& s) { s.bind(1, until_ms).bind(2, id).bind(3, owner); });
  }

  bool set_progress(std::string_view id, std::string_view owner, double progress,
                    std::int64_t now_ms) override {
    return owned_update(
        "UPDATE jobs SET progress = ?, updated_ms = ?, version = version + 1 "
        "WHERE id = ? AND lease_owner = ? AND status = 'running'",
        [&](Statement& s) { s.bind(1, progress).bind(2, now_ms).bind(3, id).bind(4, owner); });
  }

  bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                std::int64_t now_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    std::int64_t seq = 0;
    {
      auto s = c->prepare(
          "SELECT seq FROM jobs WHERE id = ? AND lease_owner = ? AND status = 'running'");
      s.bind(1, id).bind(2, owner);
      if (!s.step()) return false;
      seq = s.int64(0);
    }
    {
      auto s = c->prepare(
          "INSERT INTO job_bodies (job_seq, body_index, name, mass_kg, animated, initial_pose, "
          "vertices, triangles) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
      for (std::size_t i = 0; i < result.bodies.size(); ++i) {
        const StoredBody& b = result.bodies[i];
        s.bind(1, seq).bind(2, static_cast<std::int64_t>(i)).bind(3, b.name).bind(4, b.mass_kg);
        s.bind(5, b.animated ? 1 : 0);
        s.bind_blob(6, std::span<const double>(b.initial_pose));
        s.bind_blob(7, std::span<const float>(b.vertices));
        s.bind_blob(8, std::span<const std::uint32_t>(b.triangles));
        s.run();
        s.reset();
      }
    }
    if (!result.encoded.empty()) {
      auto s = c->prepare("INSERT INTO job_results (job_seq, data) VALUES (?, ?)");
      s.bind(1, seq).bind_blob(2, std::span<const char>(result.encoded));
      s.run();
    }
    {
      auto s =
          c->prepare("INSERT INTO job_frames (job_seq, frame, time_s, poses) VALUES (?, ?, ?, ?)");
      for (std::size_t f = 0; f < result.frames.size(); ++f) {
        s.bind(1, seq).bind(2, static_cast<std::int64_t>(f)).bind(3, result.frames[f].time_s);
        s.bind_blob(4, std::span<const float>(result.frames[f].poses));
        s.run();
        s.reset();
      }
    }
    {
      auto s = c->prepare(
          "UPDATE jobs SET status = 'succeeded', progress = 1, finished_ms = ?, updated_ms = ?, "
          "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, stats = ?, "
          "result_summary = ?, result_blob = NULLIF(?, '') WHERE seq = ?");
      s.bind(1, now_ms).bind(2, now_ms).bind(3, result.stats_json).bind(4, result.summary_json);
      s.bind(5, result.blob_digest).bind(6, seq);
      s.run();
    }
    tx.commit();
    return true;
  }

  bool fail(std::string_view id, std::string_view owner, std::string_view error_type,
            std::string_view message, std::int64_t now_ms) override {
    return owned_update(
        "UPDATE jobs SET status = 'failed', finished_ms = ?, updated_ms = ?, "
        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, error_type = ?, "
        "error = ? WHERE id = ? AND lease_owner = ? AND status = 'running'",
        [&](Statement& s) {
          s.bind(1, now_ms).bind(2, now_ms).bind(3, error_type).bind(4, message);
          s.bind(5, id).bind(6, owner);
        });
  }

  bool finish_cancelled(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return owned_update(
        "UPDATE jobs SET status = 'cancelled', finished_ms = ?, updated_ms = ?, "
        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL "
        "WHERE id = ? AND lease_owner = ? AND status = 'running'",
        [&](Statement& s) { s.bind(1, now_ms).bind(2, now_ms).bind(3, id).bind(4, owner); });
  }

  bool release(std::string_view id, std::string_view owner, std::int64_t now_ms) override {
    return owned_update(
        "UPDATE jobs SET status = 'queued', progress = 0, started_ms = NULL, updated_ms = ?, "
        "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, "
        "attempts = max(attempts - 1, 0) WHERE id = ? AND lease_owner = ? AND status = 'running'",
        [&](Statement& s) { s.bind(1, now_ms).bind(2, id).bind(3, owner); });
  }

  bool cancel_requested(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare("SELECT cancel_requested FROM jobs WHERE id = ?");
    s.bind(1, id);
    return !s.step() || s.int64(0) != 0;  // a deleted job counts as cancelled
  }

  CancelOutcome request_cancel(std::string_view id, std::int64_t now_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    JobStatus status;
    {
      auto s = c->prepare("SELECT status FROM jobs WHERE id = ?");
      s.bind(1, id);
      if (!s.step()) return CancelOutcome::not_found;
      status = parse_job_status(s.text(0)).value_or(JobStatus::queued);
    }
    CancelOutcome outcome = CancelOutcome::already_final;
    if (status == JobStatus::queued) {
      auto s = c->prepare(
          "UPDATE jobs SET status = 'cancelled', cancel_requested = 1, finished_ms = ?, "
          "updated_ms = ?, version = version + 1 WHERE id = ?");
      s.bind(1, now_ms).bind(2, now_ms).bind(3, id);
      s.run();
      outcome = CancelOutcome::cancelled;
    } else if (status == JobStatus::running) {
      auto s = c->prepare(
          "UPDATE jobs SET cancel_requested = 1, updated_ms = ?, version = version + 1 "
          "WHERE id = ? AND cancel_requested = 0");
      s.bind(1, now_ms).bind(2, id);
      s.run();
      outcome = CancelOutcome::requested;
    }
    tx.commit();
    return outcome;
  }

  bool delete_job(std::string_view id) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    auto s = c->prepare("DELETE FROM jobs WHERE id = ?");
    s.bind(1, id);
    s.run();
    const bool deleted = c->changes() > 0;
    tx.commit();
    return deleted;
  }

  PutAsset put_asset(const AssetRecord& asset, std::string_view bytes) override {
    auto c = acquire();
    bool created = false;
    {
      std::lock_guard write(write_mutex_);
      Transaction tx(*c, true);
      auto s = c->prepare(
          "INSERT INTO assets (owner, id, format, size_bytes, nodes, created_ms, bytes) "
          "VALUES (?, ?, ?, ?, ?, ?, ?) ON CONFLICT (owner, id) DO NOTHING");
      s.bind(1, asset.owner).bind(2, asset.id).bind(3, asset.format);
      s.bind(4, asset.size_bytes).bind(5, asset.nodes_json).bind(6, asset.created_ms);
      s.bind_blob(7, std::span<const char>(bytes.data(), bytes.size()));
      s.run();
      created = c->changes() > 0;
      tx.commit();
    }
    auto stored = get_asset(asset.id, std::string_view(asset.owner));
    if (!stored) throw StorageError("sqlite: asset " + asset.id + " vanished after its insert");
    return {std::move(*stored), created};
  }

  std::optional<AssetRecord> get_asset(std::string_view id,
                                       std::optional<std::string_view> owner) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT id, owner, format, size_bytes, nodes, created_ms FROM assets "
        "WHERE id = ? AND (? = 0 OR owner = ?) ORDER BY created_ms, owner LIMIT 1");
    s.bind(1, id).bind(2, owner ? 1 : 0).bind(3, owner.value_or(""));
    if (!s.step()) return std::nullopt;
    return AssetRecord{s.text(0), s.text(1), s.text(2), s.int64(3), s.text(4), s.int64(5)};
  }

  std::optional<std::string> asset_bytes(std::string_view id,
                                         std::optional<std::string_view> owner) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT bytes FROM assets WHERE id = ? AND (? = 0 OR owner = ?) "
        "ORDER BY created_ms, owner LIMIT 1");
    s.bind(1, id).bind(2, owner ? 1 : 0).bind(3, owner.value_or(""));
    if (!s.step()) return std::nullopt;
    const std::vector<char> bytes = s.blob<char>(0);
    return std::string(bytes.begin(), bytes.end());
  }

  std::optional<std::string> scene(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare("SELECT scene FROM jobs WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return s.text(0);
  }

  std::optional<std::string> result_summary(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare("SELECT result_summary FROM jobs WHERE id = ? AND status = 'succeeded'");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return s.text(0);
  }

  std::optional<std::string> result_blob(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT coalesce(result_blob, '') FROM jobs WHERE id = ? AND status = 'succeeded'");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return s.text(0);
  }

  std::vector<std::string> blob_references() override {
    auto c = acquire();
    auto s = c->prepare("SELECT DISTINCT result_blob FROM jobs WHERE result_blob IS NOT NULL");
    std::vector<std::string> digests;
    while (s.step())
      digests.push_back(s.text(0));
    return digests;
  }

  std::vector<StoredBody> result_bodies(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT b.name, b.mass_kg, b.animated, b.initial_pose, b.vertices, b.triangles "
        "FROM job_bodies b JOIN jobs j ON j.seq = b.job_seq WHERE j.id = ? "
        "ORDER BY b.body_index");
    s.bind(1, id);
    std::vector<StoredBody> bodies;
    while (s.step()) {
      StoredBody b;
      b.name = s.text(0);
      b.mass_kg = s.real(1);
      b.animated = s.int64(2) != 0;
      const auto pose = s.blob<double>(3);
      std::copy_n(pose.begin(), std::min<std::size_t>(pose.size(), 7), b.initial_pose.begin());
      b.vertices = s.blob<float>(4);
      b.triangles = s.blob<std::uint32_t>(5);
      bodies.push_back(std::move(b));
    }
    return bodies;
  }

  std::optional<std::string> result_encoded(std::string_view id) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT r.data FROM job_results r JOIN jobs j ON j.seq = r.job_seq "
        "WHERE j.id = ? AND j.status = 'succeeded'");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    const std::vector<char> bytes = s.blob<char>(0);
    return std::string(bytes.begin(), bytes.end());
  }

  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                         std::int64_t to) override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT f.time_s, f.poses FROM job_frames f JOIN jobs j ON j.seq = f.job_seq "
        "WHERE j.id = ? AND f.frame >= ? AND f.frame < ? ORDER BY f.frame");
    s.bind(1, id).bind(2, from).bind(3, to);
    std::vector<StoredFrame> frames;
    while (s.step())
      frames.push_back({s.real(0), s.blob<float>(1)});
    return frames;
  }

  RecoveryReport recover_expired(std::int64_t now_ms, int max_attempts) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    RecoveryReport report;
    {
      auto s = c->prepare(
          "UPDATE jobs SET status = 'failed', finished_ms = ?, updated_ms = ?, "
          "version = version + 1, lease_owner = NULL, lease_expires_ms = NULL, "
          "error_type = 'worker_lost', error = 'the worker running this job stopped (crashed or "
          "was killed) ' || attempts || ' times; the job is not retried again' "
          "WHERE status = 'running' AND lease_expires_ms < ? AND attempts >= ?");
      s.bind(1, now_ms).bind(2, now_ms).bind(3, now_ms).bind(4, max_attempts);
      s.run();
      report.failed = c->changes();
    }
    {
      // A job whose cancel was requested is not run again.
      auto s = c->prepare(
          "UPDATE jobs SET status = CASE cancel_requested WHEN 1 THEN 'cancelled' ELSE 'queued' "
          "END, finished_ms = CASE cancel_requested WHEN 1 THEN ? ELSE NULL END, "
          "progress = 0, started_ms = NULL, updated_ms = ?, version = version + 1, "
          "lease_owner = NULL, lease_expires_ms = NULL "
          "WHERE status = 'running' AND lease_expires_ms < ?");
      s.bind(1, now_ms).bind(2, now_ms).bind(3, now_ms);
      s.run();
      report.requeued = c->changes();
    }
    tx.commit();
    return report;
  }

  std::vector<std::string> running_owners() override {
    auto c = acquire();
    auto s = c->prepare(
        "SELECT DISTINCT lease_owner FROM jobs WHERE status = 'running' AND lease_owner IS NOT "
        "NULL");
    std::vector<std::string> owners;
    while (s.step())
      owners.push_back(s.text(0));
    return owners;
  }

  std::int64_t expire_leases(std::string_view owner) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    auto s = c->prepare(
        "UPDATE jobs SET lease_expires_ms = 0 WHERE status = 'running' AND lease_owner = ?");
    s.bind(1, owner);
    s.run();
    const std::int64_t n = c->changes();
    tx.commit();
    return n;
  }

  std::optional<JobRecord> claim_callback(std::int64_t now_ms, std::int64_t lease_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    std::optional<JobRecord> job;
    {
      auto s = c->prepare("SELECT " JOB_COLUMNS
                          " FROM jobs WHERE callback_state = 'pending' AND status IN "
                          "('succeeded', 'failed', 'cancelled') AND callback_next_ms <= ? "
                          "ORDER BY callback_next_ms LIMIT 1");
      s.bind(1, now_ms);
      if (!s.step()) return std::nullopt;
      job = read_job(s);
    }
    auto s = c->prepare("UPDATE jobs SET callback_next_ms = ? WHERE id = ?");
    s.bind(1, now_ms + lease_ms).bind(2, job->id);
    s.run();
    tx.commit();
    return job;
  }

  bool record_callback(std::string_view id, std::string_view deliveries_json,
                       std::string_view state, std::int64_t next_ms, std::int64_t now_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    auto s = c->prepare(
        "UPDATE jobs SET callback_deliveries = ?, callback_state = ?, callback_next_ms = ?, "
        "version = version + 1, updated_ms = ? WHERE id = ?");
    s.bind(1, deliveries_json).bind(2, state).bind(3, next_ms).bind(4, now_ms).bind(5, id);
    s.run();
    const bool found = c->changes() > 0;
    tx.commit();
    return found;
  }

  std::int64_t prune_finished(std::int64_t before_ms) override {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    auto s = c->prepare(
        "DELETE FROM jobs WHERE finished_ms < ? AND status IN ('succeeded', 'failed', "
        "'cancelled')");
    s.bind(1, before_ms);
    s.run();
    const std::int64_t n = c->changes();
    tx.commit();
    return n;
  }

  bool ping() override {
    try {
      auto c = acquire();
      auto s = c->prepare("SELECT 1");
      return s.step() && s.int64(0) == 1;
    } catch (const StorageError&) {
      return false;
    }
  }

 private:
  // A pooled connection, returned on destruction.
  class Lease {
   public:
    Lease(SqliteStorage& owner, std::unique_ptr<Connection> c) : owner_(owner), c_(std::move(c)) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() {
      std::lock_guard lock(owner_.pool_mutex_);
      owner_.pool_.push_back(std::move(c_));
    }
    Connection* operator->() { return c_.get(); }
    Connection& operator*() { return *c_; }

   private:
    SqliteStorage& owner_;
    std::unique_ptr<Connection> c_;
  };

  Lease acquire() {
    {
      std::lock_guard lock(pool_mutex_);
      if (!pool_.empty()) {
        auto c = std::move(pool_.back());
        pool_.pop_back();
        return Lease(*this, std::move(c));
      }
    }
    return Lease(*this, std::make_unique<Connection>(options_.file, options_));
  }

  void run_batch(const std::vector<PendingCreate*>& batch) {
    try {
      auto c = acquire();
      std::lock_guard write(write_mutex_);
      Transaction tx(*c, true);
      for (PendingCreate* p : batch) {
        try {
          p->result = create_one(*c, *p->job);
        } catch (const StorageError&) {
          // A failed statement rolls back only itself; the rest of the batch goes on.
          p->error = std::current_exception();
        }
      }
      tx.commit();
    } catch (const StorageError&) {
      for (PendingCreate* p : batch) {
        if (!p->error) p->error = std::current_exception();
      }
    }
  }

  CreateResult create_one(Connection& c, const NewJob& job) {
    // Idempotency keys are the owner's own: two clients may use the same key for different jobs.
    // The column is unique, so the owner's name (keys cannot contain a line feed) prefixes it.
    const std::string scoped_key =
        job.owner.empty() ? job.idempotency_key : job.owner + "\n" + job.idempotency_key;
    if (!job.idempotency_key.empty()) {
      auto s =
          c.prepare("SELECT " JOB_COLUMNS ", request_hash FROM jobs WHERE idempotency_key = ?");
      s.bind(1, scoped_key);
      if (s.step()) {
        CreateResult existing{CreateOutcome::existing, read_job(s)};
        if (s.text(kJobColumnCount) != job.request_hash)
          existing.outcome = CreateOutcome::key_conflict;
        return existing;
      }
    }
    if (!job.create_if_missing) return {CreateOutcome::not_created, {}};
    auto s = c.prepare(
        "INSERT INTO jobs (id, status, priority, scene, created_ms, updated_ms, "
        "idempotency_key, request_hash, owner, name, labels, callback_url, callback_state) "
        "VALUES (?, 'queued', ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    s.bind(1, job.id).bind(2, job.priority).bind(3, job.scene_json);
    s.bind(4, job.now_ms).bind(5, job.now_ms);
    if (job.idempotency_key.empty()) {
      s.bind_null(6).bind_null(7);
    } else {
      s.bind(6, scoped_key).bind(7, job.request_hash);
    }
    s.bind(8, job.owner).bind(9, job.name).bind(10, job.labels_json);
    s.bind(11, job.callback_url).bind(12, initial_callback_state(job));
    s.run();
    return {CreateOutcome::created, created_record(job, c.last_insert_rowid())};
  }

  std::optional<JobRecord> read_by_id(Connection& c, std::string_view id) {
    auto s = c.prepare("SELECT " JOB_COLUMNS " FROM jobs WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return read_job(s);
  }

  template <typename Bind>
  bool owned_update(const char* sql, Bind bind) {
    auto c = acquire();
    std::lock_guard write(write_mutex_);
    Transaction tx(*c, true);
    auto s = c->prepare(sql);
    bind(s);
    s.run();
    const bool changed = c->changes() > 0;
    tx.commit();
    return changed;
  }

  void migrate(Connection& c) {
    std::lock_guard write(write_mutex_);
    c.exec(
        "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, "
        "name TEXT NOT NULL, applied_ms INTEGER NOT NULL)");
    for (const EmbeddedFile& m : embedded_migrations()) {
      const int version = std::stoi(std::string(m.name.substr(0, 3)));
      Transaction tx(c, true);
      {
        auto s = c.prepare("SELECT 1 FROM schema_migrations WHERE version = ?");
        s.bind(1, version);
        if (s.step()) continue;
      }
      c.exec(std::string(m.data).c_str());
      {
        auto s = c.prepare(
            "INSERT INTO schema_migrations (version, name, applied_ms) "
            "VALUES (?, ?, CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER))");
        s.bind(1, version).bind(2, m.name);
        s.run();
      }
      tx.commit();
    }
  }

  SqliteOptions options_;
  std::mutex write_mutex_;
  std::mutex pool_mutex_;
  GroupCommit group_;
  std::vector<std::unique_ptr<Connection>> pool_;
};

}  // namespace

std::unique_ptr<Storage> open_sqlite_storage(const SqliteOptions& options) {
  return std::make_unique<SqliteStorage>(options);
}

int sqlite_schema_version() {
  int version = 0;
  for (const EmbeddedFile& m : embedded_migrations()) {
    version = std::max(version, std::stoi(std::string(m.name.substr(0, 3))));
  }
  return version;
}

}  // namespace brisance::server
