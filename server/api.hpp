// server/api: the HTTP API as a pure function from request to response (STYLE.md §15): routing,
// authentication, parameters, JSON bodies and RFC 9457 problems. The Beast server
// (server/http_server) does the I/O; this file knows no sockets, so tests drive it directly.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/api_keys.hpp"
#include "server/free_space.hpp"
#include "server/http_types.hpp"
#include "server/job_service.hpp"
#include "server/metrics.hpp"

namespace brisance::server {

struct ApiOptions {
  // The data folder's free space against its floor: below it, submissions get 507 and /readyz
  // says not ready. nullptr: not checked.
  std::shared_ptr<FreeSpace> free_space;
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
  // Finds and runs the handler; `label` gets the matched route template.
  HttpResponse route(const HttpRequest& request, const std::optional<LongPoll>& poll,
                     std::string& label);

  JobService& service_;
  Metrics& metrics_;
  const ApiKeys& keys_;
  std::function<WorkerGauges()> workers_;
  ApiOptions options_;
};

}  // namespace brisance::server
