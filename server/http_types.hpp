// server/http_types: a request and a response as the API sees them, free of any transport: the
// Beast server (server/http_server) fills a request from the socket and writes the response back.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace brisance::server {

struct HttpRequest {
  std::string method;                                        // "GET", "POST", ...
  std::string target;                                        // path and query, as sent
  std::vector<std::pair<std::string, std::string>> headers;  // names lower-case
  std::string body;
  std::string request_id;

  std::string_view header(std::string_view lower_case_name) const;
};

// A GET /v1/jobs/{id}?wait=S that has nothing new yet: the server waits for the job to change
// (ChangeNotifier) or the deadline, then calls Api::handle again with this state.
struct LongPoll {
  std::string job_id;
  std::string etag;  // the state the client is waiting to see change
  std::chrono::steady_clock::time_point deadline;
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string route = "unmatched";  // route template, for metrics and logs
  std::optional<LongPoll> wait;     // set: not a response yet, wait and ask again
  // Set: the body is made piece by piece and sent chunked (`body` is ignored), so a large
  // result is never whole in memory. Each call appends the next piece to `out` and returns
  // whether more follow; it runs on the connection's I/O thread, so a piece must be cheap to
  // make. A throw ends the connection (the status line is already sent).
  std::function<bool(std::string& out)> stream;
};

}  // namespace brisance::server
