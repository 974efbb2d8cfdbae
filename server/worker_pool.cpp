#include "server/worker_pool.hpp"

#include <cerrno>
#include <cstdio>
#include <random>

#include <nlohmann/json.hpp>
#include <signal.h>
#include <unistd.h>

#include "server/log.hpp"
#include "sim/engine/simulator.hpp"

namespace brisance::server {
namespace {

using Clock = std::chrono::steady_clock;

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "localhost";
  return name;
}

std::string make_owner() {
  std::random_device device;
  return host_name() + "/" + std::to_string(getpid()) + "/" + std::to_string(device());
}

// An owner "host/pid/token" on this host whose process is gone (or is this process under an
// earlier token, which cannot be: tokens are per start).
bool owner_is_dead_here(const std::string& owner, const std::string& self) {
  const auto first = owner.find('/');
  const auto second = owner.find('/', first == std::string::npos ? first : first + 1);
  if (first == std::string::npos || second == std::string::npos) return false;
  if (owner.substr(0, first) != host_name() || owner == self) return false;
  const std::string pid_text = owner.substr(first + 1, second - first - 1);
  char* end = nullptr;
  const long pid = std::strtol(pid_text.c_str(), &end, 10);
  if (end == pid_text.c_str() || *end != '\0' || pid <= 0) return false;
  if (pid == getpid()) return true;  // an earlier run of this process id, now reused by us
  return kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

WorkerPool::WorkerPool(JobService& service, Metrics& metrics, WorkerOptions options)
    : service_(service), metrics_(metrics), options_(options), owner_(make_owner()) {
  service_.set_work_signal([this] { wake_all(); });
}

WorkerPool::~WorkerPool() {
  service_.set_work_signal({});  // the store's listener thread may outlive this pool
  stop(std::chrono::milliseconds(0));
}

void WorkerPool::wake_all() {
  {
    std::lock_guard lock(mutex_);
    ++signals_;
  }
  wake_.notify_all();
}

void WorkerPool::start() {
  if (started_) return;
  started_ = true;
  const RecoveryReport report = service_.recover_abandoned(
      [this](const std::string& owner) { return owner_is_dead_here(owner, owner_); });
  if (report.requeued > 0 || report.failed > 0 || report.expired_here > 0) {
    log_event(LogLevel::warn, "recovered jobs left running by a stopped process",
              {{"requeued", report.requeued}, {"failed", report.failed}});
  }
  for (int i = 0; i < options_.workers; ++i)
    threads_.emplace_back([this] { work(); });
  keeper_ = std::thread([this] { keep(); });
}

void WorkerPool::stop(std::chrono::milliseconds grace) {
  if (!started_ || stopped_) return;
  stopped_ = true;
  stopping_ = true;
  wake_all();
  const auto deadline = Clock::now() + grace;
  {
    std::unique_lock lock(mutex_);
    wake_.wait_until(lock, deadline, [this] { return running_ids_.empty(); });
  }
  abort_ = true;  // whatever still runs is cancelled and released back to the queue
  wake_all();
  for (auto& t : threads_)
    t.join();
  threads_.clear();
  if (keeper_.joinable()) keeper_.join();
}

void WorkerPool::work() {
  std::uint64_t seen = 0;
  while (!stopping_) {
    {
      // After the store failed to take a result, wait before claiming again: the job is back in
      // the queue and would otherwise be run again at once against the same full disk.
      std::unique_lock lock(mutex_);
      if (wake_.wait_until(lock, claim_pause_until_, [this] { return stopping_.load(); })) break;
    }
    std::optional<ClaimedJob> claimed;
    try {
      claimed = service_.claim(owner_, options_.lease.count());
    } catch (const std::exception& error) {
      log_event(LogLevel::error, "cannot claim a job", {{"error", error.what()}});
    }
    if (claimed) {
      run_job(std::move(*claimed));
      continue;
    }
    // Nothing queued: sleep until a submission signals, or poll again in a second (another
    // process may share the store).
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, std::chrono::seconds(1), [&] { return stopping_ || signals_ != seen; });
    seen = signals_;
  }
}

void WorkerPool::run_job(ClaimedJob claimed) {
  const std::string id = claimed.job.id;
  {
    std::lock_guard lock(mutex_);
    running_ids_.insert(id);
  }
  ++busy_;
  auto cancel_flag = service_.register_running(id);
  service_.notifier().notify(id);
  log_event(LogLevel::info, "job started", {{"job", id}, {"attempt", claimed.job.attempts}});

  const auto started = Clock::now();
  auto last_progress = started;
  bool lease_lost = false;
  bool timed_out = false;
  bool store_failed = false;
  JobStatus outcome = JobStatus::failed;
  std::string error_type, error_message;

  scene::ParseResult parsed = scene::parse_scene_text(claimed.scene_json, service_.options().limits,
                                                      service_.asset_meshes(claimed.job.owner));
  if (!parsed.scene) {
    // Accepted under other limits, or a store edited by hand.
    error_type = "invalid_scene";
    error_message = "the stored scene is no longer valid: " +
                    (parsed.errors.empty()
                         ? std::string("unknown error")
                         : parsed.errors.front().pointer + ": " + parsed.errors.front().message);
  } else {
    engine::RunHooks hooks;
    // When the store last told this worker whether the job was cancelled through another node:
    // with each progress report while stepping, and from the cancel hook in every other phase.
    auto last_cancel_check = started;
    hooks.progress = [&](double fraction) {
      const auto now = Clock::now();
      if (now - last_progress < options_.progress_interval) return;
      last_progress = now;
      last_cancel_check = now;
      try {
        switch (service_.report_progress(id, owner_, fraction)) {
          case JobService::Progress::kept:
            break;
          case JobService::Progress::lease_lost:
            lease_lost = true;
            break;
          case JobService::Progress::cancel_requested:
            cancel_flag->store(true);  // cancelled through another process
            break;
        }
      } catch (const std::exception& error) {
        log_event(LogLevel::warn, "cannot store progress", {{"job", id}, {"error", error.what()}});
      }
    };
    hooks.cancel_requested = [&] {
      if (cancel_flag->load(std::memory_order_relaxed) || lease_lost ||
          abort_.load(std::memory_order_relaxed)) {
        return true;
      }
      // A cancel through another node sets only the store's flag, and progress reports come
      // only from the step loop: breaking panes and prepare (seconds for a large scene) look it
      // up here, once per progress interval, from wherever the run polls.
      const auto now = Clock::now();
      if (now - last_cancel_check >= options_.progress_interval) {
        last_cancel_check = now;
        try {
          if (service_.cancel_requested(id)) {
            cancel_flag->store(true);
            return true;
          }
        } catch (const std::exception& error) {
          log_event(LogLevel::warn, "cannot read the cancel flag",
                    {{"job", id}, {"error", error.what()}});
        }
      }
      if (options_.job_timeout_s > 0.0 &&
          std::chrono::duration<double>(Clock::now() - started).count() > options_.job_timeout_s) {
        timed_out = true;
        return true;
      }
      return false;
    };
    try {
      engine::RunBudget budget;
      budget.limits = service_.options().limits;
      budget.memory_bytes = options_.job_memory_bytes;
      engine::RunOutcome run = engine::simulate(*parsed.scene, hooks, budget);
      if (run.over_budget) {
        // The scene's own size, found as its panes broke: the job's fault, and it would fail
        // again on any worker.
        error_type = run.over_budget->kind == engine::OverBudget::Kind::memory
                         ? "memory_budget_exceeded"
                         : "limit_exceeded";
        error_message = run.over_budget->message;
      } else if (!run.cancelled) {
        try {
          outcome =
              service_.complete(id, owner_, run.result) ? JobStatus::succeeded : JobStatus::queued;
          if (outcome == JobStatus::queued) lease_lost = true;
        } catch (const StorageError& error) {
          // Not the job's fault (a full disk, say): it goes back to the queue without counting
          // the attempt, and this worker waits before it claims again.
          store_failed = true;
          log_event(LogLevel::warn, "cannot store the job's result; it goes back to the queue",
                    {{"job", id}, {"error", error.what()}});
        }
      } else if (timed_out) {
        error_type = "timeout";
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", options_.job_timeout_s);
        error_message = "the run exceeded the job time limit of " + std::string(limit) + " s";
      } else if (cancel_flag->load()) {
        outcome = JobStatus::cancelled;
      }
    } catch (const std::exception& error) {
      error_type = "simulation_error";
      error_message = std::string("the simulation failed: ") + error.what();
    }
  }

  const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
  std::string label(to_string(outcome));
  try {
    if (lease_lost) {
      log_event(LogLevel::warn, "job dropped: its lease was lost (deleted or taken over)",
                {{"job", id}});
    } else if (outcome == JobStatus::succeeded) {
      metrics_.record_job(outcome, seconds);
    } else if (outcome == JobStatus::cancelled) {
      service_.finish_cancelled(id, owner_);
      metrics_.record_job(outcome, seconds);
    } else if (store_failed) {
      service_.release(id, owner_);
      label = "requeued (its result could not be stored)";
      std::lock_guard lock(mutex_);
      claim_pause_until_ = Clock::now() + options_.store_failure_pause;
    } else if (error_type.empty() && abort_) {
      service_.release(id, owner_);
      label = "requeued (shutting down)";
    } else {
      service_.fail(id, owner_, error_type, error_message);
      metrics_.record_job(JobStatus::failed, seconds);
    }
  } catch (const std::exception& error) {
    // The lease expires and the keeper of whichever process runs next requeues the job.
    log_event(LogLevel::error, "cannot store the job's outcome",
              {{"job", id}, {"error", error.what()}});
  }
  if (!lease_lost) {
    log_event(LogLevel::info, "job finished",
              error_message.empty()
                  ? nlohmann::json{{"job", id}, {"status", label}, {"seconds", seconds}}
                  : nlohmann::json{{"job", id},
                                   {"status", label},
                                   {"seconds", seconds},
                                   {"error_type", error_type},
                                   {"error", error_message}});
  }
  service_.unregister_running(id);
  --busy_;
  {
    std::lock_guard lock(mutex_);
    running_ids_.erase(id);
  }
  wake_.notify_all();
  service_.notifier().notify(id);
}

void WorkerPool::keep() {
  auto last_prune = Clock::time_point{};
  auto last_collect = Clock::now();
  const auto tick = std::max(std::chrono::milliseconds(50), options_.lease / 5);
  while (true) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, tick, [this] { return abort_.load(); });
      if (abort_ && running_ids_.empty()) return;
    }
    std::vector<std::string> ids;
    {
      std::lock_guard lock(mutex_);
      ids.assign(running_ids_.begin(), running_ids_.end());
    }
    try {
      const RecoveryReport report = service_.keep_leases(ids, owner_, options_.lease.count());
      if (report.requeued > 0 || report.failed > 0) {
        log_event(LogLevel::warn, "recovered jobs whose worker stopped renewing its lease",
                  {{"requeued", report.requeued}, {"failed", report.failed}});
        wake_all();
      }
      // Blobs no job names any more (deleted or pruned jobs) go, whatever the retention.
      if (Clock::now() - last_collect > options_.blob_collect_interval) {
        last_collect = Clock::now();
        if (const std::int64_t removed = service_.collect_blobs(); removed > 0) {
          log_event(LogLevel::info, "collected result blobs no job names", {{"blobs", removed}});
        }
      }
      if (options_.retention.count() > 0 && Clock::now() - last_prune > std::chrono::minutes(1)) {
        last_prune = Clock::now();
        const auto retention =
            std::chrono::duration_cast<std::chrono::milliseconds>(options_.retention);
        if (const std::int64_t pruned = service_.prune_finished(retention); pruned > 0) {
          log_event(LogLevel::info, "pruned finished jobs past retention", {{"jobs", pruned}});
        }
      }
    } catch (const std::exception& error) {
      log_event(LogLevel::error, "lease keeper failed", {{"error", error.what()}});
    }
  }
}

}  // namespace brisance::server
