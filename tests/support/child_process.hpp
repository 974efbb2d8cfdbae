// tests/support/child_process: a child process started with posix_spawn — its arguments, where its
// standard streams go, waiting for it and ending it — for the tests and benches that start
// `brisance serve` (tests/server/server_process.hpp, bench/load/server_process.hpp) or
// PostgreSQL (tests/server/postgres_fixture.hpp); and the port a server's "listening" log line
// names.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
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

struct SpawnOptions {
  std::filesystem::path stdout_path = "/dev/null";
  std::filesystem::path stderr_path;  // empty: where stdout goes
  bool append = false;                // append to the files instead of truncating them
  bool stdin_null = false;            // stdin from /dev/null instead of this process's
  std::filesystem::path working_dir;  // empty: this process's
};

// A server's way: stdout to /dev/null, stderr (its log) to a fresh file.
inline SpawnOptions log_to(const std::filesystem::path& log) {
  SpawnOptions options;
  options.stderr_path = log;
  return options;
}

// Starts args[0] (a path) with `args`; throws std::runtime_error naming it if it cannot.
inline pid_t spawn_process(std::vector<std::string> args, const SpawnOptions& options) {
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  const int flags = O_WRONLY | O_CREAT | (options.append ? O_APPEND : O_TRUNC);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, options.stdout_path.c_str(), flags, 0666);
  if (options.stderr_path.empty()) {
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  } else {
    posix_spawn_file_actions_addopen(&actions, 2, options.stderr_path.c_str(), flags, 0666);
  }
  if (options.stdin_null) posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  if (!options.working_dir.empty())
    posix_spawn_file_actions_addchdir_np(&actions, options.working_dir.c_str());
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + args.front() + ": " + std::strerror(rc));
  return pid;
}

// A wait status as one code: the exit code, or 128 + the signal that ended the process.
inline int exit_code_of(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A spawned child, killed (SIGKILL) and reaped when this object goes unless it exited first.
class ChildProcess {
 public:
  ChildProcess(std::vector<std::string> args, const SpawnOptions& options)
      : pid_(spawn_process(std::move(args), options)) {}
  ~ChildProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  int exit_code() const { return exit_code_; }  // -1 until it has exited

  bool exited() {
    if (pid_ <= 0) return true;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_code_ = exit_code_of(status);
      pid_ = -1;
      return true;
    }
    return false;
  }

  void signal(int number) {
    if (pid_ > 0) kill(pid_, number);
  }

  // The exit code, or -1 if it has not exited within the limit.
  int wait_exit(std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!exited()) {
      if (std::chrono::steady_clock::now() > deadline) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return exit_code_;
  }

 private:
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

// The port of the first `"msg":"listening"` line of a `brisance serve` log, if there is one.
inline std::optional<std::uint16_t> listening_port(const std::string& log) {
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.find("\"msg\":\"listening\"") == std::string::npos) continue;
    return nlohmann::json::parse(line).at("port").get<std::uint16_t>();
  }
  return std::nullopt;
}

}  // namespace brisance::testing
