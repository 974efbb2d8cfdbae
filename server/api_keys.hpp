// server/api_keys: optional API keys (`Authorization: Bearer KEY`). The keys file stores only
// SHA-256 hashes, one key per line:
//   # comment
//   NAME read|write sha256:HEX
// `brisance api-key` prints a new key and its line. A write key can also read.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brisance::server {

// read: GET its own jobs; write: also submit, cancel and delete them; admin: write, on every key's
// jobs.
enum class Scope { read, write, admin };

struct ApiKey {
  std::string name;
  Scope scope = Scope::read;
  std::string hash_hex;  // sha256 of the key
};

class ApiKeys {
 public:
  ApiKeys() = default;
  // Throws std::runtime_error naming the file and line of the first problem.
  static ApiKeys load(const std::filesystem::path& file);
  static ApiKeys parse(std::string_view text, std::string_view origin);

  bool enabled() const { return !keys_.empty(); }
  std::size_t size() const { return keys_.size(); }
  // The key whose hash matches, comparing against every stored hash in constant time.
  std::optional<ApiKey> authenticate(std::string_view presented_key) const;

 private:
  std::vector<ApiKey> keys_;
};

// A new random key: "bk_" and 40 hex digits (160 bits from the system's random source).
std::string generate_api_key();
// The keys-file line for a key.
std::string api_key_line(std::string_view name, Scope scope, std::string_view key);

}  // namespace brisance::server
