// server/http_util: what every handler needs of a request and a response — the target split into
// decoded path segments and query parameters (Boost.URL), typed query parameters, ETags and
// conditional requests, JSON bodies.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/http_types.hpp"

namespace brisance::server {

// A request target in origin form. Path segments are percent-decoded one by one (so "%2F" stays
// inside its segment and "+" stays "+"); query names and values are decoded as HTML forms send
// them ("+" is a space, "%2B" a plus sign). A repeated parameter keeps its last value.
struct Target {
  std::string path;                   // "/" + the segments joined by "/"
  std::vector<std::string> segments;  // decoded, empty segments dropped
  std::map<std::string, std::string, std::less<>> query;

  std::optional<std::string_view> get(std::string_view name) const;
};

// nullopt when the target is not a valid origin-form target (RFC 9112 §3.2.1).
std::optional<Target> parse_target(std::string_view target);

// Typed query parameters; a bad value throws BadParameter (a 400 problem naming it).
std::int64_t integer_param(const Target& t, std::string_view name, std::int64_t fallback,
                           std::int64_t lo, std::int64_t hi);
std::optional<double> number_param(const Target& t, std::string_view name);
// "true" or "false" (absent: `fallback`).
bool boolean_param(const Target& t, std::string_view name, bool fallback);

// A strong ETag from the representation itself, for lists and the queue view.
std::string body_etag(std::string_view body);
// If-None-Match: "*" or a comma-separated list of entity tags (weak ones compared weakly).
bool etag_matches(std::string_view if_none_match, std::string_view etag);

HttpResponse json_text_response(int status, std::string body);
HttpResponse not_modified(std::string etag);
// A cacheable JSON response validated by an ETag of its body (304 when the client has it).
HttpResponse etagged(const HttpRequest& request, std::string body);

}  // namespace brisance::server
