// The compact result encoding (server/compact_result): lossless to the bit, pages across chunk
// boundaries, frames of differing pose counts, malformed bytes refused, and smaller than the raw
// float32 rows for a trajectory that moves smoothly.
#include "server/compact_result.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace brisance::testing {
namespace {

using server::StoredBody;
using server::StoredFrame;

std::vector<StoredFrame> smooth_frames(std::size_t count, std::size_t bodies) {
  std::vector<StoredFrame> frames;
  for (std::size_t f = 0; f < count; ++f) {
    StoredFrame frame;
    frame.time_s = 0.001 * static_cast<double>(f);
    for (std::size_t b = 0; b < bodies; ++b) {
      const float t = static_cast<float>(frame.time_s);
      // Half the bodies rest; the others fly and spin.
      const float moving = b % 2 == 0 ? 1.0f : 0.0f;
      const float angle = moving * 3.0f * t;
      frame.poses.insert(frame.poses.end(),
                         {static_cast<float>(b) + moving * 20.0f * t, 1.5f - moving * 4.9f * t * t,
                          -2.0f, 0.0f, std::sin(angle / 2), 0.0f, std::cos(angle / 2)});
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

void expect_bit_identical(const std::vector<StoredFrame>& a, const std::vector<StoredFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t f = 0; f < a.size(); ++f) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[f].time_s), std::bit_cast<std::uint64_t>(b[f].time_s));
    ASSERT_EQ(a[f].poses.size(), b[f].poses.size()) << "frame " << f;
    if (!a[f].poses.empty()) {
      EXPECT_EQ(
          0, std::memcmp(a[f].poses.data(), b[f].poses.data(), a[f].poses.size() * sizeof(float)))
          << "frame " << f;
    }
  }
}

TEST(CompactResult, FramesComeBackBitForBitInAnyPage) {
  std::vector<StoredFrame> frames = smooth_frames(300, 5);
  // Bits a rounding or text step would change: a NaN payload, -0, a denormal, infinity.
  frames[7].poses[0] = std::bit_cast<float>(0x7fc12345u);
  frames[7].poses[1] = -0.0f;
  frames[128].poses[2] = 1e-40f;
  frames[255].poses[3] = std::numeric_limits<float>::infinity();
  // A frame with fewer poses (not delta-coded against its neighbours) and one with none.
  frames[200].poses.resize(14);
  frames[201].poses.clear();
  const std::string bytes = server::encode_compact_result({}, frames, 3, 128);
  ASSERT_TRUE(server::is_compact_result(bytes));
  EXPECT_EQ(server::compact_frame_count(bytes), 300);

  expect_bit_identical(server::decode_compact_frames(bytes, 0, INT64_MAX), frames);
  // Pages inside a chunk, across one and two chunk boundaries, and clamped at the ends.
  for (const auto& [from, to] : std::vector<std::pair<std::int64_t, std::int64_t>>{
           {0, 1}, {5, 9}, {127, 129}, {100, 260}, {199, 203}, {256, 300}, {290, 400}, {-3, 2}}) {
    const std::int64_t first = std::max<std::int64_t>(from, 0);
    const std::int64_t last = std::min<std::int64_t>(to, 300);
    expect_bit_identical(server::decode_compact_frames(bytes, from, to),
                         std::vector<StoredFrame>(frames.begin() + first, frames.begin() + last));
  }
  EXPECT_TRUE(server::decode_compact_frames(bytes, 300, 310).empty());
}

TEST(CompactResult, BodiesComeBackWithTheirMeshes) {
  StoredBody body;
  body.name = "pane \xe2\x80\x94 fragment";
  body.mass_kg = 2.5;
  body.animated = true;
  body.initial_pose = {1, 2, 3, 0, 0, 0, 1};
  body.vertices = {0, -0.0f, 1e-40f, 1, 0, 0, 0, 1, 0.1f, 0, 0, 1};
  body.triangles = {0, 1, 2, 0xffffffffu, 7, 3};
  const std::string bytes = server::encode_compact_result({body, StoredBody{}}, {});
  const std::vector<StoredBody> back = server::decode_compact_bodies(bytes);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].name, body.name);
  EXPECT_EQ(back[0].mass_kg, body.mass_kg);
  EXPECT_TRUE(back[0].animated);
  EXPECT_EQ(back[0].initial_pose, body.initial_pose);
  EXPECT_EQ(0, std::memcmp(back[0].vertices.data(), body.vertices.data(), 12 * sizeof(float)));
  EXPECT_EQ(back[0].triangles, body.triangles);
  EXPECT_TRUE(back[1].vertices.empty());
  EXPECT_EQ(server::compact_frame_count(bytes), 0);
}

TEST(CompactResult, SmoothFramesTakeFarLessThanRawRows) {
  const std::vector<StoredFrame> frames = smooth_frames(2000, 40);
  const std::size_t raw = frames.size() * (8 + 40 * 7 * sizeof(float));
  const std::string bytes = server::encode_compact_result({}, frames);
  // The float32 rows hold 2000 x (8 + 1120) bytes; resting bodies XOR to zero words and the
  // moving ones share sign, exponent and high mantissa bytes from frame to frame.
  EXPECT_LT(bytes.size(), raw / 3) << bytes.size() << " of " << raw;
}

TEST(CompactResult, MalformedBytesAreAStorageErrorNotAWrongResult) {
  const std::string bytes = server::encode_compact_result({}, smooth_frames(300, 3));
  EXPECT_THROW(server::decode_compact_frames(bytes.substr(0, bytes.size() - 1), 0, 300),
               server::StorageError);
  std::string flipped = bytes;
  flipped[flipped.size() - 40] ^= 0x5a;  // inside the last chunk's zstd frame
  EXPECT_THROW(server::decode_compact_frames(flipped, 256, 300), server::StorageError);
  EXPECT_THROW(server::decode_compact_bodies("BRISANCE-RESULT-BLOB 1\n"), server::StorageError);
  // The frame count (an int64 after the 23-byte magic line, native little-endian) changed: a
  // huge one names more chunks than there are bytes, a slightly larger one disagrees with the
  // frames its chunks hold.
  std::string huge_count = bytes;
  huge_count[30] = '\x7f';
  EXPECT_THROW(server::decode_compact_frames(huge_count, 0, 1), server::StorageError);
  std::string more_frames = bytes;
  more_frames[23] = static_cast<char>(more_frames[23] + 1);
  EXPECT_EQ(server::compact_frame_count(more_frames), 301);
  EXPECT_THROW(server::decode_compact_frames(more_frames, 0, 301), server::StorageError);
}

TEST(CompactResult, MakeCompactRecordsTheStoredBytesInTheStats) {
  server::StoredResult result;
  result.frames = smooth_frames(10, 2);
  result.stats_json = R"({"steps":3})";
  result.summary_json = R"({"frame_count":10,"stats":{"steps":3}})";
  server::make_compact(&result);
  EXPECT_TRUE(result.frames.empty());
  ASSERT_TRUE(server::is_compact_result(result.encoded));
  const std::string size = std::to_string(result.encoded.size());
  EXPECT_EQ(result.stats_json, R"({"steps":3,"stored_bytes":)" + size + "}");
  EXPECT_EQ(result.summary_json,
            R"({"frame_count":10,"stats":{"steps":3,"stored_bytes":)" + size + "}}");
}

}  // namespace
}  // namespace brisance::testing
