// server/group_commit: concurrent job submissions share one transaction, for both stores. The
// first caller to find no batch running leads it and commits everything queued so far; the
// others wait for that commit. Every caller returns only after its own job is committed, so
// durability per job is unchanged while one commit (one fsync, one WAL flush) serves many jobs.
#pragma once

#include <condition_variable>
#include <exception>
#include <mutex>
#include <utility>
#include <vector>

#include "server/storage.hpp"

namespace brisance::server {

// One submission waiting in a batch; the batch's runner sets its result or its error.
struct PendingCreate {
  const NewJob* job;
  CreateResult result;
  std::exception_ptr error;
  bool done;
};

class GroupCommit {
 public:
  // Queues `job` and returns once it is committed; run_batch(const std::vector<PendingCreate*>&)
  // commits a whole batch (in one transaction), setting each entry's result or error.
  template <typename RunBatch>
  CreateResult submit(const NewJob& job, RunBatch&& run_batch) {
    PendingCreate me{&job, {}, nullptr, false};
    std::unique_lock lock(mutex_);
    queue_.push_back(&me);
    while (!me.done) {
      if (leader_) {
        done_.wait(lock);
        continue;
      }
      leader_ = true;
      std::vector<PendingCreate*> batch;
      batch.swap(queue_);
      lock.unlock();
      run_batch(batch);
      lock.lock();
      for (PendingCreate* p : batch)
        p->done = true;
      leader_ = false;
      done_.notify_all();
    }
    if (me.error) std::rethrow_exception(me.error);
    return std::move(me.result);
  }

 private:
  std::mutex mutex_;
  std::condition_variable done_;
  std::vector<PendingCreate*> queue_;
  bool leader_ = false;
};

}  // namespace brisance::server
