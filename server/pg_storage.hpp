// server/pg_storage: the job store on PostgreSQL, shared by any number of `brisance serve` nodes
// (DESIGN.md "Scale-out").
//
// - Migrations (server/migrations/postgres, numbered like SQLite's) run under an advisory lock, so
//   whichever node starts first applies them and the others wait, then find them applied.
// - A claim takes the queued job of highest priority with FOR UPDATE SKIP LOCKED: nodes claiming
//   at once skip each other's rows instead of waiting on them or taking the same job.
// - Leases work as on SQLite (owner + expiry renewed by the owner's keeper; any node's keeper
//   requeues an expired one). Times are the callers' clocks: nodes need NTP-level agreement,
//   far below a lease.
// - Every change NOTIFYs (channel brisance_jobs, payload the job id; brisance_queue when a job
//   is queued) in its transaction; one LISTEN connection per node wakes its idle workers and the
//   long-polls parked on the job.
// - Connections are pooled; a broken one is dropped, and new ones are attempted with exponential
//   backoff (100 ms to 5 s) while the server is unreachable, so ping() — /readyz — answers at
//   once either way.
// - Results (meshes, frames) are bytea rows, as on SQLite.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <string_view>

#include "server/storage.hpp"

namespace brisance::server {

struct PostgresOptions {
  std::string conninfo;  // postgres://user@host:port/db?… or libpq key=value pairs
  std::chrono::milliseconds first_backoff{100};
  std::chrono::milliseconds max_backoff{5000};
};

// True for a postgres:// or postgresql:// URL (what --store takes for this store).
bool is_postgres_url(std::string_view text);

// Connects and migrates; StorageError if the server cannot be reached or the migration fails.
std::unique_ptr<Storage> open_postgres_storage(const PostgresOptions& options);

// The schema version the numbered migrations bring a database to.
int postgres_schema_version();

}  // namespace brisance::server
