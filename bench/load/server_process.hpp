// bench/load/server_process: the `brisance serve` processes load_bench spawns (--server, --nodes)
// and the CPU time of processes, for load_bench's per-phase CPU columns.
#pragma once

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include "tests/support/child_process.hpp"

namespace brisance::load {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

inline std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class ServerProcess {
 public:
  ServerProcess(const std::string& binary, int workers, const std::string& store)
      : dir_(make_dir()), log_(dir_ / "server.log") {
    std::vector<std::string> args = {binary,        "serve",
                                     "--port",      "0",
                                     "--data",      (dir_ / "data").string(),
                                     "--workers",   std::to_string(workers),
                                     "--max-queue", "1000000",
                                     "--log-level", "warn"};
    if (!store.empty()) args.insert(args.end(), {"--store", store});
    command_ = args[0];
    for (std::size_t i = 1; i < args.size(); ++i)
      command_ += " " + args[i];
    try {
      process_.emplace(args, testing::log_to(log_));
    } catch (...) {
      std::error_code ignored;
      fs::remove_all(dir_, ignored);
      throw;
    }
  }
  ~ServerProcess() {
    process_.reset();  // killed and reaped before its folder goes
    if (remove_dir_) {
      std::error_code ignored;
      fs::remove_all(dir_, ignored);
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  const std::string& command() const { return command_; }
  const fs::path& dir() const { return dir_; }
  pid_t pid() const { return process_->pid(); }
  void keep_dir() { remove_dir_ = false; }

  std::string log() const { return read_file(log_); }
  std::string log_tail(std::size_t bytes = 2000) const {
    const std::string text = log();
    return text.size() > bytes ? "..." + text.substr(text.size() - bytes) : text;
  }

  // The port: from the "listening" log line if the log level shows it, else the process's
  // listening socket in /proc (at --log-level warn the line is not written). 0 if it exited.
  int wait_port(std::chrono::seconds limit) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      if (const auto port = testing::listening_port(log())) return *port;
      if (const int port = listening_port_from_proc(); port > 0) return port;
      if (exited()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
  }

  bool exited() { return process_->exited(); }
  int exit_code() const { return process_->exit_code(); }

  // SIGTERM, then the exit code; -1 if it had not exited within the limit (it is then killed).
  int terminate(std::chrono::seconds limit) {
    process_->signal(SIGTERM);
    return process_->wait_exit(limit);
  }

 private:
  static fs::path make_dir() {
    char pattern[] = "/tmp/brisance-load-XXXXXX";
    if (!mkdtemp(pattern)) throw std::runtime_error("cannot make a temporary directory");
    return pattern;
  }

  int listening_port_from_proc() const {
    std::set<std::string> inodes;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator("/proc/" + std::to_string(pid()) + "/fd", ec)) {
      std::error_code link_ec;
      const std::string target = fs::read_symlink(entry.path(), link_ec).string();
      if (!link_ec && target.rfind("socket:[", 0) == 0) {
        inodes.insert(target.substr(8, target.size() - 9));
      }
    }
    if (inodes.empty()) return 0;
    for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
      std::ifstream in(table);
      std::string line;
      std::getline(in, line);  // header
      while (std::getline(in, line)) {
        // sl local_address rem_address st tx:rx tr:when retrnsmt uid timeout inode
        std::istringstream fields(line);
        std::string sl, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
        fields >> sl >> local >> remote >> state >> queues >> timer >> retransmits >> uid >>
            timeout >> inode;
        if (state != "0A" || !inodes.contains(inode)) continue;  // 0A: LISTEN
        const auto colon = local.rfind(':');
        if (colon == std::string::npos) continue;
        return static_cast<int>(std::strtol(local.c_str() + colon + 1, nullptr, 16));
      }
    }
    return 0;
  }

  fs::path dir_;
  fs::path log_;
  std::string command_;
  std::optional<testing::ChildProcess> process_;
  bool remove_dir_ = true;
};

// CPU seconds (user + system) used by this process so far.
inline double own_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// CPU seconds used by process `pid` so far (fields 14 and 15 of /proc/PID/stat); NaN if unknown.
inline double process_cpu_seconds(pid_t pid) {
  if (pid <= 0) return std::nan("");
  const std::string stat = read_file("/proc/" + std::to_string(pid) + "/stat");
  const auto paren = stat.rfind(')');  // the command name may hold spaces
  if (paren == std::string::npos) return std::nan("");
  std::istringstream fields(stat.substr(paren + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i >= 14) ticks += std::strtod(field.c_str(), nullptr);
  }
  return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// CPU seconds all processes of the machine have used so far (the busy time in /proc/stat).
inline double machine_cpu_seconds() {
  std::ifstream in("/proc/stat");
  std::string cpu;
  in >> cpu;
  if (cpu != "cpu") return std::nan("");
  // user nice system idle iowait irq softirq steal
  double busy = 0;
  for (int i = 0; i < 8; ++i) {
    double ticks = 0;
    if (!(in >> ticks)) return std::nan("");
    if (i != 3 && i != 4 && i != 7) busy += ticks;
  }
  return busy / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace brisance::load
