// server/problem: RFC 9457 problem details, the one way the API reports an error. A problem
// carries a stable type (urn:brisance:problem:TYPE, listed in docs/service.md), a title, the
// status, a detail that names the fix, and optionally a list of errors each pointing at what is
// wrong (a JSON pointer into the request body, or a query parameter). Its body is built once and
// is valid UTF-8 whatever bytes a client sent: text that echoes a request is repaired, never
// allowed to throw.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/http_types.hpp"

namespace brisance::server {

struct Problem {
  int status = 500;
  std::string type;  // without the urn:brisance:problem: prefix
  std::string title;
  std::string detail;
  // Each error as (key, value) pairs in order, e.g. {{"pointer", "/scene/x"}, {"detail", "…"}}.
  std::vector<std::vector<std::pair<std::string, std::string>>> errors;
  std::vector<std::pair<std::string, std::string>> headers;

  Problem& error(std::string_view key, std::string_view value, std::string_view detail_text);
  Problem& header(std::string name, std::string value);
  HttpResponse response() const;
};

Problem problem(int status, std::string_view type, std::string_view title, std::string_view detail);

// The usual answers.
HttpResponse not_found(std::string_view what);
HttpResponse job_not_found(std::string_view id);
// 405 with the Allow header.
HttpResponse method_not_allowed(std::string_view allow);

// A query parameter the handler cannot use; Api turns it into a 400 problem naming it.
struct BadParameter {
  std::string name;
  std::string message;
};

}  // namespace brisance::server
