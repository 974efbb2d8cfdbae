#include "server/blob_store.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <set>
#include <system_error>
#include <unordered_set>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "server/sha256.hpp"

namespace brisance::server {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kGcPrefix = ".gc-";
constexpr std::string_view kTmpPrefix = ".tmp-";
constexpr std::string_view kMagic = "BRISANCE-RESULT-BLOB 1\n";

std::string errno_text() {
  return std::strerror(errno);
}

// fsync of a file or folder by path; StorageError when it fails.
void sync_path(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw StorageError("blob store: cannot open " + path.string() + ": " + errno_text());
  const int rc = ::fsync(fd);
  const std::string error = rc != 0 ? errno_text() : "";
  ::close(fd);
  if (rc != 0) throw StorageError("blob store: fsync of " + path.string() + " failed: " + error);
}

// The whole file, or nullopt when it does not exist.
std::optional<std::string> read_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return std::nullopt;
    throw BlobError("blob store: cannot open " + path.string() + ": " + errno_text());
  }
  std::string bytes;
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string error = errno_text();
      ::close(fd);
      throw BlobError("blob store: cannot read " + path.string() + ": " + error);
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return bytes;
}

// Writes `bytes` to a new file at `path` and fsyncs it.
void write_new_file(const fs::path& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw StorageError("blob store: cannot create " + path.string() + ": " + errno_text());
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string error = errno_text();
      ::close(fd);
      ::unlink(path.c_str());
      throw StorageError("blob store: cannot write " + path.string() + ": " + error);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const std::string error = errno_text();
    ::close(fd);
    ::unlink(path.c_str());
    throw StorageError("blob store: fsync of " + path.string() + " failed: " + error);
  }
  ::close(fd);
}

class Writer {
 public:
  explicit Writer(std::string& out) : out_(out) {}
  template <typename T>
  void value(const T& v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(std::string_view s) {
    value(static_cast<std::uint64_t>(s.size()));
    out_.append(s);
  }

 private:
  std::string& out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <typename T>
  T value() {
    T v;
    std::memcpy(&v, take(sizeof v).data(), sizeof v);
    return v;
  }
  template <typename T>
  std::vector<T> array() {
    const auto n = value<std::uint64_t>();
    if (n > in_.size() / sizeof(T)) malformed();
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), take(n * sizeof(T)).data(), n * sizeof(T));
    return v;
  }
  std::string text() {
    const auto n = value<std::uint64_t>();
    if (n > in_.size()) malformed();
    return std::string(take(n));
  }
  std::string_view take(std::size_t n) {
    if (n > in_.size()) malformed();
    const std::string_view part = in_.substr(0, n);
    in_.remove_prefix(n);
    return part;
  }
  bool done() const { return in_.empty(); }
  [[noreturn]] static void malformed() {
    throw BlobError("blob store: a result blob is truncated or of another format");
  }

 private:
  std::string_view in_;
};

}  // namespace

bool is_blob_digest(std::string_view text) {
  return text.size() == 64 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

BlobStore::BlobStore(BlobOptions options) : options_(std::move(options)) {
  std::error_code ec;
  fs::create_directories(options_.dir, ec);
  if (ec || !fs::is_directory(options_.dir)) {
    throw StorageError("blob store: cannot create folder " + options_.dir.string() + ": " +
                       (ec ? ec.message() : "not a folder"));
  }
}

fs::path BlobStore::path_of(std::string_view digest) const {
  return options_.dir / std::string(digest.substr(0, 2)) / std::string(digest);
}

bool BlobStore::contains(std::string_view digest) const {
  std::error_code ec;
  return is_blob_digest(digest) && fs::exists(path_of(digest), ec);
}

std::string BlobStore::put(std::string_view bytes) {
  const std::string digest = sha256_hex(bytes);
  const fs::path path = path_of(digest);
  if (auto present = read_file(path); present && sha256_hex(*present) == digest) {
    // Named by a new job now: the touch keeps a collector's grace period off it.
    if (::utimensat(AT_FDCWD, path.c_str(), nullptr, 0) != 0 && errno != ENOENT) {
      throw StorageError("blob store: cannot touch " + path.string() + ": " + errno_text());
    }
    if (contains(digest)) return digest;
  }
  const fs::path folder = path.parent_path();
  std::error_code ec;
  if (fs::create_directory(folder, ec)) sync_path(options_.dir, O_RDONLY | O_DIRECTORY);
  if (ec) throw StorageError("blob store: cannot create " + folder.string() + ": " + ec.message());
  static std::atomic<std::uint64_t> counter{0};
  const fs::path temporary =
      folder / (std::string(kTmpPrefix) + digest + "-" + std::to_string(::getpid()) + "-" +
                std::to_string(counter.fetch_add(1)));
  write_new_file(temporary, bytes);
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string error = errno_text();
    ::unlink(temporary.c_str());
    throw StorageError("blob store: cannot rename into " + path.string() + ": " + error);
  }
  sync_path(folder, O_RDONLY | O_DIRECTORY);
  return digest;
}

std::string BlobStore::get(std::string_view digest) const {
  if (!is_blob_digest(digest)) {
    throw BlobError("blob store: '" + std::string(digest) + "' is not a blob digest");
  }
  const fs::path path = path_of(digest);
  std::optional<std::string> bytes = read_file(path);
  // Renamed aside by a collector that will put it back (see the header comment).
  if (!bytes)
    bytes = read_file(path.parent_path() / (std::string(kGcPrefix) + std::string(digest)));
  if (!bytes) throw BlobError("blob store: blob " + path.string() + " is missing");
  if (sha256_hex(*bytes) != digest) {
    throw BlobError("blob store: blob " + path.string() + " is corrupt (its bytes hash to " +
                    sha256_hex(*bytes) + ")");
  }
  return std::move(*bytes);
}

std::int64_t BlobStore::collect(const std::function<std::vector<std::string>()>& named,
                                fs::file_time_type now) {
  const auto before = now - options_.grace;
  std::unordered_set<std::string> first;
  for (std::string& digest : named())
    first.insert(std::move(digest));
  // Pass 1: rename aside the old unnamed blobs (and take up any a stopped collector left aside).
  std::vector<std::string> aside;
  std::error_code ec;
  for (const fs::directory_entry& folder : fs::directory_iterator(options_.dir, ec)) {
    const std::string folder_name = folder.path().filename().string();
    if (folder_name.size() != 2 || !folder.is_directory(ec)) continue;
    // Listed before renaming, so a renamed entry is not met again under its new name.
    std::vector<fs::path> entries;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder.path(), ec))
      entries.push_back(entry.path());
    for (const fs::path& entry : entries) {
      const std::string name = entry.filename().string();
      std::error_code time_ec;
      const auto mtime = fs::last_write_time(entry, time_ec);
      if (time_ec || mtime >= before) continue;
      if (name.starts_with(kTmpPrefix)) {
        fs::remove(entry, time_ec);  // a writer that stopped before its rename
      } else if (name.starts_with(kGcPrefix) && is_blob_digest(name.substr(kGcPrefix.size()))) {
        aside.push_back(name.substr(kGcPrefix.size()));
      } else if (is_blob_digest(name) && !first.contains(name)) {
        if (::rename(entry.c_str(), (folder.path() / (std::string(kGcPrefix) + name)).c_str()) ==
            0) {
          aside.push_back(name);
        }
      }
    }
  }
  if (aside.empty()) return 0;
  // Pass 2: a row committed since the first question may name one of them now.
  std::set<std::string> second;
  for (std::string& digest : named())
    second.insert(std::move(digest));
  std::int64_t removed = 0;
  for (const std::string& digest : aside) {
    const fs::path path = path_of(digest);
    const fs::path renamed = path.parent_path() / (std::string(kGcPrefix) + digest);
    if (second.contains(digest)) {
      ::rename(renamed.c_str(), path.c_str());
    } else if (::unlink(renamed.c_str()) == 0) {
      ++removed;
    }
  }
  return removed;
}

std::string encode_result_blob(const std::vector<StoredBody>& bodies,
                               const std::vector<StoredFrame>& frames) {
  std::string out(kMagic);
  Writer w(out);
  w.value(static_cast<std::uint64_t>(bodies.size()));
  for (const StoredBody& b : bodies) {
    w.text(b.name);
    w.value(b.mass_kg);
    w.value(static_cast<std::uint8_t>(b.animated ? 1 : 0));
    w.value(b.initial_pose);
    w.array(b.vertices);
    w.array(b.triangles);
  }
  w.value(static_cast<std::uint64_t>(frames.size()));
  for (const StoredFrame& f : frames) {
    w.value(f.time_s);
    w.array(f.poses);
  }
  return out;
}

void decode_result_blob(std::string_view bytes, std::vector<StoredBody>* bodies,
                        std::vector<StoredFrame>* frames) {
  Reader r(bytes);
  if (r.take(kMagic.size()) != kMagic) Reader::malformed();
  const auto body_count = r.value<std::uint64_t>();
  std::vector<StoredBody> read_bodies;
  for (std::uint64_t i = 0; i < body_count; ++i) {
    StoredBody b;
    b.name = r.text();
    b.mass_kg = r.value<double>();
    b.animated = r.value<std::uint8_t>() != 0;
    b.initial_pose = r.value<std::array<double, 7>>();
    b.vertices = r.array<float>();
    b.triangles = r.array<std::uint32_t>();
    read_bodies.push_back(std::move(b));
  }
  if (bodies) *bodies = std::move(read_bodies);
  if (!frames) return;
  const auto frame_count = r.value<std::uint64_t>();
  frames->clear();
  for (std::uint64_t f = 0; f < frame_count; ++f) {
    StoredFrame frame;
    frame.time_s = r.value<double>();
    frame.poses = r.array<float>();
    frames->push_back(std::move(frame));
  }
  if (!r.done()) Reader::malformed();
}

}  // namespace brisance::server
