// sim/io/number_text: numbers in request text (query parameters, flags) and back, for the
// calculators' readers (blast_json, response_json).
#pragma once

#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

namespace brisance::io {

// A finite number spelled exactly by `text`, or nullopt (the caller reports it).
inline std::optional<double> to_number(std::string_view text) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

// The shortest text that reads back as `value`, for echoing an input in a message.
inline std::string shown(double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("?");
}

}  // namespace brisance::io
