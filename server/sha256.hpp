// server/sha256: SHA-256 (FIPS 180-4, from libcrypto), for hashing API keys at rest and ETags.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace brisance::server {

std::array<std::uint8_t, 32> sha256(std::string_view data);
std::string sha256_hex(std::string_view data);  // 64 lowercase hex digits

// True when a and b are equal, in time that depends only on their lengths.
bool constant_time_equal(std::string_view a, std::string_view b);

}  // namespace brisance::server
