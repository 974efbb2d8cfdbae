#include <charconv>
#include <cmath>

#include "cli/commands.hpp"

namespace brisance::cli {

ParsedFlags::ParsedFlags(std::string_view command, const Args& args,
                         std::initializer_list<FlagSpec> specs)
    : command_(command) {
  auto find_spec = [&](std::string_view token) -> const FlagSpec* {
    for (const FlagSpec& spec : specs) {
      if (token.starts_with("--") && token.substr(2) == spec.name) return &spec;
      if (!spec.alias.empty() && token.size() > 1 && token[0] == '-' &&
          token.substr(1) == spec.alias)
        return &spec;
    }
    return nullptr;
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view token = args[i];
    if (token.size() < 2 || token[0] != '-' || token == "--") {
      positional_.push_back(token);
      continue;
    }
    std::optional<std::string_view> inline_value;
    if (const auto eq = token.find('='); token.starts_with("--") && eq != std::string_view::npos) {
      inline_value = token.substr(eq + 1);
      token = token.substr(0, eq);
    }
    const FlagSpec* spec = find_spec(token);
    if (spec == nullptr) fail("unknown option '" + std::string(token) + "'");
    if (has(spec->name)) fail("option --" + std::string(spec->name) + " given twice");
    std::optional<std::string_view> value;
    if (spec->takes_value) {
      if (inline_value) {
        value = inline_value;
      } else if (i + 1 < args.size()) {
        value = args[++i];
      } else {
        fail("option --" + std::string(spec->name) + " needs a value");
      }
    } else if (inline_value) {
      fail("option --" + std::string(spec->name) + " takes no value");
    }
    seen_.emplace_back(spec->name, value);
  }
}

bool ParsedFlags::has(std::string_view name) const {
  for (const auto& [seen_name, value] : seen_)
    if (seen_name == name) return true;
  return false;
}

std::optional<std::string_view> ParsedFlags::value(std::string_view name) const {
  for (const auto& [seen_name, value] : seen_)
    if (seen_name == name) return value;
  return std::nullopt;
}

std::optional<double> ParsedFlags::number(std::string_view name) const {
  const auto text = value(name);
  if (!text) return std::nullopt;
  double parsed = 0.0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, parsed);
  if (ec != std::errc() || ptr != end || !std::isfinite(parsed))
    fail("--" + std::string(name) + " must be a number, got '" + std::string(*text) + "'");
  return parsed;
}

void ParsedFlags::fail(const std::string& message) const {
  throw UsageError{"brisance " + command_ + ": " + message};
}

}  // namespace brisance::cli
