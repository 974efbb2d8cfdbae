// The one `brisance` binary: subcommands dispatch to their own files.
// Exit codes (DESIGN.md): 0 success, 2 invalid input (message on stderr), 1 internal failure.
#include <exception>
#include <iostream>
#include <span>
#include <string_view>

#include "cli/commands.hpp"

namespace {

constexpr std::string_view kUsage =
    "usage: brisance <command> [options]\n"
    "\n"
    "commands:\n"
    "  serve     run the job service: HTTP API, queue and workers (brisance serve --help)\n"
    "  api-key   make an API key for 'serve --api-keys'\n"
    "  run       simulate a scene: brisance run SCENE.json -o OUT.glb|OUT.json\n"
    "  validate  check a scene file and list every problem\n"
    "  blast     blast-wave parameters of a charge at a distance (Kingery-Bulmash)\n"
    "  response  peak response of a structural element (SDOF) to a charge or a pulse\n"
    "  pi        pressure-impulse curve of an element: brisance pi --element E.json -o pi.svg\n"
    "  fracture  grow a crack pattern on a pane: brisance fracture --width W --height H -o F.svg\n"
    "  version   print the version\n"
    "  help      print this help\n"
    "\n"
    "Run 'brisance <command> --help' for the options of a command.\n";

}  // namespace

int main(int argc, char** argv) {
  const std::span<char*> all(argv, static_cast<std::size_t>(argc));
  if (all.size() < 2) {
    std::cerr << "brisance: no command given (run 'brisance help' for the list)\n";
    return brisance::cli::kExitInvalidInput;
  }
  const std::string_view command = all[1];
  const brisance::cli::Args args(all.begin() + 2, all.end());
  try {
    if (command == "blast") return brisance::cli::run_blast(args, std::cout);
    if (command == "response") return brisance::cli::run_response(args, std::cout);
    if (command == "pi") return brisance::cli::run_pi(args, std::cout);
    if (command == "fracture") return brisance::cli::run_fracture(args, std::cout);
    if (command == "run") return brisance::cli::run_simulation(args, std::cout);
    if (command == "validate") return brisance::cli::run_validate(args, std::cout);
    if (command == "serve") return brisance::cli::run_serve(args, std::cout);
    if (command == "api-key") return brisance::cli::run_api_key(args, std::cout);
    if (command == "version" || command == "--version") {
      std::cout << "brisance " << BRISANCE_VERSION << "\n";
      return brisance::cli::kExitOk;
    }
    if (command == "help" || command == "--help" || command == "-h") {
      std::cout << kUsage;
      return brisance::cli::kExitOk;
    }
    std::cerr << "brisance: unknown command '" << command
              << "' (run 'brisance help' for the list)\n";
    return brisance::cli::kExitInvalidInput;
  } catch (const brisance::cli::UsageError& error) {
    std::cerr << error.message << "\n";
    return brisance::cli::kExitInvalidInput;
  } catch (const std::exception& error) {
    std::cerr << "brisance " << command << ": internal error: " << error.what() << "\n";
    return brisance::cli::kExitInternal;
  }
}
