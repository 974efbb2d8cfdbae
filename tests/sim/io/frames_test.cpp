// Tests of sim/io/frames: the one frame shape. The JSON and BRF1 encoders are pinned byte for
// byte on a small frame set (the bytes GET /v1/jobs/{id}/frames served before the codec
// existed), and the streamed writer must equal the DOM for awkward numbers.
#include "sim/io/frames.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace brisance::io {
namespace {

using nlohmann::json;

engine::Pose pose(std::array<double, 3> position, std::array<double, 4> orientation) {
  engine::Pose p;
  p.position = position;
  p.orientation = orientation;
  return p;
}

// Frames 3 and 4 of a result, bodies 2 and 0 (in that order); every number exact in float32.
FrameSet small_frames() {
  FrameSet frames;
  frames.first_frame = 3;
  frames.bodies = {2, 0};
  frames.times_s = {0.125, 0.25};
  frames.poses = {pose({1.0, 0.5, -2.0}, {0.0, 0.0, 0.0, 1.0}),
                  pose({0.25, 0.0, 6.0}, {0.0, 0.0, 1.0, 0.0}),
                  pose({1.0, 0.5, -2.0}, {0.0, 0.0, 0.0, 1.0}),
                  pose({0.5, -0.125, 6.5}, {0.5, 0.5, -0.5, 0.5})};
  return frames;
}

std::string hex(const std::string& bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (const char c : bytes) {
    const auto b = static_cast<unsigned char>(c);
    out += kDigits[b >> 4];
    out += kDigits[b & 0xf];
  }
  return out;
}

TEST(Frames, DocumentJsonIsPinned) {
  EXPECT_EQ(frames_document_json(small_frames(), 10),
            "{\"bodies\":[2,0],\"frame_count\":10,\"frames\":[{\"index\":3,\"poses\":[{\"body\":2"
            ",\"orientation\":[0.0,0.0,0.0,1.0],\"position\":[1.0,0.5,-2.0]},{\"body\":0,\"orient"
            "ation\":[0.0,0.0,1.0,0.0],\"position\":[0.25,0.0,6.0]}],\"time\":0.125},{\"index\":4"
            ",\"poses\":[{\"body\":2,\"orientation\":[0.0,0.0,0.0,1.0],\"position\":[1.0,0.5,-2.0"
            "]},{\"body\":0,\"orientation\":[0.5,0.5,-0.5,0.5],\"position\":[0.5,-0.125,6.5]}],\""
            "time\":0.25}],\"from\":3,\"to\":5}");
}

TEST(Frames, Brf1IsPinned) {
  EXPECT_EQ(hex(frames_to_brf1(small_frames())),
            "425246310300000002000000020000000200000000000000000000000000c03f0000803f0000003f"
            "000000c00000000000000000000000000000803f0000803e000000000000c0400000000000000000"
            "0000803f00000000000000000000d03f0000803f0000003f000000c0000000000000000000000000"
            "0000803f0000003f000000be0000d0400000003f0000003f000000bf0000003f");
}

TEST(Frames, StreamedBrf1EqualsTheString) {
  for (FrameSet frames : {small_frames(), FrameSet{}}) {
    std::ostringstream out;
    write_brf1(frames, out);
    EXPECT_EQ(out.str(), frames_to_brf1(frames));
  }
}

TEST(Frames, StreamedFrameEqualsTheDom) {
  FrameSet odd = small_frames();
  odd.poses[0].position = {std::nan(""), -0.0, 3.0};
  odd.poses[1].position = {1e-300, -1.7976931348623157e308, 0.1 + 0.2};
  odd.poses[2].orientation = {5e-324, 1e21, -1e-7, 123456789.0};
  FrameSet no_bodies = small_frames();
  no_bodies.bodies.clear();
  no_bodies.poses.clear();
  for (const FrameSet& frames :
       {small_frames(), odd, no_bodies, with_velocities(small_frames()), with_velocities(odd)}) {
    for (std::size_t f = 0; f < frames.frame_count(); ++f) {
      std::ostringstream out;
      write_frame_json(out, frames, f);
      EXPECT_EQ(out.str(), frame_to_json(frames, f).dump());
    }
    // The document is the DOM of the same members.
    json document = {{"from", frames.first_frame},
                     {"to", frames.first_frame + frames.frame_count()},
                     {"frame_count", 10},
                     {"bodies", frames.bodies},
                     {"frames", json::array()}};
    for (std::size_t f = 0; f < frames.frame_count(); ++f)
      document["frames"].push_back(frame_to_json(frames, f));
    EXPECT_EQ(frames_document_json(frames, 10), document.dump());
  }
}

TEST(Frames, VelocitiesOfSteadyMotionAreExactAndPagesTakeTheirNeighbours) {
  // A body moving at v = (2, -1, 0.5) m/s and turning at 3 rad/s about (0, 0.6, 0.8), sampled at
  // 30 frames a second: the central differences give v and omega exactly (to round-off), at the
  // ends too (one-sided).
  const std::array<double, 3> v{2.0, -1.0, 0.5};
  const Eigen::Vector3d axis(0.0, 0.6, 0.8);
  const double rate = 3.0;
  FrameSet all;
  all.bodies = {4};
  for (int f = 0; f < 10; ++f) {
    const double t = f / 30.0;
    const Eigen::Quaterniond q(Eigen::AngleAxisd(rate * t, axis));
    all.times_s.push_back(t);
    all.poses.push_back(
        pose({1.0 + v[0] * t, 2.0 + v[1] * t, v[2] * t}, {q.x(), q.y(), q.z(), q.w()}));
  }
  const FrameSet moving = with_velocities(all);
  ASSERT_EQ(moving.velocities.size(), 10u);
  for (std::size_t f = 0; f < 10; ++f) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(moving.velocities[f].linear_m_s[c], v[c], 1e-12) << f;
      EXPECT_NEAR(moving.velocities[f].angular_rad_s[c], rate * axis[c], 1e-9) << f;
    }
  }
  // Frames 3..6 as a page: with one neighbour on each side they equal the whole set's.
  FrameSet page = all;
  page.first_frame = 2;
  page.times_s.assign(all.times_s.begin() + 2, all.times_s.begin() + 8);
  page.poses.assign(all.poses.begin() + 2, all.poses.begin() + 8);
  const FrameSet trimmed = with_velocities(page, 1, 1);
  EXPECT_EQ(trimmed.first_frame, 3u);
  ASSERT_EQ(trimmed.frame_count(), 4u);
  ASSERT_EQ(trimmed.velocities.size(), 4u);
  EXPECT_EQ(trimmed.times_s.front(), all.times_s[3]);
  EXPECT_EQ(frame_to_json(trimmed, 0).dump(), [&] {
    json frame = frame_to_json(moving, 3);
    frame["index"] = 3;
    return frame.dump();
  }());
  const json pose_json = frame_to_json(trimmed, 1)["poses"][0];
  EXPECT_NEAR(pose_json["linear_velocity"][0].get<double>(), 2.0, 1e-12);
  EXPECT_TRUE(frame_to_json(all, 0)["poses"][0].count("linear_velocity") == 0);
}

TEST(Frames, FramesOfAResultAreItsAnimatedBodiesFromFrameZero) {
  engine::Result result;
  result.bodies.resize(3);
  result.animated = {2, 0};
  result.frame_times_s = {0.0, 0.5};
  const FrameSet small = small_frames();
  result.poses = small.poses;
  const FrameSet frames = frames_of(result);
  EXPECT_EQ(frames.first_frame, 0u);
  EXPECT_EQ(frames.bodies, result.animated);
  EXPECT_EQ(frames.times_s, result.frame_times_s);
  ASSERT_EQ(frames.poses.size(), 4u);
  EXPECT_EQ(frames.pose(1, 1).position, small.pose(1, 1).position);
  EXPECT_EQ(frames.pose(1, 1).orientation, small.pose(1, 1).orientation);
}

}  // namespace
}  // namespace brisance::io
