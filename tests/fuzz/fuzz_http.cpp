// fuzz_http: raw bytes as one HTTP/1.1 request, parsed by Beast's request parser as the server's
// sessions parse it (server/http_server.cpp: same body limit, same conversion to HttpRequest),
// then answered by server::Api against a real JobService on a SQLite file in a temporary folder
// (no sockets, no workers: submitted jobs stay queued). No request may crash the process or be
// answered 500 (every failure the API can foresee has a 4xx problem); every problem is
// application/problem+json whose body parses and repeats the status.
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <boost/asio/buffer.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "server/api.hpp"
#include "server/log.hpp"
#include "server/sqlite_storage.hpp"

namespace {

namespace http = boost::beast::http;
using namespace brisance::server;

constexpr std::size_t kBodyLimit = 1 << 20;

struct Service {
  std::filesystem::path dir;
  std::unique_ptr<Storage> storage;
  std::unique_ptr<JobService> jobs;
  Metrics metrics;
  ApiKeys keys;
  std::unique_ptr<Api> api;

  Service() {
    const std::filesystem::path shm("/dev/shm");
    dir = (std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path()) /
          ("brisance-fuzz-http-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    SqliteOptions store;
    store.file = dir / "brisance.sqlite3";
    storage = open_sqlite_storage(store);
    jobs = std::make_unique<JobService>(*storage, ServiceOptions{});
    ApiOptions options;
    options.body_limit_bytes = kBodyLimit;
    options.max_wait = std::chrono::seconds(1);
    api = std::make_unique<Api>(
        *jobs, metrics, keys,
        [] {
          return WorkerGauges{0, 1};
        },
        options);
  }
  ~Service() {
    api.reset();
    jobs.reset();
    storage.reset();
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

void check(bool condition) {
  if (!condition) std::abort();
}

// The body as the session sends it: a streamed one (frames) made piece by piece, as the
// session's write loop does.
std::string body_of(const HttpResponse& response) {
  if (!response.stream) return response.body;
  std::string body, piece;
  for (bool more = true; more;) {
    piece.clear();
    more = response.stream(piece);
    body += piece;
  }
  return body;
}

void check_response(const HttpResponse& response) {
  check(response.status >= 200 && response.status <= 599);
  check(response.status != 500);
  const std::string body = body_of(response);
  if (response.status >= 400) {
    check(response.content_type == "application/problem+json");
    const nlohmann::json problem = nlohmann::json::parse(body);
    check(problem.at("status") == response.status);
    check(problem.at("type").is_string() && problem.at("title").is_string());
  } else if (response.content_type == "application/json" && !body.empty()) {
    (void)nlohmann::json::parse(body);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  set_log_level(LogLevel::error);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Service service;
  http::request_parser<http::string_body> parser;
  parser.body_limit(kBodyLimit);
  parser.eager(true);
  boost::beast::error_code ec;
  parser.put(boost::asio::buffer(data, size), ec);
  if (!ec && !parser.is_done()) parser.put_eof(ec);
  if (ec || !parser.is_done()) return 0;  // the session answers 400/413 without the API
  auto& message = parser.get();
  // As the session does (RFC 9112 §6.1): a non-chunked Transfer-Encoding is refused before the
  // API sees the request.
  if (message.find(http::field::transfer_encoding) != message.end() && !message.chunked()) return 0;
  HttpRequest request;
  request.method = std::string(message.method_string());
  request.target = std::string(message.target());
  for (const auto& field : message) {
    std::string name(field.name_string());
    for (char& c : name)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    request.headers.emplace_back(std::move(name), std::string(field.value()));
  }
  request.body = std::move(message.body());
  request.request_id = "fuzz";
  HttpResponse response = service.api->handle(request);
  if (response.wait) {
    // A long-poll with nothing new: the session waits, then asks again at the deadline.
    LongPoll poll = *response.wait;
    poll.deadline = std::chrono::steady_clock::now();
    response = service.api->handle(request, poll);
    check(!response.wait);
  }
  check_response(response);
  return 0;
}
