#include "server/job_service.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <random>

#include <boost/url/parse.hpp>
#include <nlohmann/json.hpp>

#include "server/compact_result.hpp"
#include "server/sha256.hpp"
#include "sim/engine/budget.hpp"
#include "sim/io/gltf.hpp"
#include "sim/io/result_codec.hpp"
#include "sim/scene/reader.hpp"

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

namespace {

// Text a person typed, shown on a page: no control characters (a NUL or an escape sequence
// would corrupt logs and terminals).
bool printable(std::string_view text) {
  return std::none_of(text.begin(), text.end(),
                      [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

// UTF-8 characters, for limits a person can count.
std::size_t characters(std::string_view text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
    return (static_cast<unsigned char>(c) & 0xc0) != 0x80;
  }));
}

}  // namespace

std::optional<std::string> check_callback_url(std::string_view url) {
  if (url.size() > 2000) return "callback URLs have at most 2000 characters";
  const auto parsed = boost::urls::parse_absolute_uri(url);
  if (!parsed) return "callback must be an absolute URL http[s]://host[:port][/path]";
  if (parsed->scheme() != "http" && parsed->scheme() != "https")
    return "callback URLs use http:// or https://";
  if (parsed->host().empty()) return "callback URL without a host";
  if (parsed->has_userinfo()) return "callback URLs take no user:password@; use the signature";
  if (parsed->has_port() && (parsed->port_number() == 0 || parsed->port().empty()))
    return "callback URL with an invalid port";
  return std::nullopt;
}

bool valid_label_key(std::string_view key) {
  if (key.empty() || key.size() > kMaxLabelKey) return false;
  const auto allowed = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-' || c == '/';
  };
  return std::all_of(key.begin(), key.end(), allowed);
}

std::optional<std::string> check_job_name(const nlohmann::json& name) {
  if (!name.is_string()) return "name must be a string";
  const auto& text = name.get_ref<const std::string&>();
  if (characters(text) > kMaxJobName)
    return "name must be at most " + std::to_string(kMaxJobName) + " characters";
  if (!printable(text)) return "name must not contain control characters";
  return std::nullopt;
}

void check_job_labels(const nlohmann::json& labels,
                      const std::function<void(std::string, std::string)>& invalid) {
  if (!labels.is_object()) {
    invalid("/labels", "labels must be an object of strings, e.g. {\"shot\": \"sq010\"}");
    return;
  }
  if (labels.size() > kMaxLabels) {
    invalid("/labels", "at most " + std::to_string(kMaxLabels) + " labels, not " +
                           std::to_string(labels.size()));
  }
  for (const auto& [key, value] : labels.items()) {
    const std::string pointer = "/labels/" + scene::escape_token(key);
    if (!valid_label_key(key)) {
      invalid(pointer, "label key '" + key + "' must be 1 to " + std::to_string(kMaxLabelKey) +
                           " letters, digits or '_', '.', '-', '/'");
    }
    if (!value.is_string()) {
      invalid(pointer, "label values must be strings");
      continue;
    }
    const auto& text = value.get_ref<const std::string&>();
    if (characters(text) > kMaxLabelValue) {
      invalid(pointer,
              "label values must be at most " + std::to_string(kMaxLabelValue) + " characters");
    } else if (!printable(text) || text.find(',') != std::string::npos) {
      invalid(pointer,
              "label values must not contain control characters or ',' (it separates "
              "selectors in ?label=)");
    }
  }
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
    : storage_(storage), options_(std::move(options)) {
  // Changes other nodes make on a shared store wake this node's long-polls and idle workers.
  storage_.watch([this](const std::string& id) { notifier_.notify(id); },
                 [this] { signal_work(); });
}

JobService::~JobService() {
  storage_.watch({}, {});
}

void JobService::set_work_signal(std::function<void()> signal) {
  std::lock_guard lock(work_signal_mutex_);
  work_signal_ = std::move(signal);
}

void JobService::signal_work() {
  // Called under the lock, so a pool that cleared its signal is never called afterwards.
  std::lock_guard lock(work_signal_mutex_);
  if (work_signal_) work_signal_();
}

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
  std::string name;
  std::string callback = options_.default_callback_url;
  json labels = json::object();
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
      } else if (key == "name") {
        if (auto problem = check_job_name(value)) {
          invalid("/name", std::move(*problem));
        } else {
          name = value.get<std::string>();
        }
      } else if (key == "callback") {
        if (!value.is_string()) {
          invalid("/callback",
                  "callback must be a URL string, e.g. \"http://render-farm:9000/done\"");
        } else if (auto problem = check_callback_url(value.get_ref<const std::string&>())) {
          invalid("/callback", std::move(*problem));
        } else {
          callback = value.get<std::string>();
        }
      } else if (key == "labels") {
        const std::size_t before = outcome.errors.size();
        check_job_labels(value, invalid);
        if (outcome.errors.size() == before) labels = value;
      } else {
        invalid("/" + scene::escape_token(key),
                "unknown field '" + key + "'" +
                    (key == "label" ? " (did you mean 'labels'?)" : "") +
                    ": a job has only 'scene', 'priority', 'name', 'labels' and 'callback'");
      }
    }
    if (!scene_json) invalid("/scene", "missing 'scene': the scene to simulate");
  }
  if (scene_json) {
    scene::ParseResult parsed =
        scene::parse_scene(*scene_json, options_.limits, asset_meshes(request.owner));
    for (auto& e : parsed.errors)
      invalid("/scene" + e.pointer, std::move(e.message));
    if (parsed.scene) {
      // A scene its run would certainly stop for its size (fragments, panels, frames x bodies,
      // memory), judged from lower bounds without breaking a pane, fails here rather than later.
      engine::RunBudget budget;
      budget.limits = options_.limits;
      budget.memory_bytes = options_.job_memory_bytes;
      if (auto refusal = engine::refuse_before_run(*parsed.scene, budget)) {
        const json* explicit_objects = scene_json->is_object() && scene_json->contains("objects")
                                           ? &scene_json->at("objects")
                                           : nullptr;
        const std::size_t explicit_count =
            explicit_objects && explicit_objects->is_array() ? explicit_objects->size() : 0;
        invalid(refusal->object < explicit_count
                    ? "/scene/objects/" + std::to_string(refusal->object)
                    : std::string("/scene/generators"),
                "the run of this scene would stop for its size (judged before it runs, from a "
                "lower bound of what it creates): " +
                    refusal->what.message);
      }
    }
  }
  if (!outcome.errors.empty()) {
    outcome.kind = SubmitOutcome::Kind::invalid;
    return outcome;
  }

  NewJob job;
  job.scene_json = scene_json->dump();
  job.priority = priority;
  job.name = std::move(name);
  job.labels_json = labels.dump();
  job.callback_url = std::move(callback);
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
  if (outcome.kind == SubmitOutcome::Kind::accepted) signal_work();
  return outcome;
}

AssetOutcome JobService::upload_asset(const AssetUpload& upload) {
  AssetOutcome outcome;
  if (upload.bytes.size() > options_.max_asset_bytes) {
    outcome.kind = AssetOutcome::Kind::too_large;
    outcome.message = "the file has " + std::to_string(upload.bytes.size()) +
                      " bytes, more than the limit of " + std::to_string(options_.max_asset_bytes) +
                      " bytes; simplify the mesh or split the file";
    return outcome;
  }
  outcome.kind = AssetOutcome::Kind::invalid;
  const io::MeshImport imported = io::import_mesh(upload.bytes, upload.format);
  if (!imported.mesh) {
    outcome.message = imported.error;
    return outcome;
  }
  if (imported.mesh->vertices.size() > options_.limits.max_mesh_vertices) {
    outcome.message = "the file has " + std::to_string(imported.mesh->vertices.size()) +
                      " distinct vertices, more than the limit max_mesh_vertices = " +
                      std::to_string(options_.limits.max_mesh_vertices) + "; simplify the mesh";
    return outcome;
  }
  // Every mesh of the file must be closed and manifold, so any node a scene picks is too.
  if (auto problem = geometry::check_closed_mesh(*imported.mesh)) {
    outcome.message = "the file's meshes cannot be simulated: " + *problem +
                      "; every mesh must be closed, with each edge shared by exactly two "
                      "triangles wound counter-clockwise seen from outside";
    return outcome;
  }
  AssetRecord record;
  record.id = sha256_hex(upload.bytes);
  record.owner = std::string(upload.owner);
  record.format = std::string(io::to_string(upload.format));
  record.size_bytes = static_cast<std::int64_t>(upload.bytes.size());
  record.nodes_json = json(imported.nodes).dump(-1, ' ', false, json::error_handler_t::replace);
  record.created_ms = now_ms();
  Storage::PutAsset stored = storage_.put_asset(record, upload.bytes);
  outcome.kind = stored.created ? AssetOutcome::Kind::created : AssetOutcome::Kind::existing;
  outcome.asset = std::move(stored.asset);
  return outcome;
}

scene::MeshSources JobService::asset_meshes(std::string_view owner) {
  scene::MeshSources sources;
  sources.asset = [this, owner = std::string(owner)](const scene::MeshReference& reference) {
    scene::ResolvedMesh resolved;
    const auto record = storage_.get_asset(reference.reference, std::string_view(owner));
    const auto bytes =
        record ? storage_.asset_bytes(reference.reference, std::string_view(owner)) : std::nullopt;
    const auto format = record ? io::parse_mesh_format(record->format) : std::nullopt;
    if (!record || !bytes || !format) {
      resolved.error =
          "no such asset; upload the mesh file with POST /v1/assets and use the id "
          "it returns";
      return resolved;
    }
    io::MeshImport imported = io::import_mesh(*bytes, *format, reference.node);
    resolved.mesh = std::move(imported.mesh);
    resolved.error = std::move(imported.error);
    return resolved;
  };
  return sources;
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

RecoveryReport JobService::recover_abandoned(
    const std::function<bool(const std::string&)>& owner_is_dead) {
  std::int64_t expired = 0;
  for (const std::string& owner : storage_.running_owners()) {
    if (owner_is_dead(owner)) expired += storage_.expire_leases(owner);
  }
  RecoveryReport report = storage_.recover_expired(now_ms(), options_.max_attempts);
  report.expired_here = expired;
  return report;
}

std::optional<ClaimedJob> JobService::claim(std::string_view owner, std::int64_t lease_ms) {
  return storage_.claim_next(owner, now_ms(), lease_ms);
}

JobService::Progress JobService::report_progress(const std::string& id, std::string_view owner,
                                                 double fraction) {
  Progress progress = Progress::kept;
  if (!storage_.set_progress(id, owner, fraction, now_ms())) {
    progress = Progress::lease_lost;
  } else if (storage_.cancel_requested(id)) {
    progress = Progress::cancel_requested;
  }
  notifier_.notify(id);
  return progress;
}

bool JobService::complete(const std::string& id, std::string_view owner,
                          const engine::Result& result) {
  // Encoded here rather than in the store so the size is known to count; the store keeps the
  // bytes as they are.
  StoredResult stored = to_stored_result(result);
  make_compact(&stored);
  const std::uint64_t bytes = stored.encoded.size();
  if (!storage_.complete(id, owner, stored, now_ms())) return false;
  ++stored_results_;
  stored_result_bytes_ += bytes;
  return true;
}

void JobService::fail(const std::string& id, std::string_view owner, std::string_view error_type,
                      std::string_view error_message) {
  storage_.fail(id, owner, error_type, error_message, now_ms());
}

void JobService::finish_cancelled(const std::string& id, std::string_view owner) {
  storage_.finish_cancelled(id, owner, now_ms());
}

void JobService::release(const std::string& id, std::string_view owner) {
  storage_.release(id, owner, now_ms());
}

RecoveryReport JobService::keep_leases(const std::vector<std::string>& running,
                                       std::string_view owner, std::int64_t lease_ms) {
  const std::int64_t now = now_ms();
  for (const std::string& id : running)
    storage_.renew_lease(id, owner, now + lease_ms);
  return storage_.recover_expired(now, options_.max_attempts);
}

std::int64_t JobService::prune_finished(std::chrono::milliseconds retention) {
  return storage_.prune_finished(now_ms() - retention.count());
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

// x y z qx qy qz qw, as stored, widened to double.
template <typename Number>
engine::Pose pose_from(const Number* p) {
  engine::Pose pose;
  pose.position = {p[0], p[1], p[2]};
  pose.orientation = {p[3], p[4], p[5], p[6]};
  return pose;
}

// The pose rounded to float32, as the stored frames hold poses.
engine::Pose rounded_to_float(const engine::Pose& pose) {
  engine::Pose rounded;
  for (std::size_t c = 0; c < 3; ++c)
    rounded.position[c] = static_cast<float>(pose.position[c]);
  for (std::size_t c = 0; c < 4; ++c)
    rounded.orientation[c] = static_cast<float>(pose.orientation[c]);
  return rounded;
}

engine::BodyInfo body_info(const StoredBody& stored) {
  engine::BodyInfo info;
  info.name = stored.name;
  info.mass_kg = stored.mass_kg;
  info.initial_pose = pose_from(stored.initial_pose.data());
  info.mesh.vertices.reserve(stored.vertices.size() / 3);
  for (std::size_t v = 0; v + 2 < stored.vertices.size(); v += 3)
    info.mesh.vertices.emplace_back(stored.vertices[v], stored.vertices[v + 1],
                                    stored.vertices[v + 2]);
  info.mesh.triangles.reserve(stored.triangles.size() / 3);
  for (std::size_t t = 0; t + 2 < stored.triangles.size(); t += 3)
    info.mesh.triangles.push_back(
        {stored.triangles[t], stored.triangles[t + 1], stored.triangles[t + 2]});
  return info;
}

// Every stored frame of the animated bodies, quaternions renormalised (float32 rounding leaves
// |q| a few ulp off 1): the animation the glb carries.
io::FrameSet animation_frames(std::vector<StoredFrame> stored,
                              const std::vector<std::uint32_t>& animated) {
  io::FrameSet frames;
  frames.bodies = animated;
  frames.times_s.reserve(stored.size());
  frames.poses.reserve(stored.size() * animated.size());
  for (const StoredFrame& frame : stored) {
    frames.times_s.push_back(frame.time_s);
    for (std::size_t k = 0; k < animated.size(); ++k) {
      assert(7 * k + 7 <= frame.poses.size());
      engine::Pose pose = pose_from(frame.poses.data() + 7 * k);
      double norm = 0.0;
      for (const double q : pose.orientation)
        norm += q * q;
      norm = std::sqrt(norm);
      if (norm > 0.0) {
        for (double& q : pose.orientation)
          q /= norm;
      }
      frames.poses.push_back(pose);
    }
  }
  return frames;
}

}  // namespace

StoredResult to_stored_result(const engine::Result& result) {
  StoredResult stored;
  const std::vector<bool> animated = io::animated_flags(result.bodies.size(), result.animated);
  stored.bodies.reserve(result.bodies.size());
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

  const json summary = io::result_summary(result);
  stored.stats_json = summary.at("stats").dump();
  stored.summary_json = summary.dump();
  return stored;
}

std::optional<ResultLayout> JobService::result_layout(std::string_view id) {
  const std::optional<std::string> summary_text = storage_.result_summary(id);
  if (!summary_text) return std::nullopt;
  const json summary = json::parse(*summary_text);
  ResultLayout layout;
  layout.frame_count = summary.at("frame_count").get<std::int64_t>();
  layout.animated = summary.at("animated").get<std::vector<std::uint32_t>>();
  for (const json& body : summary.at("bodies")) {
    engine::Pose pose;
    pose.position = body.at("position").get<std::array<double, 3>>();
    pose.orientation = body.at("orientation").get<std::array<double, 4>>();
    layout.initial_poses.push_back(pose);
  }
  return layout;
}

io::FrameSet JobService::result_frame_set(std::string_view id, const ResultLayout& layout,
                                          std::int64_t from, std::int64_t to,
                                          const std::vector<std::uint32_t>& bodies) {
  return frame_set(
      [this, id](std::int64_t a, std::int64_t b) { return storage_.result_frames(id, a, b); },
      layout, from, to, bodies);
}

io::FrameSet JobService::frame_set(const Storage::FrameReader& reader, const ResultLayout& layout,
                                   std::int64_t from, std::int64_t to,
                                   const std::vector<std::uint32_t>& bodies) {
  assert(0 <= from && from <= to);
  // Where each requested body's pose sits in a stored frame: its animated slot, or none.
  std::vector<std::int64_t> slot(layout.body_count(), -1);
  for (std::size_t k = 0; k < layout.animated.size(); ++k)
    slot[layout.animated[k]] = static_cast<std::int64_t>(k);
  io::FrameSet frames;
  frames.first_frame = static_cast<std::uint64_t>(from);
  frames.bodies = bodies;
  const std::vector<StoredFrame> stored = reader(from, to);
  frames.times_s.reserve(stored.size());
  frames.poses.reserve(stored.size() * bodies.size());
  for (const StoredFrame& frame : stored) {
    frames.times_s.push_back(frame.time_s);
    for (const std::uint32_t body : bodies) {
      assert(body < layout.body_count());
      const std::size_t base = 7 * static_cast<std::size_t>(std::max<std::int64_t>(slot[body], 0));
      if (slot[body] >= 0 && base + 7 <= frame.poses.size()) {
        frames.poses.push_back(pose_from(frame.poses.data() + base));
      } else {
        frames.poses.push_back(rounded_to_float(layout.initial_poses[body]));
      }
    }
  }
  return frames;
}

std::vector<engine::BodyInfo> JobService::stored_bodies(std::string_view id,
                                                        std::vector<bool>* animated) {
  const std::vector<StoredBody> stored = storage_.result_bodies(id);
  std::vector<engine::BodyInfo> bodies;
  bodies.reserve(stored.size());
  for (const StoredBody& body : stored) {
    bodies.push_back(body_info(body));
    if (animated) animated->push_back(body.animated);
  }
  // Each body's material and whether it is a fragment live in the summary (results stored
  // before they were recorded have neither: no material, not a fragment).
  if (const std::optional<std::string> summary_text = storage_.result_summary(id)) {
    const json summary = json::parse(*summary_text);
    const json& listed = summary.at("bodies");
    for (std::size_t b = 0; b < bodies.size() && b < listed.size(); ++b) {
      bodies[b].material = listed[b].value("material", std::string());
      bodies[b].fragment = listed[b].value("fragment", false);
    }
  }
  return bodies;
}

std::string JobService::result_meshes_json(std::string_view id) {
  std::vector<bool> animated;
  const std::vector<engine::BodyInfo> bodies = stored_bodies(id, &animated);
  return io::meshes_document_json(bodies, animated);
}

std::optional<std::vector<std::uint8_t>> JobService::result_glb(std::string_view id) {
  const std::optional<ResultLayout> layout = result_layout(id);
  if (!layout) return std::nullopt;
  const std::vector<engine::BodyInfo> bodies = stored_bodies(id, nullptr);
  return io::to_glb(bodies,
                    animation_frames(storage_.result_frames(id, 0, INT64_MAX), layout->animated));
}

}  // namespace brisance::server
