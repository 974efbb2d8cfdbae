// The job store with results in a blob store (server/blob_store.hpp): every call goes to the
// inner store (server/forwarding_storage) except writing a result, reading its bodies and frames,
// and collecting blobs.
#include <algorithm>
#include <utility>

#include <nlohmann/json.hpp>

#include "server/blob_store.hpp"
#include "server/forwarding_storage.hpp"
#include "server/log.hpp"

namespace brisance::server {
namespace {

class BlobStorage final : public ForwardingStorage {
 public:
  BlobStorage(std::unique_ptr<Storage> inner, std::unique_ptr<BlobStore> blobs)
      : ForwardingStorage(std::move(inner)), blobs_(std::move(blobs)) {}

  // The blob is durable before the row says succeeded; a blob whose row then fails to commit (the
  // lease was lost) is named by no job and collected later.
  bool complete(std::string_view id, std::string_view owner, const StoredResult& result,
                std::int64_t now_ms) override {
    if (!blobs_) return inner_->complete(id, owner, result, now_ms);
    const std::string bytes = encode_result_blob(result.bodies, result.frames);
    StoredResult row;
    row.summary_json = result.summary_json;
    row.stats_json = result.stats_json;
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

  std::vector<StoredBody> result_bodies(std::string_view id) override {
    const std::optional<std::string> digest = inner_->result_blob(id);
    if (!digest || digest->empty()) return inner_->result_bodies(id);
    std::vector<StoredBody> bodies;
    decode_result_blob(load(id, *digest), &bodies, nullptr);
    return bodies;
  }

  std::vector<StoredFrame> result_frames(std::string_view id, std::int64_t from,
                                         std::int64_t to) override {
    const std::optional<std::string> digest = inner_->result_blob(id);
    if (!digest || digest->empty()) return inner_->result_frames(id, from, to);
    std::vector<StoredFrame> frames;
    decode_result_blob(load(id, *digest), nullptr, &frames);
    const auto size = static_cast<std::int64_t>(frames.size());
    const std::int64_t first = std::clamp<std::int64_t>(from, 0, size);
    const std::int64_t last = std::clamp<std::int64_t>(to, first, size);
    frames.erase(frames.begin() + last, frames.end());
    frames.erase(frames.begin(), frames.begin() + first);
    return frames;
  }

  std::int64_t collect_blobs(std::int64_t now_ms) override {
    (void)now_ms;  // the blobs' ages are file times, compared with the file system's clock
    if (!blobs_) return 0;
    return blobs_->collect([this] { return inner_->blob_references(); },
                           std::filesystem::file_time_type::clock::now());
  }

 private:
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
