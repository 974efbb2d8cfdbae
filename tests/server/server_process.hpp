// tests/server/server_process: `brisance serve` as a child process with its log in a file, the
// port read off its "listening" line, and its exit waited for.
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace brisance::testing {

class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& data, std::vector<std::string> extra,
                const std::filesystem::path& log)
      : log_(log) {
    std::vector<std::string> args = {BRISANCE_BINARY, "serve", "--data", data.string()};
    if (std::find(extra.begin(), extra.end(), "--port") == extra.end()) {
      args.insert(args.end(), {"--port", "0"});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot start " + args[0]);
  }
  ~ServerProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }

  std::string log() const {
    std::ifstream in(log_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // The port from the "listening" log line, or 0 if the process exited first.
  std::uint16_t wait_listening(std::chrono::seconds limit = std::chrono::seconds(60)) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      std::istringstream lines(log());
      std::string line;
      while (std::getline(lines, line)) {
        if (line.find("\"msg\":\"listening\"") == std::string::npos) continue;
        return nlohmann::json::parse(line).at("port").get<std::uint16_t>();
      }
      if (exited()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
  }

  bool exited() {
    if (pid_ <= 0) return true;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      pid_ = -1;
      return true;
    }
    return false;
  }

  // Sends the signal and waits for the exit code (-1 if it does not exit in time).
  int signal_and_wait(int signal, std::chrono::seconds limit) {
    if (pid_ > 0) kill(pid_, signal);
    return wait_exit(limit);
  }
  int wait_exit(std::chrono::seconds limit) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + limit;
    while (!exited()) {
      if (Clock::now() > deadline) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return exit_code_;
  }

 private:
  std::filesystem::path log_;
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

}  // namespace brisance::testing
