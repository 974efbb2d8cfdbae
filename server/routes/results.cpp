// server/routes/results: a succeeded job's results — GET /v1/jobs/{id}/result (the summary),
// /frames (JSON or the BRF1 binary layout of api/openapi.yaml), /meshes and /result.glb.
#include <bit>
#include <charconv>
#include <cstring>
#include <variant>

#include <nlohmann/json.hpp>

#include "server/routes/routes.hpp"
#include "sim/io/gltf.hpp"

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

void append_u32(std::string& out, std::uint32_t v) {
  char bytes[4];
  for (int i = 0; i < 4; ++i)
    bytes[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  out.append(bytes, 4);
}

template <typename T>
void append_raw(std::string& out, T value) {
  // The binary frame format is little-endian; so is every machine this builds for (x86-64,
  // aarch64), which the static_assert below checks.
  static_assert(std::endian::native == std::endian::little);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// BRF1 (api/openapi.yaml, "binary frames"): "BRF1", first frame, frame count, body count, the body
// indices (u32 LE each), then per frame its time (f64) and per body 7 float32 (position,
// [x,y,z,w]).
std::string encode_frames_binary(
    std::int64_t from, const std::vector<StoredFrame>& frames,
    const std::vector<std::uint32_t>& bodies,
    const std::function<std::array<float, 7>(const StoredFrame&, std::uint32_t)>& pose_of) {
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
  return out;
}

json frames_json(
    std::int64_t from, std::int64_t to, std::int64_t frame_count,
    const std::vector<StoredFrame>& frames, const std::vector<std::uint32_t>& bodies,
    const std::function<std::array<float, 7>(const StoredFrame&, std::uint32_t)>& pose_of) {
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
  return json{{"from", from},
              {"to", to},
              {"frame_count", frame_count},
              {"bodies", bodies},
              {"frames", std::move(out_frames)}};
}

json meshes_json(const std::vector<StoredBody>& stored) {
  json bodies = json::array();
  std::size_t index = 0;
  for (const StoredBody& b : stored) {
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
  return json{{"bodies", std::move(bodies)}};
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
  return etagged(c.request, meshes_json(c.service.result_bodies(c.id)).dump());
}

HttpResponse job_glb(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  auto result = c.service.stored_result(c.id);
  if (!result) return job_not_found(c.id);
  const std::vector<std::uint8_t> glb = io::result_to_glb(*result);
  HttpResponse r;
  r.content_type = "model/gltf-binary";
  r.body.assign(reinterpret_cast<const char*>(glb.data()), glb.size());
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + c.id + ".glb\"");
  r.headers.emplace_back("ETag", job_etag(std::get<JobRecord>(job)));
  return r;
}

HttpResponse job_frames(const Context& c) {
  auto job = succeeded_job(c);
  if (auto* answer = std::get_if<HttpResponse>(&job)) return std::move(*answer);
  auto summary_text = c.service.result_summary(c.id);
  if (!summary_text) return job_not_found(c.id);
  const json summary = json::parse(*summary_text);
  const auto frame_count = summary.at("frame_count").get<std::int64_t>();
  const auto& body_list = summary.at("bodies");
  const auto animated = summary.at("animated").get<std::vector<std::uint32_t>>();
  const std::int64_t from = integer_param(c.target, "from", 0, 0, frame_count);
  const std::int64_t to = integer_param(c.target, "to", frame_count, from, frame_count);
  std::vector<std::uint32_t> bodies = parse_body_list(c.target, body_list.size());
  if (!c.target.get("bodies")) bodies = animated;
  // Where each requested body's pose sits in a stored frame: its animated slot, or none.
  std::vector<std::int64_t> slot(body_list.size(), -1);
  for (std::size_t k = 0; k < animated.size(); ++k)
    slot[animated[k]] = static_cast<std::int64_t>(k);
  std::vector<std::array<float, 7>> fixed(body_list.size());
  for (std::uint32_t b : bodies) {
    if (slot[b] >= 0) continue;
    const json& info = body_list.at(b);
    for (int k = 0; k < 3; ++k)
      fixed[b][static_cast<std::size_t>(k)] = info.at("position").at(k).get<float>();
    for (int k = 0; k < 4; ++k)
      fixed[b][static_cast<std::size_t>(3 + k)] = info.at("orientation").at(k).get<float>();
  }
  const std::vector<StoredFrame> frames = c.service.result_frames(c.id, from, to);
  const auto pose_of = [&](const StoredFrame& f, std::uint32_t b) {
    std::array<float, 7> p = fixed[b];
    if (slot[b] >= 0) {
      const auto base = static_cast<std::size_t>(slot[b]) * 7;
      if (base + 7 <= f.poses.size())
        std::copy_n(f.poses.begin() + static_cast<std::ptrdiff_t>(base), 7, p.begin());
    }
    return p;
  };
  const std::string_view accept = c.request.header("accept");
  HttpResponse r;
  if (accept.find("application/octet-stream") != std::string_view::npos) {
    r.content_type = "application/octet-stream";
    r.body = encode_frames_binary(from, frames, bodies, pose_of);
  } else if (!accept.empty() && accept.find("json") == std::string_view::npos &&
             accept.find("*/*") == std::string_view::npos) {
    r = problem(406, "not-acceptable", "Not acceptable",
                "frames are served as application/json or application/octet-stream")
            .response();
  } else {
    r.body = frames_json(from, to, frame_count, frames, bodies, pose_of).dump();
  }
  r.headers.emplace_back("Vary", "Accept");
  return r;
}

}  // namespace brisance::server::routes
