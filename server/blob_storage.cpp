// The job store with results in a blob store (server/blob_store.hpp): every call goes to the
// inner store (server/forwarding_storage) except writing a result, reading its bodies and frames,
// and collecting blobs.
#include <algorithm>
#include <memory>
#include <utility>

#include <nlohmann/json.hpp>

#include "server/blob_store.hpp"
#include "server/compact_result.hpp"
#include "server/forwarding_storage.hpp"
#include "server/log.hpp"

namespace brisance::server {
namespace {

class BlobStorage final : public ForwardingStorage {
 public:
  BlobStorage(std::unique_ptr<Storage> inner, std::unique_ptr<BlobStore> blobs)
      : ForwardingStorage(std::move(inner)), blobs_(std::move(blobs)) {}

  // The result is encoded once here (server/compact_result) unless the caller did; the blob is
  // durable before the row says succeeded; a blob whose row then fails to commit (the lease was
  // lost) is named by no job and collected later.
  bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                std::int64_t now_ms) override {
    StoredResult row = result;
    make_compact(&row);
    if (!blobs_ || row.encoded.empty()) return inner_->complete(id, owner, row, now_ms);
    const std::string bytes = std::move(row.encoded);
    row.encoded.clear();
    row.blob_digest = blobs_->put(bytes);
    if (!inner_->complete(id, owner, row, now_ms)) return false;
    // A collector on another node may have taken the blob between its put and this commit.
    if (!blobs_->contains(row.blob_digest)) {
      log_event(LogLevel::warn, "result blob collected before its job committed: written again",
                {{"job", std::string(id)}, {"blob", row.blob_digest}});
      blobs_->put(bytes);
    }
    return true;
  }

  // Where a result is, newest layout first: a blob (compact, or the older uncompressed blob
  // layout), a compact row, or job_bodies and job_frames rows.
  std::vector<StoredBody> result_bodies(std::string_view id) override {
    if (const std::optional<std::string> bytes = compact_or_blob(id)) {
      if (is_compact_result(*bytes)) return decode_compact_bodies(*bytes);
      std::vector<StoredBody> bodies;
      decode_result_blob(*bytes, &bodies, nullptr);
      return bodies;
    }
    return inner_->result_bodies(id);
  }

  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                         std::int64_t to) override {
    const std::optional<std::string> bytes = compact_or_blob(id);
    if (!bytes) return inner_->result_frames(id, from, to);
    if (is_compact_result(*bytes)) return decode_compact_frames(*bytes, from, to);
    std::vector<StoredFrame> frames;
    decode_result_blob(*bytes, nullptr, &frames);
    const auto size = static_cast<std::int64_t>(frames.size());
    const std::int64_t first = std::clamp<std::int64_t>(from, 0, size);
    const std::int64_t last = std::clamp<std::int64_t>(to, first, size);
    frames.erase(frames.begin() + last, frames.end());
    frames.erase(frames.begin(), frames.begin() + first);
    return frames;
  }

  FrameReader frame_reader(std::string_view id) override {
    std::optional<std::string> bytes = compact_or_blob(id);
    if (!bytes) return ForwardingStorage::frame_reader(id);
    if (is_compact_result(*bytes)) {
      auto held = std::make_shared<const std::string>(std::move(*bytes));
      return [held](std::int64_t from, std::int64_t to) {
        return decode_compact_frames(*held, from, to);
      };
    }
    auto frames = std::make_shared<std::vector<StoredFrame>>();
    decode_result_blob(*bytes, nullptr, frames.get());
    return [frames](std::int64_t from, std::int64_t to) {
      const auto size = static_cast<std::int64_t>(frames->size());
      const std::int64_t first = std::clamp<std::int64_t>(from, 0, size);
      const std::int64_t last = std::clamp<std::int64_t>(to, first, size);
      return std::vector<StoredFrame>(frames->begin() + first, frames->begin() + last);
    };
  }

  std::int64_t collect_blobs(std::int64_t now_ms) override {
    (void)now_ms;  // the blobs' ages are file times, compared with the file system's clock
    if (!blobs_) return 0;
    return blobs_->collect([this] { return inner_->blob_references(); },
                           std::filesystem::file_time_type::clock::now());
  }

 private:
  // The bytes of job `id`'s blob or compact row; nullopt when its result is in rows.
  std::optional<std::string> compact_or_blob(std::string_view id) {
    const std::optional<std::string> digest = inner_->result_blob(id);
    if (digest && !digest->empty()) return load(id, *digest);
    return inner_->result_encoded(id);
  }

  // The checked bytes of job `id`'s blob; a BlobError (logged here, with the job) when there are
  // none to give.
  std::string load(std::string_view id, const std::string& digest) {
    try {
      if (!blobs_) {
        throw BlobError("the result of job " + std::string(id) + " is in a blob store (" + digest +
                        ") but this node runs without --blobs");
      }
      return blobs_->get(digest);
    } catch (const BlobError& error) {
      log_event(LogLevel::error, "result blob unreadable",
                {{"job", std::string(id)}, {"blob", digest}, {"error", error.what()}});
      throw;
    }
  }

  std::unique_ptr<BlobStore> blobs_;
};

}  // namespace

std::unique_ptr<Storage> with_blob_store(std::unique_ptr<Storage> inner,
                                         std::unique_ptr<BlobStore> blobs) {
  return std::make_unique<BlobStorage>(std::move(inner), std::move(blobs));
}

}  // namespace brisance::server
