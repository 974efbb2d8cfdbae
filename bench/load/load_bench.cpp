// Load bench of the job service: a bounded load test against the queue over HTTP. It submits N
// jobs, reads them back, holds a fixed request rate while the workers are busy, then waits for
// the queue to drain, and prints throughput and latency percentiles per phase and the service's
// goals (>= 2 000 durable POST /v1/jobs per second, >= 15 000 GET /v1/jobs/{id} per second, p99
// under 25 ms at a fixed 500 requests per second while the workers are busy).
//
// The client is one thread running Boost.Beast over many keep-alive connections, so it costs
// little CPU next to the server it measures. Run `load_bench --help` for the flags.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/load/http_connection.hpp"
#include "bench/load/server_process.hpp"

namespace {

// The spawned servers and the client's connections: bench/load/server_process.hpp and
// bench/load/http_connection.hpp (with the namespace aliases both use).
using namespace brisance::load;

// ---------------------------------------------------------------------------------------------
// Flags

constexpr std::string_view kHelp =
    "usage: load_bench (--server PATH | --port P) [options]\n"
    "\n"
    "Load test of the Brisance job service. Phases:\n"
    "  POST   N job submissions, closed loop over C connections, as fast as possible\n"
    "  GET    GET /v1/jobs/{id} of random submitted jobs for S seconds, closed loop\n"
    "  RATE   open loop at R requests/s (90% GET /v1/jobs/{id}, 10% POST /v1/jobs) while the\n"
    "         workers run the queue; latency is measured from each request's scheduled send\n"
    "         time, so a stalled server is not hidden by waiting clients\n"
    "  DRAIN  polls GET /v1/queue every 200 ms until nothing is queued or running, and checks\n"
    "         that every accepted job succeeded\n"
    "then a table of the service's goals. Exit 0 if no request failed (goals not met are\n"
    "reported, not failures), 1 on request errors or a failed check, 2 on bad flags.\n"
    "\n"
    "  --server PATH        spawn 'PATH serve --port 0 --data <fresh temp dir> --workers W\n"
    "                       --max-queue 1000000 --log-level warn', stop it with SIGTERM at the\n"
    "                       end and check it exits 0\n"
    "  --port P             use a server already listening on 127.0.0.1:P instead\n"
    "  --workers W          simulation workers of the spawned server (default 1)\n"
    "  --store URL          the spawned server's --store (default: its SQLite store in the\n"
    "                       temp dir); a postgres:// URL benches the PostgreSQL store\n"
    "  --nodes N            spawn N servers on the one --store (a postgres:// URL when N > 1),\n"
    "                       each with W workers; connection i goes to node i mod N, the\n"
    "                       queue is read on node 1, srv CPU sums the nodes (default 1)\n"
    "  --connections C      keep-alive connections (default 32)\n"
    "  --jobs N             jobs submitted in the POST phase (default 5000)\n"
    "  --get-seconds S      length of the GET phase (default 5; 0 skips it)\n"
    "  --rate R             requests per second of the RATE phase (default 500)\n"
    "  --rate-seconds S     length of the RATE phase (default 10; 0 skips it)\n"
    "  --drain-timeout S    longest wait for the queue to drain (default 600)\n"
    "  --no-drain           skip the DRAIN phase\n"
    "  --scene FILE         scene of every job (default scenes/three_blocks.json); a relative\n"
    "                       path is looked up in the current directory, then in the source tree\n"
    "  --csv FILE           also write the phase table as CSV\n"
    "  --help               print this help\n";

struct Options {
  std::string server;
  int port = 0;
  int workers = 1;
  bool workers_set = false;
  std::string store;  // the spawned server's --store; empty: SQLite
  int nodes = 1;      // servers spawned on the one store
  int connections = 32;
  long long jobs = 5000;
  double get_seconds = 5;
  double rate = 500;
  double rate_seconds = 10;
  double drain_timeout = 600;
  bool drain = true;
  std::string scene = "scenes/three_blocks.json";
  std::string csv;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "load_bench: " << message << "\n(run 'load_bench --help' for the flags)\n";
  std::exit(2);
}

long long parse_integer(std::string_view flag, const std::string& text, long long lo,
                        long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || value < lo || value > hi) {
    usage_error("--" + std::string(flag) + " must be an integer from " + std::to_string(lo) +
                " to " + std::to_string(hi) + ", got '" + text + "'");
  }
  return value;
}

double parse_number(std::string_view flag, const std::string& text, double lo, double hi) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value) || value < lo || value > hi) {
    usage_error("--" + std::string(flag) + " must be a number from " + std::to_string(lo) + " to " +
                std::to_string(hi) + ", got '" + text + "'");
  }
  return value;
}

Options parse_options(int argc, char** argv) {
  Options o;
  const std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i];
    std::optional<std::string> inline_value;
    if (name.rfind("--", 0) != 0) usage_error("unexpected argument '" + name + "'");
    name = name.substr(2);
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    auto value = [&]() -> std::string {
      if (inline_value) return *inline_value;
      if (i + 1 >= args.size()) usage_error("--" + name + " needs a value");
      return args[++i];
    };
    auto no_value = [&] {
      if (inline_value) usage_error("--" + name + " takes no value");
    };
    if (name == "help" || name == "h") {
      std::cout << kHelp;
      std::exit(0);
    } else if (name == "server") {
      o.server = value();
      if (o.server.empty()) usage_error("--server needs the path of the brisance binary");
    } else if (name == "port") {
      o.port = static_cast<int>(parse_integer(name, value(), 1, 65535));
    } else if (name == "workers") {
      o.workers = static_cast<int>(parse_integer(name, value(), 1, 256));
      o.workers_set = true;
    } else if (name == "store") {
      o.store = value();
    } else if (name == "nodes") {
      o.nodes = static_cast<int>(parse_integer(name, value(), 1, 16));
    } else if (name == "connections") {
      o.connections = static_cast<int>(parse_integer(name, value(), 1, 10000));
    } else if (name == "jobs") {
      o.jobs = parse_integer(name, value(), 1, 100000000);
    } else if (name == "get-seconds") {
      o.get_seconds = parse_number(name, value(), 0, 86400);
    } else if (name == "rate") {
      o.rate = parse_number(name, value(), 0.1, 1e6);
    } else if (name == "rate-seconds") {
      o.rate_seconds = parse_number(name, value(), 0, 86400);
    } else if (name == "drain-timeout") {
      o.drain_timeout = parse_number(name, value(), 0.2, 1e6);
    } else if (name == "no-drain") {
      no_value();
      o.drain = false;
    } else if (name == "scene") {
      o.scene = value();
    } else if (name == "csv") {
      o.csv = value();
      if (o.csv.empty()) usage_error("--csv needs a file name");
    } else {
      usage_error("unknown flag '--" + name + "'");
    }
  }
  if (o.server.empty() == (o.port == 0)) {
    usage_error(
        "give exactly one of --server PATH (spawn a server) or --port P (use a running one)");
  }
  if (o.port != 0 && (o.workers_set || !o.store.empty() || o.nodes > 1)) {
    usage_error("--workers, --store and --nodes apply only to servers spawned with --server");
  }
  if (o.nodes > 1 && o.store.rfind("postgres", 0) != 0) {
    usage_error("--nodes above 1 needs a shared --store postgres://… URL");
  }
  return o;
}

fs::path resolve_scene(const std::string& name) {
  const fs::path path(name);
  if (path.is_absolute() || fs::exists(path)) return path;
  const fs::path in_source = fs::path(BRISANCE_SOURCE_DIR) / path;
  if (fs::exists(in_source)) return in_source;
  std::cerr << "load_bench: no scene file '" << name << "' (looked in the current directory and "
            << BRISANCE_SOURCE_DIR << ")\n";
  std::exit(2);
}

// ---------------------------------------------------------------------------------------------
// Measurement

std::string snippet(std::string_view text, std::size_t limit = 200) {
  std::string out(text.substr(0, limit));
  for (char& c : out) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (text.size() > limit) out += "...";
  return out;
}

struct Phase {
  std::string name;
  std::size_t requests = 0;
  std::size_t errors = 0;
  double seconds = 0;
  double client_cpu_s = std::nan("");  // CPU time of this process during the phase
  double server_cpu_s = std::nan("");  // of the spawned server (unknown with --port)
  double other_cpu_s = std::nan("");   // of every other process on the machine (--server only)
  std::vector<double> latencies_ms;
  std::map<std::string, std::size_t> error_kinds;
  std::vector<std::string> error_samples;

  explicit Phase(std::string n) : name(std::move(n)) {}

  // Counts the response; true if it had the expected status.
  bool record(std::string_view method, std::string_view target, const Response& r, int expected) {
    ++requests;
    latencies_ms.push_back(r.latency_ms);
    if (r.status == expected) return true;
    ++errors;
    const std::string kind =
        r.status == 0 ? "transport error (" + r.error + ")" : "HTTP " + std::to_string(r.status);
    // One example of each kind of error, up to five kinds.
    if (++error_kinds[kind] == 1 && error_samples.size() < 5) {
      error_samples.push_back(std::string(method) + " " + std::string(target) + " -> " + kind +
                              (r.body.empty() ? "" : ": " + snippet(r.body)));
    }
    return false;
  }

  double rate() const { return seconds > 0 ? static_cast<double>(requests) / seconds : 0.0; }

  // Nearest-rank percentile; NaN without samples.
  double percentile(double p) {
    if (latencies_ms.empty()) return std::nan("");
    if (!sorted_) {
      std::sort(latencies_ms.begin(), latencies_ms.end());
      sorted_ = true;
    }
    const auto n = static_cast<double>(latencies_ms.size());
    const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(p / 100.0 * n)));
    return latencies_ms[std::min(rank, latencies_ms.size()) - 1];
  }

  void print_errors() const {
    if (errors == 0) return;
    std::printf("  %s: %zu error(s)\n", name.c_str(), errors);
    for (const auto& [kind, count] : error_kinds)
      std::printf("    %zu x %s\n", count, kind.c_str());
    for (const auto& sample : error_samples)
      std::printf("    e.g. %s\n", sample.c_str());
  }

 private:
  bool sorted_ = false;
};

std::string ms_text(double ms) {
  if (std::isnan(ms)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, ms < 10 ? "%.2f" : "%.1f", ms);
  return buffer;
}

void print_table(std::vector<Phase>& phases, const std::string& csv) {
  // CPU columns: CPU time over wall time, in % of one core (the machine has 2).
  auto cpu = [](double cpu_s, double wall_s) {
    if (std::isnan(cpu_s) || wall_s <= 0) return std::string("-");
    return std::to_string(std::lround(100 * cpu_s / wall_s)) + "%";
  };
  std::printf("\n%-10s %9s %7s %8s %10s %8s %8s %8s %8s %8s %8s %8s\n", "phase", "requests",
              "errors", "seconds", "req/s", "p50 ms", "p90 ms", "p99 ms", "max ms", "cli CPU",
              "srv CPU", "oth CPU");
  for (Phase& p : phases) {
    std::printf("%-10s %9zu %7zu %8.2f %10.0f %8s %8s %8s %8s %8s %8s %8s\n", p.name.c_str(),
                p.requests, p.errors, p.seconds, p.rate(), ms_text(p.percentile(50)).c_str(),
                ms_text(p.percentile(90)).c_str(), ms_text(p.percentile(99)).c_str(),
                ms_text(p.percentile(100)).c_str(), cpu(p.client_cpu_s, p.seconds).c_str(),
                cpu(p.server_cpu_s, p.seconds).c_str(), cpu(p.other_cpu_s, p.seconds).c_str());
  }
  std::printf(
      "(CPU: %% of one core over the phase; the machine has %u. cli: this client, srv: the "
      "server,\n oth: every other process - other work on a shared machine skews the numbers)\n",
      std::thread::hardware_concurrency());
  if (csv.empty()) return;
  std::ofstream out(csv);
  out << "phase,requests,errors,seconds,req_per_s,p50_ms,p90_ms,p99_ms,max_ms,client_cpu_s,"
         "server_cpu_s,other_cpu_s\n";
  for (Phase& p : phases) {
    out << p.name << ',' << p.requests << ',' << p.errors << ',' << p.seconds << ',' << p.rate()
        << ',' << p.percentile(50) << ',' << p.percentile(90) << ',' << p.percentile(99) << ','
        << p.percentile(100) << ',' << p.client_cpu_s << ',' << p.server_cpu_s << ','
        << p.other_cpu_s << '\n';
  }
  if (!out) std::fprintf(stderr, "load_bench: cannot write %s\n", csv.c_str());
}

// CPU use of the client, the server and everything else over a phase.
class CpuMeter {
 public:
  // `servers`: the spawned nodes, whose CPU is summed (none with --port: unknown).
  explicit CpuMeter(std::vector<pid_t> servers) : servers_(std::move(servers)) {
    client_ = own_cpu_seconds();
    server_start_ = servers_cpu_seconds();
    machine_ = machine_cpu_seconds();
  }
  void stop(Phase& phase) const {
    phase.client_cpu_s = own_cpu_seconds() - client_;
    phase.server_cpu_s = servers_cpu_seconds() - server_start_;
    const double others =
        machine_cpu_seconds() - machine_ - phase.client_cpu_s - phase.server_cpu_s;
    phase.other_cpu_s = std::isnan(others) ? others : std::max(0.0, others);
  }

 private:
  double servers_cpu_seconds() const {
    if (servers_.empty()) return std::nan("");
    double sum = 0;
    for (const pid_t pid : servers_)
      sum += process_cpu_seconds(pid);
    return sum;
  }

  std::vector<pid_t> servers_;
  double client_ = 0;
  double server_start_ = 0;
  double machine_ = 0;
};

// ---------------------------------------------------------------------------------------------
// The bench

struct QueueCounts {
  std::int64_t queued = 0, running = 0, succeeded = 0, failed = 0, cancelled = 0;
};

class Bench {
 public:
  // Connection i goes to ports[i mod ports.size()].
  Bench(const Options& options, const std::vector<int>& ports, std::string job_body)
      : options_(options), job_body_(std::move(job_body)) {
    for (int i = 0; i < options.connections; ++i) {
      const tcp::endpoint endpoint(
          asio::ip::make_address("127.0.0.1"),
          static_cast<std::uint16_t>(ports[static_cast<std::size_t>(i) % ports.size()]));
      connections_.push_back(std::make_unique<Connection>(ioc_, endpoint));
    }
  }

  // One request on the first connection (node 1), waited for.
  Response fetch(const Request& request) {
    Response out;
    connections_.front()->send(request, Clock::now(), [&out](Response&& r) { out = std::move(r); });
    ioc_.restart();
    ioc_.run();
    return out;
  }

  // GET /v1/queue; nullopt (and the reason in `error`) if it failed.
  std::optional<QueueCounts> queue(std::string* error = nullptr, Phase* phase = nullptr) {
    const Response r = fetch({http::verb::get, "/v1/queue", nullptr});
    if (phase) phase->record("GET", "/v1/queue", r, 200);
    if (r.status != 200) {
      if (error) {
        *error =
            r.status == 0 ? r.error : "HTTP " + std::to_string(r.status) + ": " + snippet(r.body);
      }
      return std::nullopt;
    }
    try {
      const json counts = json::parse(r.body).at("counts");
      QueueCounts q;
      q.queued = counts.value("queued", std::int64_t{0});
      q.running = counts.value("running", std::int64_t{0});
      q.succeeded = counts.value("succeeded", std::int64_t{0});
      q.failed = counts.value("failed", std::int64_t{0});
      q.cancelled = counts.value("cancelled", std::int64_t{0});
      return q;
    } catch (const json::exception& e) {
      if (error) *error = std::string("unexpected /v1/queue body: ") + e.what();
      return std::nullopt;
    }
  }

  // Phase 1: N submissions, closed loop.
  Phase post_phase() {
    Phase phase("POST");
    std::size_t issued = 0;
    const auto total = static_cast<std::size_t>(options_.jobs);
    std::function<void(Connection*)> next = [&](Connection* c) {
      if (issued >= total) return;
      ++issued;
      c->send(post_request(), Clock::now(), [&, c](Response&& r) {
        accept_post(phase, r);
        next(c);
      });
    };
    phase.seconds = run_closed_loop(next);
    return phase;
  }

  // Phase 2: reads of random submitted jobs for S seconds, closed loop.
  Phase get_phase(const char* name = "GET") {
    Phase phase(name);
    const auto deadline = Clock::now() + seconds(options_.get_seconds);
    std::function<void(Connection*)> next = [&](Connection* c) {
      if (Clock::now() >= deadline) return;
      Request request = get_request();
      c->send(request, Clock::now(), [&, c, target = request.target](Response&& r) {
        phase.record("GET", target, r, 200);
        next(c);
      });
    };
    phase.seconds = run_closed_loop(next);
    return phase;
  }

  // Phase 3: open loop at a fixed rate; request i is due at t0 + i / R and its latency counts
  // from then, whether or not a connection was free.
  struct RatePhases {
    Phase all{"RATE"};
    Phase gets{"RATE GET"};
    Phase posts{"RATE POST"};
    std::size_t max_backlog = 0;
    double achieved_rate = 0;
  };
  RatePhases rate_phase() {
    RatePhases out;
    struct Due {
      Clock::time_point at;
      bool post;
    };
    const auto total =
        static_cast<std::size_t>(std::llround(options_.rate * options_.rate_seconds));
    std::deque<Due> backlog;
    std::vector<Connection*> idle;
    for (auto it = connections_.rbegin(); it != connections_.rend(); ++it)
      idle.push_back(it->get());
    const Clock::time_point t0 = Clock::now() + std::chrono::milliseconds(5);
    auto due_at = [&](std::size_t i) {
      return t0 + std::chrono::duration_cast<Clock::duration>(
                      std::chrono::duration<double>(static_cast<double>(i) / options_.rate));
    };
    std::size_t scheduled = 0;
    std::size_t completed = 0;
    Clock::time_point last_done = t0;

    std::function<void()> dispatch = [&] {
      while (!backlog.empty() && !idle.empty()) {
        Connection* c = idle.back();
        idle.pop_back();
        const Due due = backlog.front();
        backlog.pop_front();
        const Request request = due.post ? post_request() : get_request();
        c->send(request, due.at, [&, c, due, target = request.target](Response&& r) {
          if (due.post) {
            accept_post(out.posts, r);
            out.all.record("POST", "/v1/jobs", r, 202);
          } else {
            out.gets.record("GET", target, r, 200);
            out.all.record("GET", target, r, 200);
          }
          ++completed;
          last_done = Clock::now();
          idle.push_back(c);
          dispatch();
        });
      }
    };
    asio::steady_timer timer(ioc_);
    std::function<void()> tick = [&] {
      const auto now = Clock::now();
      while (scheduled < total && due_at(scheduled) <= now) {
        // Every tenth request is a submission: 10% POST, spread evenly.
        backlog.push_back({due_at(scheduled), scheduled % 10 == 9});
        ++scheduled;
      }
      out.max_backlog = std::max(out.max_backlog, backlog.size());
      dispatch();
      if (scheduled < total) {
        timer.expires_at(due_at(scheduled));
        timer.async_wait([&](beast::error_code) { tick(); });
      }
    };
    tick();
    ioc_.restart();
    ioc_.run();
    const double seconds = std::chrono::duration<double>(last_done - t0).count();
    out.all.seconds = out.gets.seconds = out.posts.seconds = seconds;
    out.achieved_rate = seconds > 0 ? static_cast<double>(completed) / seconds : 0;
    return out;
  }

  std::size_t accepted() const { return accepted_; }
  std::size_t ids() const { return ids_.size(); }
  std::size_t connects() const {
    std::size_t n = 0;
    for (const auto& c : connections_)
      n += c->connects();
    return n;
  }

 private:
  static Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  Request post_request() const { return {http::verb::post, "/v1/jobs", &job_body_}; }

  Request get_request() {
    std::uniform_int_distribution<std::size_t> pick(0, ids_.size() - 1);
    return {http::verb::get, "/v1/jobs/" + ids_[pick(random_)], nullptr};
  }

  // Records a submission's response and keeps the new job's id.
  void accept_post(Phase& phase, const Response& r) {
    if (!phase.record("POST", "/v1/jobs", r, 202)) return;
    ++accepted_;
    std::string id;
    constexpr std::string_view kPrefix = "/v1/jobs/";
    if (r.location.rfind(kPrefix, 0) == 0) {
      id = r.location.substr(kPrefix.size());
    } else {
      const json body = json::parse(r.body, nullptr, false);
      if (body.is_object() && body.contains("id") && body["id"].is_string()) id = body["id"];
    }
    if (!id.empty()) ids_.push_back(std::move(id));
  }

  // Starts `next` on every connection and runs until none has work left; the elapsed seconds.
  double run_closed_loop(std::function<void(Connection*)>& next) {
    const auto start = Clock::now();
    for (auto& c : connections_)
      next(c.get());
    ioc_.restart();
    ioc_.run();
    return std::chrono::duration<double>(Clock::now() - start).count();
  }

  const Options& options_;
  std::string job_body_;
  asio::io_context ioc_;
  std::vector<std::unique_ptr<Connection>> connections_;
  std::vector<std::string> ids_;
  std::size_t accepted_ = 0;
  std::mt19937_64 random_{12345};
};

struct Goal {
  std::string goal;
  std::string measured;
  bool met = false;
  std::string note;
};

int run(const Options& options) {
  const fs::path scene_path = resolve_scene(options.scene);
  json scene;
  try {
    scene = json::parse(read_file(scene_path));
  } catch (const json::exception& e) {
    std::cerr << "load_bench: " << scene_path.string() << " is not JSON: " << e.what() << "\n";
    return 2;
  }
  const std::string body = json{{"scene", scene}, {"priority", 0}}.dump();

  // The spawned nodes (none with --port), all on options.store.
  std::vector<std::unique_ptr<ServerProcess>> servers;
  std::vector<int> ports;
  if (!options.server.empty()) {
    for (int n = 0; n < options.nodes; ++n) {
      try {
        servers.push_back(
            std::make_unique<ServerProcess>(options.server, options.workers, options.store));
      } catch (const std::exception& e) {
        std::cerr << "load_bench: " << e.what() << "\n";
        return 1;
      }
      ServerProcess& server = *servers.back();
      const int port = server.wait_port(std::chrono::seconds(60));
      if (port == 0) {
        std::cerr << "load_bench: the server did not start listening (exit code "
                  << server.exit_code() << "); its log:\n"
                  << server.log_tail() << "\n";
        return 1;
      }
      ports.push_back(port);
      std::printf("server%s: %s (pid %d, port %d)\n",
                  options.nodes > 1 ? (" " + std::to_string(n + 1)).c_str() : "",
                  server.command().c_str(), static_cast<int>(server.pid()), port);
    }
  } else {
    ports.push_back(options.port);
    std::printf("server: 127.0.0.1:%d (already running)\n", options.port);
  }
  const bool spawned = !servers.empty();
  std::printf(
      "load: %lld jobs of %s (%zu-byte body), %d connections, GET %.3g s, RATE %.6g req/s for "
      "%.3g s, drain %s\n",
      options.jobs, scene_path.filename().string().c_str(), body.size(), options.connections,
      options.get_seconds, options.rate, options.rate_seconds, options.drain ? "on" : "off");
  std::fflush(stdout);

  Bench bench(options, ports, body);
  bool failed = false;
  std::vector<std::string> problems;

  std::string error;
  // With --server a fresh database could still be migrating when the socket appears; the first
  // request waits for it. Retry a few times before giving up.
  std::optional<QueueCounts> baseline;
  for (int attempt = 0; attempt < 50 && !baseline; ++attempt) {
    baseline = bench.queue(&error);
    if (!baseline) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (!baseline) {
    std::cerr << "load_bench: GET /v1/queue failed: " << error << "\n";
    if (spawned) std::cerr << "server log:\n" << servers.front()->log_tail() << "\n";
    return 1;
  }

  std::vector<pid_t> server_pid;
  for (const auto& server : servers)
    server_pid.push_back(server->pid());
  std::vector<Phase> phases;
  const auto post_start = Clock::now();
  {
    const CpuMeter meter(server_pid);
    phases.push_back(bench.post_phase());
    meter.stop(phases.back());
  }
  std::printf("POST done: %zu accepted in %.2f s\n", bench.accepted(), phases.back().seconds);
  std::fflush(stdout);
  // Only accepted submissions (202) count toward the goal.
  const double post_rate = phases.back().seconds > 0
                               ? static_cast<double>(bench.accepted()) / phases.back().seconds
                               : 0.0;
  const std::size_t post_errors = phases.back().errors;

  std::optional<double> get_rate;
  if (options.get_seconds > 0 && bench.ids() > 0) {
    const CpuMeter meter(server_pid);
    phases.push_back(bench.get_phase());
    meter.stop(phases.back());
    get_rate = phases.back().rate();
    std::printf("GET done: %zu requests in %.2f s\n", phases.back().requests,
                phases.back().seconds);
    std::fflush(stdout);
  }

  std::optional<double> rate_p99;
  double achieved_rate = 0;
  bool workers_busy = false;
  if (options.rate_seconds > 0 && bench.ids() > 0) {
    // A job runs for about a millisecond between claims and commits, so one look at the queue
    // can miss it: look up to 20 times, 10 ms apart, for a running job.
    std::optional<QueueCounts> before;
    int looks = 0;
    for (; looks < 20; ++looks) {
      if (looks > 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      before = bench.queue(&error);
      if (!before || before->running > 0) break;
    }
    if (!before) {
      std::printf("note: GET /v1/queue before RATE failed (%s)\n", error.c_str());
    } else {
      workers_busy = before->running > 0;
      std::printf("queue before RATE: queued %lld, running %lld (look %d)%s\n",
                  static_cast<long long>(before->queued), static_cast<long long>(before->running),
                  std::min(looks + 1, 20),
                  workers_busy ? ""
                               : "  -- NOTE: no job running in 20 looks: the workers are idle, "
                                 "RATE is not measured under load (use more --jobs)");
    }
    std::fflush(stdout);
    const CpuMeter meter(server_pid);
    Bench::RatePhases rate = bench.rate_phase();
    meter.stop(rate.all);
    if (const auto after = bench.queue(); before && after) {
      const auto finished = [](const QueueCounts& q) {
        return q.succeeded + q.failed + q.cancelled;
      };
      std::printf("workers during RATE: %lld jobs finished (%.1f jobs/s); queued %lld at the end\n",
                  static_cast<long long>(finished(*after) - finished(*before)),
                  static_cast<double>(finished(*after) - finished(*before)) / rate.all.seconds,
                  static_cast<long long>(after->queued));
    }
    achieved_rate = rate.achieved_rate;
    rate_p99 = rate.all.percentile(99);
    std::printf("RATE done: target %.6g req/s, achieved %.1f req/s, largest backlog %zu\n",
                options.rate, rate.achieved_rate, rate.max_backlog);
    std::fflush(stdout);
    phases.push_back(std::move(rate.all));
    phases.push_back(std::move(rate.gets));
    phases.push_back(std::move(rate.posts));
  }

  std::optional<double> drain_jobs_per_s;
  if (options.drain) {
    Phase phase("DRAIN");
    const CpuMeter meter(server_pid);
    const auto start = Clock::now();
    const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(options.drain_timeout));
    std::optional<QueueCounts> first, last;
    bool drained = false;
    while (true) {
      const auto counts = bench.queue(&error, &phase);
      if (counts) {
        if (!first) first = counts;
        last = counts;
        if (counts->queued == 0 && counts->running == 0) {
          drained = true;
          break;
        }
      }
      if (Clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    phase.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    meter.stop(phase);
    if (!drained) {
      problems.push_back("the queue did not drain within " + std::to_string(options.drain_timeout) +
                         " s (queued " + (last ? std::to_string(last->queued) : "?") +
                         ", running " + (last ? std::to_string(last->running) : "?") + ")");
    }
    if (first && last) {
      const auto finished = [](const QueueCounts& q) {
        return q.succeeded + q.failed + q.cancelled;
      };
      const double jobs = static_cast<double>(finished(*last) - finished(*first));
      drain_jobs_per_s = phase.seconds > 0 ? jobs / phase.seconds : 0;
      const auto succeeded = last->succeeded - baseline->succeeded;
      const auto failed_jobs = last->failed - baseline->failed;
      const auto cancelled = last->cancelled - baseline->cancelled;
      std::printf(
          "DRAIN done: %.0f jobs finished in %.2f s (%.1f jobs/s); since the start: %lld "
          "succeeded, %lld failed, %lld cancelled of %zu accepted\n",
          jobs, phase.seconds, *drain_jobs_per_s, static_cast<long long>(succeeded),
          static_cast<long long>(failed_jobs), static_cast<long long>(cancelled), bench.accepted());
      const double total_s = std::chrono::duration<double>(Clock::now() - post_start).count();
      const double all_jobs = static_cast<double>(finished(*last) - finished(*baseline));
      std::printf(
          "jobs: %.0f finished in %.2f s from the first POST to an empty queue (%.1f jobs/s)\n",
          all_jobs, total_s, all_jobs / total_s);
      if (drained && succeeded != static_cast<std::int64_t>(bench.accepted())) {
        problems.push_back(std::to_string(succeeded) + " jobs succeeded but " +
                           std::to_string(bench.accepted()) + " were accepted");
      }
      if (failed_jobs > 0) problems.push_back(std::to_string(failed_jobs) + " jobs failed");
      if (cancelled > 0) problems.push_back(std::to_string(cancelled) + " jobs were cancelled");
    }
    phases.push_back(std::move(phase));
  }

  // GET again once the workers are idle: the status reads alone, as a dashboard or pipeline
  // polling a finished queue sees them.
  std::optional<double> idle_get_rate;
  if (options.drain && options.get_seconds > 0 && bench.ids() > 0) {
    const CpuMeter meter(server_pid);
    phases.push_back(bench.get_phase("GET idle"));
    meter.stop(phases.back());
    idle_get_rate = phases.back().rate();
    std::printf("GET idle done: %zu requests in %.2f s\n", phases.back().requests,
                phases.back().seconds);
  }

  print_table(phases, options.csv);
  std::printf("(%zu connections opened in all)\n", bench.connects());

  std::size_t request_errors = 0;
  for (const Phase& p : phases) {
    if (p.name == "RATE GET" || p.name == "RATE POST") continue;  // counted in RATE
    request_errors += p.errors;
  }
  if (request_errors > 0) {
    std::printf("\nrequest errors:\n");
    for (const Phase& p : phases)
      p.print_errors();
    failed = true;
  }

  // The goals.
  std::vector<Goal> goals;
  {
    char text[64];
    std::snprintf(text, sizeof text, "%.0f /s", post_rate);
    goals.push_back({">= 2000 durable POST /v1/jobs per s", text,
                     post_rate >= 2000 && post_errors == 0,
                     post_errors > 0         ? "with errors"
                     : !spawned              ? ""
                     : options.store.empty() ? "server at --sync normal (default)"
                                             : "PostgreSQL: durable as its synchronous_commit"});
  }
  if (get_rate) {
    char text[64];
    std::snprintf(text, sizeof text, "%.0f /s", *get_rate);
    goals.push_back({">= 15000 GET /v1/jobs/{id} per s", text, *get_rate >= 15000,
                     "GET phase: a worker is busy meanwhile"});
    if (idle_get_rate) {
      std::snprintf(text, sizeof text, "%.0f /s", *idle_get_rate);
      goals.push_back({">= 15000 GET /v1/jobs/{id} per s", text, *idle_get_rate >= 15000,
                       "GET idle phase: workers idle"});
    }
  } else {
    goals.push_back({">= 15000 GET /v1/jobs/{id} per s", "-", false, "GET phase skipped"});
  }
  if (rate_p99) {
    char text[64];
    std::snprintf(text, sizeof text, "%s ms", ms_text(*rate_p99).c_str());
    std::string note;
    char rate_text[96];
    std::snprintf(rate_text, sizeof rate_text, "at %.1f of %.6g req/s", achieved_rate,
                  options.rate);
    note = rate_text;
    const bool at_rate = achieved_rate >= 0.95 * options.rate;
    if (options.rate != 500) note += "; goal is at 500 req/s";
    if (!workers_busy) note += "; workers were idle";
    if (!at_rate) note += "; rate not held";
    goals.push_back({"p99 < 25 ms at 500 req/s, busy", text,
                     *rate_p99 < 25 && at_rate && workers_busy && options.rate == 500, note});
  } else {
    goals.push_back({"p99 < 25 ms at 500 req/s, busy", "-", false, "RATE phase skipped"});
  }
  std::printf("\n%-38s %12s  %-8s %s\n", "goal", "measured", "status", "note");
  for (const Goal& g : goals) {
    std::printf("%-38s %12s  %-8s %s\n", g.goal.c_str(), g.measured.c_str(),
                g.met ? "met" : "NOT met", g.note.c_str());
  }
  if (drain_jobs_per_s) std::printf("drain throughput: %.1f jobs/s\n", *drain_jobs_per_s);

  for (std::size_t n = 0; n < servers.size(); ++n) {
    ServerProcess& server = *servers[n];
    const std::string which = servers.size() > 1 ? "server " + std::to_string(n + 1) : "server";
    const int code = server.terminate(std::chrono::seconds(60));
    if (code != 0) {
      problems.push_back(code < 0 ? "the " + which + " did not exit within 60 s of SIGTERM"
                                  : "the " + which + " exited with " + std::to_string(code) +
                                        " after SIGTERM");
      std::printf("\n%s log (%s kept):\n%s\n", which.c_str(), server.dir().c_str(),
                  server.log_tail().c_str());
      server.keep_dir();
    } else {
      std::printf("%s stopped cleanly (SIGTERM, exit 0)\n", which.c_str());
    }
  }
  for (const std::string& p : problems)
    std::printf("FAILED: %s\n", p.c_str());
  if (!problems.empty()) failed = true;
  std::printf("%s\n", failed ? "result: FAILED (see above)" : "result: no request errors");
  return failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse_options(argc, argv);
  std::signal(SIGPIPE, SIG_IGN);
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::cerr << "load_bench: " << e.what() << "\n";
    return 1;
  }
}
