// Run time versus error of the simulator (issue: "a run-time-versus-error study"). For each
// example scene, every combination of integrator, time step and panel size runs against a
// converged reference (rk4, 10 us steps, 0.0025 m^2 panels); the error is the RMS over bodies
// of the final position and velocity differences. Prints a table and writes a CSV and an SVG plot
// of error against run time. The runs stop at 0.3 s by default: the bricks are then in flight
// after the blast, before they tumble on the ground, where contact is chaotic (two runs that
// differ by 1e-6 m at landing lie 0.2 m apart a second later) and no scheme converges.
//
// usage: accuracy_study [--scenes DIR] [--out DIR] [--duration S] [--repeats N]
// (make accuracy-study runs it on scenes/ into bench/results/)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim/engine/simulator.hpp"
#include "sim/scene/scene.hpp"

namespace {

using brisance::engine::Result;
using brisance::scene::Integrator;
using brisance::scene::Scene;

struct Setting {
  Integrator integrator;
  std::string step;        // "fixed 1e-4" or "tol 1e-3"
  double time_step = 0.0;  // 0: adaptive with `tolerance`
  double tolerance = 1e-3;
  double panel_area = 0.05;
};

struct Row {
  std::string scene;
  Setting setting;
  double seconds = 0.0;
  double position_error_m = 0.0;
  double velocity_error_m_s = 0.0;
  unsigned long long steps = 0;
};

const char* name(Integrator integrator) {
  switch (integrator) {
    case Integrator::explicit_euler:
      return "explicit_euler";
    case Integrator::semi_implicit_euler:
      return "semi_implicit_euler";
    case Integrator::rk4:
      return "rk4";
  }
  return "?";
}

Scene with(Scene scene, const Setting& s, double duration) {
  scene.simulation.integrator = s.integrator;
  scene.simulation.max_panel_area_m2 = s.panel_area;
  scene.simulation.duration_s = duration;
  if (s.time_step > 0.0) {
    scene.simulation.time_step_s = s.time_step;
  } else {
    scene.simulation.time_step_s.reset();
    scene.simulation.tolerance = s.tolerance;
  }
  return scene;
}

// Median wall time of `repeats` runs, and the last result.
std::pair<double, Result> timed(const Scene& scene, int repeats) {
  std::vector<double> times;
  Result result;
  for (int i = 0; i < repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    result = brisance::engine::simulate(scene).result;
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return {times[times.size() / 2], std::move(result)};
}

std::pair<double, double> rms_errors(const Result& run, const Result& reference) {
  double position = 0.0, velocity = 0.0;
  const double n = static_cast<double>(reference.final_state.size());
  for (std::size_t b = 0; b < reference.final_state.size(); ++b) {
    for (int k = 0; k < 3; ++k) {
      position += std::pow(
          run.final_state[b].pose.position[k] - reference.final_state[b].pose.position[k], 2);
      velocity += std::pow(run.final_state[b].linear_velocity_m_s[k] -
                               reference.final_state[b].linear_velocity_m_s[k],
                           2);
    }
  }
  return {std::sqrt(position / n), std::sqrt(velocity / n)};
}

void write_svg(const std::filesystem::path& path, const std::vector<Row>& rows) {
  // Log-log: x = run time (s), y = position error (m); one colour per integrator.
  const double width = 760, height = 520, left = 80, right = 180, top = 30, bottom = 60;
  double x_min = INFINITY, x_max = 0, y_min = INFINITY, y_max = 0;
  for (const Row& r : rows) {
    const double y = std::max(r.position_error_m, 1e-12);
    x_min = std::min(x_min, r.seconds), x_max = std::max(x_max, r.seconds);
    y_min = std::min(y_min, y), y_max = std::max(y_max, y);
  }
  const double lx0 = std::floor(std::log10(x_min)), lx1 = std::ceil(std::log10(x_max));
  const double ly0 = std::floor(std::log10(y_min)), ly1 = std::ceil(std::log10(y_max));
  auto px = [&](double x) {
    return left + (std::log10(x) - lx0) / (lx1 - lx0) * (width - left - right);
  };
  auto py = [&](double y) {
    return top + (ly1 - std::log10(std::max(y, 1e-12))) / (ly1 - ly0) * (height - top - bottom);
  };
  const std::map<Integrator, const char*> colour = {{Integrator::explicit_euler, "#d62728"},
                                                    {Integrator::semi_implicit_euler, "#1f77b4"},
                                                    {Integrator::rk4, "#2ca02c"}};
  std::ofstream svg(path);
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' "
         "fill='white'/>\n";
  for (double e = lx0; e <= lx1; ++e)
    svg << "<line x1='" << px(std::pow(10, e)) << "' y1='" << top << "' x2='" << px(std::pow(10, e))
        << "' y2='" << height - bottom << "' stroke='#ddd'/><text x='" << px(std::pow(10, e)) - 12
        << "' y='" << height - bottom + 18 << "'>1e" << e << "</text>\n";
  for (double e = ly0; e <= ly1; ++e)
    svg << "<line x1='" << left << "' y1='" << py(std::pow(10, e)) << "' x2='" << width - right
        << "' y2='" << py(std::pow(10, e)) << "' stroke='#ddd'/><text x='" << left - 45 << "' y='"
        << py(std::pow(10, e)) + 4 << "'>1e" << e << "</text>\n";
  svg << "<text x='" << (width - right + left) / 2 - 60 << "' y='" << height - 15
      << "'>run time (s)</text>\n<text x='15' y='" << top + 10
      << "'>RMS final position error (m)</text>\n";
  for (const Row& r : rows)
    svg << "<circle cx='" << px(r.seconds) << "' cy='" << py(r.position_error_m) << "' r='4' fill='"
        << colour.at(r.setting.integrator) << "' fill-opacity='0.7'><title>" << r.scene << " "
        << name(r.setting.integrator) << " " << r.setting.step << " panel " << r.setting.panel_area
        << "</title></circle>\n";
  double y = top + 10;
  for (const auto& [integrator, c] : colour) {
    svg << "<circle cx='" << width - right + 20 << "' cy='" << y << "' r='5' fill='" << c
        << "'/><text x='" << width - right + 30 << "' y='" << y + 4 << "'>" << name(integrator)
        << "</text>\n";
    y += 20;
  }
  svg << "</svg>\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path scenes_dir = "scenes", out_dir = "bench/results";
  double duration = 0.3;
  int repeats = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--scenes")
      scenes_dir = argv[i + 1];
    else if (flag == "--out")
      out_dir = argv[i + 1];
    else if (flag == "--duration")
      duration = std::stod(argv[i + 1]);
    else if (flag == "--repeats")
      repeats = std::stoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "accuracy_study: unknown option %s\n", flag.c_str());
      return 2;
    }
  }
  std::vector<Setting> settings;
  for (Integrator integrator :
       {Integrator::explicit_euler, Integrator::semi_implicit_euler, Integrator::rk4}) {
    for (double area : {0.2, 0.05, 0.01}) {
      char label[32];
      for (double step : {1e-2, 1e-3, 1e-4}) {
        std::snprintf(label, sizeof label, "fixed %.0e", step);
        settings.push_back({integrator, label, step, 0.0, area});
      }
      for (double tolerance : {1e-2, 1e-3, 1e-4}) {
        std::snprintf(label, sizeof label, "tol %.0e", tolerance);
        settings.push_back({integrator, label, 0.0, tolerance, area});
      }
    }
  }
  std::vector<Row> rows;
  for (const char* file : {"brick_wall.json", "brick_wall_strong.json", "three_blocks.json"}) {
    std::ifstream in(scenes_dir / file);
    std::stringstream text;
    text << in.rdbuf();
    const auto parsed = brisance::scene::parse_scene_text(text.str());
    if (!parsed.scene) {
      std::fprintf(stderr, "accuracy_study: %s does not parse\n", file);
      return 1;
    }
    const Setting reference_setting{Integrator::rk4, "fixed 1e-5", 1e-5, 0.0, 0.0025};
    const Result reference =
        brisance::engine::simulate(with(*parsed.scene, reference_setting, duration)).result;
    for (const Setting& setting : settings) {
      auto [seconds, result] = timed(with(*parsed.scene, setting, duration), repeats);
      const auto [position, velocity] = rms_errors(result, reference);
      rows.push_back({file, setting, seconds, position, velocity, result.stats.steps});
    }
  }
  std::filesystem::create_directories(out_dir);
  std::ofstream csv(out_dir / "accuracy_study.csv");
  csv << "scene,integrator,step,panel_area_m2,run_time_s,steps,position_rms_error_m,velocity_rms_"
         "error_m_s\n";
  std::printf("%-24s %-20s %-12s %6s %10s %7s %12s %12s\n", "scene", "integrator", "step", "panel",
              "time (ms)", "steps", "pos err (m)", "vel err (m/s)");
  for (const Row& r : rows) {
    csv << r.scene << ',' << name(r.setting.integrator) << ',' << r.setting.step << ','
        << r.setting.panel_area << ',' << r.seconds << ',' << r.steps << ',' << r.position_error_m
        << ',' << r.velocity_error_m_s << '\n';
    std::printf("%-24s %-20s %-12s %6.3g %10.3f %7llu %12.3e %12.3e\n", r.scene.c_str(),
                name(r.setting.integrator), r.setting.step.c_str(), r.setting.panel_area,
                1e3 * r.seconds, r.steps, r.position_error_m, r.velocity_error_m_s);
  }
  write_svg(out_dir / "accuracy_study.svg", rows);
  std::printf("wrote %s and %s (duration %.3g s, median of %d runs)\n",
              (out_dir / "accuracy_study.csv").c_str(), (out_dir / "accuracy_study.svg").c_str(),
              duration, repeats);
  return 0;
}
