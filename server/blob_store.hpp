// server/blob_store: results (meshes and frames) as content-addressed files in a folder that any
// number of nodes share (`brisance serve --blobs DIR`), instead of rows in the job store.
//
// A blob is named by the SHA-256 of its bytes, DIR/ab/abcd…(64 hex digits). It is written to a
// temporary file, fsync'd, renamed into place and its folder fsync'd before the job row that names
// it is marked succeeded, so a row that reads succeeded never names a blob that a crash can lose.
// Every read checks the digest: a missing or corrupt blob is a BlobError, never wrong bytes.
//
// Garbage collection, with several nodes sharing DIR and the database: a blob goes only when no
// job row names it. The race to close is a node writing (or finding) blob X for a new job while
// another node's collector finds X unnamed. Two guards:
//  1. a grace period: a blob whose mtime is younger than `grace` is never collected, and a writer
//     that finds X already present touches its mtime;
//  2. rename, re-check, unlink: the collector renames the unnamed blobs aside (DIR/ab/.gc-…),
//     asks the store once more which digests are named, renames back the ones that now are and
//     unlinks the rest; a writer checks its blob is in place after its row commits and writes it
//     again if not (a reader that misses the blob in between reads the renamed file).
// Rejected: a reference check in the same transaction as the unlink; the file system is not part
// of the transaction, so it cannot see a writer that has written its blob but not yet committed.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/storage.hpp"

namespace brisance::server {

// A blob that is missing, corrupt (its bytes do not hash to its name) or unreadable, or a row
// naming a blob on a node without a blob store.
struct BlobError : StorageError {
  using StorageError::StorageError;
};

struct BlobOptions {
  std::filesystem::path dir;
  // An unnamed blob younger than this is kept (a writer may be about to commit its row).
  std::chrono::seconds grace{600};
};

class BlobStore {
 public:
  // Creates the folder; StorageError when it cannot.
  explicit BlobStore(BlobOptions options);

  const BlobOptions& options() const { return options_; }

  // Stores `bytes` durably under their SHA-256 and returns it (64 lowercase hex digits). A blob
  // already present is checked and its mtime touched; a corrupt one is replaced.
  std::string put(std::string_view bytes);
  // The bytes named `digest`, checked against it; BlobError when missing or corrupt.
  std::string get(std::string_view digest) const;
  // Whether a blob named `digest` is in place (not checked).
  bool contains(std::string_view digest) const;
  std::filesystem::path path_of(std::string_view digest) const;

  // Removes the blobs (and stale temporary files) older than the grace period that no digest of
  // `named()` names; `named` is asked twice (see the header comment). Returns how many blobs went.
  std::int64_t collect(const std::function<std::vector<std::string>()>& named,
                       std::filesystem::file_time_type now);

 private:
  BlobOptions options_;
};

// True for 64 lowercase hex digits.
bool is_blob_digest(std::string_view text);

// A result's bodies and frames as one blob, and back (BlobError when the bytes are not one).
// Native byte order: the nodes sharing a folder are one architecture.
std::string encode_result_blob(const std::vector<StoredBody>& bodies,
                               const std::vector<StoredFrame>& frames);
void decode_result_blob(std::string_view bytes, std::vector<StoredBody>* bodies,
                        std::vector<StoredFrame>* frames);

// The job store `inner` with results in `blobs` when given (else in `inner`, as before). Rows that
// name a blob are read from the blob store whatever `blobs` is: without one, such a read is a
// BlobError, not an empty result.
std::unique_ptr<Storage> with_blob_store(std::unique_ptr<Storage> inner,
                                         std::unique_ptr<BlobStore> blobs);

}  // namespace brisance::server
