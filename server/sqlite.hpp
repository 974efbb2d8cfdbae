// server/sqlite: a thin RAII layer over the SQLite C API for the SQLite store — a connection
// opened with the store's pragmas, prepared statements cached per connection and reset on scope
// exit, and transactions that roll back unless committed. The counterpart of server/pg for
// PostgreSQL. Everything throws StorageError (server/storage.hpp) on failure; sqlite3.h stays in
// server/sqlite.cpp.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "server/storage.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace brisance::server {

enum class Synchronous { normal, full };

struct SqliteOptions {
  std::filesystem::path file;  // created with its directory if missing
  Synchronous synchronous = Synchronous::normal;
  int busy_timeout_ms = 5000;
  // Largest size the database may grow to, bytes (0: no limit): writes beyond it fail as they
  // would on a full disk (SQLITE_FULL), which is how the tests fill a disk.
  std::int64_t max_size_bytes = 0;
};

namespace sqlite {

// One prepared statement of a Connection's cache, reset on scope exit so it can be reused.
class Statement {
 public:
  explicit Statement(sqlite3_stmt* stmt) : stmt_(stmt) {}
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() { reset(); }

  Statement& bind(int i, std::int64_t v);
  Statement& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
  Statement& bind(int i, double v);
  Statement& bind(int i, std::string_view v);
  Statement& bind_null(int i);
  // A zero-length blob is still a blob, not NULL.
  template <typename T>
  Statement& bind_blob(int i, std::span<const T> v) {
    return bind_bytes(i, v.data(), v.size_bytes());
  }

  // True while there is a row.
  bool step();
  void run() {
    while (step()) {
    }
  }
  // Ready to bind and run again.
  void reset();

  bool is_null(int c) const;
  std::int64_t int64(int c) const;
  double real(int c) const;
  std::string text(int c) const;
  template <typename T>
  std::vector<T> blob(int c) const {
    const std::span<const unsigned char> bytes = blob_bytes(c);
    std::vector<T> out(bytes.size() / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
  }

 private:
  Statement& bind_bytes(int i, const void* data, std::size_t size);
  std::span<const unsigned char> blob_bytes(int c) const;
  void check(int rc) const;
  [[noreturn]] void fail(int rc) const;
  sqlite3_stmt* stmt_;
};

class Connection {
 public:
  // Opens (creating) `file` in WAL mode with the options' synchronous level, busy timeout and
  // size cap, foreign keys on and reads memory-mapped.
  Connection(const std::filesystem::path& file, const SqliteOptions& options);
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  void exec(const char* sql);
  // Prepared once per connection, keyed by the SQL text (a list query builds its text from the
  // filter's shape, a bounded set).
  Statement prepare(const char* sql);

  int changes() const;
  std::int64_t last_insert_rowid() const;

 private:
  sqlite3* db_ = nullptr;
  struct TextHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view text) const {
      return std::hash<std::string_view>()(text);
    }
  };
  std::unordered_map<std::string, sqlite3_stmt*, TextHash, std::equal_to<>> cache_;
};

// A transaction that rolls back unless committed.
class Transaction {
 public:
  Transaction(Connection& c, bool immediate) : c_(c) {
    c_.exec(immediate ? "BEGIN IMMEDIATE" : "BEGIN");
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction();
  void commit() {
    c_.exec("COMMIT");
    done_ = true;
  }

 private:
  Connection& c_;
  bool done_ = false;
};

}  // namespace sqlite
}  // namespace brisance::server
