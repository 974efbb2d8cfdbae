#include "server/sqlite.hpp"

#include <algorithm>

#include <sqlite3.h>

namespace brisance::server::sqlite {

Statement& Statement::bind(int i, std::int64_t v) {
  check(sqlite3_bind_int64(stmt_, i, v));
  return *this;
}

Statement& Statement::bind(int i, double v) {
  check(sqlite3_bind_double(stmt_, i, v));
  return *this;
}

Statement& Statement::bind(int i, std::string_view v) {
  check(sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
  return *this;
}

Statement& Statement::bind_null(int i) {
  check(sqlite3_bind_null(stmt_, i));
  return *this;
}

Statement& Statement::bind_bytes(int i, const void* data, std::size_t size) {
  static const char kEmpty = 0;
  if (size == 0) data = &kEmpty;
  check(sqlite3_bind_blob(stmt_, i, data, static_cast<int>(size), SQLITE_TRANSIENT));
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  fail(rc);
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::is_null(int c) const {
  return sqlite3_column_type(stmt_, c) == SQLITE_NULL;
}

std::int64_t Statement::int64(int c) const {
  return sqlite3_column_int64(stmt_, c);
}

double Statement::real(int c) const {
  return sqlite3_column_double(stmt_, c);
}

std::string Statement::text(int c) const {
  const auto* p = sqlite3_column_text(stmt_, c);
  return p ? std::string(reinterpret_cast<const char*>(p),
                         static_cast<std::size_t>(sqlite3_column_bytes(stmt_, c)))
           : std::string();
}

std::span<const unsigned char> Statement::blob_bytes(int c) const {
  const auto* p = static_cast<const unsigned char*>(sqlite3_column_blob(stmt_, c));
  const auto bytes = static_cast<std::size_t>(sqlite3_column_bytes(stmt_, c));
  if (p == nullptr) return {};
  return {p, bytes};
}

void Statement::check(int rc) const {
  if (rc != SQLITE_OK) fail(rc);
}

void Statement::fail(int rc) const {
  throw StorageError(std::string("sqlite: ") + sqlite3_errstr(rc) + ": " +
                     sqlite3_errmsg(sqlite3_db_handle(stmt_)));
}

Connection::Connection(const std::filesystem::path& file, const SqliteOptions& options) {
  const int rc =
      sqlite3_open_v2(file.c_str(), &db_,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    std::string message = "cannot open database " + file.string() + ": " +
                          (db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc));
    sqlite3_close(db_);
    throw StorageError(message);
  }
  sqlite3_busy_timeout(db_, options.busy_timeout_ms);
  exec("PRAGMA journal_mode = WAL");
  exec(options.synchronous == Synchronous::full ? "PRAGMA synchronous = FULL"
                                                : "PRAGMA synchronous = NORMAL");
  exec("PRAGMA foreign_keys = ON");
  // Reads map the file instead of copying pages (256 MiB of address space per connection).
  exec("PRAGMA mmap_size = 268435456");
  if (options.max_size_bytes > 0) {
    // max_page_count is per connection; every connection of the store applies it.
    const std::string pragma = "PRAGMA max_page_count = " + std::to_string(std::max<std::int64_t>(
                                                                1, options.max_size_bytes / 4096));
    exec(pragma.c_str());
  }
}

Connection::~Connection() {
  for (auto& [sql, stmt] : cache_)
    sqlite3_finalize(stmt);
  sqlite3_close(db_);
}

void Connection::exec(const char* sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    std::string message = std::string("sqlite: ") + (error ? error : "error") + " in: " + sql;
    sqlite3_free(error);
    throw StorageError(message);
  }
}

Statement Connection::prepare(const char* sql) {
  auto it = cache_.find(std::string_view(sql));
  if (it == cache_.end()) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v3(db_, sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt, nullptr) != SQLITE_OK) {
      throw StorageError(std::string("sqlite: ") + sqlite3_errmsg(db_) + " in: " + sql);
    }
    it = cache_.emplace(sql, stmt).first;
  }
  return Statement(it->second);
}

int Connection::changes() const {
  return sqlite3_changes(db_);
}

std::int64_t Connection::last_insert_rowid() const {
  return sqlite3_last_insert_rowid(db_);
}

Transaction::~Transaction() {
  if (!done_) {
    try {
      c_.exec("ROLLBACK");
    } catch (const StorageError&) {  // nothing more to do: the connection is reset on reuse
    }
  }
}

}  // namespace brisance::server::sqlite
