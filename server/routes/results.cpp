// server/routes/results: a succeeded job's results — GET /v1/jobs/{id}/result (the summary),
// /frames (JSON or the BRF1 binary layout of api/openapi.yaml), /meshes and /result.glb.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <sstream>
#include <stdexcept>
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

// The body of a frames page made block by block (HttpResponse::stream): the page's head, then
// each block of frames read and encoded on its own, then the tail, so the memory a page holds is
// one block (and, for a result stored as one byte string, that string), whatever its length. The
// bytes equal io::frames_document_json and io::frames_to_brf1 of the whole page.
class FrameStream {
 public:
  FrameStream(JobService& service, const std::string& id, ResultLayout layout, std::int64_t from,
              std::int64_t to, std::vector<std::uint32_t> bodies, bool binary, bool velocities)
      : reader_(service.result_frame_reader(id)),
        layout_(std::move(layout)),
        from_(from),
        to_(to),
        next_(from),
        bodies_(std::move(bodies)),
        binary_(binary),
        velocities_(velocities) {}

  bool operator()(std::string& out) {
    if (!started_) {
      started_ = true;
      if (binary_) {
        out = io::brf1_header(static_cast<std::uint64_t>(from_),
                              static_cast<std::uint64_t>(to_ - from_), bodies_);
      } else {
        out = "{\"bodies\":" + json(bodies_).dump() +
              ",\"frame_count\":" + std::to_string(layout_.frame_count) + ",\"frames\":[";
      }
      return true;
    }
    if (next_ < to_) {
      const std::int64_t end = std::min(to_, next_ + block_frames());
      const io::FrameSet block = read_block(next_, end);
      // Deleted (or pruned) while it streamed: cut the body short rather than end it wrongly.
      if (std::ssize(block.times_s) != end - next_) {
        throw std::runtime_error("the result of the job went away while its frames streamed");
      }
      if (binary_) {
        io::append_brf1_frames(out, block);
      } else {
        std::ostringstream text;
        for (std::size_t f = 0; f < block.frame_count(); ++f) {
          if (next_ != from_ || f != 0) text << ',';
          io::write_frame_json(text, block, f);
        }
        out = std::move(text).str();
      }
      next_ = end;
      if (next_ < to_ || !binary_) return true;
      return false;
    }
    if (!binary_) {
      out = "],\"from\":" + std::to_string(from_) + ",\"to\":" + std::to_string(to_) + "}";
    }
    return false;
  }

 private:
  // About 8 192 poses a block (some 1.5 MB of JSON), whatever the body count.
  std::int64_t block_frames() const {
    return std::max<std::int64_t>(1, 8192 / std::max<std::int64_t>(1, std::ssize(bodies_)));
  }

  io::FrameSet read_block(std::int64_t first, std::int64_t end) const {
    if (!velocities_) return JobService::frame_set(reader_, layout_, first, end, bodies_);
    // Each frame's velocity takes its neighbours in the whole run: one more frame on each side
    // the block has, so a block's velocities equal the whole run's.
    const std::int64_t lo = std::max<std::int64_t>(0, first - 1);
    const std::int64_t hi = std::min<std::int64_t>(layout_.frame_count, end + 1);
    return io::with_velocities(JobService::frame_set(reader_, layout_, lo, hi, bodies_),
                               static_cast<std::size_t>(first - lo),
                               static_cast<std::size_t>(hi - end));
  }

  Storage::FrameReader reader_;
  ResultLayout layout_;
  std::int64_t from_, to_, next_;
  std::vector<std::uint32_t> bodies_;
  bool binary_, velocities_;
  bool started_ = false;
};

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
  const auto layout = c.service.result_layout(c.id);
  if (!layout) return job_not_found(c.id);
  const std::int64_t samples =
      layout->frame_count * static_cast<std::int64_t>(layout->animated.size());
  if (samples > c.service.options().max_glb_frame_samples) {
    return problem(422, "result-too-large", "Result too large for glb",
                   "job " + c.id + " has " + std::to_string(layout->frame_count) + " frames x " +
                       std::to_string(layout->animated.size()) +
                       " animated bodies = " + std::to_string(samples) +
                       " samples; result.glb is built in memory for at most " +
                       std::to_string(c.service.options().max_glb_frame_samples) +
                       ". Read the frames (streamed, any page size) and the meshes instead")
        .response();
  }
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
  const bool binary = accept.find("application/octet-stream") != std::string_view::npos;
  if (binary && velocities) {
    throw BadParameter{"velocities",
                       "velocities are part of the JSON frames only; BRF1 frames hold poses (ask "
                       "for application/json, or difference the poses)"};
  }
  if (!binary && !accept.empty() && accept.find("json") == std::string_view::npos &&
      accept.find("*/*") == std::string_view::npos) {
    HttpResponse r = problem(406, "not-acceptable", "Not acceptable",
                             "frames are served as application/json or application/octet-stream")
                         .response();
    r.headers.emplace_back("Vary", "Accept");
    return r;
  }
  HttpResponse r;
  if (binary) r.content_type = "application/octet-stream";
  r.stream = FrameStream(c.service, c.id, *layout, from, to, bodies, binary, velocities);
  r.headers.emplace_back("Vary", "Accept");
  return r;
}

}  // namespace brisance::server::routes
