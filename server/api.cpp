#include "server/api.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ctime>
#include <map>
#include <numbers>

#include <nlohmann/json.hpp>

#include "server/embedded.hpp"
#include "server/log.hpp"
#include "server/sha256.hpp"
#include "sim/blast/blast_point.hpp"
#include "sim/blast/explosives.hpp"
#include "sim/io/blast_json.hpp"
#include "sim/io/gltf.hpp"

namespace brisance::server {

using nlohmann::json;

std::string_view HttpRequest::header(std::string_view lower_case_name) const {
  for (const auto& [name, value] : headers) {
    if (name == lower_case_name) return value;
  }
  return {};
}

namespace {

// Problem types (RFC 9457 `type`): stable URNs, listed with their meaning in docs/service.md
// and api/openapi.yaml.
constexpr std::string_view kProblemPrefix = "urn:brisance:problem:";

struct BadParameter {
  std::string name;
  std::string message;
};

std::string percent_decode(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '+') {
      out.push_back(' ');
    } else if (c == '%' && i + 2 < text.size()) {
      int value = 0;
      const auto [ptr, ec] = std::from_chars(text.data() + i + 1, text.data() + i + 3, value, 16);
      if (ec == std::errc() && ptr == text.data() + i + 3) {
        out.push_back(static_cast<char>(value));
        i += 2;
      } else {
        out.push_back(c);
      }
    } else {
      out.push_back(c);
    }
  }
  return out;
}

struct Target {
  std::string path;
  std::map<std::string, std::string, std::less<>> query;

  std::optional<std::string_view> get(std::string_view name) const {
    auto it = query.find(name);
    if (it == query.end()) return std::nullopt;
    return std::string_view(it->second);
  }
};

Target parse_target(std::string_view target) {
  Target t;
  const auto q = target.find('?');
  t.path = percent_decode(target.substr(0, q));
  if (q == std::string_view::npos) return t;
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    const auto eq = pair.find('=');
    const std::string key = percent_decode(pair.substr(0, eq));
    const std::string value =
        eq == std::string_view::npos ? "" : percent_decode(pair.substr(eq + 1));
    if (!key.empty()) t.query[key] = value;
    if (amp == std::string_view::npos) break;
    rest = rest.substr(amp + 1);
  }
  return t;
}

std::vector<std::string_view> split_path(std::string_view path) {
  std::vector<std::string_view> parts;
  while (!path.empty()) {
    if (path.front() == '/') {
      path.remove_prefix(1);
      continue;
    }
    const auto slash = path.find('/');
    parts.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash);
  }
  return parts;
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

std::string iso_time(std::int64_t ms) {
  return iso_time_utc(ms);
}

std::string job_path(std::string_view id) {
  return "/v1/jobs/" + std::string(id);
}

// The job's JSON, written as text: it is the most requested representation, and building a DOM
// for it (and re-parsing the stored stats) cost more than the database read. Keys are in
// nlohmann's sorted order so the text equals what a DOM would dump.
std::string job_json(const JobRecord& job) {
  const auto time_or_null = [](const std::optional<std::int64_t>& ms) {
    return ms ? "\"" + iso_time(*ms) + "\"" : std::string("null");
  };
  const std::string self = job_path(job.id);
  std::string out;
  out.reserve(640 + job.stats_json.size() + job.error.size());
  out += "{\"attempts\":" + std::to_string(job.attempts);
  out += ",\"cancel_requested\":";
  out += job.cancel_requested ? "true" : "false";
  out += ",\"created_at\":\"" + iso_time(job.created_ms) + "\"";
  out += ",\"error\":";
  if (job.error_type.empty()) {
    out += "null";
  } else {
    out += json{{"message", job.error}, {"type", job.error_type}}.dump();
  }
  out += ",\"finished_at\":" + time_or_null(job.finished_ms);
  out += ",\"id\":\"" + job.id + "\"";
  out += ",\"links\":{\"cancel\":\"" + self + "/cancel\"";
  if (job.status == JobStatus::succeeded) {
    out += ",\"frames\":\"" + self + "/frames\",\"glb\":\"" + self + "/result.glb\",\"meshes\":\"" +
           self + "/meshes\",\"result\":\"" + self + "/result\"";
  }
  out += ",\"scene\":\"" + self + "/scene\",\"self\":\"" + self + "\"}";
  out += ",\"priority\":" + std::to_string(job.priority);
  out += ",\"progress\":" + json(job.progress).dump();
  out += ",\"started_at\":" + time_or_null(job.started_ms);
  out += ",\"stats\":" + (job.stats_json.empty() ? std::string("null") : job.stats_json);
  out += ",\"status\":\"" + std::string(to_string(job.status)) + "\"";
  out += ",\"updated_at\":\"" + iso_time(job.updated_ms) + "\"}";
  return out;
}

HttpResponse json_text_response(int status, std::string body) {
  HttpResponse r;
  r.status = status;
  r.body = std::move(body);
  return r;
}

std::string job_etag(const JobRecord& job) {
  return "\"" + job.id + "." + std::to_string(job.version) + "\"";
}

// A strong ETag from the representation itself, for lists and the queue view.
std::string body_etag(std::string_view body) {
  return "\"" + sha256_hex(body).substr(0, 32) + "\"";
}

// If-None-Match: "*" or a comma-separated list of entity tags (weak ones compared weakly).
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

template <typename Json>
HttpResponse json_response(int status, const Json& body) {
  HttpResponse r;
  r.status = status;
  r.body = body.dump();
  return r;
}

HttpResponse not_modified(std::string etag) {
  HttpResponse r;
  r.status = 304;
  r.content_type.clear();
  r.headers.emplace_back("ETag", std::move(etag));
  return r;
}

// A cacheable JSON response validated by an ETag of its body.
HttpResponse etagged(const HttpRequest& request, std::string body) {
  std::string etag = body_etag(body);
  if (etag_matches(request.header("if-none-match"), etag)) return not_modified(std::move(etag));
  HttpResponse r;
  r.body = std::move(body);
  r.headers.emplace_back("ETag", std::move(etag));
  r.headers.emplace_back("Cache-Control", "no-cache");
  return r;
}

HttpResponse not_found(std::string_view what) {
  return Api::problem(404, "not-found", "Not found", what);
}

HttpResponse job_not_found(std::string_view id) {
  return not_found("no job '" + std::string(id) + "' (it may have been deleted or pruned)");
}

HttpResponse method_not_allowed(std::string_view allow) {
  HttpResponse r = Api::problem(405, "method-not-allowed", "Method not allowed",
                                "this resource accepts " + std::string(allow));
  r.headers.emplace_back("Allow", std::string(allow));
  return r;
}

std::vector<std::uint32_t> parse_body_list(const Target& t, std::size_t body_count) {
  std::vector<std::uint32_t> out;
  const auto text = t.get("bodies");
  if (!text) return out;
  std::string_view rest = *text;
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    std::uint32_t value = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (ec != std::errc() || ptr != item.data() + item.size() || value >= body_count) {
      throw BadParameter{"bodies",
                         "'bodies' must be a comma-separated list of body indices "
                         "from 0 to " +
                             std::to_string(body_count - 1)};
    }
    out.push_back(value);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return out;
}

void append_u32(std::string& out, std::uint32_t v) {
  char bytes[4];
  for (int i = 0; i < 4; ++i)
    bytes[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  out.append(bytes, 4);
}

template <typename T>
void append_raw(std::string& out, T value) {
  // The binary frame format is little-endian; so is every machine this builds for (x86-64,
  // aarch64), which a static_assert in the frames handler checks.
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

std::string_view route_template(const std::vector<std::string_view>& parts) {
  if (parts.size() >= 2 && parts[0] == "v1" && parts[1] == "jobs") {
    if (parts.size() == 2) return "/v1/jobs";
    if (parts.size() == 3) return "/v1/jobs/{id}";
    if (parts.size() == 4) {
      if (parts[3] == "cancel") return "/v1/jobs/{id}/cancel";
      if (parts[3] == "scene") return "/v1/jobs/{id}/scene";
      if (parts[3] == "result") return "/v1/jobs/{id}/result";
      if (parts[3] == "frames") return "/v1/jobs/{id}/frames";
      if (parts[3] == "meshes") return "/v1/jobs/{id}/meshes";
      if (parts[3] == "result.glb") return "/v1/jobs/{id}/result.glb";
    }
  }
  return {};
}

}  // namespace

HttpResponse Api::problem(int status, std::string_view type, std::string_view title,
                          std::string_view detail) {
  HttpResponse r;
  r.status = status;
  r.content_type = "application/problem+json";
  r.body = json{
      {"type", std::string(kProblemPrefix) + std::string(type)},
      {"title", title},
      {"status", status},
      {"detail",
       detail}}.dump();
  return r;
}

Api::Api(JobService& service, Metrics& metrics, const ApiKeys& keys,
         std::function<WorkerGauges()> workers, ApiOptions options)
    : service_(service),
      metrics_(metrics),
      keys_(keys),
      workers_(std::move(workers)),
      options_(std::move(options)) {}

// The route template a path falls under, for the metrics of requests that failed early.
static std::string route_label(std::string_view target) {
  const Target t = parse_target(target);
  if (t.path == "/metrics" || t.path == "/openapi.yaml") return t.path;
  const auto parts = split_path(t.path);
  if (const std::string_view tmpl = route_template(parts); !tmpl.empty()) return std::string(tmpl);
  if (parts.size() == 2 && parts[0] == "v1") return "/v1/" + std::string(parts[1]);
  return "unmatched";
}

HttpResponse Api::handle(const HttpRequest& request, const std::optional<LongPoll>& poll) {
  HttpResponse response;
  bool failed = true;
  try {
    response = route(request, poll);
    failed = false;
  } catch (const BadParameter& bad) {
    response = problem(400, "invalid-parameter", "Invalid query parameter", bad.message);
    json body = json::parse(response.body);
    body["errors"] = json::array({json{{"parameter", bad.name}, {"detail", bad.message}}});
    response.body = body.dump();
  } catch (const StorageError&) {
    response = problem(503, "storage-unavailable", "Storage unavailable",
                       "the job store could not complete the request; retry later");
    response.headers.emplace_back("Retry-After", "1");
  } catch (const std::exception&) {
    response = problem(500, "internal-error", "Internal error",
                       "the server failed to answer this request; the request id is in the "
                       "X-Request-Id header and the server log");
  }
  // Early answers (401, 403, 405) and failures still count under their route.
  if (failed || response.route == "unmatched") response.route = route_label(request.target);
  return response;
}

HttpResponse Api::route(const HttpRequest& request, const std::optional<LongPoll>& poll) {
  const Target target = parse_target(request.target);
  const std::vector<std::string_view> parts = split_path(target.path);
  const std::string& method = request.method;
  const bool get = method == "GET" || method == "HEAD";

  // Unauthenticated probes.
  if (target.path == "/healthz") {
    HttpResponse r = json_response(200, json{{"status", "ok"}});
    r.route = "/healthz";
    return r;
  }
  if (target.path == "/readyz") {
    const bool db = service_.database_ok();
    const WorkerGauges workers = workers_ ? workers_() : WorkerGauges{};
    const bool ready = db && workers.total > 0;
    HttpResponse r =
        json_response(ready ? 200 : 503, json{{"status", ready ? "ready" : "not ready"},
                                              {"database", db ? "ok" : "unreachable"},
                                              {"workers", workers.total}});
    r.route = "/readyz";
    return r;
  }

  // The dashboard's static files carry no data; the dashboard asks for the key itself.
  const bool api_path = (!parts.empty() && parts[0] == "v1") || target.path == "/metrics" ||
                        target.path == "/openapi.yaml";
  if (!api_path) {
    if (!get) return method_not_allowed("GET, HEAD");
    if (options_.static_file) {
      std::string_view path = target.path;
      while (!path.empty() && path.front() == '/')
        path.remove_prefix(1);
      if (path.empty()) path = "index.html";
      if (auto file = options_.static_file(path)) {
        HttpResponse r;
        r.route = "/{static}";
        r.content_type = std::string(file->first);
        r.body = std::string(file->second);
        r.headers.emplace_back("Cache-Control", "no-cache");
        return r;
      }
    }
    HttpResponse r = not_found("no resource at " + target.path);
    r.route = "unmatched";
    return r;
  }

  if (keys_.enabled()) {
    const std::string_view auth = request.header("authorization");
    constexpr std::string_view kBearer = "Bearer ";
    std::optional<ApiKey> key;
    if (auth.size() > kBearer.size() && auth.substr(0, kBearer.size()) == kBearer) {
      key = keys_.authenticate(auth.substr(kBearer.size()));
    }
    if (!key) {
      HttpResponse r = problem(401, "unauthorized", "API key required",
                               "send a valid key as 'Authorization: Bearer KEY'");
      r.headers.emplace_back("WWW-Authenticate", "Bearer realm=\"brisance\"");
      return r;
    }
    if (!get && key->scope != Scope::write) {
      return problem(403, "forbidden", "Write scope required",
                     "the API key '" + key->name + "' may only read");
    }
  }

  if (target.path == "/metrics") {
    if (!get) return method_not_allowed("GET, HEAD");
    HttpResponse r;
    r.route = "/metrics";
    r.content_type = "text/plain; version=0.0.4; charset=utf-8";
    r.body = metrics_.render(service_.queue_counts(), workers_ ? workers_() : WorkerGauges{});
    return r;
  }
  if (target.path == "/openapi.yaml") {
    if (!get) return method_not_allowed("GET, HEAD");
    HttpResponse r;
    r.route = "/openapi.yaml";
    r.content_type = "application/yaml";
    for (const EmbeddedFile& file : embedded_api()) {
      if (file.name == "openapi.yaml") r.body = std::string(file.data);
    }
    return r;
  }

  if (parts.size() == 2 && parts[1] == "queue") {
    if (!get) return method_not_allowed("GET, HEAD");
    const QueueCounts counts = service_.queue_counts();
    const WorkerGauges workers = workers_ ? workers_() : WorkerGauges{};
    json by_status = json::object();
    for (JobStatus s : {JobStatus::queued, JobStatus::running, JobStatus::succeeded,
                        JobStatus::failed, JobStatus::cancelled}) {
      by_status[std::string(to_string(s))] = counts.by_status[static_cast<std::size_t>(s)];
    }
    json oldest = nullptr;
    if (counts.oldest_queued_created_ms) {
      oldest = json{
          {"created_at", iso_time(*counts.oldest_queued_created_ms)},
          {"age_s",
           std::max<double>(
               0.0, static_cast<double>(now_ms() - *counts.oldest_queued_created_ms) / 1000.0)}};
    }
    HttpResponse r = etagged(request, json{{"counts", by_status},
                                           {"workers",
                                            {{"total", workers.total},
                                             {"busy", workers.busy},
                                             {"idle", workers.total - workers.busy}}},
                                           {"oldest_queued", oldest},
                                           {"throughput_per_min", counts.finished_last_minute}}
                                          .dump());
    r.route = "/v1/queue";
    return r;
  }

  if (parts.size() == 2 && parts[1] == "explosives") {
    if (!get) return method_not_allowed("GET, HEAD");
    json list = json::array();
    for (const blast::Explosive& e : blast::known_explosives()) {
      list.push_back(json{{"name", e.name},
                          {"tnt_factor", e.tnt_factor},
                          {"basis", e.basis},
                          {"source", e.source}});
    }
    HttpResponse r = etagged(request, json{{"explosives", list}}.dump());
    r.route = "/v1/explosives";
    return r;
  }

  if (parts.size() == 2 && parts[1] == "blast") {
    if (!get) return method_not_allowed("GET, HEAD");
    HttpResponse r = [&] {
      const auto charge = number_param(target, "charge_kg");
      const auto distance = number_param(target, "distance_m");
      if (!charge || *charge <= 0.0) {
        throw BadParameter{"charge_kg", "'charge_kg' is required: the charge mass in kg (> 0)"};
      }
      if (!distance || *distance <= 0.0) {
        throw BadParameter{"distance_m",
                           "'distance_m' is required: the distance from the charge in m (> 0)"};
      }
      blast::Charge c;
      double factor = 1.0;
      if (auto name = target.get("explosive")) {
        auto explosive = blast::find_explosive(*name);
        if (!explosive) {
          throw BadParameter{"explosive", "unknown explosive '" + std::string(*name) +
                                              "'; known: " + blast::known_explosive_names()};
        }
        factor = explosive->tnt_factor;
      }
      if (auto burst = target.get("burst")) {
        if (*burst == "surface") {
          c.burst = blast::Burst::surface;
        } else if (*burst != "air") {
          throw BadParameter{"burst", "'burst' must be 'air' or 'surface'"};
        }
      }
      const double angle = number_param(target, "angle_deg").value_or(0.0);
      if (angle < 0.0 || angle > 90.0) {
        throw BadParameter{"angle_deg", "'angle_deg' must be between 0 and 90"};
      }
      c.tnt_equivalent_kg = *charge * factor;
      const blast::BlastPoint point = blast::blast_point(c, *distance);
      return json_response(
          200, io::blast_report_json(point, io::reflect(point, angle * std::numbers::pi / 180.0)));
    }();
    r.route = "/v1/blast";
    return r;
  }

  const std::string_view tmpl = route_template(parts);
  if (tmpl.empty()) return not_found("no resource at " + target.path);
  HttpResponse r;
  if (tmpl == "/v1/jobs") {
    if (method == "POST") {
      const std::string_view content_type = request.header("content-type");
      if (!content_type.empty() && content_type.find("json") == std::string_view::npos) {
        r = problem(415, "unsupported-media-type", "Unsupported media type",
                    "send the job as application/json");
      } else {
        const std::string_view key = request.header("idempotency-key");
        if (key.size() > 255) {
          r = problem(400, "invalid-parameter", "Invalid Idempotency-Key",
                      "the Idempotency-Key header must be at most 255 characters");
        } else {
          SubmitOutcome outcome = service_.submit({request.body, key});
          using Kind = SubmitOutcome::Kind;
          switch (outcome.kind) {
            case Kind::accepted:
            case Kind::existing: {
              r = json_text_response(outcome.kind == Kind::accepted ? 202 : 200,
                                     job_json(outcome.job));
              r.headers.emplace_back("Location", job_path(outcome.job.id));
              r.headers.emplace_back("Retry-After", "1");
              r.headers.emplace_back("ETag", job_etag(outcome.job));
              break;
            }
            case Kind::malformed:
              r = problem(400, "malformed-json", "Malformed JSON", outcome.message);
              break;
            case Kind::invalid: {
              r = problem(422, "invalid-scene", "Invalid job",
                          std::to_string(outcome.errors.size()) +
                              " problem(s) in the job; each is listed in 'errors' with a JSON "
                              "pointer into the request body");
              json body = json::parse(r.body);
              json errors = json::array();
              for (const auto& e : outcome.errors) {
                errors.push_back(json{{"pointer", e.pointer}, {"detail", e.message}});
              }
              body["errors"] = std::move(errors);
              r.body = body.dump();
              break;
            }
            case Kind::key_conflict:
              r = problem(422, "idempotency-key-reused", "Idempotency key reused",
                          "this Idempotency-Key was used for a different request body (job " +
                              outcome.job.id + "); use a new key for a new job");
              break;
            case Kind::queue_full:
              r = problem(429, "queue-full", "Queue full",
                          "the queue holds its maximum of " +
                              std::to_string(service_.options().max_queue) +
                              " waiting jobs; retry after the Retry-After delay");
              r.headers.emplace_back("Retry-After", "5");
              break;
          }
        }
      }
    } else if (get) {
      std::optional<JobStatus> status;
      if (auto text = target.get("status")) {
        status = parse_job_status(*text);
        if (!status) {
          throw BadParameter{"status",
                             "'status' must be one of queued, running, succeeded, "
                             "failed, cancelled"};
        }
      }
      const int limit = static_cast<int>(integer_param(target, "limit", 50, 1, 500));
      const std::int64_t cursor = integer_param(target, "cursor", 0, 0, INT64_MAX);
      const JobPage page = service_.list(status, cursor, limit);
      std::string body = "{\"jobs\":[";
      for (std::size_t i = 0; i < page.jobs.size(); ++i) {
        if (i > 0) body += ',';
        body += job_json(page.jobs[i]);
      }
      body += "],\"next_cursor\":";
      body += page.cursor ? "\"" + std::to_string(*page.cursor) + "\"" : std::string("null");
      body += '}';
      if (page.cursor) {
        std::string next =
            "/v1/jobs?limit=" + std::to_string(limit) + "&cursor=" + std::to_string(*page.cursor);
        if (status) next += "&status=" + std::string(to_string(*status));
        r.headers.emplace_back("Link", "<" + next + ">; rel=\"next\"");
      }
      const auto link = r.headers;
      r = etagged(request, std::move(body));
      r.headers.insert(r.headers.end(), link.begin(), link.end());
    } else {
      r = method_not_allowed("GET, HEAD, POST");
    }
    r.route = std::string(tmpl);
    return r;
  }

  const std::string id(parts[2]);
  if (tmpl == "/v1/jobs/{id}") {
    if (get) {
      auto job = service_.job(id);
      if (!job) {
        r = job_not_found(id);
      } else {
        const std::string etag = job_etag(*job);
        const std::string_view if_none_match = request.header("if-none-match");
        const auto wait_s = integer_param(target, "wait", 0, 0, options_.max_wait.count());
        // Long-poll: wait while the job is as the client last saw it (If-None-Match) or, without
        // one, as it was when the wait began.
        const std::string& watched =
            poll ? poll->etag : (if_none_match.empty() ? etag : std::string(if_none_match));
        const bool unchanged = poll ? etag == poll->etag : etag_matches(watched, etag);
        const bool expired = poll && std::chrono::steady_clock::now() >= poll->deadline;
        if (wait_s > 0 && unchanged && !is_final(job->status) && !expired) {
          r.wait = LongPoll{id, etag,
                            poll ? poll->deadline
                                 : std::chrono::steady_clock::now() + std::chrono::seconds(wait_s)};
        } else if (etag_matches(if_none_match, etag)) {
          r = not_modified(etag);
        } else {
          r = json_text_response(200, job_json(*job));
          r.headers.emplace_back("ETag", etag);
          r.headers.emplace_back("Cache-Control", "no-cache");
          if (!is_final(job->status)) r.headers.emplace_back("Retry-After", "1");
        }
      }
    } else if (method == "DELETE") {
      if (service_.remove(id)) {
        r.status = 204;
        r.content_type.clear();
      } else {
        r = job_not_found(id);
      }
    } else {
      r = method_not_allowed("GET, HEAD, DELETE");
    }
    r.route = std::string(tmpl);
    return r;
  }

  if (tmpl == "/v1/jobs/{id}/cancel") {
    if (method != "POST") {
      r = method_not_allowed("POST");
    } else {
      const CancelOutcome outcome = service_.cancel(id);
      if (outcome == CancelOutcome::not_found) {
        r = job_not_found(id);
      } else {
        auto job = service_.job(id);
        if (!job) {
          r = job_not_found(id);
        } else if (outcome == CancelOutcome::already_final) {
          r = problem(409, "job-finished", "Job already finished",
                      "job " + id + " is " + std::string(to_string(job->status)) +
                          "; only queued or running jobs can be cancelled");
        } else {
          // Queued: cancelled now. Running: the worker stops within one simulation step.
          r = json_text_response(outcome == CancelOutcome::cancelled ? 200 : 202, job_json(*job));
          r.headers.emplace_back("Location", job_path(id));
        }
      }
    }
    r.route = std::string(tmpl);
    return r;
  }

  if (tmpl == "/v1/jobs/{id}/scene") {
    if (!get) {
      r = method_not_allowed("GET, HEAD");
    } else if (auto scene = service_.storage().scene(id)) {
      r.body = std::move(*scene);
    } else {
      r = job_not_found(id);
    }
    r.route = std::string(tmpl);
    return r;
  }

  // Results.
  if (!get) {
    r = method_not_allowed("GET, HEAD");
    r.route = std::string(tmpl);
    return r;
  }
  auto job = service_.job(id);
  if (!job) {
    r = job_not_found(id);
  } else if (job->status != JobStatus::succeeded) {
    r = problem(409, "result-not-ready", "No result",
                "job " + id + " is " + std::string(to_string(job->status)) +
                    (is_final(job->status) ? " and has no result"
                                           : "; its result is available once it has succeeded"));
    if (!is_final(job->status)) r.headers.emplace_back("Retry-After", "1");
  } else if (tmpl == "/v1/jobs/{id}/result") {
    auto summary = service_.result_summary(id);
    if (!summary) {
      r = job_not_found(id);
    } else {
      json body = json::parse(*summary);
      body["job"] = json::parse(job_json(*job));
      r = json_response(200, body);
      r.headers.emplace_back("ETag", job_etag(*job));
    }
  } else if (tmpl == "/v1/jobs/{id}/meshes") {
    json bodies = json::array();
    std::size_t index = 0;
    for (const StoredBody& b : service_.result_bodies(id)) {
      json vertices = json::array();
      for (std::size_t v = 0; v + 2 < b.vertices.size(); v += 3) {
        vertices.push_back(json::array({b.vertices[v], b.vertices[v + 1], b.vertices[v + 2]}));
      }
      json triangles = json::array();
      for (std::size_t t = 0; t + 2 < b.triangles.size(); t += 3) {
        triangles.push_back(json::array({b.triangles[t], b.triangles[t + 1], b.triangles[t + 2]}));
      }
      const auto& p = b.initial_pose;
      bodies.push_back(json{{"index", index++},
                            {"name", b.name},
                            {"mass", b.mass_kg},
                            {"animated", b.animated},
                            {"position", json::array({p[0], p[1], p[2]})},
                            {"orientation", json::array({p[3], p[4], p[5], p[6]})},
                            {"mesh", {{"vertices", vertices}, {"triangles", triangles}}}});
    }
    r = etagged(request, json{{"bodies", std::move(bodies)}}.dump());
  } else if (tmpl == "/v1/jobs/{id}/result.glb") {
    auto result = service_.stored_result(id);
    if (!result) {
      r = job_not_found(id);
    } else {
      const std::vector<std::uint8_t> glb = io::result_to_glb(*result);
      r.content_type = "model/gltf-binary";
      r.body.assign(reinterpret_cast<const char*>(glb.data()), glb.size());
      r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + id + ".glb\"");
      r.headers.emplace_back("ETag", job_etag(*job));
    }
  } else {  // frames
    auto summary_text = service_.result_summary(id);
    if (!summary_text) {
      r = job_not_found(id);
    } else {
      const json summary = json::parse(*summary_text);
      const auto frame_count = summary.at("frame_count").get<std::int64_t>();
      const auto& body_list = summary.at("bodies");
      const auto animated = summary.at("animated").get<std::vector<std::uint32_t>>();
      const std::int64_t from = integer_param(target, "from", 0, 0, frame_count);
      const std::int64_t to = integer_param(target, "to", frame_count, from, frame_count);
      std::vector<std::uint32_t> bodies = parse_body_list(target, body_list.size());
      if (!target.get("bodies")) bodies = animated;
      // Where each requested body's pose sits in a stored frame: its animated slot, or none.
      std::vector<std::int64_t> slot(body_list.size(), -1);
      for (std::size_t k = 0; k < animated.size(); ++k)
        slot[animated[k]] = static_cast<std::int64_t>(k);
      std::vector<std::array<float, 7>> fixed(body_list.size());
      for (std::uint32_t b : bodies) {
        if (slot[b] >= 0) continue;
        const json& info = body_list.at(b);
        for (int c = 0; c < 3; ++c)
          fixed[b][static_cast<std::size_t>(c)] = info.at("position").at(c).get<float>();
        for (int c = 0; c < 4; ++c)
          fixed[b][static_cast<std::size_t>(3 + c)] = info.at("orientation").at(c).get<float>();
      }
      const std::vector<StoredFrame> frames = service_.result_frames(id, from, to);
      auto pose_of = [&](const StoredFrame& f, std::uint32_t b) {
        std::array<float, 7> p = fixed[b];
        if (slot[b] >= 0) {
          const auto base = static_cast<std::size_t>(slot[b]) * 7;
          if (base + 7 <= f.poses.size())
            std::copy_n(f.poses.begin() + static_cast<std::ptrdiff_t>(base), 7, p.begin());
        }
        return p;
      };
      const std::string_view accept = request.header("accept");
      if (accept.find("application/octet-stream") != std::string_view::npos) {
        static_assert(std::endian::native == std::endian::little);
        std::string out = "BRF1";
        append_u32(out, static_cast<std::uint32_t>(from));
        append_u32(out, static_cast<std::uint32_t>(frames.size()));
        append_u32(out, static_cast<std::uint32_t>(bodies.size()));
        for (std::uint32_t b : bodies)
          append_u32(out, b);
        for (const StoredFrame& f : frames) {
          append_raw(out, f.time_s);
          for (std::uint32_t b : bodies) {
            for (float x : pose_of(f, b))
              append_raw(out, x);
          }
        }
        r.content_type = "application/octet-stream";
        r.body = std::move(out);
      } else if (!accept.empty() && accept.find("json") == std::string_view::npos &&
                 accept.find("*/*") == std::string_view::npos) {
        r = problem(406, "not-acceptable", "Not acceptable",
                    "frames are served as application/json or application/octet-stream");
      } else {
        json out_frames = json::array();
        std::int64_t index = from;
        for (const StoredFrame& f : frames) {
          json poses = json::array();
          for (std::uint32_t b : bodies) {
            const auto p = pose_of(f, b);
            poses.push_back(json{{"body", b},
                                 {"position", json::array({p[0], p[1], p[2]})},
                                 {"orientation", json::array({p[3], p[4], p[5], p[6]})}});
          }
          out_frames.push_back(json{{"index", index++}, {"time", f.time_s}, {"poses", poses}});
        }
        r = json_response(200, json{{"from", from},
                                    {"to", to},
                                    {"frame_count", frame_count},
                                    {"bodies", bodies},
                                    {"frames", std::move(out_frames)}});
      }
      r.headers.emplace_back("Vary", "Accept");
    }
  }
  r.route = std::string(tmpl);
  return r;
}

}  // namespace brisance::server
