// server/http_server: the Boost.Beast transport (STYLE.md §15) — an acceptor and one session per
// connection, each on its own strand, with read and idle timeouts, a body limit (413), requests
// answered in order one at a time (pipelined ones wait in a bounded buffer), keep-alive, and
// long-polls parked on the job's change notifications. All Beast code lives in http_server.cpp.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "server/api.hpp"

namespace brisance::server {

struct HttpOptions {
  std::string bind = "127.0.0.1";
  std::uint16_t port = 8080;  // 0: any free port (see HttpServer::port)
  int io_threads = 4;         // requests run to completion on them, waits included
  std::size_t body_limit_bytes = 16 * 1024 * 1024;
  std::chrono::seconds read_timeout{30};  // a request must arrive whole within this
  std::chrono::seconds idle_timeout{60};  // a keep-alive connection may sit idle this long
  // Open connections at most; one more is answered 503 `overloaded` and closed at once.
  std::size_t max_connections = 1024;
  // A request with a body of at least this many bytes (a scene to parse and validate, an asset
  // to import) is answered on a pool of `request_threads` threads of its own, not on an I/O
  // thread, so a few slow ones cannot hold up /healthz and the rest. At most `request_queue`
  // such requests wait for the pool; one more is answered 503 `overloaded`.
  std::size_t offload_body_bytes = 64 * 1024;
  int request_threads = 2;
  std::size_t request_queue = 16;
  std::string server_name = "brisance";
};

class HttpServer {
 public:
  HttpServer(Api& api, JobService& service, Metrics& metrics, HttpOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds and listens; std::runtime_error naming the address if it cannot.
  void listen();
  std::uint16_t port() const;
  // Starts the I/O threads; returns at once.
  void start();
  // Graceful stop: no new connections, idle keep-alive connections closed, parked long-polls
  // answered, in-flight requests finished (for up to `drain`), then the I/O threads joined.
  void stop(std::chrono::milliseconds drain);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace brisance::server
