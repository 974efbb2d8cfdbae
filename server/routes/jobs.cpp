// server/routes/jobs: the job resource — POST and GET /v1/jobs, GET (with long-poll) and DELETE
// /v1/jobs/{id}, POST /v1/jobs/{id}/cancel and GET /v1/jobs/{id}/scene.
#include <algorithm>

#include <boost/url/encode.hpp>
#include <boost/url/rfc/unreserved_chars.hpp>
#include <nlohmann/json.hpp>

#include "server/log.hpp"
#include "server/routes/routes.hpp"

namespace brisance::server::routes {

using nlohmann::json;

std::string job_path(std::string_view id) {
  return "/v1/jobs/" + std::string(id);
}

std::string job_etag(const JobRecord& job) {
  return "\"" + job.id + "." + std::to_string(job.version) + "\"";
}

// The job's JSON, written as text: it is the most requested representation, and building a DOM
// for it (and re-parsing the stored stats) cost more than the database read. Keys are in
// nlohmann's sorted order so the text equals what a DOM would dump.
std::string job_json(const JobRecord& job) {
  const auto time_or_null = [](const std::optional<std::int64_t>& ms) {
    return ms ? "\"" + iso_time_utc(*ms) + "\"" : std::string("null");
  };
  const std::string self = job_path(job.id);
  std::string out;
  out.reserve(640 + job.stats_json.size() + job.error.size() + job.name.size() +
              job.labels_json.size());
  out += "{\"attempts\":" + std::to_string(job.attempts);
  out += ",\"callback\":";
  if (job.callback_url.empty()) {
    out += "null";
  } else {
    out += "{\"deliveries\":" + job.callback_deliveries_json;
    out += ",\"state\":\"" + job.callback_state + "\"";
    out +=
        ",\"url\":" + json(job.callback_url).dump(-1, ' ', false, json::error_handler_t::replace);
    out += '}';
  }
  out += ",\"cancel_requested\":";
  out += job.cancel_requested ? "true" : "false";
  out += ",\"created_at\":\"" + iso_time_utc(job.created_ms) + "\"";
  out += ",\"error\":";
  if (job.error_type.empty()) {
    out += "null";
  } else {
    out += json{{"message", job.error}, {"type", job.error_type}}.dump(
        -1, ' ', false, json::error_handler_t::replace);
  }
  out += ",\"finished_at\":" + time_or_null(job.finished_ms);
  out += ",\"id\":\"" + job.id + "\"";
  out += ",\"labels\":" + job.labels_json;
  out += ",\"links\":{\"cancel\":\"" + self + "/cancel\"";
  if (job.status == JobStatus::succeeded) {
    out += ",\"frames\":\"" + self + "/frames\",\"glb\":\"" + self + "/result.glb\",\"meshes\":\"" +
           self + "/meshes\",\"result\":\"" + self + "/result\"";
  }
  out += ",\"scene\":\"" + self + "/scene\",\"self\":\"" + self + "\"}";
  out += ",\"name\":" + json(job.name).dump(-1, ' ', false, json::error_handler_t::replace);
  out += ",\"priority\":" + std::to_string(job.priority);
  out += ",\"progress\":" + json(job.progress).dump();
  out += ",\"started_at\":" + time_or_null(job.started_ms);
  out += ",\"stats\":" + (job.stats_json.empty() ? std::string("null") : job.stats_json);
  out += ",\"status\":\"" + std::string(to_string(job.status)) + "\"";
  out += ",\"updated_at\":\"" + iso_time_utc(job.updated_ms) + "\"}";
  return out;
}

HttpResponse submit_job(const Context& c) {
  const std::string_view content_type = c.request.header("content-type");
  if (!content_type.empty() && content_type.find("json") == std::string_view::npos) {
    return problem(415, "unsupported-media-type", "Unsupported media type",
                   "send the job as application/json")
        .response();
  }
  if (c.options.free_space && c.options.free_space->low()) {
    // Refused before the disk is full, so the jobs already accepted can still store results and
    // deletes can still make room.
    return problem(507, "insufficient-storage", "Insufficient storage",
                   "the data folder has " +
                       std::to_string(c.options.free_space->available_bytes() >> 20) +
                       " MiB free, below the floor of " +
                       std::to_string(c.options.free_space->floor_bytes() >> 20) +
                       " MiB (--min-free-mb); delete finished jobs or free space, then retry")
        .header("Retry-After", "60")
        .response();
  }
  const std::string_view key = c.request.header("idempotency-key");
  if (key.size() > 255) {
    return problem(400, "invalid-parameter", "Invalid Idempotency-Key",
                   "the Idempotency-Key header must be at most 255 characters")
        .response();
  }
  SubmitOutcome outcome =
      c.service.submit({c.request.body, key, c.key ? std::string_view(c.key->name) : ""});
  using Kind = SubmitOutcome::Kind;
  switch (outcome.kind) {
    case Kind::accepted:
    case Kind::existing: {
      HttpResponse r =
          json_text_response(outcome.kind == Kind::accepted ? 202 : 200, job_json(outcome.job));
      r.headers.emplace_back("Location", job_path(outcome.job.id));
      r.headers.emplace_back("Retry-After", "1");
      r.headers.emplace_back("ETag", job_etag(outcome.job));
      return r;
    }
    case Kind::malformed:
      return problem(400, "malformed-json", "Malformed JSON", outcome.message).response();
    case Kind::invalid: {
      Problem p =
          problem(422, "invalid-scene", "Invalid job",
                  std::to_string(outcome.errors.size()) +
                      " problem(s) in the job; each is listed in 'errors' with a JSON pointer "
                      "into the request body");
      for (const auto& e : outcome.errors)
        p.error("pointer", e.pointer, e.message);
      return p.response();
    }
    case Kind::key_conflict:
      return problem(422, "idempotency-key-reused", "Idempotency key reused",
                     "this Idempotency-Key was used for a different request body (job " +
                         outcome.job.id + "); use a new key for a new job")
          .response();
    case Kind::queue_full:
      return problem(429, "queue-full", "Queue full",
                     "the queue holds its maximum of " +
                         std::to_string(c.service.options().max_queue) +
                         " waiting jobs; retry after the Retry-After delay")
          .header("Retry-After", "5")
          .response();
  }
  return problem(500, "internal-error", "Internal error", "unknown submission outcome").response();
}

namespace {

constexpr std::size_t kMaxLabelSelectors = 8;

// `?label=shot=sq010,artist` — comma-separated selectors, each a key (present) or key=value.
std::vector<LabelSelector> parse_label_selectors(std::string_view text) {
  std::vector<LabelSelector> selectors;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string_view item = text.substr(begin, comma - begin);
    LabelSelector selector;
    const std::size_t equals = item.find('=');
    selector.key = std::string(item.substr(0, equals));
    if (equals != std::string_view::npos) selector.value = std::string(item.substr(equals + 1));
    if (!valid_label_key(selector.key)) {
      throw BadParameter{"label", "'label' is a comma-separated list of KEY or KEY=VALUE; '" +
                                      std::string(item) +
                                      "' has no valid key (letters, digits, '_', "
                                      "'.', '-', '/')"};
    }
    selectors.push_back(std::move(selector));
    if (selectors.size() > kMaxLabelSelectors) {
      throw BadParameter{
          "label", "'label' takes at most " + std::to_string(kMaxLabelSelectors) + " selectors"};
    }
    begin = comma + 1;
  }
  return selectors;
}

std::string query_value(std::string_view text) {
  return boost::urls::encode(text, boost::urls::unreserved_chars);
}

}  // namespace

HttpResponse list_jobs(const Context& c) {
  JobFilter filter;
  if (auto text = c.target.get("status")) {
    filter.status = parse_job_status(*text);
    if (!filter.status) {
      throw BadParameter{"status",
                         "'status' must be one of queued, running, succeeded, failed, cancelled"};
    }
  }
  const auto label = c.target.get("label");
  if (label) filter.labels = parse_label_selectors(*label);
  const auto name = c.target.get("name");
  if (name) {
    if (name->size() > kMaxJobName) {
      throw BadParameter{"name",
                         "'name' must be at most " + std::to_string(kMaxJobName) + " characters"};
    }
    filter.name_contains = std::string(*name);
  }
  if (auto owner = c.owner_filter()) filter.owner = std::string(*owner);
  const int limit = static_cast<int>(integer_param(c.target, "limit", 50, 1, 500));
  const std::int64_t cursor = integer_param(c.target, "cursor", 0, 0, INT64_MAX);
  const JobPage page = c.service.list(filter, cursor, limit);
  std::string body = "{\"jobs\":[";
  for (std::size_t i = 0; i < page.jobs.size(); ++i) {
    if (i > 0) body += ',';
    body += job_json(page.jobs[i]);
  }
  body += "],\"next_cursor\":";
  body += page.cursor ? "\"" + std::to_string(*page.cursor) + "\"" : std::string("null");
  body += '}';
  HttpResponse r = etagged(c.request, std::move(body));
  if (page.cursor) {
    std::string next =
        "/v1/jobs?limit=" + std::to_string(limit) + "&cursor=" + std::to_string(*page.cursor);
    if (filter.status) next += "&status=" + std::string(to_string(*filter.status));
    if (label) next += "&label=" + query_value(*label);
    if (name) next += "&name=" + query_value(*name);
    r.headers.emplace_back("Link", "<" + next + ">; rel=\"next\"");
  }
  return r;
}

HttpResponse get_job(const Context& c) {
  auto job = c.visible_job();
  if (!job) return job_not_found(c.id);
  const std::string etag = job_etag(*job);
  const std::string_view if_none_match = c.request.header("if-none-match");
  const auto wait_s = integer_param(c.target, "wait", 0, 0, c.options.max_wait.count());
  // Long-poll: wait while the job is as the client last saw it (If-None-Match) or, without one,
  // as it was when the wait began.
  const std::string& watched =
      c.poll ? c.poll->etag : (if_none_match.empty() ? etag : std::string(if_none_match));
  const bool unchanged = c.poll ? etag == c.poll->etag : etag_matches(watched, etag);
  const bool expired = c.poll && std::chrono::steady_clock::now() >= c.poll->deadline;
  if (wait_s > 0 && unchanged && !is_final(job->status) && !expired) {
    HttpResponse r;
    r.wait = LongPoll{c.id, etag,
                      c.poll ? c.poll->deadline
                             : std::chrono::steady_clock::now() + std::chrono::seconds(wait_s)};
    return r;
  }
  if (etag_matches(if_none_match, etag)) return not_modified(etag);
  HttpResponse r = json_text_response(200, job_json(*job));
  r.headers.emplace_back("ETag", etag);
  r.headers.emplace_back("Cache-Control", "no-cache");
  if (!is_final(job->status)) r.headers.emplace_back("Retry-After", "1");
  return r;
}

HttpResponse delete_job(const Context& c) {
  if (!c.visible_job() || !c.service.remove(c.id)) return job_not_found(c.id);
  HttpResponse r;
  r.status = 204;
  r.content_type.clear();
  return r;
}

HttpResponse cancel_job(const Context& c) {
  if (!c.visible_job()) return job_not_found(c.id);
  const CancelOutcome outcome = c.service.cancel(c.id);
  if (outcome == CancelOutcome::not_found) return job_not_found(c.id);
  auto job = c.service.job(c.id);
  if (!job) return job_not_found(c.id);
  if (outcome == CancelOutcome::already_final) {
    return problem(409, "job-finished", "Job already finished",
                   "job " + c.id + " is " + std::string(to_string(job->status)) +
                       "; only queued or running jobs can be cancelled")
        .response();
  }
  // Queued: cancelled now. Running: the worker stops within one simulation step.
  HttpResponse r =
      json_text_response(outcome == CancelOutcome::cancelled ? 200 : 202, job_json(*job));
  r.headers.emplace_back("Location", job_path(c.id));
  return r;
}

HttpResponse job_scene(const Context& c) {
  if (!c.visible_job()) return job_not_found(c.id);
  auto scene = c.service.scene(c.id);
  if (!scene) return job_not_found(c.id);
  HttpResponse r;
  r.body = std::move(*scene);
  return r;
}

}  // namespace brisance::server::routes
