// server/job_service: what the HTTP handlers ask for, in domain terms — submit a scene (validated
// fully first), read, list, cancel and delete jobs, read results — plus the in-process change
// notifications that long-polling requests wait on. No HTTP here; storage does the persistence.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "server/storage.hpp"
#include "sim/engine/result.hpp"
#include "sim/io/frames.hpp"
#include "sim/io/mesh_import.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::server {

// The scene limits of the service: the simulator's, with at most 5 000 000 frames x bodies
// instead of its 5e7 (`brisance run` streams its output to files; the service stores every
// result and serves it back: docs/service.md, "Result sizes and their bound").
inline constexpr std::size_t kServiceMaxFrameSamples = 5000000;
inline scene::Limits service_limits() {
  scene::Limits limits;
  limits.max_frame_samples = kServiceMaxFrameSamples;
  return limits;
}

struct ServiceOptions {
  std::int64_t max_queue = 10000;  // queued jobs above which submissions get 429
  int max_attempts = 3;            // claims before a job that keeps killing workers fails
  std::size_t max_asset_bytes = 8 * 1024 * 1024;  // larger uploads to /v1/assets get 413
  scene::Limits limits = service_limits();
  // The workers' memory budget of one run (--job-memory-mb; 0: none): a scene whose run would
  // certainly pass it, or a limit, is refused at submission (engine::refuse_before_run).
  std::uint64_t job_memory_bytes = 0;
  std::string default_callback_url;  // for jobs that name none ('' none); --callback-url
  // The most frames x animated bodies a result.glb is built for: it is made whole in memory
  // (docs/service.md, bench/results/result_storage.md); above it the route answers 422
  // result-too-large and points to the frames, which stream.
  std::int64_t max_glb_frame_samples = 2000000;
};

// A callback URL a job may name: http[s]://host[:port][/path], at most 2000 characters. nullopt
// when valid, else why not.
std::optional<std::string> check_callback_url(std::string_view url);

std::int64_t now_ms();

// Calls back whoever waits on a job when it changes. Callbacks run on the thread that made the
// change and must only post work elsewhere.
class ChangeNotifier {
 public:
  using Callback = std::function<void()>;
  std::uint64_t subscribe(const std::string& job_id, Callback callback);
  void unsubscribe(std::uint64_t token);
  void notify(const std::string& job_id);

 private:
  std::mutex mutex_;
  std::uint64_t next_token_ = 1;
  std::multimap<std::string, std::pair<std::uint64_t, Callback>> waiters_;
};

// The shape of a stored result, read from its summary: enough to validate frame requests and to
// place the bodies that are not in the stored frames.
struct ResultLayout {
  std::int64_t frame_count = 0;
  std::vector<std::uint32_t> animated;      // body index of each stored pose slot
  std::vector<engine::Pose> initial_poses;  // one per body, as in the summary

  std::size_t body_count() const { return initial_poses.size(); }
};

// Limits on what a job carries beside its scene (docs/service.md "Names and labels").
inline constexpr std::size_t kMaxJobName = 200;  // characters
inline constexpr std::size_t kMaxLabels = 32;
inline constexpr std::size_t kMaxLabelKey = 63;     // letters, digits, '_', '.', '-', '/'
inline constexpr std::size_t kMaxLabelValue = 200;  // characters, no ',' or control characters

bool valid_label_key(std::string_view key);
// nullopt when `name` is a valid job name, else why not.
std::optional<std::string> check_job_name(const nlohmann::json& name);
// Reports each problem of `labels` with its JSON pointer in the request body.
void check_job_labels(const nlohmann::json& labels,
                      const std::function<void(std::string, std::string)>& invalid);

struct SubmitRequest {
  std::string_view body;             // {"scene": {...}, "priority": N}
  std::string_view idempotency_key;  // empty: none
  std::string_view owner;            // the API key's name; empty when keys are off
};

struct SubmitOutcome {
  enum class Kind { accepted, existing, malformed, invalid, key_conflict, queue_full };
  Kind kind = Kind::accepted;
  JobRecord job;                               // accepted, existing
  std::string message;                         // malformed
  std::vector<scene::ValidationError> errors;  // invalid
};

struct AssetUpload {
  std::string_view bytes;  // the file as uploaded
  io::MeshFormat format = io::MeshFormat::glb;
  std::string_view owner;  // the API key's name; empty when keys are off
};

struct AssetOutcome {
  enum class Kind { created, existing, too_large, invalid };
  Kind kind = Kind::created;
  AssetRecord asset;    // created, existing
  std::string message;  // too_large, invalid: why
};

class JobService {
 public:
  JobService(Storage& storage, ServiceOptions options);
  ~JobService();
  JobService(const JobService&) = delete;
  JobService& operator=(const JobService&) = delete;

  SubmitOutcome submit(const SubmitRequest& request);
  std::optional<JobRecord> job(std::string_view id) { return storage_.get_job(id); }
  JobPage list(const JobFilter& filter, std::int64_t before_seq, int limit) {
    return storage_.list_jobs(filter, before_seq, limit);
  }
  CancelOutcome cancel(const std::string& id);

  // Callbacks (server/callbacks): a finished job whose callback is due, held for lease_ms; and
  // the outcome of an attempt, which wakes the job's long-polls.
  std::optional<JobRecord> claim_callback(std::int64_t lease_ms) {
    return storage_.claim_callback(now_ms(), lease_ms);
  }
  bool record_callback(const std::string& id, std::string_view deliveries_json,
                       std::string_view state, std::int64_t next_ms) {
    const bool found = storage_.record_callback(id, deliveries_json, state, next_ms, now_ms());
    if (found) notifier_.notify(id);
    return found;
  }
  bool remove(const std::string& id);

  // Stores an uploaded mesh file once it reads and every mesh in it is closed and manifold.
  AssetOutcome upload_asset(const AssetUpload& upload);
  // The asset `id` among `owner`'s (nullopt: anyone's).
  std::optional<AssetRecord> asset(std::string_view id, std::optional<std::string_view> owner) {
    return storage_.get_asset(id, owner);
  }
  // `asset` shapes read from the store: a scene uses the assets of the key that submits it
  // (`owner`, empty when keys are off). Used when a job is submitted and when it runs.
  scene::MeshSources asset_meshes(std::string_view owner);

  // The scene JSON a job was submitted with.
  std::optional<std::string> scene(std::string_view id) { return storage_.scene(id); }
  std::optional<std::string> result_summary(std::string_view id) {
    return storage_.result_summary(id);
  }

  // The result forms of the HTTP API, built from the stored rows and encoded by sim/io (the
  // CLI's codec), so `brisance run` and the API give one shape.
  //
  // What the frames handler checks its parameters against (from the stored summary); nullopt
  // when the job has no result.
  std::optional<ResultLayout> result_layout(std::string_view id);
  // Frames [from, to) of `bodies` as stored: poses of animated bodies as their float32 rows,
  // bodies that do not move at their initial pose rounded to float32 (api/openapi.yaml). Needs
  // 0 <= from <= to and every body below layout.body_count(). Encode with
  // io::frames_document_json(set, layout.frame_count) or io::frames_to_brf1(set).
  io::FrameSet result_frame_set(std::string_view id, const ResultLayout& layout, std::int64_t from,
                                std::int64_t to, const std::vector<std::uint32_t>& bodies);
  // The same from a reader of the result's frames (result_frame_reader), for a page streamed in
  // blocks: each block is read and encoded on its own.
  static io::FrameSet frame_set(const Storage::FrameReader& reader, const ResultLayout& layout,
                                std::int64_t from, std::int64_t to,
                                const std::vector<std::uint32_t>& bodies);
  Storage::FrameReader result_frame_reader(std::string_view id) {
    return storage_.frame_reader(id);
  }
  // The body of GET /v1/jobs/{id}/meshes ({"bodies": []} without a result).
  std::string result_meshes_json(std::string_view id);
  // The body of GET /v1/jobs/{id}/result.glb: the stored meshes and float32 frames (quaternions
  // renormalised) through io::to_glb; nullopt when the job has no result. It is built whole in
  // memory, so the route refuses results above ServiceOptions::max_glb_frame_samples.
  std::optional<std::vector<std::uint8_t>> result_glb(std::string_view id);

  // For the workers (server/worker_pool): a claimed job's life under its owner's lease, `owner`
  // being the pool's "host/pid/token". The worker wakes the job's long-polls (notifier()) once
  // it has let go of the job; report_progress wakes them itself.
  //
  // At start: the jobs whose owner `owner_is_dead` says is gone lose their lease, then every
  // expired lease is recovered (requeued, or failed after max_attempts claims).
  RecoveryReport recover_abandoned(const std::function<bool(const std::string&)>& owner_is_dead);
  // The queued job to run next (highest priority, oldest), leased to `owner` for lease_ms.
  std::optional<ClaimedJob> claim(std::string_view owner, std::int64_t lease_ms);
  // Whether the store holds a cancel request for a running job (one made through another node
  // or process reaches this one only through the store).
  bool cancel_requested(const std::string& id) { return storage_.cancel_requested(id); }
  enum class Progress { kept, cancel_requested, lease_lost };
  // Stores a running job's progress (0..1); whether it was cancelled through another node, or
  // its lease is gone (deleted, or taken over after it expired).
  Progress report_progress(const std::string& id, std::string_view owner, double fraction);
  // Stores the result and marks the job succeeded; false when the lease was lost. Throws
  // StorageError when the store cannot take the result (a full disk).
  bool complete(const std::string& id, std::string_view owner, const engine::Result& result);
  void fail(const std::string& id, std::string_view owner, std::string_view error_type,
            std::string_view error_message);
  void finish_cancelled(const std::string& id, std::string_view owner);
  // Back to the queue without counting the attempt (shutting down, or the store was full).
  void release(const std::string& id, std::string_view owner);
  // Renews the leases of `running` for lease_ms and recovers the expired leases of any node.
  RecoveryReport keep_leases(const std::vector<std::string>& running, std::string_view owner,
                             std::int64_t lease_ms);
  // Deletes the jobs that finished longer than `retention` ago; how many.
  std::int64_t prune_finished(std::chrono::milliseconds retention);
  // Removes the result blobs no job names any more (--blobs); how many.
  std::int64_t collect_blobs() { return storage_.collect_blobs(now_ms()); }

  QueueCounts queue_counts() { return storage_.queue_counts(now_ms()); }
  // Results this process stored and their encoded bytes (server/compact_result), for /metrics.
  StoredResultTotals stored_result_totals() const {
    return {stored_results_.load(), stored_result_bytes_.load()};
  }
  bool database_ok() { return storage_.ping(); }

  ChangeNotifier& notifier() { return notifier_; }
  const ServiceOptions& options() const { return options_; }

  // Cancellation flags of the jobs running in this process, polled by their workers every step.
  std::shared_ptr<std::atomic<bool>> register_running(const std::string& id);
  void unregister_running(const std::string& id);
  // Wakes a worker waiting for work (a job was queued, here or on another node of the store).
  void set_work_signal(std::function<void()> signal);

 private:
  std::int64_t queued_estimate();
  // The stored bodies of a result with their meshes, materials and fragment flags (and, with
  // `animated`, whether each moves).
  std::vector<engine::BodyInfo> stored_bodies(std::string_view id, std::vector<bool>* animated);
  void forget_queued_count();  // the next submission counts again (room was made)
  void signal_work();

  Storage& storage_;
  ServiceOptions options_;
  ChangeNotifier notifier_;
  std::mutex work_signal_mutex_;  // the store's listener thread signals too
  std::function<void()> work_signal_;

  std::mutex running_mutex_;
  std::map<std::string, std::shared_ptr<std::atomic<bool>>, std::less<>> running_;

  std::atomic<std::uint64_t> stored_results_{0};
  std::atomic<std::uint64_t> stored_result_bytes_{0};

  std::mutex queued_mutex_;
  std::int64_t queued_cached_ = 0;
  std::chrono::steady_clock::time_point queued_checked_{};
};

// engine::Result → what storage keeps: the summary JSON of io::result_summary (bodies without
// meshes, frame count and times, final state, stats, warnings, fracture), meshes once per body,
// float32 frames.
StoredResult to_stored_result(const engine::Result& result);

// A random job id: "j" and 24 hex digits.
std::string new_job_id();

}  // namespace brisance::server
