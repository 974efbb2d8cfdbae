// cli/commands: the subcommands of the `brisance` binary and the small flag parser they share.
#pragma once

#include <initializer_list>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace brisance::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitInvalidInput = 2;

using Args = std::vector<std::string_view>;

// Bad flags or values; main() prints it as one line on stderr and exits with code 2.
struct UsageError {
  std::string message;
};

struct FlagSpec {
  FlagSpec(std::string_view flag_name, bool flag_takes_value = true,
           std::string_view short_alias = {})
      : name(flag_name), takes_value(flag_takes_value), alias(short_alias) {}
  std::string_view name;  // without the leading "--"
  bool takes_value;
  std::string_view alias;  // optional short form without the "-", e.g. "o"
};

// Parses "--name value", "--name=value", "-o value" and boolean "--name" flags against a
// declared list. Unknown, repeated or value-less flags are a UsageError that names them.
class ParsedFlags {
 public:
  ParsedFlags(std::string_view command, const Args& args, std::initializer_list<FlagSpec> specs);

  bool has(std::string_view name) const;
  std::optional<std::string_view> value(std::string_view name) const;
  // The flag's value as a finite number; a UsageError if it is not one.
  std::optional<double> number(std::string_view name) const;
  const std::vector<std::string_view>& positional() const { return positional_; }

  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string command_;
  std::vector<std::pair<std::string_view, std::optional<std::string_view>>> seen_;
  std::vector<std::string_view> positional_;
};

int run_blast(const Args& args, std::ostream& out);
int run_fracture(const Args& args, std::ostream& out);
int run_response(const Args& args, std::ostream& out);
int run_pi(const Args& args, std::ostream& out);
int run_simulation(const Args& args, std::ostream& out);
int run_validate(const Args& args, std::ostream& out);
int run_serve(const Args& args, std::ostream& out);
int run_api_key(const Args& args, std::ostream& out);

}  // namespace brisance::cli
