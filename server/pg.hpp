// server/pg: a thin RAII layer over libpq for the PostgreSQL store — a connection, parameterised
// statements (text parameters, bytea ones sent binary), results read as text, transactions that
// roll back unless committed, and LISTEN/NOTIFY notifications.
//
// Not libpqxx: Debian 12 ships libpqxx 6.4 (C++17-era API, a shared library of its own to carry
// into every image) and its headers cost more compile time than the store itself; the store
// needs only the few calls below. Everything throws StorageError (server/storage.hpp) on failure.
#pragma once

#include <cstdint>
#include <cstring>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/storage.hpp"

struct pg_conn;
struct pg_result;

namespace brisance::server::pg {

// A failed statement or connection; `sqlstate` is PostgreSQL's five-character error code (empty
// when the connection itself failed).
struct Error : StorageError {
  Error(const std::string& message, std::string state)
      : StorageError(message), sqlstate(std::move(state)) {}
  std::string sqlstate;
};

// Whether PostgreSQL can hold `text` in a text column: valid UTF-8 (the database encoding) and no
// NUL (libpq passes text parameters as C strings). SQLite stores any bytes, so the PostgreSQL
// store handles a client's bytes that PostgreSQL cannot hold the same way for both stores: an id
// or owner that is not storable names no job, and an idempotency key that is not storable is
// stored encoded (storable_key).
bool storable(std::string_view text);
// A key PostgreSQL can store for any bytes: itself when storable, else a line feed (which no
// HTTP header holds, so no storable key looks like it) and its bytes in hex.
std::string storable_key(std::string_view key);

// The parameters $1, $2 … of one statement. Values are copied in.
class Params {
 public:
  Params& add(std::string_view text);
  Params& add(const char* text) { return add(std::string_view(text)); }
  Params& add(const std::string& text) { return add(std::string_view(text)); }
  Params& add(std::int64_t value);
  Params& add(int value) { return add(static_cast<std::int64_t>(value)); }
  Params& add(double value);
  Params& add(bool value);
  Params& add_null();
  // Raw bytes for a bytea parameter (sent in binary format).
  template <typename T>
  Params& add_bytes(std::span<const T> values) {
    return add_raw(reinterpret_cast<const char*>(values.data()), values.size_bytes());
  }

  int size() const { return static_cast<int>(values_.size()); }
  const char* const* values() const { return pointers_.data(); }
  const int* lengths() const { return lengths_.data(); }
  const int* formats() const { return formats_.data(); }

 private:
  Params& add_raw(const char* data, std::size_t size);
  Params& push(std::string value, int format);

  std::deque<std::string> values_;  // stable addresses
  std::vector<const char*> pointers_;
  std::vector<int> lengths_;
  std::vector<int> formats_;
};

// The rows of one statement, every column as text.
class Result {
 public:
  explicit Result(pg_result* result) : result_(result) {}
  Result(Result&& other) noexcept : result_(std::exchange(other.result_, nullptr)) {}
  Result& operator=(Result&&) = delete;
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;
  ~Result();

  int rows() const;
  // Rows an INSERT, UPDATE or DELETE touched.
  std::int64_t affected() const;
  bool is_null(int row, int column) const;
  std::string_view text(int row, int column) const;
  std::int64_t int64(int row, int column) const;
  double real(int row, int column) const;
  bool boolean(int row, int column) const;
  std::optional<std::int64_t> optional_int64(int row, int column) const;
  // A bytea column (hex output) decoded into values of T.
  template <typename T>
  std::vector<T> bytes(int row, int column) const {
    const std::string raw = decode_bytea(row, column);
    std::vector<T> out(raw.size() / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), raw.data(), out.size() * sizeof(T));
    return out;
  }

 private:
  std::string decode_bytea(int row, int column) const;
  pg_result* result_;
};

struct Notification {
  std::string channel;
  std::string payload;
};

class Connection {
 public:
  // `conninfo`: a postgres:// URL or key=value pairs (libpq's syntax). Throws Error if the
  // server cannot be reached or refuses the connection.
  explicit Connection(const std::string& conninfo);
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  Result exec(const char* sql);
  Result exec(const char* sql, const Params& params);
  // False once the connection is broken (the server went away); it cannot be reused.
  bool ok() const;

  // LISTEN side: the socket to wait on, then read what arrived. consume() returns false when the
  // connection broke.
  int socket() const;
  bool consume();
  std::optional<Notification> next_notification();

 private:
  Result check(pg_result* result, const char* sql);
  pg_conn* conn_ = nullptr;
};

// BEGIN … COMMIT; rolls back on scope exit unless committed.
class Transaction {
 public:
  explicit Transaction(Connection& c) : c_(c) { c_.exec("BEGIN"); }
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

}  // namespace brisance::server::pg
