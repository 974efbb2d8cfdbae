// server/storage: the durable job queue and result store behind an interface, so the SQLite back
// end (server/sqlite_storage) and a PostgreSQL one can be swapped without touching the services.
//
// Every method is one transaction. A job moves queued → running → succeeded | failed | cancelled;
// a running job is held by a lease (owner + expiry) that its worker renews, and every write a
// worker makes is conditional on still holding the lease, so a job that was requeued after its
// worker died can complete only once.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace brisance::server {

enum class JobStatus { queued, running, succeeded, failed, cancelled };

std::string_view to_string(JobStatus status);
std::optional<JobStatus> parse_job_status(std::string_view text);
inline bool is_final(JobStatus status) {
  return status == JobStatus::succeeded || status == JobStatus::failed ||
         status == JobStatus::cancelled;
}

// Storage failed (disk full, database locked beyond the busy timeout, corrupt file). The message
// is for logs only; clients see a generic problem.
struct StorageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct JobRecord {
  std::string id;
  std::int64_t seq = 0;  // insertion order; the pagination cursor
  JobStatus status = JobStatus::queued;
  int priority = 0;
  double progress = 0.0;
  std::int64_t version = 1;  // bumped by every change: the ETag
  int attempts = 0;          // times a worker claimed it
  bool cancel_requested = false;
  std::int64_t created_ms = 0;
  std::int64_t updated_ms = 0;
  std::optional<std::int64_t> started_ms;
  std::optional<std::int64_t> finished_ms;
  std::string error_type;          // stable code, empty unless failed
  std::string error;               // message for the client, empty unless failed
  std::string stats_json;          // the result's `stats` object once succeeded, else empty
  std::string owner;               // the API key that submitted it; empty when keys are off
  std::string name;                // given at submission; empty when none
  std::string labels_json = "{}";  // given at submission: a flat object of strings, compact
  // Told when the job ends (server/callbacks): the URL ('' none), the delivery state ('' none,
  // pending, delivered, failed) and the attempts so far as a JSON array.
  std::string callback_url;
  std::string callback_state;
  std::string callback_deliveries_json = "[]";
};

struct NewJob {
  std::string id;
  std::string scene_json;  // validated scene, as compact JSON
  int priority = 0;
  std::string owner;               // the submitting API key's name; empty when keys are off
  std::string name;                // free text, validated by the service
  std::string labels_json = "{}";  // a flat object of strings, compact, validated by the service
  std::string callback_url;        // '' none; else delivered once the job ends
  std::string idempotency_key;     // empty: none; scoped to the owner
  std::string request_hash;        // hash of the request body, for the idempotency check
  std::int64_t now_ms = 0;
  bool create_if_missing = true;  // false: only look the idempotency key up (queue full)
};

// A new job's callback state: pending when it names a URL, else none.
inline std::string_view initial_callback_state(const NewJob& job) {
  return job.callback_url.empty() ? "" : "pending";
}

// The row create_job inserts for `job`, as a JobRecord, without reading it back.
inline JobRecord created_record(const NewJob& job, std::int64_t seq) {
  JobRecord created;
  created.id = job.id;
  created.seq = seq;
  created.priority = job.priority;
  created.created_ms = job.now_ms;
  created.updated_ms = job.now_ms;
  created.owner = job.owner;
  created.name = job.name;
  created.labels_json = job.labels_json;
  created.callback_url = job.callback_url;
  created.callback_state = std::string(initial_callback_state(job));
  return created;
}

enum class CreateOutcome { created, existing, key_conflict, not_created };
struct CreateResult {
  CreateOutcome outcome = CreateOutcome::created;
  JobRecord job;  // the new job, or the one the idempotency key already names
};

// A label selector of `GET /v1/jobs?label=`: the key is present (no value) or has that value.
// Keys are letters, digits and "_.-/" only (the service checks), so stores may quote them.
struct LabelSelector {
  std::string key;
  std::optional<std::string> value;
};

// What a job list shows: every given condition holds.
struct JobFilter {
  std::optional<JobStatus> status;
  std::optional<std::string> owner;  // only this API key's jobs
  std::vector<LabelSelector> labels;
  std::string name_contains;  // a substring of the name, ASCII case ignored; empty: any
};

struct JobPage {
  std::vector<JobRecord> jobs;         // newest first
  std::optional<std::int64_t> cursor;  // pass back as `before_seq` for the next page
};

struct ClaimedJob {
  JobRecord job;
  std::string scene_json;
};

// One body of a stored result; the mesh is stored once per body.
struct StoredBody {
  std::string name;
  double mass_kg = 0.0;
  bool animated = false;
  std::array<double, 7> initial_pose{};  // x, y, z, qx, qy, qz, qw
  std::vector<float> vertices;           // x, y, z per vertex, shape frame
  std::vector<std::uint32_t> triangles;  // three indices per triangle
};

// A frame: its time and, per animated body in `animated` order, x y z qx qy qz qw as float32.
struct StoredFrame {
  double time_s = 0.0;
  std::vector<float> poses;
};

struct StoredResult {
  std::string summary_json;  // bodies (without meshes), final_state, stats, warnings
  std::string stats_json;
  std::vector<StoredBody> bodies;
  std::vector<StoredFrame> frames;
  // Non-empty: the bodies and frames are in the blob store (server/blob_store) under this SHA-256
  // (64 hex digits) and `bodies` and `frames` are empty; the job row keeps only the digest.
  std::string blob_digest;
  // Non-empty: the bodies and frames as one compact byte string (server/compact_result), stored
  // as one row of job_results; `bodies` and `frames` are then empty.
  std::string encoded;
};

// Results stored by this process since it started, and their encoded size in bytes.
struct StoredResultTotals {
  std::uint64_t results = 0;
  std::uint64_t bytes = 0;
};

struct QueueCounts {
  std::array<std::int64_t, 5> by_status{};  // indexed by JobStatus
  std::optional<std::int64_t> oldest_queued_created_ms;
  std::int64_t finished_last_minute = 0;  // succeeded or failed in the last 60 s
};

// An uploaded mesh file (POST /v1/assets) that scenes name with {"type": "asset"}. Its id is
// the SHA-256 of its bytes, so uploading the same file twice gives the same asset; like jobs,
// an asset belongs to the API key that uploaded it.
struct AssetRecord {
  std::string id;      // 64 hex digits: SHA-256 of the bytes
  std::string owner;   // the uploading API key's name; empty when keys are off
  std::string format;  // "glb", "gltf" or "obj"
  std::int64_t size_bytes = 0;
  std::string nodes_json;  // JSON array of the names of the nodes with meshes
  std::int64_t created_ms = 0;
};

enum class CancelOutcome { not_found, cancelled, requested, already_final };

struct RecoveryReport {
  std::int64_t requeued = 0;
  std::int64_t failed = 0;
  std::int64_t expired_here = 0;  // leases of dead processes on this host ended first
};

class Storage {
 public:
  virtual ~Storage() = default;

  // Inserts the job, or returns the job its idempotency key names (key_conflict if that job was
  // created from a different request body).
  virtual CreateResult create_job(const NewJob& job) = 0;
  virtual std::optional<JobRecord> get_job(std::string_view id) = 0;
  // Newest first; `before_seq` 0 starts at the newest.
  virtual JobPage list_jobs(const JobFilter& filter, std::int64_t before_seq, int limit) = 0;
  virtual std::int64_t count_queued() = 0;
  virtual QueueCounts queue_counts(std::int64_t now_ms) = 0;

  // Worker side. claim_next takes the queued job of highest priority (oldest first), marks it
  // running under `owner` until now + lease and counts the attempt.
  virtual std::optional<ClaimedJob> claim_next(std::string_view owner, std::int64_t now_ms,
                                               std::int64_t lease_ms) = 0;
  // The following return false when the job is no longer running under `owner` (deleted,
  // requeued after a lost lease); the worker then drops it.
  virtual bool renew_lease(std::string_view id, std::string_view owner, std::int64_t until_ms) = 0;
  virtual bool set_progress(std::string_view id, std::string_view owner, double progress,
                            std::int64_t now_ms) = 0;
  virtual bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                        std::int64_t now_ms) = 0;
  virtual bool fail(std::string_view id, std::string_view owner, std::string_view error_type,
                    std::string_view message, std::int64_t now_ms) = 0;
  virtual bool finish_cancelled(std::string_view id, std::string_view owner,
                                std::int64_t now_ms) = 0;
  // Back to the queue without counting the attempt (graceful shutdown).
  virtual bool release(std::string_view id, std::string_view owner, std::int64_t now_ms) = 0;
  virtual bool cancel_requested(std::string_view id) = 0;

  // Client side.
  virtual CancelOutcome request_cancel(std::string_view id, std::int64_t now_ms) = 0;
  virtual bool delete_job(std::string_view id) = 0;
  virtual std::optional<std::string> scene(std::string_view id) = 0;  // as submitted, compact
  virtual std::optional<std::string> result_summary(std::string_view id) = 0;
  virtual std::vector<StoredBody> result_bodies(std::string_view id) = 0;
  // Frames [from, to) of a succeeded job.
  virtual std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                                 std::int64_t to) = 0;
  // Reads frames [from, to) of one result, page after page: a store whose result is one byte
  // string (server/blob_storage) reads it once for all the pages.
  using FrameReader = std::function<std::vector<StoredFrame>(std::int64_t from, std::int64_t to)>;
  virtual FrameReader frame_reader(std::string_view id) {
    return [this, id = std::string(id)](std::int64_t from, std::int64_t to) {
      return result_frames(id, from, to);
    };
  }
  // A succeeded job's compact result (StoredResult::encoded); nullopt when it has none (its
  // result is in job_bodies and job_frames rows, or in the blob store, or it has not succeeded).
  virtual std::optional<std::string> result_encoded(std::string_view id) = 0;

  // Assets. put_asset stores the asset unless the owner already has one with that id; it returns
  // the stored record and whether it was new. get_asset and asset_bytes look among `owner`'s
  // assets, or among everyone's when `owner` is nullopt (no keys, an admin key, a worker).
  struct PutAsset {
    AssetRecord asset;
    bool created = false;
  };
  virtual PutAsset put_asset(const AssetRecord& asset, std::string_view bytes) = 0;
  virtual std::optional<AssetRecord> get_asset(std::string_view id,
                                               std::optional<std::string_view> owner) = 0;
  virtual std::optional<std::string> asset_bytes(std::string_view id,
                                                 std::optional<std::string_view> owner) = 0;

  // Maintenance. Running jobs whose lease expired go back to the queue, or end failed once
  // they have used `max_attempts`.
  virtual RecoveryReport recover_expired(std::int64_t now_ms, int max_attempts) = 0;
  // The owners holding leases on running jobs, and expiring every lease of one (its process is
  // known to be dead) so recover_expired takes its jobs back at once.
  virtual std::vector<std::string> running_owners() = 0;
  virtual std::int64_t expire_leases(std::string_view owner) = 0;
  // Deletes finished jobs (and their results) that finished before `before_ms`.
  virtual std::int64_t prune_finished(std::int64_t before_ms) = 0;
  virtual bool ping() = 0;

  // Result blobs (server/blob_store). result_blob: a succeeded job's blob digest, "" when its
  // result is in the database, nullopt when no succeeded job has that id. blob_references: every
  // digest a job row names, on every node. collect_blobs: removes the blobs no job names
  // (only the blob store does any work); returns how many.
  virtual std::optional<std::string> result_blob(std::string_view id) = 0;
  virtual std::vector<std::string> blob_references() = 0;
  virtual std::int64_t collect_blobs(std::int64_t now_ms) {
    (void)now_ms;
    return 0;
  }

  // Callbacks. claim_callback takes a finished job whose callback is pending and due (oldest due
  // first) and holds it until now + lease_ms (another sender skips it meanwhile);
  // record_callback stores the attempts so far, the state (pending, delivered or failed) and,
  // pending, when to try again; it bumps the job's version. False: the job is gone.
  virtual std::optional<JobRecord> claim_callback(std::int64_t now_ms, std::int64_t lease_ms) = 0;
  virtual bool record_callback(std::string_view id, std::string_view deliveries_json,
                               std::string_view state, std::int64_t next_ms,
                               std::int64_t now_ms) = 0;

  // Changes made by other processes on a shared store: `job_changed` hears the id of a job that
  // changed (to wake long-polls parked on it), `work_queued` that a job may be waiting (to wake
  // idle workers). Called on a thread of the store's own; they must only post work. The SQLite
  // store has no such channel and never calls them (its workers poll).
  using JobChanged = std::function<void(const std::string& job_id)>;
  using WorkQueued = std::function<void()>;
  virtual void watch(JobChanged job_changed, WorkQueued work_queued) {
    (void)job_changed;
    (void)work_queued;
  }
};

}  // namespace brisance::server
