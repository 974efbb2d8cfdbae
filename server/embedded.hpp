// server/embedded: files compiled into the binary (cmake/embed.cmake): the SQL migrations, the
// OpenAPI contract.
#pragma once

#include <span>
#include <string_view>

namespace brisance {

struct EmbeddedFile {
  std::string_view name;  // path relative to its base folder, e.g. "001_jobs.sql"
  std::string_view data;
};

std::span<const EmbeddedFile> embedded_migrations();  // server/migrations/*.sql, sorted by name
// server/migrations/postgres/*.sql, sorted by name
std::span<const EmbeddedFile> embedded_pg_migrations();
std::span<const EmbeddedFile> embedded_api();  // api/openapi.yaml

}  // namespace brisance
