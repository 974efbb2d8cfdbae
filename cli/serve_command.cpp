// `brisance serve`: the job service — HTTP API, durable queue and worker pool on one SQLite file
// (the default) or on PostgreSQL shared by several nodes (--store postgres://…).
// `brisance api-key`: makes a key for --api-keys.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <ostream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>
#include <pthread.h>
#include <signal.h>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "server/api.hpp"
#include "server/api_keys.hpp"
#include "server/blob_store.hpp"
#include "server/callbacks.hpp"
#include "server/http_server.hpp"
#include "server/job_service.hpp"
#include "server/log.hpp"
#include "server/metrics.hpp"
#include "server/pg_storage.hpp"
#include "server/sqlite_storage.hpp"
#include "server/static_files.hpp"
#include "server/worker_pool.hpp"

namespace brisance::cli {
namespace {

constexpr std::string_view kHelp =
    "usage: brisance serve [--bind ADDR] [--port N] [--data DIR | --store URL] [--workers N]\n"
    "                      [--max-queue N] [--api-keys FILE] [options]\n"
    "\n"
    "Runs the job service: the HTTP/JSON API under /v1, the durable job queue and the simulation\n"
    "workers, on an SQLite store in DIR, or on PostgreSQL (--store postgres://…) shared by any\n"
    "number of nodes. Every flag can also be set by the environment variable in brackets; a flag\n"
    "wins over the variable.\n"
    "  --bind ADDR          address to listen on (default 127.0.0.1)         [BRISANCE_BIND]\n"
    "  --port N             TCP port, 0 for any free one (default 8080)       [BRISANCE_PORT]\n"
    "  --data DIR           where the SQLite database lives (default ./data) [BRISANCE_DATA]\n"
    "  --store URL          postgres://user:pass@host:port/db: the PostgreSQL [BRISANCE_STORE]\n"
    "                       store instead of SQLite (default: sqlite, in DIR)\n"
    "  --blobs DIR          results' meshes and frames as content-addressed     [BRISANCE_BLOBS]\n"
    "                       files in DIR (shared by every node) instead of in\n"
    "                       the store's database (the default for both stores)\n"
    "  --blob-grace-s S     an unnamed blob younger than S is kept (600) [BRISANCE_BLOB_GRACE_S]\n"
    "  --workers N          simulation threads (default: cores, at least 1)  [BRISANCE_WORKERS]\n"
    "  --max-queue N        queued jobs at which POST gets 429 (10000)        "
    "[BRISANCE_MAX_QUEUE]\n"
    "  --api-keys FILE      require API keys listed (hashed) in FILE          [BRISANCE_API_KEYS]\n"
    "  --io-threads N       HTTP I/O threads (default 4)                      "
    "[BRISANCE_IO_THREADS]\n"
    "  --request-threads N  threads that parse and validate bodies of 64 KiB  "
    "[BRISANCE_REQUEST_THREADS]\n"
    "                       and more, off the I/O threads (default 2)\n"
    "  --request-queue N    such bodies waiting for them at most (16; 503     "
    "[BRISANCE_REQUEST_QUEUE]\n"
    "                       above)\n"
    "  --body-limit-mb M    largest request body, MiB (default 16)          "
    "[BRISANCE_BODY_LIMIT_MB]\n"
    "  --max-asset-mb M     largest mesh file POST /v1/assets takes, MiB    "
    "[BRISANCE_MAX_ASSET_MB]\n"
    "                       (default 8; 413 above)\n"
    "  --max-connections N  open connections; more get 503 (default 1024) "
    "[BRISANCE_MAX_CONNECTIONS]\n"
    "  --min-free-mb M      free space the data folder keeps: below it POST  "
    "[BRISANCE_MIN_FREE_MB]\n"
    "                       gets 507 and /readyz 503 (default 256, 0: off)\n"
    "  --job-timeout-s S    wall-clock limit per job run, 0 none (600)      "
    "[BRISANCE_JOB_TIMEOUT_S]\n"
    "  --job-memory-mb M    memory budget per job run, MiB, 0 none (2048)  "
    "[BRISANCE_JOB_MEMORY_MB]\n"
    "  --max-attempts N     runs a job may crash before it fails (3)        "
    "[BRISANCE_MAX_ATTEMPTS]\n"
    "  --retention-h H      keep finished jobs H hours, 0 forever (168)      "
    "[BRISANCE_RETENTION_H]\n"
    "  --sync normal|full   SQLite synchronous: full fsyncs every commit     [BRISANCE_SYNC]\n"
    "                       (survives power loss), normal (default) survives\n"
    "                       any process crash\n"
    "  --grace-s S          on SIGTERM, time running jobs get to finish (10)  [BRISANCE_GRACE_S]\n"
    "  --callback-url URL   http(s):// URL told when a job that names none ends "
    "[BRISANCE_CALLBACK_URL]\n"
    "  --callback-secret S  HMAC-SHA256 key that signs callback deliveries "
    "[BRISANCE_CALLBACK_SECRET]\n"
    "                       (Brisance-Signature; docs/service.md \"Callbacks\")\n"
    "  --callback-ca FILE   PEM CA certificates https receivers must chain to "
    "[BRISANCE_CALLBACK_CA]\n"
    "                       (default: the system's trusted CAs)\n"
    "  --log-level L        debug, info (default), warn or error             "
    "[BRISANCE_LOG_LEVEL]\n";

constexpr std::string_view kKeyHelp =
    "usage: brisance api-key [--name NAME] [--scope read|write|admin]\n"
    "\n"
    "Prints a new random API key and the line to add to the --api-keys file (which stores only\n"
    "its SHA-256 hash). Give clients the key; keep the file on the server.\n";

// A flag's value, else the environment variable's, else nothing.
std::optional<std::string> setting(const ParsedFlags& flags, std::string_view flag,
                                   const char* variable) {
  if (auto value = flags.value(flag)) return std::string(*value);
  if (const char* env = std::getenv(variable); env && *env) return std::string(env);
  return std::nullopt;
}

long long integer_setting(const ParsedFlags& flags, std::string_view flag, const char* variable,
                          long long fallback, long long lo, long long hi) {
  const auto text = setting(flags, flag, variable);
  if (!text) return fallback;
  char* end = nullptr;
  const long long value = std::strtoll(text->c_str(), &end, 10);
  if (end == text->c_str() || *end != '\0' || value < lo || value > hi) {
    flags.fail(text::printf("--%.*s (or %s) must be an integer from %lld to %lld, got '%s'",
                            static_cast<int>(flag.size()), flag.data(), variable, lo, hi,
                            text->c_str()));
  }
  return value;
}

double number_setting(const ParsedFlags& flags, std::string_view flag, const char* variable,
                      double fallback, double lo, double hi) {
  const auto text = setting(flags, flag, variable);
  if (!text) return fallback;
  char* end = nullptr;
  const double value = std::strtod(text->c_str(), &end);
  if (end == text->c_str() || *end != '\0' || !std::isfinite(value) || value < lo || value > hi) {
    flags.fail(text::printf("--%.*s (or %s) must be a number from %g to %g, got '%s'",
                            static_cast<int>(flag.size()), flag.data(), variable, lo, hi,
                            text->c_str()));
  }
  return value;
}

// A postgres:// URL with its password (user:PASSWORD@) masked, for the logs.
std::string without_password(const std::string& url) {
  const auto scheme = url.find("://");
  const auto at = url.find('@', scheme == std::string::npos ? 0 : scheme);
  if (scheme == std::string::npos || at == std::string::npos) return url;
  const auto colon = url.find(':', scheme + 3);
  if (colon == std::string::npos || colon > at) return url;
  return url.substr(0, colon + 1) + "***" + url.substr(at);
}

}  // namespace

int run_serve(const Args& args, std::ostream& out) {
  const ParsedFlags flags("serve", args,
                          {{"bind"},
                           {"port"},
                           {"data"},
                           {"store"},
                           {"blobs"},
                           {"blob-grace-s"},
                           {"workers"},
                           {"max-queue"},
                           {"api-keys"},
                           {"io-threads"},
                           {"request-threads"},
                           {"request-queue"},
                           {"body-limit-mb"},
                           {"max-asset-mb"},
                           {"max-connections"},
                           {"min-free-mb"},
                           {"job-timeout-s"},
                           {"job-memory-mb"},
                           {"max-attempts"},
                           {"retention-h"},
                           {"sync"},
                           {"grace-s"},
                           {"callback-url"},
                           {"callback-secret"},
                           {"callback-ca"},
                           {"log-level"},
                           {"web-dir"},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kHelp;
    return kExitOk;
  }
  if (!flags.positional().empty()) {
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  }
  using namespace server;

  HttpOptions http;
  http.bind = setting(flags, "bind", "BRISANCE_BIND").value_or("127.0.0.1");
  http.port =
      static_cast<std::uint16_t>(integer_setting(flags, "port", "BRISANCE_PORT", 8080, 0, 65535));
  http.io_threads =
      static_cast<int>(integer_setting(flags, "io-threads", "BRISANCE_IO_THREADS", 4, 1, 64));
  http.request_threads = static_cast<int>(
      integer_setting(flags, "request-threads", "BRISANCE_REQUEST_THREADS", 2, 1, 64));
  http.request_queue = static_cast<std::size_t>(
      integer_setting(flags, "request-queue", "BRISANCE_REQUEST_QUEUE", 16, 0, 100000));
  http.max_connections = static_cast<std::size_t>(
      integer_setting(flags, "max-connections", "BRISANCE_MAX_CONNECTIONS", 1024, 1, 1000000));
  http.body_limit_bytes = static_cast<std::size_t>(
      number_setting(flags, "body-limit-mb", "BRISANCE_BODY_LIMIT_MB", 16, 0.001, 4096) * 1024 *
      1024);

  const std::string store_setting = setting(flags, "store", "BRISANCE_STORE").value_or("sqlite");
  const bool postgres = is_postgres_url(store_setting);
  if (!postgres && store_setting != "sqlite") {
    flags.fail("--store must be 'sqlite' or a postgres:// URL, got '" + store_setting + "'");
  }
  PostgresOptions pg_store;
  pg_store.conninfo = store_setting;
  SqliteOptions store;
  store.file = std::filesystem::path(setting(flags, "data", "BRISANCE_DATA").value_or("data")) /
               "brisance.sqlite3";
  const std::string sync = setting(flags, "sync", "BRISANCE_SYNC").value_or("normal");
  if (sync == "full") {
    store.synchronous = Synchronous::full;
  } else if (sync != "normal") {
    flags.fail("--sync must be 'normal' or 'full', got '" + sync + "'");
  }

  ServiceOptions service_options;
  service_options.max_queue =
      integer_setting(flags, "max-queue", "BRISANCE_MAX_QUEUE", 10000, 1, 100000000);
  service_options.max_asset_bytes = static_cast<std::size_t>(
      number_setting(flags, "max-asset-mb", "BRISANCE_MAX_ASSET_MB", 8, 0.001, 4096) * 1024 * 1024);
  service_options.max_attempts =
      static_cast<int>(integer_setting(flags, "max-attempts", "BRISANCE_MAX_ATTEMPTS", 3, 1, 100));

  WorkerOptions workers;
  const long long cores = std::max(1u, std::thread::hardware_concurrency());
  workers.workers =
      static_cast<int>(integer_setting(flags, "workers", "BRISANCE_WORKERS", cores, 1, 256));
  workers.job_timeout_s =
      number_setting(flags, "job-timeout-s", "BRISANCE_JOB_TIMEOUT_S", 600, 0, 1e7);
  workers.job_memory_bytes = static_cast<std::uint64_t>(
      number_setting(flags, "job-memory-mb", "BRISANCE_JOB_MEMORY_MB", 2048, 0, 1e7) * 1024 * 1024);
  service_options.job_memory_bytes = workers.job_memory_bytes;
  workers.retention = std::chrono::hours(
      integer_setting(flags, "retention-h", "BRISANCE_RETENTION_H", 168, 0, 1000000));
  const double grace_s = number_setting(flags, "grace-s", "BRISANCE_GRACE_S", 10, 0, 3600);
  service_options.default_callback_url =
      setting(flags, "callback-url", "BRISANCE_CALLBACK_URL").value_or("");
  if (!service_options.default_callback_url.empty()) {
    if (auto problem = check_callback_url(service_options.default_callback_url))
      flags.fail("--callback-url (or BRISANCE_CALLBACK_URL): " + *problem);
  }
  CallbackOptions callback_options;
  callback_options.secret =
      setting(flags, "callback-secret", "BRISANCE_CALLBACK_SECRET").value_or("");
  callback_options.ca_file = setting(flags, "callback-ca", "BRISANCE_CALLBACK_CA").value_or("");
  if (!callback_options.ca_file.empty() && !std::ifstream(callback_options.ca_file))
    flags.fail("--callback-ca (or BRISANCE_CALLBACK_CA): cannot read '" + callback_options.ca_file +
               "'");

  const std::string level = setting(flags, "log-level", "BRISANCE_LOG_LEVEL").value_or("info");
  if (level == "debug") {
    set_log_level(LogLevel::debug);
  } else if (level == "info") {
    set_log_level(LogLevel::info);
  } else if (level == "warn") {
    set_log_level(LogLevel::warn);
  } else if (level == "error") {
    set_log_level(LogLevel::error);
  } else {
    flags.fail("--log-level must be debug, info, warn or error, got '" + level + "'");
  }

  ApiKeys keys;
  if (auto file = setting(flags, "api-keys", "BRISANCE_API_KEYS")) {
    try {
      keys = ApiKeys::load(*file);
    } catch (const std::runtime_error& error) {
      flags.fail(error.what());
    }
    if (!keys.enabled()) flags.fail("the API keys file " + *file + " lists no key");
  }

  // SIGINT and SIGTERM are taken by sigwait below, in this thread only: block them before any
  // thread starts so every thread inherits the mask.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  const std::optional<std::string> blobs_dir = setting(flags, "blobs", "BRISANCE_BLOBS");
  BlobOptions blob_options;
  blob_options.grace = std::chrono::seconds(
      integer_setting(flags, "blob-grace-s", "BRISANCE_BLOB_GRACE_S", 600, 0, 100000000));

  std::unique_ptr<Storage> storage;
  try {
    std::unique_ptr<BlobStore> blobs;
    if (blobs_dir) {
      blob_options.dir = *blobs_dir;
      blobs = std::make_unique<BlobStore>(blob_options);
    }
    // Wrapped even without --blobs, so a row naming a blob is an error here, not an empty result.
    storage = with_blob_store(
        postgres ? open_postgres_storage(pg_store) : open_sqlite_storage(store), std::move(blobs));
  } catch (const StorageError& error) {
    std::cerr << "brisance serve: " << error.what() << "\n";
    return kExitInternal;
  }
  JobService service(*storage, service_options);
  Metrics metrics;
  WorkerPool pool(service, metrics, workers);
  CallbackSender callbacks(service, callback_options);
  ApiOptions api_options;
  api_options.body_limit_bytes = http.body_limit_bytes;
  const auto min_free_bytes = static_cast<std::uint64_t>(
      number_setting(flags, "min-free-mb", "BRISANCE_MIN_FREE_MB", 256, 0, 1e9) * 1024 * 1024);
  // PostgreSQL's disk is the database server's to watch, not this node's.
  if (!postgres) {
    api_options.free_space = std::make_shared<FreeSpace>(store.file.parent_path(), min_free_bytes);
  }
  StaticFiles web(setting(flags, "web-dir", "BRISANCE_WEB_DIR").value_or(BRISANCE_WEB_DIR));
  if (web.available()) {
    api_options.static_file = [&web](std::string_view path) { return web.get(path); };
  } else {
    log_event(LogLevel::warn, "no dashboard: index.html not found (run make run, or --web-dir)",
              {{"web_dir", web.root().string()}});
  }
  Api api(
      service, metrics, keys,
      [&pool] {
        return WorkerGauges{pool.busy(), pool.size()};
      },
      api_options);
  HttpServer server(api, service, metrics, http);
  try {
    server.listen();
  } catch (const std::runtime_error& error) {
    std::cerr << "brisance serve: " << error.what() << "\n";
    return kExitInternal;
  }
  pool.start();
  server.start();
  log_event(LogLevel::info, "listening",
            {{"url", "http://" + http.bind + ":" + std::to_string(server.port())},
             {"port", server.port()},
             {"database", postgres ? without_password(store_setting) : store.file.string()},
             {"workers", workers.workers},
             {"api_keys", keys.size()},
             {"store", postgres ? "postgres" : "sqlite"},
             {"blobs", blobs_dir ? *blobs_dir : "in the database"},
             {"synchronous", sync},
             {"dashboard", web.available()}});

  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  log_event(LogLevel::info, "shutting down",
            {{"signal", signal_number == SIGTERM ? "SIGTERM" : "SIGINT"}, {"grace_s", grace_s}});
  server.stop(std::chrono::seconds(10));
  pool.stop(std::chrono::milliseconds(static_cast<long long>(grace_s * 1000)));
  log_event(LogLevel::info, "stopped");
  return kExitOk;
}

int run_api_key(const Args& args, std::ostream& out) {
  const ParsedFlags flags("api-key", args, {{"name"}, {"scope"}, {"help", false, "h"}});
  if (flags.has("help")) {
    out << kKeyHelp;
    return kExitOk;
  }
  const std::string name(flags.value("name").value_or("default"));
  if (name.empty() || name.find_first_of(" \t\n#") != std::string::npos) {
    flags.fail("--name must be one word without spaces or '#'");
  }
  const std::string_view scope = flags.value("scope").value_or("write");
  if (scope != "read" && scope != "write" && scope != "admin") {
    flags.fail("--scope must be 'read', 'write' or 'admin', got '" + std::string(scope) + "'");
  }
  const std::string key = server::generate_api_key();
  out << "key:  " << key << "\n"
      << "line: "
      << server::api_key_line(name,
                              scope == "admin"   ? server::Scope::admin
                              : scope == "write" ? server::Scope::write
                                                 : server::Scope::read,
                              key)
      << "\n";
  return kExitOk;
}

}  // namespace brisance::cli
