// Peak memory of serving one job's frames, the whole run as one page, the way the route did
// before it streamed (the page built whole: result_frame_set, then the document) and the way it
// streams now (a block of frames at a time, each block dropped once encoded), or of its glb.
//
//   frames_memory_bench DATA_DIR JOB_ID whole-json|stream-json|whole-brf|stream-brf|glb
//
// Opens DATA_DIR/brisance.sqlite3 (a `brisance serve --data DATA_DIR` store) and prints the
// bytes produced and VmHWM (peak resident set) before and after, from /proc/self/status. One
// mode per process, so each peak is its own.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "server/blob_store.hpp"
#include "server/job_service.hpp"
#include "server/sqlite_storage.hpp"
#include "sim/io/frames.hpp"

namespace {

using namespace brisance;

long peak_kib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr,
                 "usage: frames_memory_bench DATA_DIR JOB_ID "
                 "whole-json|stream-json|whole-brf|stream-brf|glb\n");
    return 2;
  }
  const std::string mode = argv[3];
  server::SqliteOptions options;
  options.file = std::string(argv[1]) + "/brisance.sqlite3";
  auto storage = server::with_blob_store(server::open_sqlite_storage(options), nullptr);
  server::JobService service(*storage, {});
  const std::string id = argv[2];
  const auto layout = service.result_layout(id);
  if (!layout) {
    std::fprintf(stderr, "no result for %s\n", id.c_str());
    return 1;
  }
  const long before = peak_kib();
  std::size_t bytes = 0;
  const std::int64_t to = layout->frame_count;
  if (mode == "whole-json") {
    bytes = io::frames_document_json(service.result_frame_set(id, *layout, 0, to, layout->animated),
                                     static_cast<std::uint64_t>(to))
                .size();
  } else if (mode == "whole-brf") {
    bytes =
        io::frames_to_brf1(service.result_frame_set(id, *layout, 0, to, layout->animated)).size();
  } else if (mode == "stream-json" || mode == "stream-brf") {
    // What routes/results.cpp's FrameStream does, block by block.
    const auto reader = service.result_frame_reader(id);
    const std::int64_t block =
        std::max<std::int64_t>(1, 8192 / std::max<std::int64_t>(1, std::ssize(layout->animated)));
    for (std::int64_t first = 0; first < to; first += block) {
      const io::FrameSet set = server::JobService::frame_set(
          reader, *layout, first, std::min(to, first + block), layout->animated);
      if (mode == "stream-brf") {
        std::string out;
        io::append_brf1_frames(out, set);
        bytes += out.size();
      } else {
        std::ostringstream out;
        for (std::size_t f = 0; f < set.frame_count(); ++f)
          io::write_frame_json(out, set, f);
        bytes += out.str().size();
      }
    }
  } else if (mode == "glb") {
    bytes = service.result_glb(id)->size();
  } else {
    std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
    return 2;
  }
  std::printf("%s %s: %zu frames x %zu bodies, %zu bytes, VmHWM %ld -> %ld KiB\n", mode.c_str(),
              id.c_str(), static_cast<std::size_t>(to), layout->animated.size(), bytes, before,
              peak_kib());
  return 0;
}
