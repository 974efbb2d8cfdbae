// server/pg_pool: how the PostgreSQL store holds its connections — a pool of reusable ones that
// reconnects with exponential backoff while the server is unreachable (and then fails at once
// instead of waiting on a timeout), and the one LISTEN connection per node whose thread hands
// every notification to a callback.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "server/pg.hpp"

namespace brisance::server::pg {

struct PoolOptions {
  std::string conninfo;  // a postgres:// URL or libpq key=value pairs
  std::chrono::milliseconds first_backoff{100};
  std::chrono::milliseconds max_backoff{5000};
  std::size_t max_idle = 16;  // idle connections kept; more open when more threads need one
};

class Pool {
 public:
  explicit Pool(PoolOptions options);
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  // Runs `f` on a pooled connection. When a reused connection turns out broken (the server
  // restarted since it was pooled), every idle one is presumed broken too and `f` runs once more
  // on a new connection: a statement that failed because the connection was dead never reached
  // the server's commit.
  template <typename F>
  std::invoke_result_t<F&, Connection&> with_connection(F f) {
    for (int attempt = 0;; ++attempt) {
      Lease c = acquire();
      try {
        return f(*c);
      } catch (const StorageError&) {
        if ((*c).ok()) throw;
        drop_idle();
        if (!c.reused() || attempt > 0) throw;
      }
    }
  }

 private:
  // A pooled connection, returned on destruction unless it broke.
  class Lease {
   public:
    Lease(Pool& pool, std::unique_ptr<Connection> c, bool reused)
        : pool_(pool), c_(std::move(c)), reused_(reused) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { pool_.give_back(std::move(c_)); }
    Connection& operator*() { return *c_; }
    bool reused() const { return reused_; }

   private:
    Pool& pool_;
    std::unique_ptr<Connection> c_;
    bool reused_;
  };

  Lease acquire();
  void give_back(std::unique_ptr<Connection> c);
  void drop_idle();
  // A new connection, unless the last attempt failed less than the backoff ago: then it throws
  // at once that the server is unreachable.
  std::unique_ptr<Connection> connect();

  PoolOptions options_;
  std::mutex idle_mutex_;
  std::vector<std::unique_ptr<Connection>> idle_;
  std::mutex backoff_mutex_;
  std::chrono::steady_clock::time_point retry_at_{};
  std::chrono::milliseconds backoff_;
  std::string last_error_;
};

// A thread holding one connection that LISTENs on `channels` and calls `received` with every
// notification; it reconnects with backoff and calls `connected` after each (re)connection, since
// notifications sent while it was away are lost. The callbacks run on the listener's thread.
class Listener {
 public:
  Listener(PoolOptions options, std::vector<std::string> channels,
           std::function<void(const Notification&)> received, std::function<void()> connected);
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;
  ~Listener();  // stops the thread within its 200 ms poll

 private:
  void run();

  PoolOptions options_;
  std::vector<std::string> channels_;
  std::function<void(const Notification&)> received_;
  std::function<void()> connected_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace brisance::server::pg
