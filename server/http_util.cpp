// server/http_util: see http_util.hpp. This is the one translation unit that compiles Boost.URL
// (header-only mode: Debian's libboost1.81-dev ships its sources, not a library to link).
#include "server/http_util.hpp"

#include <charconv>
#include <cmath>

#include <boost/url/parse.hpp>
#include <boost/url/src.hpp>  // NOLINT: compiles Boost.URL into this translation unit
#include <boost/url/url_view.hpp>

#include "server/problem.hpp"
#include "server/sha256.hpp"

namespace brisance::server {

std::string_view HttpRequest::header(std::string_view lower_case_name) const {
  for (const auto& [name, value] : headers) {
    if (name == lower_case_name) return value;
  }
  return {};
}

std::optional<std::string_view> Target::get(std::string_view name) const {
  auto it = query.find(name);
  if (it == query.end()) return std::nullopt;
  return std::string_view(it->second);
}

std::optional<Target> parse_target(std::string_view text) {
  const auto parsed = boost::urls::parse_origin_form(text);
  if (!parsed) return std::nullopt;
  const boost::urls::url_view url = *parsed;
  Target target;
  for (const std::string segment : url.segments()) {
    if (segment.empty()) continue;
    target.path += '/';
    target.path += segment;
    target.segments.push_back(segment);
  }
  if (target.path.empty()) target.path = "/";
  for (const auto& param : url.params(boost::urls::encoding_opts(true))) {
    if (!param.key.empty()) target.query[param.key] = param.has_value ? param.value : std::string();
  }
  return target;
}

bool boolean_param(const Target& t, std::string_view name, bool fallback) {
  const auto text = t.get(name);
  if (!text) return fallback;
  if (*text == "true") return true;
  if (*text == "false") return false;
  throw BadParameter{std::string(name), "'" + std::string(name) + "' must be true or false"};
}

std::int64_t integer_param(const Target& t, std::string_view name, std::int64_t fallback,
                           std::int64_t lo, std::int64_t hi) {
  const auto text = t.get(name);
  if (!text) return fallback;
  std::int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec != std::errc() || ptr != text->data() + text->size() || value < lo || value > hi) {
    throw BadParameter{std::string(name), "'" + std::string(name) + "' must be an integer from " +
                                              std::to_string(lo) + " to " + std::to_string(hi)};
  }
  return value;
}

std::optional<double> number_param(const Target& t, std::string_view name) {
  const auto text = t.get(name);
  if (!text) return std::nullopt;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec != std::errc() || ptr != text->data() + text->size() || !std::isfinite(value)) {
    throw BadParameter{std::string(name), "'" + std::string(name) + "' must be a finite number"};
  }
  return value;
}

std::string body_etag(std::string_view body) {
  return "\"" + sha256_hex(body).substr(0, 32) + "\"";
}

bool etag_matches(std::string_view if_none_match, std::string_view etag) {
  if (if_none_match.empty()) return false;
  while (!if_none_match.empty()) {
    const auto comma = if_none_match.find(',');
    std::string_view tag = if_none_match.substr(0, comma);
    while (!tag.empty() && (tag.front() == ' ' || tag.front() == '\t'))
      tag.remove_prefix(1);
    while (!tag.empty() && (tag.back() == ' ' || tag.back() == '\t'))
      tag.remove_suffix(1);
    if (tag.rfind("W/", 0) == 0) tag.remove_prefix(2);
    if (tag == "*" || tag == etag) return true;
    if (comma == std::string_view::npos) break;
    if_none_match.remove_prefix(comma + 1);
  }
  return false;
}

HttpResponse json_text_response(int status, std::string body) {
  HttpResponse r;
  r.status = status;
  r.body = std::move(body);
  return r;
}

HttpResponse not_modified(std::string etag) {
  HttpResponse r;
  r.status = 304;
  r.content_type.clear();
  r.headers.emplace_back("ETag", std::move(etag));
  return r;
}

HttpResponse etagged(const HttpRequest& request, std::string body) {
  std::string etag = body_etag(body);
  if (etag_matches(request.header("if-none-match"), etag)) return not_modified(std::move(etag));
  HttpResponse r;
  r.body = std::move(body);
  r.headers.emplace_back("ETag", std::move(etag));
  r.headers.emplace_back("Cache-Control", "no-cache");
  return r;
}

}  // namespace brisance::server
