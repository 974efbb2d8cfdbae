// bench/load/http_connection: load_bench's client side — keep-alive connections on one
// io_context, one request at a time each, timed from each request's scheduled send time.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

namespace brisance::load {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct Request {
  http::verb verb = http::verb::get;
  std::string target;
  const std::string* body = nullptr;  // JSON, or none
};

struct Response {
  int status = 0;     // 0: transport error (see `error`)
  std::string error;  // transport error
  std::string body;
  std::string location;
  double latency_ms = 0;
};

using Done = std::function<void(Response&&)>;

constexpr auto kRequestTimeout = std::chrono::seconds(30);
// The server closes keep-alive connections idle for 60 s; reconnect well before that rather than
// race its close.
constexpr auto kMaxIdle = std::chrono::seconds(20);

class Connection {
 public:
  Connection(asio::io_context& ioc, tcp::endpoint endpoint) : stream_(ioc), endpoint_(endpoint) {}

  // Sends the request; `done` gets the response with its latency measured from `start`.
  void send(const Request& request, Clock::time_point start, Done done) {
    start_ = start;
    done_ = std::move(done);
    request_ = {};
    request_.method(request.verb);
    request_.target(request.target);
    request_.version(11);
    request_.set(http::field::host, "127.0.0.1");
    request_.keep_alive(true);
    if (request.body) {
      request_.set(http::field::content_type, "application/json");
      request_.body() = *request.body;
    }
    request_.prepare_payload();
    if (open_ && Clock::now() - last_used_ > kMaxIdle) close();
    if (open_) return write();
    stream_.expires_after(std::chrono::seconds(10));
    stream_.async_connect(endpoint_, [this](beast::error_code ec) {
      if (ec) return fail(ec, "connect");
      beast::error_code ignored;
      stream_.socket().set_option(tcp::no_delay(true), ignored);
      open_ = true;
      ++connects_;
      write();
    });
  }

  std::size_t connects() const { return connects_; }

 private:
  void write() {
    stream_.expires_after(kRequestTimeout);
    http::async_write(stream_, request_, [this](beast::error_code ec, std::size_t) {
      if (ec) return fail(ec, "write");
      read();
    });
  }

  void read() {
    parser_.emplace();
    parser_->body_limit(std::uint64_t{1} << 30);
    http::async_read(stream_, buffer_, *parser_, [this](beast::error_code ec, std::size_t) {
      if (ec) return fail(ec, "read");
      stream_.expires_never();
      auto& message = parser_->get();
      Response r;
      r.status = static_cast<int>(message.result_int());
      r.body = std::move(message.body());
      if (const auto it = message.find(http::field::location); it != message.end()) {
        r.location = std::string(it->value());
      }
      if (!message.keep_alive()) close();
      last_used_ = Clock::now();
      finish(std::move(r));
    });
  }

  void fail(beast::error_code ec, const char* what) {
    close();
    Response r;
    r.error = std::string(what) + ": " + ec.message();
    finish(std::move(r));
  }

  void finish(Response&& r) {
    r.latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
    Done done = std::move(done_);  // `done` may send the next request on this connection
    done_ = nullptr;
    done(std::move(r));
  }

  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_.socket().close(ignored);
    buffer_.clear();
    open_ = false;
  }

  beast::tcp_stream stream_;
  tcp::endpoint endpoint_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  std::optional<http::response_parser<http::string_body>> parser_;
  Clock::time_point start_;
  Clock::time_point last_used_;
  Done done_;
  bool open_ = false;
  std::size_t connects_ = 0;
};

}  // namespace brisance::load
