#include "server/job_service.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "server/sha256.hpp"
#include "sim/io/result_json.hpp"

namespace brisance::server {

using nlohmann::json;

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string new_job_id() {
  static std::mutex mutex;
  static std::mt19937_64 generator = [] {
    std::random_device device;
    std::seed_seq seed{device(), device(), device(), device()};
    return std::mt19937_64(seed);
  }();
  static constexpr char kHex[] = "0123456789abcdef";
  std::uint64_t a, b;
  {
    std::lock_guard lock(mutex);
    a = generator();
    b = generator();
  }
  std::string id = "j";
  for (int i = 0; i < 16; ++i)
    id.push_back(kHex[(a >> (4 * i)) & 0xf]);
  for (int i = 0; i < 8; ++i)
    id.push_back(kHex[(b >> (4 * i)) & 0xf]);
  return id;
}

std::uint64_t ChangeNotifier::subscribe(const std::string& job_id, Callback callback) {
  std::lock_guard lock(mutex_);
  const std::uint64_t token = next_token_++;
  waiters_.emplace(job_id, std::make_pair(token, std::move(callback)));
  return token;
}

void ChangeNotifier::unsubscribe(std::uint64_t token) {
  std::lock_guard lock(mutex_);
  for (auto it = waiters_.begin(); it != waiters_.end(); ++it) {
    if (it->second.first == token) {
      waiters_.erase(it);
      return;
    }
  }
}

void ChangeNotifier::notify(const std::string& job_id) {
  std::vector<Callback> callbacks;
  {
    std::lock_guard lock(mutex_);
    auto [first, last] = waiters_.equal_range(job_id);
    for (auto it = first; it != last; ++it)
      callbacks.push_back(it->second.second);
    waiters_.erase(first, last);
  }
  for (auto& callback : callbacks)
    callback();
}

JobService::JobService(Storage& storage, ServiceOptions options)
    : storage_(storage), options_(std::move(options)) {}

std::int64_t JobService::queued_estimate() {
  // Counting queued rows on every submission would cost more than the insert; a count at most
  // 100 ms old plus this process's own submissions since is exact enough for backpressure.
  std::lock_guard lock(queued_mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (now - queued_checked_ > std::chrono::milliseconds(100)) {
    queued_cached_ = storage_.count_queued();
    queued_checked_ = now;
  }
  return queued_cached_;
}

SubmitOutcome JobService::submit(const SubmitRequest& request) {
  SubmitOutcome outcome;
  json document = json::parse(request.body, nullptr, false);
  if (document.is_discarded()) {
    outcome.kind = SubmitOutcome::Kind::malformed;
    outcome.message = "the request body is not valid JSON";
    return outcome;
  }
  auto invalid = [&](std::string pointer, std::string message) {
    outcome.errors.push_back({std::move(pointer), std::move(message)});
  };
  int priority = 0;
  const json* scene_json = nullptr;
  if (!document.is_object()) {
    invalid("", "the body must be an object {\"scene\": {...}, \"priority\": 0}");
  } else {
    for (const auto& [key, value] : document.items()) {
      if (key == "scene") {
        scene_json = &value;
      } else if (key == "priority") {
        if (!value.is_number_integer() || value.get<std::int64_t>() < -100 ||
            value.get<std::int64_t>() > 100) {
          invalid("/priority", "priority must be an integer from -100 to 100 (higher runs first)");
        } else {
          priority = value.get<int>();
        }
      } else {
        invalid("/" + key, "unknown field '" + key + "': a job has only 'scene' and 'priority'");
      }
    }
    if (!scene_json) invalid("/scene", "missing 'scene': the scene to simulate");
  }
  if (scene_json) {
    scene::ParseResult parsed = scene::parse_scene(*scene_json, options_.limits);
    for (auto& e : parsed.errors)
      invalid("/scene" + e.pointer, std::move(e.message));
  }
  if (!outcome.errors.empty()) {
    outcome.kind = SubmitOutcome::Kind::invalid;
    return outcome;
  }

  NewJob job;
  job.scene_json = scene_json->dump();
  job.priority = priority;
  job.idempotency_key = std::string(request.idempotency_key);
  job.owner = std::string(request.owner);
  if (!job.idempotency_key.empty()) job.request_hash = sha256_hex(request.body);
  job.now_ms = now_ms();

  job.id = new_job_id();
  if (queued_estimate() >= options_.max_queue) {
    // Full: no new job, but an idempotent retry of an accepted one still finds it.
    if (job.idempotency_key.empty()) {
      outcome.kind = SubmitOutcome::Kind::queue_full;
      return outcome;
    }
    job.create_if_missing = false;
  }
  CreateResult created = storage_.create_job(job);
  switch (created.outcome) {
    case CreateOutcome::created: {
      outcome.kind = SubmitOutcome::Kind::accepted;
      std::lock_guard lock(queued_mutex_);
      ++queued_cached_;
      break;
    }
    case CreateOutcome::existing:
      outcome.kind = SubmitOutcome::Kind::existing;
      break;
    case CreateOutcome::key_conflict:
      outcome.kind = SubmitOutcome::Kind::key_conflict;
      break;
    case CreateOutcome::not_created:
      outcome.kind = SubmitOutcome::Kind::queue_full;
      return outcome;
  }
  outcome.job = std::move(created.job);
  if (outcome.kind == SubmitOutcome::Kind::accepted && work_signal_) work_signal_();
  return outcome;
}

void JobService::forget_queued_count() {
  std::lock_guard lock(queued_mutex_);
  queued_checked_ = {};
}

CancelOutcome JobService::cancel(const std::string& id) {
  const CancelOutcome outcome = storage_.request_cancel(id, now_ms());
  if (outcome == CancelOutcome::cancelled) forget_queued_count();
  if (outcome == CancelOutcome::requested || outcome == CancelOutcome::cancelled) {
    {
      std::lock_guard lock(running_mutex_);
      if (auto it = running_.find(id); it != running_.end()) it->second->store(true);
    }
    notifier_.notify(id);
  }
  return outcome;
}

bool JobService::remove(const std::string& id) {
  const bool removed = storage_.delete_job(id);
  if (removed) {
    forget_queued_count();
    {
      std::lock_guard lock(running_mutex_);
      if (auto it = running_.find(id); it != running_.end()) it->second->store(true);
    }
    notifier_.notify(id);
  }
  return removed;
}

std::shared_ptr<std::atomic<bool>> JobService::register_running(const std::string& id) {
  auto flag = std::make_shared<std::atomic<bool>>(false);
  std::lock_guard lock(running_mutex_);
  running_[id] = flag;
  return flag;
}

void JobService::unregister_running(const std::string& id) {
  std::lock_guard lock(running_mutex_);
  running_.erase(id);
}

namespace {

std::array<double, 7> pose7(const engine::Pose& pose) {
  return {pose.position[0],    pose.position[1],    pose.position[2],   pose.orientation[0],
          pose.orientation[1], pose.orientation[2], pose.orientation[3]};
}

engine::Pose pose_from(const double* p) {
  engine::Pose pose;
  pose.position = {p[0], p[1], p[2]};
  pose.orientation = {p[3], p[4], p[5], p[6]};
  return pose;
}

std::array<double, 3> vec3_from(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

}  // namespace

StoredResult to_stored_result(const engine::Result& result) {
  StoredResult stored;
  std::vector<bool> animated(result.bodies.size(), false);
  for (std::uint32_t index : result.animated)
    animated[index] = true;

  json bodies = json::array();
  for (std::size_t i = 0; i < result.bodies.size(); ++i) {
    const engine::BodyInfo& info = result.bodies[i];
    StoredBody body;
    body.name = info.name;
    body.mass_kg = info.mass_kg;
    body.animated = animated[i];
    body.initial_pose = pose7(info.initial_pose);
    body.vertices.reserve(info.mesh.vertices.size() * 3);
    for (const auto& v : info.mesh.vertices) {
      for (int c = 0; c < 3; ++c)
        body.vertices.push_back(static_cast<float>(v[c]));
    }
    body.triangles.reserve(info.mesh.triangles.size() * 3);
    for (const auto& t : info.mesh.triangles)
      body.triangles.insert(body.triangles.end(), t.begin(), t.end());
    stored.bodies.push_back(std::move(body));
    bodies.push_back(
        json{{"index", i},
             {"name", info.name},
             {"mass", info.mass_kg},
             {"animated", animated[i]},
             {"position", json::array({info.initial_pose.position[0], info.initial_pose.position[1],
                                       info.initial_pose.position[2]})},
             {"orientation",
              json::array({info.initial_pose.orientation[0], info.initial_pose.orientation[1],
                           info.initial_pose.orientation[2], info.initial_pose.orientation[3]})}});
  }

  const std::size_t n = result.animated.size();
  stored.frames.reserve(result.frame_times_s.size());
  for (std::size_t f = 0; f < result.frame_times_s.size(); ++f) {
    StoredFrame frame;
    frame.time_s = result.frame_times_s[f];
    frame.poses.reserve(7 * n);
    for (std::size_t k = 0; k < n; ++k) {
      for (double x : pose7(result.pose(f, k)))
        frame.poses.push_back(static_cast<float>(x));
    }
    stored.frames.push_back(std::move(frame));
  }

  json final_state = json::array();
  for (const auto& state : result.final_state)
    final_state.push_back(io::final_state_to_json(state));
  json warnings = json::array();
  for (const auto& warning : result.warnings)
    warnings.push_back(io::warning_to_json(warning));
  const json stats = io::stats_to_json(result.stats);
  const double duration = result.frame_times_s.empty() ? 0.0 : result.frame_times_s.back();
  json summary{{"bodies", std::move(bodies)},
               {"animated", result.animated},
               {"frame_count", result.frame_times_s.size()},
               {"duration", duration},
               {"frame_times", result.frame_times_s},
               {"final_state", std::move(final_state)},
               {"stats", stats},
               {"warnings", std::move(warnings)},
               {"fracture", io::fracture_to_json(result.fracture)}};
  stored.stats_json = stats.dump();
  stored.summary_json = summary.dump();
  return stored;
}

std::optional<engine::Result> JobService::stored_result(std::string_view id) {
  auto summary_text = storage_.result_summary(id);
  if (!summary_text) return std::nullopt;
  const json summary = json::parse(*summary_text);
  engine::Result result;
  for (StoredBody& b : storage_.result_bodies(id)) {
    engine::BodyInfo info;
    info.name = std::move(b.name);
    info.mass_kg = b.mass_kg;
    info.initial_pose = pose_from(b.initial_pose.data());
    for (std::size_t v = 0; v + 2 < b.vertices.size(); v += 3) {
      info.mesh.vertices.emplace_back(b.vertices[v], b.vertices[v + 1], b.vertices[v + 2]);
    }
    for (std::size_t t = 0; t + 2 < b.triangles.size(); t += 3) {
      info.mesh.triangles.push_back({b.triangles[t], b.triangles[t + 1], b.triangles[t + 2]});
    }
    result.bodies.push_back(std::move(info));
  }
  result.animated = summary.at("animated").get<std::vector<std::uint32_t>>();
  for (StoredFrame& frame : storage_.result_frames(id, 0, INT64_MAX)) {
    result.frame_times_s.push_back(frame.time_s);
    std::array<double, 7> p{};
    for (std::size_t k = 0; k + 6 < frame.poses.size(); k += 7) {
      for (std::size_t c = 0; c < 7; ++c)
        p[c] = frame.poses[k + c];
      engine::Pose pose = pose_from(p.data());
      // Renormalise: float32 rounding leaves |q| a few ulp off 1.
      double norm = 0.0;
      for (double q : pose.orientation)
        norm += q * q;
      norm = std::sqrt(norm);
      if (norm > 0.0) {
        for (double& q : pose.orientation)
          q /= norm;
      }
      result.poses.push_back(pose);
    }
  }
  for (const json& state : summary.at("final_state")) {
    engine::FinalState fs;
    fs.name = state.at("name").get<std::string>();
    const auto position = vec3_from(state.at("position"));
    fs.pose.position = position;
    const json& q = state.at("orientation");
    fs.pose.orientation = {q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(),
                           q.at(3).get<double>()};
    fs.linear_velocity_m_s = vec3_from(state.at("linear_velocity"));
    fs.angular_velocity_rad_s = vec3_from(state.at("angular_velocity"));
    result.final_state.push_back(std::move(fs));
  }
  return result;
}

}  // namespace brisance::server
