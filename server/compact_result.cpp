#include "server/compact_result.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>

#include <nlohmann/json.hpp>
#include <zstd.h>

#include "server/blob_store.hpp"

namespace brisance::server {
namespace {

constexpr std::string_view kMagic = "BRISANCE-RESULT-ZSTD 1\n";

[[noreturn]] void malformed(std::string_view what) {
  throw StorageError("a stored result is malformed: " + std::string(what));
}

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Reads fixed-size values from a byte string, refusing to read past its end.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : bytes_(bytes) {}
  template <typename T>
  T value() {
    T out;
    std::memcpy(&out, take(sizeof(T)).data(), sizeof(T));
    return out;
  }
  std::string_view take(std::size_t n) {
    if (n > bytes_.size() - at_) malformed("truncated");
    const std::string_view out = bytes_.substr(at_, n);
    at_ += n;
    return out;
  }
  std::size_t at() const { return at_; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

// One zstd frame with its content size and a checksum, so a flipped bit in a database row is an
// error on reading, as it is in the blob store (whose files are named by their SHA-256).
std::string compress(std::string_view raw, int level) {
  const std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> context(ZSTD_createCCtx(),
                                                                     &ZSTD_freeCCtx);
  if (!context) throw StorageError("zstd: out of memory");
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
  std::string out(ZSTD_compressBound(raw.size()), '\0');
  const std::size_t size =
      ZSTD_compress2(context.get(), out.data(), out.size(), raw.data(), raw.size());
  if (ZSTD_isError(size)) throw StorageError(std::string("zstd: ") + ZSTD_getErrorName(size));
  out.resize(size);
  return out;
}

// At most this many bytes come out of one section: a chunk of 128 frames of the largest result
// the limits allow is far below it, and a corrupt size field cannot make us allocate more.
constexpr unsigned long long kMaxSectionBytes = 1ULL << 32;

std::string decompress(std::string_view packed) {
  const unsigned long long size = ZSTD_getFrameContentSize(packed.data(), packed.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN ||
      size > kMaxSectionBytes) {
    malformed("a section is not one zstd frame of known size");
  }
  std::string out(static_cast<std::size_t>(size), '\0');
  const std::size_t got = ZSTD_decompress(out.data(), out.size(), packed.data(), packed.size());
  if (ZSTD_isError(got) || got != size) malformed("a section does not inflate");
  return out;
}

// One chunk of frames, before zstd: u32 frame count, per frame f64 time and u32 pose-word count,
// then every pose word (float32 bits) XORed with the same word of the frame before when that
// frame has as many words, as byte planes (all first bytes, then all second bytes, ...).
std::string chunk_bytes(const StoredFrame* frames, std::size_t count) {
  std::string out;
  put(out, static_cast<std::uint32_t>(count));
  std::size_t words = 0;
  for (std::size_t f = 0; f < count; ++f) {
    put(out, frames[f].time_s);
    put(out, static_cast<std::uint32_t>(frames[f].poses.size()));
    words += frames[f].poses.size();
  }
  std::vector<std::uint32_t> deltas;
  deltas.reserve(words);
  for (std::size_t f = 0; f < count; ++f) {
    const std::vector<float>& poses = frames[f].poses;
    const bool delta = f > 0 && frames[f - 1].poses.size() == poses.size();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      std::uint32_t word = std::bit_cast<std::uint32_t>(poses[i]);
      if (delta) word ^= std::bit_cast<std::uint32_t>(frames[f - 1].poses[i]);
      deltas.push_back(word);
    }
  }
  const std::size_t planes_at = out.size();
  out.resize(planes_at + 4 * words);
  for (std::size_t i = 0; i < words; ++i) {
    for (std::size_t b = 0; b < 4; ++b)
      out[planes_at + b * words + i] = static_cast<char>((deltas[i] >> (8 * b)) & 0xff);
  }
  return out;
}

void read_chunk(std::string_view raw, std::size_t expected_count, std::vector<StoredFrame>* out,
                std::size_t skip, std::size_t keep) {
  Cursor c(raw);
  const auto count = c.value<std::uint32_t>();
  if (count != expected_count) malformed("a chunk holds another number of frames");
  if (count > raw.size() / 12) malformed("a chunk's frame count exceeds its bytes");
  std::vector<std::uint32_t> sizes(count);
  std::vector<double> times(count);
  std::size_t words = 0;
  for (std::uint32_t f = 0; f < count; ++f) {
    times[f] = c.value<double>();
    sizes[f] = c.value<std::uint32_t>();
    words += sizes[f];
    if (words > raw.size() / 4) malformed("a chunk's pose count exceeds its bytes");
  }
  const std::string_view planes = c.take(4 * words);
  if (c.at() != raw.size()) malformed("a chunk has trailing bytes");
  std::vector<float> previous;
  std::size_t at = 0;
  for (std::uint32_t f = 0; f < count && f < skip + keep; ++f) {
    StoredFrame frame;
    frame.time_s = times[f];
    frame.poses.resize(sizes[f]);
    const bool delta = f > 0 && previous.size() == sizes[f];
    for (std::size_t i = 0; i < sizes[f]; ++i, ++at) {
      std::uint32_t word = 0;
      for (std::size_t b = 0; b < 4; ++b)
        word |= static_cast<std::uint32_t>(static_cast<unsigned char>(planes[b * words + at]))
                << (8 * b);
      if (delta) word ^= std::bit_cast<std::uint32_t>(previous[i]);
      frame.poses[i] = std::bit_cast<float>(word);
    }
    previous = frame.poses;
    if (f >= skip) out->push_back(std::move(frame));
  }
}

struct Index {
  std::int64_t frame_count = 0;
  std::uint32_t frames_per_chunk = 1;
  std::string_view bodies;
  std::vector<std::string_view> chunks;
};

Index read_index(std::string_view bytes) {
  if (!is_compact_result(bytes)) malformed("not a compact result");
  Cursor c(bytes.substr(kMagic.size()));
  Index index;
  index.frame_count = c.value<std::int64_t>();
  index.frames_per_chunk = c.value<std::uint32_t>();
  if (index.frame_count < 0 || index.frames_per_chunk == 0) malformed("bad frame counts");
  const std::uint64_t chunk_count =
      (static_cast<std::uint64_t>(index.frame_count) + index.frames_per_chunk - 1) /
      index.frames_per_chunk;
  if (chunk_count > bytes.size()) malformed("more chunks than bytes");
  const auto bodies_size = c.value<std::uint64_t>();
  std::vector<std::uint64_t> sizes(chunk_count);
  for (auto& size : sizes)
    size = c.value<std::uint64_t>();
  index.bodies = c.take(bodies_size);
  for (const std::uint64_t size : sizes)
    index.chunks.push_back(c.take(size));
  if (c.at() != bytes.size() - kMagic.size()) malformed("trailing bytes");
  return index;
}

}  // namespace

std::string encode_compact_result(const std::vector<StoredBody>& bodies,
                                  const std::vector<StoredFrame>& frames, int level,
                                  std::uint32_t frames_per_chunk) {
  frames_per_chunk = std::max<std::uint32_t>(frames_per_chunk, 1);
  const std::string packed_bodies = compress(encode_result_blob(bodies, {}), level);
  std::vector<std::string> chunks;
  for (std::size_t first = 0; first < frames.size(); first += frames_per_chunk) {
    const std::size_t count = std::min<std::size_t>(frames_per_chunk, frames.size() - first);
    chunks.push_back(compress(chunk_bytes(frames.data() + first, count), level));
  }
  std::string out(kMagic);
  put(out, static_cast<std::int64_t>(frames.size()));
  put(out, frames_per_chunk);
  put(out, static_cast<std::uint64_t>(packed_bodies.size()));
  for (const std::string& chunk : chunks)
    put(out, static_cast<std::uint64_t>(chunk.size()));
  out += packed_bodies;
  for (const std::string& chunk : chunks)
    out += chunk;
  return out;
}

bool is_compact_result(std::string_view bytes) {
  return bytes.substr(0, kMagic.size()) == kMagic;
}

std::int64_t compact_frame_count(std::string_view bytes) {
  return read_index(bytes).frame_count;
}

std::vector<StoredBody> decode_compact_bodies(std::string_view bytes) {
  std::vector<StoredBody> bodies;
  try {
    decode_result_blob(decompress(read_index(bytes).bodies), &bodies, nullptr);
  } catch (const BlobError&) {
    malformed("its bodies section");
  }
  return bodies;
}

std::vector<StoredFrame> decode_compact_frames(std::string_view bytes, std::int64_t from,
                                               std::int64_t to) {
  const Index index = read_index(bytes);
  const std::int64_t first = std::clamp<std::int64_t>(from, 0, index.frame_count);
  const std::int64_t last = std::clamp<std::int64_t>(to, first, index.frame_count);
  std::vector<StoredFrame> frames;
  frames.reserve(static_cast<std::size_t>(std::min<std::int64_t>(last - first, 1 << 16)));
  const std::int64_t per_chunk = index.frames_per_chunk;
  for (std::int64_t chunk = first / per_chunk; chunk * per_chunk < last; ++chunk) {
    const std::int64_t chunk_first = chunk * per_chunk;
    const auto skip = static_cast<std::size_t>(std::max<std::int64_t>(first - chunk_first, 0));
    const auto keep = static_cast<std::size_t>(std::min(last, chunk_first + per_chunk) -
                                               std::max(first, chunk_first));
    const auto expected =
        static_cast<std::size_t>(std::min(per_chunk, index.frame_count - chunk_first));
    read_chunk(decompress(index.chunks[static_cast<std::size_t>(chunk)]), expected, &frames, skip,
               keep);
  }
  if (static_cast<std::int64_t>(frames.size()) != last - first) malformed("frames missing");
  return frames;
}

void make_compact(StoredResult* result) {
  if (!result->encoded.empty() || !result->blob_digest.empty()) return;
  result->encoded = encode_compact_result(result->bodies, result->frames);
  result->bodies.clear();
  result->frames.clear();
  const auto stored_bytes = static_cast<std::int64_t>(result->encoded.size());
  nlohmann::json stats = result->stats_json.empty() ? nlohmann::json::object()
                                                    : nlohmann::json::parse(result->stats_json);
  stats["stored_bytes"] = stored_bytes;
  result->stats_json = stats.dump();
  if (!result->summary_json.empty()) {
    nlohmann::json summary = nlohmann::json::parse(result->summary_json);
    if (summary.contains("stats")) summary["stats"]["stored_bytes"] = stored_bytes;
    result->summary_json = summary.dump();
  }
}

}  // namespace brisance::server
