// The facade shot of issue 17 end to end (goal: scenes/facade.json under 3 s on one core): read
// and parse the scene, break the pane, prepare, shield, step, and write the .glb and the .json as
// `brisance run` does, with the wall-clock time of each stage. A table, one row per run.
//
// usage: facade_bench [--scene FILE] [--runs N] [--out DIR]
//   --scene  the scene (default: scenes/facade.json of the source tree)
//   --runs   how many runs (default 1)
//   --out    where the outputs are written (default: the system's temporary folder)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "sim/engine/simulator.hpp"
#include "sim/io/gltf.hpp"
#include "sim/io/result_json.hpp"
#include "sim/scene/scene.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// CPU time of this process, s: on a machine shared with other jobs the wall times of the stages
// grow with the load, the CPU time of the run much less.
double cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

int usage() {
  std::fprintf(stderr, "usage: facade_bench [--scene FILE] [--runs N] [--out DIR]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path scene_path =
      std::filesystem::path(BRISANCE_SOURCE_DIR) / "scenes" / "facade.json";
  std::filesystem::path out_dir = std::filesystem::temp_directory_path();
  int runs = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (i + 1 >= argc) return usage();
    if (flag == "--scene") {
      scene_path = argv[++i];
    } else if (flag == "--runs") {
      runs = std::atoi(argv[++i]);
      if (runs < 1) return usage();
    } else if (flag == "--out") {
      out_dir = argv[++i];
    } else {
      return usage();
    }
  }
  std::printf("scene: %s\n", scene_path.string().c_str());
  std::printf("wall-clock seconds by stage; cpu_s: CPU time of the whole run\n");
  std::printf("%4s %8s %8s %8s %9s %9s %8s %8s %8s | %6s %7s %10s\n", "run", "parse", "fracture",
              "prepare", "shielding", "stepping", "output", "total", "cpu_s", "bodies", "steps",
              "body_steps");
  for (int run = 0; run < runs; ++run) {
    const auto start = Clock::now();
    const double cpu_start = cpu_seconds();
    std::ifstream in(scene_path);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", scene_path.string().c_str());
      return 1;
    }
    std::stringstream text;
    text << in.rdbuf();
    const brisance::scene::ParseResult parsed = brisance::scene::parse_scene_text(text.str());
    if (!parsed.scene) {
      std::fprintf(stderr, "%s: %s: %s\n", scene_path.string().c_str(),
                   parsed.errors.front().pointer.c_str(), parsed.errors.front().message.c_str());
      return 1;
    }
    const double parse_s = seconds_since(start);
    const brisance::engine::RunOutcome outcome = brisance::engine::simulate(*parsed.scene);
    const auto output_start = Clock::now();
    {
      std::ofstream glb(out_dir / "facade_bench.glb", std::ios::binary);
      brisance::io::write_glb(outcome.result, glb);
      std::ofstream json(out_dir / "facade_bench.json");
      brisance::io::write_result_json(outcome.result, json);
    }
    const double output_s = seconds_since(output_start);
    const double total_s = seconds_since(start);
    const double cpu_s = cpu_seconds() - cpu_start;
    const brisance::engine::StageTimes& t = outcome.times;
    const brisance::engine::Stats& s = outcome.result.stats;
    std::printf("%4d %8.3f %8.3f %8.3f %9.3f %9.3f %8.3f %8.3f %8.3f | %6llu %7llu %10llu\n",
                run + 1, parse_s, t.fracture_s, t.prepare_s, t.shielding_s, t.stepping_s, output_s,
                total_s, cpu_s, static_cast<unsigned long long>(s.bodies),
                static_cast<unsigned long long>(s.steps),
                static_cast<unsigned long long>(s.body_steps));
  }
  return 0;
}
