// server/log: structured logs, one JSON object per line on stderr:
//   {"ts":"2026-11-21T10:00:00.123Z","level":"info","msg":"job succeeded","job":"j…",…}
// Every request's line carries its request id.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace brisance::server {

enum class LogLevel { debug = 0, info = 1, warn = 2, error = 3 };

void set_log_level(LogLevel level);
bool log_enabled(LogLevel level);
// `fields` must be a JSON object (or null); its members follow ts, level and msg.
void log_event(LogLevel level, std::string_view message, const nlohmann::json& fields);
void log_event(LogLevel level, std::string_view message);

// "2026-11-21T10:00:00.123Z" for milliseconds since the Unix epoch.
std::string iso_time_utc(std::int64_t unix_ms);

}  // namespace brisance::server
