// server/problem: see problem.hpp.
#include "server/problem.hpp"

#include <nlohmann/json.hpp>

namespace brisance::server {
namespace {

// Problem types (RFC 9457 `type`): stable URNs, listed with their meaning in docs/service.md and
// api/openapi.yaml.
constexpr std::string_view kProblemPrefix = "urn:brisance:problem:";

}  // namespace

Problem& Problem::error(std::string_view key, std::string_view value,
                        std::string_view detail_text) {
  errors.push_back({{std::string(key), std::string(value)}, {"detail", std::string(detail_text)}});
  return *this;
}

Problem& Problem::header(std::string name, std::string value) {
  headers.emplace_back(std::move(name), std::move(value));
  return *this;
}

HttpResponse Problem::response() const {
  using nlohmann::json;
  json body{{"type", std::string(kProblemPrefix) + type},
            {"title", title},
            {"status", status},
            {"detail", detail}};
  if (!errors.empty()) {
    json list = json::array();
    for (const auto& fields : errors) {
      json item = json::object();
      for (const auto& [key, value] : fields)
        item[key] = value;
      list.push_back(std::move(item));
    }
    body["errors"] = std::move(list);
  }
  HttpResponse r;
  r.status = status;
  r.content_type = "application/problem+json";
  // A detail may echo bytes a client sent (a parameter, a job id): invalid UTF-8 is replaced
  // with U+FFFD instead of throwing.
  r.body = body.dump(-1, ' ', false, json::error_handler_t::replace);
  r.headers = headers;
  return r;
}

Problem problem(int status, std::string_view type, std::string_view title,
                std::string_view detail) {
  return Problem{status, std::string(type), std::string(title), std::string(detail), {}, {}};
}

HttpResponse not_found(std::string_view what) {
  return problem(404, "not-found", "Not found", what).response();
}

HttpResponse job_not_found(std::string_view id) {
  return not_found("no job '" + std::string(id) + "' (it may have been deleted or pruned)");
}

HttpResponse method_not_allowed(std::string_view allow) {
  return problem(405, "method-not-allowed", "Method not allowed",
                 "this resource accepts " + std::string(allow))
      .header("Allow", std::string(allow))
      .response();
}

}  // namespace brisance::server
