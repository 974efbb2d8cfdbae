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

#include "server/storage.hpp"
#include "sim/engine/result.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::server {

struct ServiceOptions {
  std::int64_t max_queue = 10000;  // queued jobs above which submissions get 429
  int max_attempts = 3;            // claims before a job that keeps killing workers fails
  scene::Limits limits;
};

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

class JobService {
 public:
  JobService(Storage& storage, ServiceOptions options);

  SubmitOutcome submit(const SubmitRequest& request);
  std::optional<JobRecord> job(std::string_view id) { return storage_.get_job(id); }
  JobPage list(std::optional<JobStatus> status, std::int64_t before_seq, int limit,
               std::optional<std::string_view> owner) {
    return storage_.list_jobs(status, before_seq, limit, owner);
  }
  CancelOutcome cancel(const std::string& id);
  bool remove(const std::string& id);

  // The scene JSON a job was submitted with.
  std::optional<std::string> scene(std::string_view id) { return storage_.scene(id); }
  std::optional<std::string> result_summary(std::string_view id) {
    return storage_.result_summary(id);
  }
  std::vector<StoredBody> result_bodies(std::string_view id) { return storage_.result_bodies(id); }
  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from, std::int64_t to) {
    return storage_.result_frames(id, from, to);
  }
  // The stored result rebuilt for the glTF writer (poses at the stored float32 precision).
  std::optional<engine::Result> stored_result(std::string_view id);

  QueueCounts queue_counts() { return storage_.queue_counts(now_ms()); }
  bool database_ok() { return storage_.ping(); }

  ChangeNotifier& notifier() { return notifier_; }
  Storage& storage() { return storage_; }
  const ServiceOptions& options() const { return options_; }

  // Cancellation flags of the jobs running in this process, polled by their workers every step.
  std::shared_ptr<std::atomic<bool>> register_running(const std::string& id);
  void unregister_running(const std::string& id);
  // Wakes a worker waiting for work (a job was queued).
  void set_work_signal(std::function<void()> signal) { work_signal_ = std::move(signal); }

 private:
  std::int64_t queued_estimate();
  void forget_queued_count();  // the next submission counts again (room was made)

  Storage& storage_;
  ServiceOptions options_;
  ChangeNotifier notifier_;
  std::function<void()> work_signal_;

  std::mutex running_mutex_;
  std::map<std::string, std::shared_ptr<std::atomic<bool>>, std::less<>> running_;

  std::mutex queued_mutex_;
  std::int64_t queued_cached_ = 0;
  std::chrono::steady_clock::time_point queued_checked_{};
};

// engine::Result → what storage keeps: summary JSON (bodies without meshes, frame times count,
// final state, stats, warnings), meshes once per body, float32 frames.
StoredResult to_stored_result(const engine::Result& result);

// A random job id: "j" and 24 hex digits.
std::string new_job_id();

}  // namespace brisance::server
