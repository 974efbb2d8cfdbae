// What a job's result takes in the store, before and after the compact encoding
// (server/compact_result), and what encoding and decoding it costs at each zstd level.
//
//   result_storage_bench SCENE.json...
//
// Per scene: the run's frames x bodies; the bytes of the meshes and frames as the stores kept
// them before (the uncompressed blob layout, the payload of job_bodies and job_frames rows) and
// the growth of a SQLite file per job both ways (rows, and one compact row); then per zstd level
// the encoded bytes, the encoding time and the time to decode every frame (median of 5).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "server/blob_store.hpp"
#include "server/compact_result.hpp"
#include "server/job_service.hpp"
#include "server/sqlite_storage.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/scene/scene.hpp"

namespace {

using namespace brisance;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

template <typename F>
double median_ms(F&& f) {
  std::vector<double> ms;
  for (int i = 0; i < 5; ++i) {
    const auto start = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[2];
}

// The bytes a SQLite store file (with its WAL checkpointed) grows by for `jobs` copies of
// `result`, stored through `wrap` (the plain store writes rows; the service's wrapper encodes).
std::uintmax_t sqlite_bytes_per_job(const server::StoredResult& result, bool compact, int jobs) {
  const fs::path dir =
      fs::temp_directory_path() / ("result_storage_bench_" + std::to_string(compact));
  fs::remove_all(dir);
  fs::create_directories(dir);
  server::SqliteOptions options;
  options.file = dir / "jobs.sqlite3";
  std::uintmax_t before = 0;
  {
    std::unique_ptr<server::Storage> storage = server::open_sqlite_storage(options);
    if (compact) storage = server::with_blob_store(std::move(storage), nullptr);
    before = fs::file_size(options.file);
    for (int j = 0; j < jobs; ++j) {
      server::NewJob job;
      job.id = "job" + std::to_string(j);
      job.scene_json = "{}";
      job.now_ms = 1;
      storage->create_job(job);
      storage->claim_next("bench", 2, 1000000);
      storage->complete(job.id, "bench", result, 3);
    }
  }  // closing the last connection checkpoints the WAL into the file
  const std::uintmax_t after = fs::file_size(options.file);
  fs::remove_all(dir);
  return (after - before) / static_cast<std::uintmax_t>(jobs);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: result_storage_bench SCENE.json...\n");
    return 2;
  }
  for (int a = 1; a < argc; ++a) {
    std::ifstream file(argv[a]);
    std::stringstream text;
    text << file.rdbuf();
    const scene::ParseResult parsed = scene::parse_scene_text(text.str());
    if (!parsed.scene) {
      std::fprintf(stderr, "%s: %s\n", argv[a], parsed.errors.front().message.c_str());
      return 1;
    }
    const engine::RunOutcome outcome = engine::simulate(*parsed.scene);
    const server::StoredResult stored = server::to_stored_result(outcome.result);
    std::size_t mesh_floats = 0;
    for (const auto& body : stored.bodies)
      mesh_floats += body.vertices.size() + body.triangles.size();
    const std::size_t frames = stored.frames.size();
    const std::size_t animated = outcome.result.animated.size();
    const std::size_t raw = server::encode_result_blob(stored.bodies, stored.frames).size();
    std::printf("%s: %zu bodies (%zu animated), %zu frames, %zu frame samples, %zu mesh words\n",
                argv[a], stored.bodies.size(), animated, frames, frames * animated, mesh_floats);
    std::printf("  uncompressed layout (rows' payload, old blobs): %zu bytes\n", raw);
    std::printf("  SQLite file growth per job: rows %ju bytes, compact row %ju bytes\n",
                sqlite_bytes_per_job(stored, false, 5), sqlite_bytes_per_job(stored, true, 5));
    std::printf("  %5s %12s %8s %10s %10s\n", "level", "bytes", "ratio", "encode_ms", "decode_ms");
    for (const int level : {1, 3, 6, 9, 12, 15, 19}) {
      std::string encoded;
      const double encode_ms = median_ms(
          [&] { encoded = server::encode_compact_result(stored.bodies, stored.frames, level); });
      const double decode_ms = median_ms([&] {
        const auto back = server::decode_compact_frames(encoded, 0, INT64_MAX);
        const auto bodies = server::decode_compact_bodies(encoded);
        if (back.size() != frames || bodies.size() != stored.bodies.size()) std::abort();
      });
      std::printf("  %5d %12zu %8.2f %10.2f %10.2f\n", level, encoded.size(),
                  static_cast<double>(raw) / static_cast<double>(encoded.size()), encode_ms,
                  decode_ms);
    }
  }
  return 0;
}
