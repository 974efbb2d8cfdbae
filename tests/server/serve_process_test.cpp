// `brisance serve` as a process: a failed bind, SIGTERM, and kill -9 with jobs queued and running
// (every accepted job must complete exactly once as clients see it).
#include <fstream>
#include <sstream>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/server/test_server.hpp"

extern char** environ;

namespace brisance::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

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
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      std::istringstream lines(log());
      std::string line;
      while (std::getline(lines, line)) {
        if (line.find("\"msg\":\"listening\"") == std::string::npos) continue;
        return json::parse(line).at("port").get<std::uint16_t>();
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

json job_of(std::uint16_t port, const std::string& id, int wait_s = 0) {
  const auto r = http_request(
      port, "GET", "/v1/jobs/" + id + (wait_s > 0 ? "?wait=" + std::to_string(wait_s) : ""));
  return json::parse(r.body);
}

std::string submit(std::uint16_t port, const json& scene, int priority = 0) {
  const auto r = http_request(port, "POST", "/v1/jobs", job_body(scene, priority));
  EXPECT_EQ(r.status, 202) << r.body;
  return json::parse(r.body).at("id");
}

json wait_status(std::uint16_t port, const std::string& id, std::string_view status,
                 std::chrono::seconds limit) {
  const auto deadline = Clock::now() + limit;
  json job = job_of(port, id);
  while (job.at("status") != status && Clock::now() < deadline)
    job = job_of(port, id, 5);
  return job;
}

// Long enough that it is still running when the test acts on it, short enough to finish.
json medium_scene() {
  json scene = slow_scene();
  scene["simulation"]["duration"] = 4;
  scene["simulation"]["time_step"] = 1e-4;
  return scene;
}

TEST(ServeProcess, ABusyPortExitsNonZeroWithTheAddressInTheMessage) {
  boost::asio::io_context ioc;
  boost::asio::ip::tcp::acceptor taken(ioc, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const auto port = taken.local_endpoint().port();
  TempDir dir;
  ServerProcess process(dir.path() / "data", {"--port", std::to_string(port)}, dir.path() / "log");
  EXPECT_EQ(process.wait_exit(std::chrono::seconds(30)), 1);
  EXPECT_NE(process.log().find("cannot listen on 127.0.0.1:" + std::to_string(port)),
            std::string::npos)
      << process.log();
}

TEST(ServeProcess, SigtermRequeuesTheRunningJobAndARestartFinishesIt) {
  TempDir dir;
  std::string id;
  {
    ServerProcess process(dir.path() / "data", {"--workers", "1", "--grace-s", "0.2"},
                          dir.path() / "log1");
    const auto port = process.wait_listening();
    ASSERT_NE(port, 0) << process.log();
    id = submit(port, slow_scene());
    ASSERT_EQ(wait_status(port, id, "running", std::chrono::seconds(30)).at("status"), "running");
    EXPECT_EQ(process.signal_and_wait(SIGTERM, std::chrono::seconds(30)), 0) << process.log();
    EXPECT_NE(process.log().find("requeued (shutting down)"), std::string::npos) << process.log();
  }
  ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log2");
  const auto port = process.wait_listening();
  ASSERT_NE(port, 0) << process.log();
  const json again = wait_status(port, id, "running", std::chrono::seconds(30));
  EXPECT_EQ(again.at("status"), "running");
  EXPECT_EQ(again.at("attempts"), 1);  // the interrupted run did not count
  EXPECT_EQ(http_request(port, "POST", "/v1/jobs/" + id + "/cancel").status, 202);
  EXPECT_EQ(wait_status(port, id, "cancelled", std::chrono::seconds(30)).at("status"), "cancelled");
  EXPECT_EQ(process.signal_and_wait(SIGINT, std::chrono::seconds(30)), 0);
}

TEST(ServeProcess, KillNineLosesNoAcceptedJobAndCompletesEachExactlyOnce) {
  TempDir dir;
  std::vector<std::string> ids;
  std::string running;
  {
    ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log1");
    const auto port = process.wait_listening();
    ASSERT_NE(port, 0) << process.log();
    running = submit(port, medium_scene(), 10);
    ASSERT_EQ(wait_status(port, running, "running", std::chrono::seconds(30)).at("status"),
              "running");
    for (int i = 0; i < 5; ++i)
      ids.push_back(submit(port, quick_scene()));
    EXPECT_EQ(process.signal_and_wait(SIGKILL, std::chrono::seconds(10)), 128 + SIGKILL);
  }
  ids.push_back(running);
  ServerProcess process(dir.path() / "data", {"--workers", "1"}, dir.path() / "log2");
  const auto port = process.wait_listening();
  ASSERT_NE(port, 0) << process.log();
  for (const std::string& id : ids) {
    const json job = wait_status(port, id, "succeeded", std::chrono::seconds(180));
    EXPECT_EQ(job.at("status"), "succeeded") << job.dump();
    EXPECT_EQ(job.at("attempts"), id == running ? 2 : 1) << id;
    const auto result = http_request(port, "GET", "/v1/jobs/" + id + "/result");
    EXPECT_EQ(result.status, 200);
  }
  const json list = json::parse(http_request(port, "GET", "/v1/jobs?limit=100").body);
  EXPECT_EQ(list.at("jobs").size(), ids.size());
  EXPECT_NE(process.log().find("recovered jobs left running"), std::string::npos) << process.log();
  EXPECT_EQ(process.signal_and_wait(SIGTERM, std::chrono::seconds(30)), 0);
}

}  // namespace
}  // namespace brisance::testing
