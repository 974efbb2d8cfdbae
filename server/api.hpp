// server/api: the HTTP API as a pure function from request to response (STYLE.md §15): routing,
// authentication, parameters, JSON bodies and RFC 9457 problems. The Beast server
// (server/http_server) does the I/O; this file knows no sockets, so tests drive it directly.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/api_keys.hpp"
#include "server/job_service.hpp"
#include "server/metrics.hpp"

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
};

struct ApiOptions {
  std::size_t body_limit_bytes = 16 * 1024 * 1024;  // for the 413 problem's detail
  std::chrono::seconds max_wait{30};
  // Static files of the dashboard by path ("index.html"); nullptr: no dashboard.
  std::function<std::optional<std::pair<std::string, std::string>>(std::string_view)>
      static_file;  // returns (content type, bytes)
};

class Api {
 public:
  Api(JobService& service, Metrics& metrics, const ApiKeys& keys,
      std::function<WorkerGauges()> workers, ApiOptions options);

  HttpResponse handle(const HttpRequest& request, const std::optional<LongPoll>& poll = {});

  // Problems the transport itself raises (body too large, malformed HTTP, timeouts).
  static HttpResponse problem(int status, std::string_view type, std::string_view title,
                              std::string_view detail);

 private:
  HttpResponse route(const HttpRequest& request, const std::optional<LongPoll>& poll);

  JobService& service_;
  Metrics& metrics_;
  const ApiKeys& keys_;
  std::function<WorkerGauges()> workers_;
  ApiOptions options_;
};

}  // namespace brisance::server
