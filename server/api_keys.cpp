#include "server/api_keys.hpp"

#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "server/sha256.hpp"

namespace brisance::server {

ApiKeys ApiKeys::load(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read the API keys file " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), file.string());
}

ApiKeys ApiKeys::parse(std::string_view text, std::string_view origin) {
  ApiKeys keys;
  std::istringstream lines{std::string(text)};
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::string name, scope, hash, extra;
    fields >> name >> scope >> hash;
    const auto where = std::string(origin) + ":" + std::to_string(number) + ": ";
    if (hash.empty() || (fields >> extra)) {
      throw std::runtime_error(where + "expected 'NAME read|write|admin sha256:HEX'");
    }
    ApiKey key;
    key.name = name;
    if (scope == "read") {
      key.scope = Scope::read;
    } else if (scope == "write") {
      key.scope = Scope::write;
    } else if (scope == "admin") {
      key.scope = Scope::admin;
    } else {
      throw std::runtime_error(where + "scope must be 'read', 'write' or 'admin', got '" + scope +
                               "'");
    }
    constexpr std::string_view kPrefix = "sha256:";
    if (hash.rfind(kPrefix, 0) != 0 || hash.size() != kPrefix.size() + 64 ||
        hash.find_first_not_of("0123456789abcdef", kPrefix.size()) != std::string::npos) {
      throw std::runtime_error(where +
                               "the hash must be 'sha256:' and 64 lowercase hex digits (run "
                               "'brisance api-key' to make a key and its line)");
    }
    key.hash_hex = hash.substr(kPrefix.size());
    keys.keys_.push_back(std::move(key));
  }
  return keys;
}

std::optional<ApiKey> ApiKeys::authenticate(std::string_view presented_key) const {
  const std::string hash = sha256_hex(presented_key);
  std::optional<ApiKey> found;
  for (const ApiKey& key : keys_) {
    // No early exit: the time taken does not depend on which key (if any) matched.
    if (constant_time_equal(hash, key.hash_hex) && !found) found = key;
  }
  return found;
}

std::string generate_api_key() {
  std::random_device device;
  static constexpr char kHex[] = "0123456789abcdef";
  std::string key = "bk_";
  for (int i = 0; i < 5; ++i) {
    const std::uint32_t word = device();
    for (int nibble = 0; nibble < 8; ++nibble)
      key.push_back(kHex[(word >> (4 * nibble)) & 0xf]);
  }
  return key;
}

std::string api_key_line(std::string_view name, Scope scope, std::string_view key) {
  const char* word = scope == Scope::admin   ? " admin "
                     : scope == Scope::write ? " write "
                                             : " read ";
  return std::string(name) + word + "sha256:" + sha256_hex(key);
}

}  // namespace brisance::server
