// server/compact_result: a result's meshes and frames as one compact, lossless byte string, made
// once above the stores (server/blob_storage) so the SQLite and PostgreSQL rows and the blob
// store's files all hold the same bytes.
//
// Layout (native byte order, like the blob store): a magic line, the frame count, the frames per
// chunk, the compressed sizes of the bodies section and of each chunk, then those sections, each
// one zstd frame with its content size and a checksum (a flipped bit is an error, not a pose). The
// bodies section is server/blob_store's encoding of the bodies (meshes once). A chunk holds up to
// `frames_per_chunk` frames: their times, their pose counts and their poses, each float32 XORed
// with the same slot of the frame before (a resting body gives zero words), the words then split
// into byte planes (exponents together, mantissas together) before zstd. Nothing is rounded:
// decoding gives back the very bits the worker stored. Quantising poses was rejected: float32
// already is the served precision (docs/service.md), and bit-exact frames keep results comparable
// across stores and with the CLI's.
//
// Chunks decode on their own, so a page of frames inflates only the chunks it covers.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "server/storage.hpp"

namespace brisance::server {

// The zstd level results are stored at; see bench/results/result_storage.md for the choice.
inline constexpr int kResultZstdLevel = 9;
inline constexpr std::uint32_t kFramesPerChunk = 128;

std::string encode_compact_result(const std::vector<StoredBody>& bodies,
                                  const std::vector<StoredFrame>& frames,
                                  int level = kResultZstdLevel,
                                  std::uint32_t frames_per_chunk = kFramesPerChunk);

// Whether `bytes` are in this layout (else they are server/blob_store's older, uncompressed one).
bool is_compact_result(std::string_view bytes);

// The frame count, the bodies, and the frames [from, to) clamped to what there is; a StorageError
// when the bytes are not a compact result.
std::int64_t compact_frame_count(std::string_view bytes);
std::vector<StoredBody> decode_compact_bodies(std::string_view bytes);
std::vector<StoredFrame> decode_compact_frames(std::string_view bytes, std::int64_t from,
                                               std::int64_t to);

// Encodes `result`'s bodies and frames into `result->encoded` (clearing both), and records the
// encoded size as `stored_bytes` in its stats (stats_json and the summary's `stats`). Does
// nothing when it is already encoded or names a blob.
void make_compact(StoredResult* result);

}  // namespace brisance::server
