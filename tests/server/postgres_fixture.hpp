// tests/server/postgres_fixture: a real PostgreSQL server for the tests — initdb into a fresh
// temporary folder, postgres on a free port of 127.0.0.1 with its unix socket in that folder,
// stopped (and the folder removed) at the end. Built from Debian's postgresql package, whose
// binaries CMake found (BRISANCE_PG_BINDIR).
//
// initdb and postgres refuse to run as root, and CI runs as root: then both run as `nobody`
// (setpriv), in a folder that user owns. Durability is switched off (fsync, synchronous_commit):
// the tests check behaviour, not crash safety of PostgreSQL itself.
#pragma once

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <netinet/in.h>
#include <pwd.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "server/pg.hpp"
#include "tests/server/temp_dir.hpp"
#include "tests/support/child_process.hpp"

namespace brisance::testing {

class PostgresServer {
 public:
  // The server CTest's `postgres` fixture started (tests/server/postgres_server.sh), found by the
  // folder it was started in: not stopped by this process.
  struct Attach {
    std::filesystem::path dir;
  };
  explicit PostgresServer(const Attach& attach) {
    std::ifstream in(attach.dir / "port");
    if (!(in >> port_)) {
      throw std::runtime_error("no shared PostgreSQL server in " + attach.dir.string() +
                               " (its fixture, postgres.server.start, did not run)");
    }
  }

  PostgresServer() {
    if (std::string(BRISANCE_PG_BINDIR).empty()) {
      throw std::runtime_error(
          "no PostgreSQL server binaries (initdb) were found when configuring: install Debian's "
          "postgresql package (make test does)");
    }
    bin_ = BRISANCE_PG_BINDIR;
    if (geteuid() == 0) {
      const passwd* nobody = getpwnam("nobody");
      if (!nobody) throw std::runtime_error("running as root, and there is no user 'nobody'");
      as_user_ = {"/usr/bin/setpriv", "--reuid=" + std::to_string(nobody->pw_uid),
                  "--regid=" + std::to_string(nobody->pw_gid), "--clear-groups", "--"};
      std::filesystem::permissions(dir_.path(), std::filesystem::perms::all);
      if (chown(dir_.path().c_str(), nobody->pw_uid, nobody->pw_gid) != 0) {
        throw std::runtime_error("cannot hand " + dir_.path().string() + " to nobody");
      }
    }
    const int rc =
        run_and_wait({(bin_ / "initdb").string(), "-D", data().string(), "-U", "brisance",
                      "--auth=trust", "--no-sync", "-E", "UTF8", "--no-instructions"},
                     dir_.path() / "initdb.log");
    if (rc != 0) throw std::runtime_error("initdb failed: " + read(dir_.path() / "initdb.log"));
    // The free port may be taken by another test's server before ours binds it: then another.
    for (int attempt = 1;; ++attempt) {
      port_ = free_port();
      try {
        start();
        return;
      } catch (const std::runtime_error&) {
        if (attempt == 3) throw;
      }
    }
  }
  ~PostgresServer() { stop(); }
  PostgresServer(const PostgresServer&) = delete;
  PostgresServer& operator=(const PostgresServer&) = delete;

  // A URL of database `name` on this server (see create_database).
  std::string url(const std::string& name) const {
    return "postgresql://brisance@127.0.0.1:" + std::to_string(port_) + "/" + name;
  }
  // A new, empty database; its URL.
  std::string create_database() {
    // Unique across the test programs sharing one server.
    const std::string name =
        "t" + std::to_string(getpid()) + "_" + std::to_string(next_database_++);
    server::pg::Connection c(url("postgres"));
    c.exec(("CREATE DATABASE " + name).c_str());
    return url(name);
  }

  // Fast shutdown (SIGINT): open connections are cut, as in a database restart.
  void stop() {
    if (pid_ <= 0) return;  // not started here (or stopped already)
    kill(pid_, SIGINT);
    waitpid(pid_, nullptr, 0);
    pid_ = 0;
  }
  // Starts the server (again, after stop()) on the same port and data, and waits until it
  // accepts connections.
  void start() {
    pid_ = spawn(
        {(bin_ / "postgres").string(), "-D", data().string(), "-p", std::to_string(port_), "-k",
         dir_.path().string(), "-c", "listen_addresses=127.0.0.1", "-c", "fsync=off", "-c",
         "synchronous_commit=off", "-c", "full_page_writes=off", "-c", "max_connections=300"},
        dir_.path() / "postgres.log");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (true) {
      try {
        server::pg::Connection c(url("postgres"));
        return;
      } catch (const server::StorageError& error) {
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
          pid_ = 0;
          throw std::runtime_error("postgres exited: " + read(dir_.path() / "postgres.log"));
        }
        if (std::chrono::steady_clock::now() > deadline) {
          stop();
          throw std::runtime_error(std::string("postgres did not start: ") + error.what());
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

  int port() const { return port_; }

 private:
  std::filesystem::path data() const { return dir_.path() / "data"; }

  static std::string read(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  static int free_port() {
    const int s = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    socklen_t length = sizeof address;
    if (bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        getsockname(s, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
      close(s);
      throw std::runtime_error("no free port");
    }
    close(s);
    return ntohs(address.sin_port);
  }

  // Runs `args` (as nobody when root) with stdout and stderr to `log`, cwd the temp folder.
  pid_t spawn(std::vector<std::string> args, const std::filesystem::path& log) {
    args.insert(args.begin(), as_user_.begin(), as_user_.end());
    SpawnOptions options;
    options.stdout_path = log;
    options.append = true;
    options.stdin_null = true;
    options.working_dir = dir_.path();
    return spawn_process(std::move(args), options);
  }

  int run_and_wait(std::vector<std::string> args, const std::filesystem::path& log) {
    const pid_t pid = spawn(std::move(args), log);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  TempDir dir_;
  std::filesystem::path bin_;
  std::vector<std::string> as_user_;
  int port_ = 0;
  pid_t pid_ = 0;
  int next_database_ = 1;
};

// One server for the test program: the one CTest's fixture started (BRISANCE_TEST_PG_DIR), else
// one of its own, started on first use. Tests that stop and start the server make their own.
inline PostgresServer& shared_postgres() {
  static PostgresServer server = [] {
    const char* dir = std::getenv("BRISANCE_TEST_PG_DIR");
    return dir && *dir ? PostgresServer(PostgresServer::Attach{dir}) : PostgresServer();
  }();
  return server;
}

}  // namespace brisance::testing
