// `brisance run` and `brisance validate`: a scene file through the simulator and the writers.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <unistd.h>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/engine/simulator.hpp"
#include "sim/io/frames.hpp"
#include "sim/io/gltf.hpp"
#include "sim/io/mesh_import.hpp"
#include "sim/io/result_json.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kRunHelp =
    "usage: brisance run SCENE.json -o OUT.glb|OUT.json|OUT.brf [--frame-velocities] [--progress]\n"
    "\n"
    "Simulates a scene and writes the result: binary glTF (.glb) with one animated node per\n"
    "body, JSON with bodies, frames, final states, stats and warnings, or the frames alone as\n"
    "BRF1 binary frames (.brf; the bytes of GET /v1/jobs/{id}/frames as octet-stream).\n"
    "  -o, --output FILE   where to write; the extension picks the format\n"
    "  --frame-velocities  .json only: each pose of the frames also gets its linear and angular\n"
    "                      velocity (for motion blur; as GET .../frames?velocities=true)\n"
    "  --progress          progress on stderr once a run takes over a second: a bar with the\n"
    "                      time left on a terminal, a line at every tenth otherwise\n"
    "  --memory-mb M       stop a run whose estimated memory (bodies, meshes, panels, frames)\n"
    "                      passes M MiB, as the service's --job-memory-mb does (default: none)\n"
    "A run whose broken panes make more fragments, panels or frame samples than the scene\n"
    "limits allow stops with an error (exit code 2) naming what to change.\n";

constexpr std::string_view kValidateHelp =
    "usage: brisance validate SCENE.json\n"
    "\n"
    "Checks a scene without running it; prints every problem with its JSON pointer.\n";

std::string read_file(const ParsedFlags& flags, std::string_view path) {
  std::ifstream in{std::string(path), std::ios::binary};
  if (!in) flags.fail("cannot read '" + std::string(path) + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string_view single_scene_path(const ParsedFlags& flags) {
  if (flags.positional().empty()) flags.fail("a scene file is required (see --help)");
  if (flags.positional().size() > 1)
    flags.fail("one scene file at a time, got '" + std::string(flags.positional()[1]) + "' too");
  return flags.positional().front();
}

// `file` shapes: a relative path is taken from the scene file's folder, so a scene and its meshes
// move together.
scene::MeshSources file_meshes(std::string_view scene_path) {
  const std::filesystem::path folder = std::filesystem::path(scene_path).parent_path();
  scene::MeshSources sources;
  sources.file = [folder](const scene::MeshReference& reference) {
    const std::filesystem::path path = folder / std::filesystem::path(reference.reference);
    io::MeshImport imported = io::import_mesh_file(path, reference.node);
    return scene::ResolvedMesh{std::move(imported.mesh), std::move(imported.error)};
  };
  return sources;
}

// Parses the scene; on errors prints them all (one line each) and throws the usage error.
scene::Scene load_scene(const ParsedFlags& flags, std::string_view path) {
  const scene::ParseResult parsed =
      scene::parse_scene_text(read_file(flags, path), {}, file_meshes(path));
  if (parsed.scene) return *parsed.scene;
  for (std::size_t i = 0; i + 1 < parsed.errors.size(); ++i) {
    const scene::ValidationError& e = parsed.errors[i];
    std::cerr << path << ": " << (e.pointer.empty() ? "(document)" : e.pointer) << ": " << e.message
              << "\n";
  }
  const scene::ValidationError& last = parsed.errors.back();
  flags.fail(
      std::string(path) + ": " + (last.pointer.empty() ? "(document)" : last.pointer) + ": " +
      last.message +
      (parsed.errors.size() > 1 ? text::printf(" (%zu problems)", parsed.errors.size()) : ""));
}

// The run's progress on stderr: on a terminal a bar redrawn in place, otherwise (a log, a CI
// job) a plain line at every tenth. Both give the time so far and the time left, estimated from
// the share of the work done (the engine's progress is in work, not simulated time).
class ProgressBar {
 public:
  ProgressBar(bool enabled, bool terminal) : enabled_(enabled), terminal_(terminal) {}
  void update(double fraction) {
    if (!enabled_) return;
    const double elapsed = seconds();
    if (elapsed < 1.0 && last_tenth_ == 0 && !drawn_) return;  // quick runs stay quiet
    // The rate since the first report: preparing (breaking panes, shielding) comes before it.
    if (!first_) first_ = {elapsed, fraction};
    const double rate =
        fraction > first_->second ? (fraction - first_->second) / (elapsed - first_->first) : 0.0;
    const std::string left =
        fraction >= 1.0 ? std::string("done")
        : rate > 0.0    ? text::printf("about %s left", duration((1.0 - fraction) / rate).c_str())
                        : std::string("estimating");
    if (!terminal_) {
      const int tenth = static_cast<int>(10.0 * fraction);
      if (tenth <= last_tenth_) return;
      last_tenth_ = tenth;
      std::fprintf(stderr, "progress %3.0f%%  %s elapsed, %s\n", 100.0 * fraction,
                   duration(elapsed).c_str(), left.c_str());
      return;
    }
    if (fraction < 1.0 && elapsed - last_draw_ < 0.1) return;
    last_draw_ = elapsed;
    const int width = 40;
    const int filled = static_cast<int>(fraction * width);
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  %s, %s   ", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), 100.0 * fraction,
                 duration(elapsed).c_str(), left.c_str());
    drawn_ = true;
  }
  void finish() {
    if (drawn_) std::fprintf(stderr, "\n");
  }

 private:
  static std::string duration(double s) {
    if (s < 10.0) return text::printf("%.1f s", s);
    if (s < 60.0) return text::printf("%.0f s", s);
    if (s < 3600.0)
      return text::printf("%d min %02d s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
    return text::printf("%d h %02d min", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
  }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool enabled_;
  bool terminal_;
  bool drawn_ = false;
  double last_draw_ = -1.0;
  int last_tenth_ = 0;
  std::optional<std::pair<double, double>> first_;  // elapsed s and fraction at the first report
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

enum class Format { glb, json, brf };

// Writes through a temporary file and a rename, so a failed run never leaves half a result.
void write_output(const std::filesystem::path& path, Format format, const engine::Result& result,
                  bool frame_velocities) {
  std::filesystem::path temporary = path;
  temporary += ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write '" + temporary.string() + "'");
    switch (format) {
      case Format::glb:
        io::write_glb(result, out);
        break;
      case Format::json:
        io::write_result_json(result, out, frame_velocities);
        break;
      case Format::brf:
        io::write_brf1(io::frames_of(result), out);
        break;
    }
    out.flush();
    if (!out) throw std::runtime_error("writing '" + temporary.string() + "' failed");
  }
  std::filesystem::rename(temporary, path);
}

}  // namespace

int run_simulation(const Args& args, std::ostream& out) {
  const ParsedFlags flags("run", args,
                          {{"output", true, "o"},
                           {"progress", false},
                           {"frame-velocities", false},
                           {"memory-mb", true},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kRunHelp;
    return kExitOk;
  }
  const std::string_view scene_path = single_scene_path(flags);
  const auto output = flags.value("output");
  if (!output) flags.fail("-o OUT.glb, -o OUT.json or -o OUT.brf is required");
  const std::filesystem::path output_path{std::string(*output)};
  const std::string extension = output_path.extension().string();
  Format format = Format::json;
  if (extension == ".glb") {
    format = Format::glb;
  } else if (extension == ".brf") {
    format = Format::brf;
  } else if (extension != ".json") {
    flags.fail("the output must end in .glb, .json or .brf, got '" + std::string(*output) + "'");
  }
  const bool frame_velocities = flags.has("frame-velocities");
  if (frame_velocities && format != Format::json)
    flags.fail("--frame-velocities needs a .json output (BRF1 frames and .glb hold poses only)");
  if (output_path.has_parent_path() && !std::filesystem::is_directory(output_path.parent_path()))
    flags.fail("the output folder '" + output_path.parent_path().string() + "' does not exist");

  const scene::Scene scene = load_scene(flags, scene_path);
  ProgressBar bar(flags.has("progress"), isatty(STDERR_FILENO) != 0);
  engine::RunHooks hooks;
  hooks.progress = [&bar](double fraction) { bar.update(fraction); };
  engine::RunBudget budget;
  if (flags.has("memory-mb")) {
    const auto megabytes = flags.number("memory-mb");
    if (!megabytes || !(*megabytes > 0.0) || *megabytes > 1e9)
      flags.fail("--memory-mb must be a number of MiB greater than 0");
    budget.memory_bytes = static_cast<std::uint64_t>(*megabytes * 1024.0 * 1024.0);
  }
  const engine::RunOutcome outcome = engine::simulate(scene, hooks, budget);
  bar.finish();
  if (outcome.over_budget)
    flags.fail(std::string(scene_path) + ": " + outcome.over_budget->message);
  const engine::Result& result = outcome.result;
  write_output(output_path, format, result, frame_velocities);
  const engine::Stats& s = result.stats;
  out << text::printf(
      "%s: %.3g s simulated in %.3g s (%llu steps); %llu bodies, %zu moved, %llu never "
      "released; %llu of %llu panels loaded; wrote %s\n",
      std::string(scene_path).c_str(), s.simulated_time_s, s.wall_time_s,
      static_cast<unsigned long long>(s.steps), static_cast<unsigned long long>(s.bodies),
      result.animated.size(), static_cast<unsigned long long>(s.bodies_never_released),
      static_cast<unsigned long long>(s.panels_loaded), static_cast<unsigned long long>(s.panels),
      output_path.string().c_str());
  // Each breakable pane: whether it broke and the hazard its glass is to the room behind it
  // (docs/fracture.md, "Hazard rating").
  for (const engine::PaneReport& pane : result.fracture) {
    const engine::PaneHazard& hazard = pane.hazard;
    out << text::printf(
        "  pane %s: %s; GSA P100 condition %s (hazard %s)\n", pane.name.c_str(),
        pane.broken ? text::printf("%llu fragments, %llu released, %llu into the room behind it",
                                   static_cast<unsigned long long>(pane.fragment_count),
                                   static_cast<unsigned long long>(pane.released),
                                   static_cast<unsigned long long>(hazard.fragments_in_room))
                          .c_str()
                    : "not broken",
        hazard.condition.c_str(), hazard.hazard_level.c_str());
  }
  for (const engine::Warning& warning : result.warnings)
    std::cerr << "warning: " << warning.code << " (x" << warning.count << "): " << warning.message
              << "\n";
  return kExitOk;
}

int run_validate(const Args& args, std::ostream& out) {
  const ParsedFlags flags("validate", args, {{"help", false, "h"}});
  if (flags.has("help")) {
    out << kValidateHelp;
    return kExitOk;
  }
  const std::string_view scene_path = single_scene_path(flags);
  const scene::Scene scene = load_scene(flags, scene_path);
  out << text::printf("%s: valid (%zu objects, %zu charges)\n", std::string(scene_path).c_str(),
                      scene.objects.size(), scene.charges.size());
  return kExitOk;
}

}  // namespace brisance::cli
