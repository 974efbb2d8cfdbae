// server/worker_pool: N threads that claim queued jobs and run the simulator on them, and one
// keeper thread that renews their leases, requeues jobs whose worker died (in this process or
// another one on the same store) and prunes old results.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "server/job_service.hpp"
#include "server/metrics.hpp"

namespace brisance::server {

struct WorkerOptions {
  int workers = 2;
  std::chrono::milliseconds lease{15000};  // a dead worker's job is requeued after this
  std::chrono::milliseconds progress_interval{250};
  double job_timeout_s = 600.0;  // 0: no limit
  // A run's estimated bytes at most (sim/engine/budget.hpp); 0: no budget.
  std::uint64_t job_memory_bytes = std::uint64_t{2048} << 20;
  std::chrono::hours retention{24 * 7};  // finished jobs kept this long; 0: forever
  // How often the blob store (serve --blobs) is swept for blobs no job names.
  std::chrono::milliseconds blob_collect_interval{std::chrono::minutes(5)};
  // After the store failed to take a job's result (a full disk), the job goes back to the queue
  // and the worker waits this long before claiming again.
  std::chrono::milliseconds store_failure_pause{5000};
};

class WorkerPool {
 public:
  WorkerPool(JobService& service, Metrics& metrics, WorkerOptions options);
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool();

  // Requeues the jobs that a dead process on this host left running, then starts the threads.
  void start();
  // Stops claiming work, lets running jobs finish for up to `grace`, then cancels the rest and
  // puts them back in the queue (their attempt not counted), and joins every thread.
  void stop(std::chrono::milliseconds grace);

  int busy() const { return busy_.load(); }
  int size() const { return static_cast<int>(options_.workers); }
  bool running() const { return started_ && !stopping_.load(); }
  const std::string& owner() const { return owner_; }

 private:
  void work();
  void run_job(ClaimedJob claimed);
  void keep();
  void wake_all();

  JobService& service_;
  Metrics& metrics_;
  WorkerOptions options_;
  std::string owner_;  // "host/pid/random": whose leases these are

  std::vector<std::thread> threads_;
  std::thread keeper_;
  bool started_ = false;
  bool stopped_ = false;
  std::atomic<bool> stopping_{false};  // no new claims
  std::atomic<bool> abort_{false};     // cancel running jobs and release them
  std::atomic<int> busy_{0};

  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t signals_ = 0;
  std::set<std::string> running_ids_;
  std::chrono::steady_clock::time_point claim_pause_until_{};  // see store_failure_pause
};

}  // namespace brisance::server
