#include "server/pg.hpp"

#include <charconv>

#include <libpq-fe.h>

namespace brisance::server::pg {

Params& Params::push(std::string value, int format) {
  values_.push_back(std::move(value));
  pointers_.push_back(values_.back().data());
  lengths_.push_back(static_cast<int>(values_.back().size()));
  formats_.push_back(format);
  return *this;
}

Params& Params::add(std::string_view text) {
  return push(std::string(text), 0);
}

Params& Params::add(std::int64_t value) {
  return push(std::to_string(value), 0);
}

Params& Params::add(double value) {
  // Shortest text that reads back to the same double.
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return push(std::string(buffer, ec == std::errc() ? end : buffer), 0);
}

Params& Params::add(bool value) {
  return push(value ? "true" : "false", 0);
}

Params& Params::add_null() {
  values_.emplace_back();
  pointers_.push_back(nullptr);
  lengths_.push_back(0);
  formats_.push_back(0);
  return *this;
}

Params& Params::add_raw(const char* data, std::size_t size) {
  return push(std::string(data, size), 1);
}

Result::~Result() {
  if (result_) PQclear(result_);
}

int Result::rows() const {
  return PQntuples(result_);
}

std::int64_t Result::affected() const {
  const char* text = PQcmdTuples(result_);
  std::int64_t n = 0;
  if (text && *text) std::from_chars(text, text + std::strlen(text), n);
  return n;
}

bool Result::is_null(int row, int column) const {
  return PQgetisnull(result_, row, column) != 0;
}

std::string_view Result::text(int row, int column) const {
  return {PQgetvalue(result_, row, column),
          static_cast<std::size_t>(PQgetlength(result_, row, column))};
}

std::int64_t Result::int64(int row, int column) const {
  const std::string_view t = text(row, column);
  std::int64_t value = 0;
  std::from_chars(t.data(), t.data() + t.size(), value);
  return value;
}

double Result::real(int row, int column) const {
  const std::string_view t = text(row, column);
  double value = 0.0;
  std::from_chars(t.data(), t.data() + t.size(), value);
  return value;
}

bool Result::boolean(int row, int column) const {
  return text(row, column) == "t";
}

std::optional<std::int64_t> Result::optional_int64(int row, int column) const {
  if (is_null(row, column)) return std::nullopt;
  return int64(row, column);
}

std::string Result::decode_bytea(int row, int column) const {
  // bytea_output = hex (the default since PostgreSQL 9.0): "\x" then two hex digits per byte.
  const std::string_view t = text(row, column);
  if (t.size() < 2 || t[0] != '\\' || t[1] != 'x') return {};
  auto nibble = [](char c) {
    return static_cast<unsigned>(c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10);
  };
  std::string out((t.size() - 2) / 2, '\0');
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<char>((nibble(t[2 + 2 * i]) << 4) | nibble(t[3 + 2 * i]));
  return out;
}

Connection::Connection(const std::string& conninfo) {
  conn_ = PQconnectdb(conninfo.c_str());
  if (!conn_ || PQstatus(conn_) != CONNECTION_OK) {
    std::string message = "postgres: cannot connect: ";
    message += conn_ ? PQerrorMessage(conn_) : "out of memory";
    while (!message.empty() && message.back() == '\n')
      message.pop_back();
    if (conn_) PQfinish(conn_);
    conn_ = nullptr;
    throw Error(message, "");
  }
  // Notices (e.g. "relation already exists, skipping") are not errors; keep them off stderr.
  PQsetNoticeProcessor(
      conn_, [](void*, const char*) {}, nullptr);
}

Connection::~Connection() {
  if (conn_) PQfinish(conn_);
}

Result Connection::check(pg_result* result, const char* sql) {
  const ExecStatusType status = result ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return Result(result);
  std::string message = "postgres: ";
  message += result ? PQresultErrorMessage(result) : PQerrorMessage(conn_);
  while (!message.empty() && message.back() == '\n')
    message.pop_back();
  message += " in: ";
  message += std::string_view(sql).substr(0, 120);
  const char* state = result ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  std::string sqlstate = state ? state : "";
  if (result) PQclear(result);
  throw Error(message, std::move(sqlstate));
}

Result Connection::exec(const char* sql) {
  return check(PQexec(conn_, sql), sql);
}

Result Connection::exec(const char* sql, const Params& params) {
  return check(PQexecParams(conn_, sql, params.size(), nullptr, params.values(), params.lengths(),
                            params.formats(), 0),
               sql);
}

bool Connection::ok() const {
  return PQstatus(conn_) == CONNECTION_OK;
}

int Connection::socket() const {
  return PQsocket(conn_);
}

bool Connection::consume() {
  return PQconsumeInput(conn_) == 1 && ok();
}

std::optional<Notification> Connection::next_notification() {
  PGnotify* n = PQnotifies(conn_);
  if (!n) return std::nullopt;
  Notification out{n->relname ? n->relname : "", n->extra ? n->extra : ""};
  PQfreemem(n);
  return out;
}

Transaction::~Transaction() {
  if (!done_ && c_.ok()) {
    try {
      c_.exec("ROLLBACK");
    } catch (const StorageError&) {  // the connection is dropped from the pool if it broke
    }
  }
}

bool storable(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == 0) return false;
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t length = 0;
    std::uint32_t code = 0;
    if ((c & 0xE0) == 0xC0) {
      length = 2;
      code = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      length = 3;
      code = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      length = 4;
      code = c & 0x07;
    } else {
      return false;
    }
    if (i + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xC0) != 0x80) return false;
      code = (code << 6) | (next & 0x3F);
    }
    // Overlong forms, UTF-16 surrogates and code points beyond U+10FFFF are not UTF-8.
    constexpr std::uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < kMin[length] || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF) {
      return false;
    }
    i += length;
  }
  return true;
}

std::string storable_key(std::string_view key) {
  if (storable(key)) return std::string(key);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out = "\n~";
  for (const char byte : key) {
    out.push_back(kHex[static_cast<unsigned char>(byte) >> 4]);
    out.push_back(kHex[static_cast<unsigned char>(byte) & 0xF]);
  }
  return out;
}

}  // namespace brisance::server::pg
