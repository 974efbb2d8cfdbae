#include "server/http_server.hpp"

#include <algorithm>
#include <atomic>
#include <functional>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include "server/log.hpp"

namespace brisance::server {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

// A request id the client sent, if it is a sane token; otherwise a fresh one.
std::string request_id_for(std::string_view sent) {
  if (!sent.empty() && sent.size() <= 64 &&
      sent.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") ==
          std::string_view::npos) {
    return std::string(sent);
  }
  thread_local std::mt19937_64 generator{std::random_device{}()};
  static constexpr char kHex[] = "0123456789abcdef";
  const std::uint64_t value = generator();
  std::string id(16, '0');
  for (int i = 0; i < 16; ++i)
    id[static_cast<std::size_t>(i)] = kHex[(value >> (4 * i)) & 0xf];
  return id;
}

}  // namespace

struct HttpServer::Impl {
  Api& api;
  JobService& service;
  Metrics& metrics;
  HttpOptions options;
  asio::io_context ioc;
  tcp::acceptor acceptor{ioc};
  std::vector<std::thread> threads;
  // Requests with large bodies (HttpOptions::offload_body_bytes) run here, off the I/O threads;
  // `offloaded` counts those queued or running.
  asio::thread_pool request_pool{static_cast<std::size_t>(std::max(1, options.request_threads))};
  std::atomic<std::size_t> offloaded{0};
  std::atomic<bool> draining{false};
  std::atomic<int> in_flight{0};  // requests read and not yet fully answered

  class Session;
  std::mutex sessions_mutex;
  std::set<std::shared_ptr<Session>> sessions;

  Impl(Api& a, JobService& s, Metrics& m, HttpOptions o)
      : api(a), service(s), metrics(m), options(std::move(o)) {}

  // Connections refused above the cap since start.
  std::atomic<std::uint64_t> rejected_connections{0};
  asio::steady_timer accept_timer{ioc};
  std::chrono::milliseconds accept_backoff{0};

  void accept();
  void reject(tcp::socket socket);
  void remove(const std::shared_ptr<Session>& session) {
    std::lock_guard lock(sessions_mutex);
    sessions.erase(session);
  }
};

class HttpServer::Impl::Session : public std::enable_shared_from_this<Session> {
 public:
  Session(Impl& server, tcp::socket socket)
      : server_(server),
        stream_(std::move(socket)),
        wait_timer_(stream_.get_executor()),
        buffer_(server.options.body_limit_bytes + 64 * 1024) {}

  void start() {
    asio::dispatch(stream_.get_executor(), [self = shared_from_this()] { self->read(); });
  }

  // Called from another thread when the server drains.
  void drain() {
    asio::post(stream_.get_executor(), [self = shared_from_this()] {
      if (self->waiting_) {
        self->wait_timer_.cancel();  // the parked long-poll answers now
      } else if (!self->busy_) {
        self->close();  // idle keep-alive: nothing in flight
      }
    });
  }

 private:
  void read() {
    busy_ = false;
    if (server_.draining) return close();
    parser_.emplace();
    parser_->body_limit(server_.options.body_limit_bytes);
    // Idle timeout until a request starts, then the read timeout for the rest of it: Beast
    // cannot switch mid-read, so the longer of the two bounds the whole read.
    stream_.expires_after(
        first_request_ ? server_.options.read_timeout
                       : std::max(server_.options.idle_timeout, server_.options.read_timeout));
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    first_request_ = false;
    if (ec == http::error::end_of_stream || ec == beast::error::timeout ||
        ec == asio::error::operation_aborted || ec == asio::error::connection_reset) {
      return close();
    }
    busy_ = true;
    ++server_.in_flight;
    started_ = Clock::now();
    if (ec) {
      // Answer what can be answered, then close: the stream is out of sync.
      keep_alive_ = false;
      HttpResponse r =
          ec == http::error::body_limit
              ? Api::problem(413, "payload-too-large", "Payload too large",
                             "the request body exceeds the limit of " +
                                 std::to_string(server_.options.body_limit_bytes) + " bytes")
              : Api::problem(400, "bad-request", "Malformed HTTP request", ec.message());
      request_ = HttpRequest{};
      request_.request_id = request_id_for({});
      request_.method = "?";
      return respond(std::move(r));
    }
    auto& message = parser_->get();
    if (message.find(http::field::transfer_encoding) != message.end() && !message.chunked()) {
      // RFC 9112 §6.1: a request whose final transfer coding is not chunked has no length the
      // server can know; answering it and reading on would take its body for the next request.
      keep_alive_ = false;
      request_ = HttpRequest{};
      request_.request_id = request_id_for({});
      request_.method = std::string(message.method_string());
      return respond(Api::problem(400, "bad-request", "Malformed HTTP request",
                                  "a request's Transfer-Encoding must end in 'chunked' "
                                  "(RFC 9112 §6.1)"));
    }
    request_ = HttpRequest{};
    request_.method = std::string(message.method_string());
    request_.target = std::string(message.target());
    for (const auto& field : message) {
      std::string name(field.name_string());
      for (char& c : name)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      request_.headers.emplace_back(std::move(name), std::string(field.value()));
    }
    request_.body = std::move(message.body());
    request_.request_id = request_id_for(request_.header("x-request-id"));
    keep_alive_ = message.keep_alive();
    if (request_.body.size() >= server_.options.offload_body_bytes) return offload();
    handle({});
  }

  void handle(const std::optional<LongPoll>& poll) { answered(answer(poll)); }

  HttpResponse answer(const std::optional<LongPoll>& poll) {
    try {
      return server_.api.handle(request_, poll);
    } catch (...) {
      // Api::handle answers every failure itself; this is the last line, so that no request can
      // end the process from a server thread.
      log_event(LogLevel::error, "request failed outside the API",
                {{"request_id", request_.request_id}});
      return Api::problem(500, "internal-error", "Internal error",
                          "the server failed to answer this request; the request id is in the "
                          "X-Request-Id header and the server log");
    }
  }

  void answered(HttpResponse r) {
    if (r.wait) return park(std::move(*r.wait));
    respond(std::move(r));
  }

  // A large body is parsed and validated on the request pool; the answer comes back to this
  // connection's strand. The session reads nothing meanwhile (one request at a time), so request_
  // is the pool's alone until then. A full pool queue is a 503, as a full connection table is.
  void offload() {
    const std::size_t limit =
        server_.options.request_queue + static_cast<std::size_t>(server_.options.request_threads);
    if (++server_.offloaded > limit) {
      --server_.offloaded;
      HttpResponse r = Api::problem(503, "overloaded", "Too many large requests",
                                    "the server is already parsing " + std::to_string(limit) +
                                        " large request bodies; retry after the Retry-After delay");
      r.headers.emplace_back("Retry-After", "1");
      return respond(std::move(r));
    }
    asio::post(server_.request_pool, [self = shared_from_this()] {
      HttpResponse r = self->answer({});
      asio::post(self->stream_.get_executor(), [self, r = std::move(r)]() mutable {
        --self->server_.offloaded;
        self->answered(std::move(r));
      });
    });
  }

  // Waits for the job to change, the deadline, or a one-second re-check (another process may
  // have changed it), whichever is first.
  void park(LongPoll poll) {
    waiting_ = true;
    if (server_.draining) poll.deadline = Clock::now();
    const auto generation = ++wait_generation_;
    auto self = shared_from_this();
    auto wake = [self, generation, poll] {
      asio::post(self->stream_.get_executor(), [self, generation, poll] {
        if (!self->waiting_ || generation != self->wait_generation_) return;
        self->wait_timer_.cancel();
      });
    };
    token_ = server_.service.notifier().subscribe(poll.job_id, wake);
    wait_timer_.expires_at(std::min(poll.deadline, Clock::now() + std::chrono::seconds(1)));
    wait_timer_.async_wait([self, generation, poll](beast::error_code) {
      if (generation != self->wait_generation_) return;
      self->server_.service.notifier().unsubscribe(self->token_);
      self->waiting_ = false;
      LongPoll next = poll;
      if (self->server_.draining) next.deadline = Clock::now();
      self->handle(next);
    });
  }

  void respond(HttpResponse r) {
    auto response = std::make_shared<http::response<http::string_body>>();
    response->version(11);
    response->result(static_cast<unsigned>(r.status));
    response->set(http::field::server, server_.options.server_name);
    if (!r.content_type.empty()) response->set(http::field::content_type, r.content_type);
    response->set("X-Request-Id", request_.request_id);
    for (auto& [name, value] : r.headers)
      response->insert(name, value);
    const bool keep = keep_alive_ && !server_.draining;
    response->keep_alive(keep);
    if (r.stream) {
      record(r);
      return stream(std::move(*response), std::move(r.stream));
    }
    if (request_.method == "HEAD") {
      // The length the GET would have sent, and no body (RFC 9110 §9.3.2).
      response->content_length(r.body.size());
    } else {
      response->body() = std::move(r.body);
      response->prepare_payload();
    }

    record(r);
    stream_.expires_after(server_.options.read_timeout);
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
                        --self->server_.in_flight;
                        if (ec || response->need_eof()) return self->close();
                        self->read();
                      });
  }

  // The metrics and the log line of an answer (for a streamed one, when its head goes out).
  void record(const HttpResponse& r) {
    const double seconds = std::chrono::duration<double>(Clock::now() - started_).count();
    server_.metrics.record_request(r.route, request_.method, r.status, seconds);
    if (log_enabled(LogLevel::info)) {
      const auto q = request_.target.find('?');
      log_event(LogLevel::info, "request",
                {{"request_id", request_.request_id},
                 {"method", request_.method},
                 {"path", request_.target.substr(0, q)},
                 {"route", r.route},
                 {"status", r.status},
                 {"ms", seconds * 1e3}});
    }
  }

  // A chunked response whose body `next` makes piece by piece (HttpResponse::stream): the head,
  // then one chunk per piece, each written before the next is made, so the memory held is one
  // piece; a HEAD gets the head only. Beast's buffer_body answers need_buffer when a piece is
  // written and more are to come.
  struct Streamed {
    http::response<http::buffer_body> message;
    std::optional<http::response_serializer<http::buffer_body>> serializer;
    std::function<bool(std::string&)> next;
    std::string piece;
    bool more = true;
  };

  void stream(http::response<http::string_body> head, std::function<bool(std::string&)> next) {
    auto s = std::make_shared<Streamed>();
    s->message.base() = std::move(head.base());
    s->message.chunked(true);
    s->message.body().data = nullptr;
    s->message.body().more = request_.method != "HEAD";
    s->next = std::move(next);
    s->serializer.emplace(s->message);
    stream_.expires_after(server_.options.read_timeout);
    http::async_write_header(stream_, *s->serializer,
                             [self = shared_from_this(), s](beast::error_code ec, std::size_t) {
                               if (ec) return self->end_stream(true);
                               if (self->request_.method == "HEAD")
                                 return self->end_stream(!s->message.keep_alive());
                               self->stream_piece(s);
                             });
  }

  void stream_piece(const std::shared_ptr<Streamed>& s) {
    s->piece.clear();
    try {
      while (s->more && s->piece.empty())
        s->more = s->next(s->piece);
    } catch (const std::exception& error) {
      log_event(LogLevel::error, "streamed response failed",
                {{"request_id", request_.request_id}, {"error", error.what()}});
      return end_stream(true);  // a chunked body cut short: the client sees it incomplete
    } catch (...) {
      log_event(LogLevel::error, "streamed response failed", {{"request_id", request_.request_id}});
      return end_stream(true);
    }
    s->message.body().data = s->piece.empty() ? nullptr : s->piece.data();
    s->message.body().size = s->piece.size();
    s->message.body().more = s->more;
    stream_.expires_after(server_.options.read_timeout);
    http::async_write(stream_, *s->serializer,
                      [self = shared_from_this(), s](beast::error_code ec, std::size_t) {
                        if (ec == http::error::need_buffer) return self->stream_piece(s);
                        if (ec) return self->end_stream(true);
                        if (!s->serializer->is_done()) return self->stream_piece(s);
                        self->end_stream(!s->message.keep_alive());
                      });
  }

  void end_stream(bool close_connection) {
    --server_.in_flight;
    if (close_connection) return close();
    read();
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    if (waiting_) server_.service.notifier().unsubscribe(token_);
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream_.socket().close(ignored);
    server_.remove(shared_from_this());
  }

  Impl& server_;
  beast::tcp_stream stream_;
  asio::steady_timer wait_timer_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  HttpRequest request_;
  Clock::time_point started_;
  bool keep_alive_ = true;
  bool first_request_ = true;
  bool busy_ = false;
  bool waiting_ = false;
  bool closed_ = false;
  std::uint64_t wait_generation_ = 0;
  std::uint64_t token_ = 0;
};

void HttpServer::Impl::accept() {
  acceptor.async_accept(asio::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec == asio::error::operation_aborted || !acceptor.is_open()) return;
      // Out of file descriptors (or another transient failure): wait before accepting again,
      // doubling the wait up to a second, so a full descriptor table does not spin the loop.
      accept_backoff = std::clamp(accept_backoff * 2, std::chrono::milliseconds(10),
                                  std::chrono::milliseconds(1000));
      log_event(LogLevel::warn, "accept failed",
                {{"error", ec.message()}, {"retry_ms", accept_backoff.count()}});
      accept_timer.expires_after(accept_backoff);
      accept_timer.async_wait([this](beast::error_code wait_ec) {
        if (!wait_ec && !draining) accept();
      });
      return;
    }
    accept_backoff = std::chrono::milliseconds(0);
    if (!draining) {
      beast::error_code ignored;
      socket.set_option(tcp::no_delay(true), ignored);
      std::size_t open = 0;
      {
        std::lock_guard lock(sessions_mutex);
        open = sessions.size();
      }
      if (open >= options.max_connections) {
        reject(std::move(socket));
      } else {
        auto session = std::make_shared<Session>(*this, std::move(socket));
        {
          std::lock_guard lock(sessions_mutex);
          sessions.insert(session);
        }
        session->start();
      }
    }
    if (!draining) accept();
  });
}

// Above the connection cap: a 503 problem and close, without reading the request.
void HttpServer::Impl::reject(tcp::socket socket) {
  ++rejected_connections;
  const HttpResponse problem =
      Api::problem(503, "overloaded", "Too many connections",
                   "the server holds its maximum of " + std::to_string(options.max_connections) +
                       " connections; retry after the Retry-After delay");
  auto text = std::make_shared<std::string>(
      "HTTP/1.1 503 Service Unavailable\r\nServer: " + options.server_name +
      "\r\nContent-Type: application/problem+json\r\nRetry-After: 1\r\nConnection: close"
      "\r\nContent-Length: " +
      std::to_string(problem.body.size()) + "\r\n\r\n" + problem.body);
  auto stream = std::make_shared<beast::tcp_stream>(std::move(socket));
  stream->expires_after(std::chrono::seconds(5));
  asio::async_write(*stream, asio::buffer(*text), [stream, text](beast::error_code, std::size_t) {
    beast::error_code ignored;
    stream->socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream->socket().close(ignored);
  });
}

HttpServer::HttpServer(Api& api, JobService& service, Metrics& metrics, HttpOptions options)
    : impl_(std::make_unique<Impl>(api, service, metrics, std::move(options))) {}

HttpServer::~HttpServer() {
  stop(std::chrono::milliseconds(0));
}

void HttpServer::listen() {
  auto& i = *impl_;
  const std::string where = i.options.bind + ":" + std::to_string(i.options.port);
  beast::error_code ec;
  tcp::resolver resolver(i.ioc);
  auto endpoints = resolver.resolve(i.options.bind, std::to_string(i.options.port),
                                    tcp::resolver::passive | tcp::resolver::numeric_service, ec);
  if (ec || endpoints.empty()) {
    throw std::runtime_error("cannot resolve the bind address " + i.options.bind + ": " +
                             ec.message());
  }
  const tcp::endpoint endpoint = endpoints.begin()->endpoint();
  i.acceptor.open(endpoint.protocol(), ec);
  if (!ec) i.acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) i.acceptor.bind(endpoint, ec);
  if (!ec) i.acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    beast::error_code ignored;
    i.acceptor.close(ignored);
    throw std::runtime_error("cannot listen on " + where + ": " + ec.message());
  }
}

std::uint16_t HttpServer::port() const {
  beast::error_code ec;
  const auto endpoint = impl_->acceptor.local_endpoint(ec);
  return ec ? 0 : endpoint.port();
}

void HttpServer::start() {
  auto& i = *impl_;
  i.accept();
  for (int t = 0; t < std::max(1, i.options.io_threads); ++t) {
    i.threads.emplace_back([&i] { i.ioc.run(); });
  }
}

void HttpServer::stop(std::chrono::milliseconds drain) {
  auto& i = *impl_;
  if (i.threads.empty()) return;
  i.draining = true;
  asio::post(i.ioc, [&i] {
    beast::error_code ignored;
    i.acceptor.close(ignored);
    i.accept_timer.cancel();
  });
  std::vector<std::shared_ptr<Impl::Session>> sessions;
  {
    std::lock_guard lock(i.sessions_mutex);
    sessions.assign(i.sessions.begin(), i.sessions.end());
  }
  for (auto& s : sessions)
    s->drain();
  const auto deadline = Clock::now() + drain;
  while (Clock::now() < deadline) {
    {
      std::lock_guard lock(i.sessions_mutex);
      if (i.sessions.empty() && i.in_flight == 0) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  // Requests still waiting for the pool are dropped (their connections close with the server).
  i.request_pool.stop();
  i.request_pool.join();
  i.ioc.stop();
  for (auto& t : i.threads)
    t.join();
  i.threads.clear();
  std::lock_guard lock(i.sessions_mutex);
  i.sessions.clear();
}

}  // namespace brisance::server
