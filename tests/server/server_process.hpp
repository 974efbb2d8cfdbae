// tests/server/server_process: `brisance serve` as a child process with its log in a file, the
// port read off its "listening" line, and its exit waited for.
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/child_process.hpp"

namespace brisance::testing {

class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& data, std::vector<std::string> extra,
                const std::filesystem::path& log)
      : log_(log), process_(arguments(data, std::move(extra)), log_to(log)) {}

  std::string log() const {
    std::ifstream in(log_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // The port from the "listening" log line, or 0 if the process exited first.
  std::uint16_t wait_listening(std::chrono::seconds limit = std::chrono::seconds(60)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      if (const auto port = listening_port(log())) return *port;
      if (exited()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
  }

  bool exited() { return process_.exited(); }

  // Sends the signal and waits for the exit code (-1 if it does not exit in time).
  int signal_and_wait(int signal, std::chrono::seconds limit) {
    process_.signal(signal);
    return wait_exit(limit);
  }
  int wait_exit(std::chrono::seconds limit) { return process_.wait_exit(limit); }

 private:
  static std::vector<std::string> arguments(const std::filesystem::path& data,
                                            std::vector<std::string> extra) {
    std::vector<std::string> args = {BRISANCE_BINARY, "serve", "--data", data.string()};
    if (std::find(extra.begin(), extra.end(), "--port") == extra.end())
      args.insert(args.end(), {"--port", "0"});
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  std::filesystem::path log_;
  ChildProcess process_;
};

}  // namespace brisance::testing
