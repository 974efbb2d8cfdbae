#include "server/pg_pool.hpp"

#include <algorithm>

#include <poll.h>

namespace brisance::server::pg {

using Clock = std::chrono::steady_clock;

Pool::Pool(PoolOptions options) : options_(std::move(options)), backoff_(options_.first_backoff) {}

Pool::Lease Pool::acquire() {
  {
    std::lock_guard lock(idle_mutex_);
    if (!idle_.empty()) {
      auto c = std::move(idle_.back());
      idle_.pop_back();
      return Lease(*this, std::move(c), true);
    }
  }
  return Lease(*this, connect(), false);
}

void Pool::give_back(std::unique_ptr<Connection> c) {
  if (!c->ok()) return;
  std::lock_guard lock(idle_mutex_);
  if (idle_.size() < options_.max_idle) idle_.push_back(std::move(c));
}

void Pool::drop_idle() {
  std::lock_guard lock(idle_mutex_);
  idle_.clear();
}

std::unique_ptr<Connection> Pool::connect() {
  {
    std::lock_guard lock(backoff_mutex_);
    if (Clock::now() < retry_at_) {
      throw StorageError("postgres: unreachable, retrying with backoff: " + last_error_);
    }
  }
  try {
    auto c = std::make_unique<Connection>(options_.conninfo);
    std::lock_guard lock(backoff_mutex_);
    backoff_ = options_.first_backoff;
    return c;
  } catch (const StorageError& error) {
    std::lock_guard lock(backoff_mutex_);
    retry_at_ = Clock::now() + backoff_;
    backoff_ = std::min(backoff_ * 2, options_.max_backoff);
    last_error_ = error.what();
    throw;
  }
}

Listener::Listener(PoolOptions options, std::vector<std::string> channels,
                   std::function<void(const Notification&)> received,
                   std::function<void()> connected)
    : options_(std::move(options)),
      channels_(std::move(channels)),
      received_(std::move(received)),
      connected_(std::move(connected)),
      thread_([this] { run(); }) {}

Listener::~Listener() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void Listener::run() {
  std::unique_ptr<Connection> c;
  auto backoff = options_.first_backoff;
  while (true) {
    {
      std::lock_guard lock(mutex_);
      if (stop_) return;
    }
    if (!c) {
      try {
        c = std::make_unique<Connection>(options_.conninfo);
        for (const std::string& channel : channels_)
          c->exec(("LISTEN " + channel).c_str());
        backoff = options_.first_backoff;
      } catch (const StorageError&) {
        c.reset();
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, backoff, [this] { return stop_; });
        backoff = std::min(backoff * 2, options_.max_backoff);
        continue;
      }
      connected_();
    }
    // A short poll, so a stop request is seen within it.
    pollfd fd{c->socket(), POLLIN, 0};
    if (poll(&fd, 1, 200) < 0) continue;
    if (!c->consume()) {
      c.reset();
      continue;
    }
    while (auto n = c->next_notification())
      received_(*n);
  }
}

}  // namespace brisance::server::pg
