// cli/text: printf-style formatting into a std::string (libstdc++ 12 has no <format>).
#pragma once

#include <string>

namespace brisance::cli::text {

[[gnu::format(printf, 1, 2)]] std::string printf(const char* format, ...);

}  // namespace brisance::cli::text
