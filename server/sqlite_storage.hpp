// server/sqlite_storage: the job store on one SQLite file in WAL mode (DESIGN.md "Scale-out").
//
// Readers run concurrently on a pool of connections; writers are serialised in-process and each
// write is a `BEGIN IMMEDIATE` transaction, so a claim can never race another claim, and a second
// process on the same file waits up to the busy timeout instead of failing.
//
// Durability (`synchronous`):
//   full   — every commit is fsynced before it returns: an accepted job survives a power loss.
//   normal — the WAL is fsynced at checkpoints only: an accepted job survives any crash of the
//            process (kill -9 included) but the last transactions before a power loss or kernel
//            crash may roll back. The default, for throughput; see docs/service.md.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "server/sqlite.hpp"
#include "server/storage.hpp"

namespace brisance::server {

// Opens (creating if needed) and migrates the database; StorageError if it cannot.
std::unique_ptr<Storage> open_sqlite_storage(const SqliteOptions& options);

// The schema version the numbered migrations bring a database to.
int sqlite_schema_version();

}  // namespace brisance::server
