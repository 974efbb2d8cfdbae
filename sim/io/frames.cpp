#include "sim/io/frames.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <ostream>
#include <sstream>
#include <string_view>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace brisance::io {

namespace {

using nlohmann::json;

// BRF1 is little-endian; so is every machine this builds for (x86-64, aarch64).
static_assert(std::endian::native == std::endian::little);

template <typename T>
void append_raw(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void append_u32(std::string& out, std::uint32_t value) {
  append_raw(out, value);
}

// The header: magic, first frame, frame count, body count and the body indices.

// One frame record: its time (f64), then x y z qx qy qz qw (f32) per body.
void append_brf1_frame(std::string& out, const FrameSet& frames, std::size_t frame) {
  append_raw(out, frames.times_s[frame]);
  for (std::size_t k = 0; k < frames.bodies.size(); ++k) {
    const engine::Pose& pose = frames.pose(frame, k);
    for (const double coordinate : pose.position)
      append_raw(out, static_cast<float>(coordinate));
    for (const double component : pose.orientation)
      append_raw(out, static_cast<float>(component));
  }
}

}  // namespace

std::string brf1_header(std::uint64_t first_frame, std::uint64_t frame_count,
                        const std::vector<std::uint32_t>& bodies) {
  std::string out = "BRF1";
  append_u32(out, static_cast<std::uint32_t>(first_frame));
  append_u32(out, static_cast<std::uint32_t>(frame_count));
  append_u32(out, static_cast<std::uint32_t>(bodies.size()));
  for (const std::uint32_t body : bodies)
    append_u32(out, body);
  return out;
}

void append_brf1_frames(std::string& out, const FrameSet& frames) {
  assert(frames.poses.size() == frames.frame_count() * frames.bodies.size());
  for (std::size_t f = 0; f < frames.frame_count(); ++f)
    append_brf1_frame(out, frames, f);
}

FrameSet frames_of(const engine::Result& result) {
  assert(result.poses.size() == result.frame_times_s.size() * result.animated.size());
  FrameSet frames;
  frames.bodies = result.animated;
  frames.times_s = result.frame_times_s;
  frames.poses = result.poses;
  return frames;
}

FrameSet with_velocities(FrameSet frames, std::size_t margin_before, std::size_t margin_after) {
  const std::size_t count = frames.frame_count();
  const std::size_t slots = frames.bodies.size();
  assert(frames.poses.size() == count * slots);
  assert(margin_before + margin_after <= count);
  const auto quaternion = [](const engine::Pose& pose) {
    return Eigen::Quaterniond(pose.orientation[3], pose.orientation[0], pose.orientation[1],
                              pose.orientation[2])
        .normalized();
  };
  frames.velocities.assign(count * slots, Twist{});
  for (std::size_t f = 0; f < count && count > 1; ++f) {
    const std::size_t before = f == 0 ? 0 : f - 1;
    const std::size_t after = f + 1 == count ? f : f + 1;
    const double dt = frames.times_s[after] - frames.times_s[before];
    if (!(dt > 0.0)) continue;
    for (std::size_t k = 0; k < slots; ++k) {
      const engine::Pose& a = frames.pose(before, k);
      const engine::Pose& b = frames.pose(after, k);
      Twist& twist = frames.velocities[f * slots + k];
      for (int c = 0; c < 3; ++c)
        twist.linear_m_s[c] = (b.position[c] - a.position[c]) / dt;
      // The shorter way round: q and -q are one rotation.
      Eigen::Quaterniond turn = quaternion(b) * quaternion(a).conjugate();
      if (turn.w() < 0.0) turn.coeffs() = -turn.coeffs();
      const Eigen::AngleAxisd axis_angle(turn);
      const Eigen::Vector3d omega = axis_angle.axis() * (axis_angle.angle() / dt);
      for (int c = 0; c < 3; ++c)
        twist.angular_rad_s[c] = std::isfinite(omega[c]) ? omega[c] : 0.0;
    }
  }
  if (margin_before + margin_after > 0) {
    const auto trim = [&](auto& values, std::size_t per_frame) {
      values.erase(values.end() - static_cast<std::ptrdiff_t>(margin_after * per_frame),
                   values.end());
      values.erase(values.begin(),
                   values.begin() + static_cast<std::ptrdiff_t>(margin_before * per_frame));
    };
    trim(frames.times_s, 1);
    trim(frames.poses, slots);
    trim(frames.velocities, slots);
    frames.first_frame += margin_before;
  }
  return frames;
}

json frame_to_json(const FrameSet& frames, std::size_t frame) {
  json poses = json::array();
  poses.get_ref<json::array_t&>().reserve(frames.bodies.size());
  for (std::size_t k = 0; k < frames.bodies.size(); ++k) {
    const engine::Pose& pose = frames.pose(frame, k);
    json entry = {
        {"body", frames.bodies[k]}, {"position", pose.position}, {"orientation", pose.orientation}};
    if (!frames.velocities.empty()) {
      const Twist& twist = frames.velocities[frame * frames.bodies.size() + k];
      entry["linear_velocity"] = twist.linear_m_s;
      entry["angular_velocity"] = twist.angular_rad_s;
    }
    poses.push_back(std::move(entry));
  }
  return json{{"index", frames.first_frame + frame},
              {"time", frames.times_s[frame]},
              {"poses", std::move(poses)}};
}

namespace {

// Writes frames as JSON text without building their DOM. The frame's numbers go into one flat
// array, dumped once so each keeps nlohmann's exact formatting, and the fixed keys are written
// around them in the order nlohmann dumps an object (sorted by key); io_tests checks the text
// equals frame_to_json(...).dump(). The buffers are reused from frame to frame.
class FrameJsonWriter {
 public:
  void write(std::ostream& out, const FrameSet& frames, std::size_t frame);

 private:
  json numbers_ = json::array();
  std::string text_;
};

void FrameJsonWriter::write(std::ostream& out, const FrameSet& frames, std::size_t frame) {
  json::array_t& values = numbers_.get_ref<json::array_t&>();
  values.clear();
  const bool moving = !frames.velocities.empty();
  values.reserve(2 + (moving ? 14 : 8) * frames.bodies.size());
  values.emplace_back(frames.first_frame + frame);
  values.emplace_back(frames.times_s[frame]);
  for (std::size_t k = 0; k < frames.bodies.size(); ++k) {
    const engine::Pose& pose = frames.pose(frame, k);
    const Twist* twist = moving ? &frames.velocities[frame * frames.bodies.size() + k] : nullptr;
    if (twist)
      for (const double component : twist->angular_rad_s)
        values.emplace_back(component);
    values.emplace_back(frames.bodies[k]);
    if (twist)
      for (const double component : twist->linear_m_s)
        values.emplace_back(component);
    for (const double component : pose.orientation)
      values.emplace_back(component);
    for (const double coordinate : pose.position)
      values.emplace_back(coordinate);
  }
  text_ = numbers_.dump();  // "[i,t,b,qx,qy,qz,qw,x,y,z,b,...]"; no number contains a comma
  std::size_t at = 1;
  const auto next = [&]() {
    const std::size_t end = std::min(text_.find(',', at), text_.size() - 1);
    const std::string_view token(text_.data() + at, end - at);
    at = end + 1;
    return token;
  };
  out << "{\"index\":" << next();
  const std::string_view time = next();
  out << ",\"poses\":[";
  for (std::size_t k = 0; k < frames.bodies.size(); ++k) {
    if (k != 0) out << ',';
    out << '{';
    if (moving) {
      out << "\"angular_velocity\":[" << next();
      for (int c = 1; c < 3; ++c)
        out << ',' << next();
      out << "],";
    }
    out << "\"body\":" << next();
    if (moving) {
      out << ",\"linear_velocity\":[" << next();
      for (int c = 1; c < 3; ++c)
        out << ',' << next();
      out << ']';
    }
    out << ",\"orientation\":[" << next();
    for (int c = 1; c < 4; ++c)
      out << ',' << next();
    out << "],\"position\":[" << next();
    for (int c = 1; c < 3; ++c)
      out << ',' << next();
    out << "]}";
  }
  out << "],\"time\":" << time << '}';
}

}  // namespace

void write_frame_json(std::ostream& out, const FrameSet& frames, std::size_t frame) {
  FrameJsonWriter().write(out, frames, frame);
}

void write_frames_array(std::ostream& out, const FrameSet& frames) {
  FrameJsonWriter writer;
  out << '[';
  for (std::size_t f = 0; f < frames.frame_count(); ++f) {
    if (f != 0) out << ',';
    writer.write(out, frames, f);
  }
  out << ']';
}

std::string frames_document_json(const FrameSet& frames, std::uint64_t total_frame_count) {
  std::ostringstream out;
  out << "{\"bodies\":" << json(frames.bodies).dump() << ",\"frame_count\":" << total_frame_count
      << ",\"frames\":";
  write_frames_array(out, frames);
  out << ",\"from\":" << frames.first_frame
      << ",\"to\":" << frames.first_frame + frames.frame_count() << '}';
  return std::move(out).str();
}

std::string frames_to_brf1(const FrameSet& frames) {
  assert(frames.poses.size() == frames.frame_count() * frames.bodies.size());
  std::string out = brf1_header(frames.first_frame, frames.frame_count(), frames.bodies);
  out.reserve(out.size() + frames.frame_count() * (8 + 28 * frames.bodies.size()));
  for (std::size_t f = 0; f < frames.frame_count(); ++f)
    append_brf1_frame(out, frames, f);
  return out;
}

// Frame by frame, so a large result never holds its whole binary form in memory.
void write_brf1(const FrameSet& frames, std::ostream& out) {
  assert(frames.poses.size() == frames.frame_count() * frames.bodies.size());
  std::string chunk = brf1_header(frames.first_frame, frames.frame_count(), frames.bodies);
  for (std::size_t f = 0; f < frames.frame_count(); ++f) {
    append_brf1_frame(chunk, frames, f);
    out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    chunk.clear();
  }
  out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
}

}  // namespace brisance::io
