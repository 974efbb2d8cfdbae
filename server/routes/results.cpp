// server/routes/results: a succeeded job's results — GET /v1/jobs/{id}/result (the summary),
// /frames (JSON or the BRF1 binary layout of api/openapi.yaml), /meshes and /result.glb.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <variant>

#include <nlohmann/json.hpp>

#include "server/routes/routes.hpp"
#include "sim/io/frames.hpp"

namespace brisance::server::routes {
namespace {

using nlohmann::json;

// The job if it has a result; otherwise the answer to give (404, or 409 while it has none).
std::variant<JobRecord, HttpResponse> succeeded_job(const Context& c) {
  auto job = c.visible_job();
  if (!job) return job_not_found(c.id);
  if (job->status == JobStatus::succeeded) return *job;
  Problem p =
      problem(409, "result-not-ready", "No result",
              "job " + c.id + " is " + std::string(to_string(job->status)) +
                  (is_final(job->status) ? " and has no result"
                                         : "; its result is available once it has succeeded"));
  if (!is_final(job->status)) p.header("Retry-After", "1");
  return p.response();
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
                         "'bodies' must be a comma-separated list of body indices from 0 to " +
                             std::to_string(body_count - 1)};
    }
    out.push_back(value);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return out;
}

}  // namespace

HttpResponse job_result(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  auto summary = c.service.result_summary(c.id);
  if (!summary) return job_not_found(c.id);
  json body = json::parse(*summary);
  body["job"] = json::parse(job_json(std::get<JobRecord>(job)));
  HttpResponse r;
  r.body = body.dump();
  r.headers.emplace_back("ETag", job_etag(std::get<JobRecord>(job)));
  return r;
}

HttpResponse job_meshes(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  return etagged(c.request, c.service.result_meshes_json(c.id));
}

HttpResponse job_glb(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  const auto glb = c.service.result_glb(c.id);
  if (!glb) return job_not_found(c.id);
  HttpResponse r;
  r.content_type = "model/gltf-binary";
  r.body.assign(reinterpret_cast<const char*>(glb->data()), glb->size());
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + c.id + ".glb\"");
  r.headers.emplace_back("ETag", job_etag(std::get<JobRecord>(job)));
  return r;
}

HttpResponse job_frames(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  const auto layout = c.service.result_layout(c.id);
  if (!layout) return job_not_found(c.id);
  const std::int64_t from = integer_param(c.target, "from", 0, 0, layout->frame_count);
  const std::int64_t to =
      integer_param(c.target, "to", layout->frame_count, from, layout->frame_count);
  const std::vector<std::uint32_t> bodies =
      c.target.get("bodies") ? parse_body_list(c.target, layout->body_count()) : layout->animated;
  const std::string_view accept = c.request.header("accept");
  const bool velocities = boolean_param(c.target, "velocities", false);
  HttpResponse r;
  if (accept.find("application/octet-stream") != std::string_view::npos) {
    if (velocities) {
      throw BadParameter{"velocities",
                         "velocities are part of the JSON frames only; BRF1 frames hold poses (ask "
                         "for application/json, or difference the poses)"};
    }
    r.content_type = "application/octet-stream";
    r.body = io::frames_to_brf1(c.service.result_frame_set(c.id, *layout, from, to, bodies));
  } else if (!accept.empty() && accept.find("json") == std::string_view::npos &&
             accept.find("*/*") == std::string_view::npos) {
    r = problem(406, "not-acceptable", "Not acceptable",
                "frames are served as application/json or application/octet-stream")
            .response();
  } else if (velocities) {
    // Each frame's velocity takes its neighbours: one more frame on each side the page has.
    const std::int64_t lo = std::max<std::int64_t>(0, from - 1);
    const std::int64_t hi = std::min<std::int64_t>(layout->frame_count, to + 1);
    io::FrameSet frames =
        io::with_velocities(c.service.result_frame_set(c.id, *layout, lo, hi, bodies),
                            static_cast<std::size_t>(from - lo), static_cast<std::size_t>(hi - to));
    r.body = io::frames_document_json(frames, static_cast<std::uint64_t>(layout->frame_count));
  } else {
    r.body = io::frames_document_json(c.service.result_frame_set(c.id, *layout, from, to, bodies),
                                      static_cast<std::uint64_t>(layout->frame_count));
  }
  r.headers.emplace_back("Vary", "Accept");
  return r;
}

}  // namespace brisance::server::routes
