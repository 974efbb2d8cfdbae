// `brisance fracture`: grow a crack pattern on a pane and write its fragments (thesis ch. 5.4).
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/fracture/fragments.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kHelp =
    "usage: brisance fracture --width W --height H [--initial-crack L] [--branch-angle-deg A]\n"
    "                         [--angle-variance-deg V] [--wiggle-prob P] [--wiggle-deg D]\n"
    "                         [--grid N] [--growth-length A_C] [--seed S]\n"
    "                         -o pattern.svg|pattern.json\n"
    "\n"
    "Grows a crack tree on a pane and writes the fragments it cuts the pane into.\n"
    "  --width W, --height H    pane size in m (> 0)\n"
    "  --initial-crack L        length of the initial micro-crack at the centre, m (default 0.02)\n"
    "  --branch-angle-deg A     angle between the two branches of a fork (default 15)\n"
    "  --angle-variance-deg V   forks open A +- V/2, uniform (default 0)\n"
    "  --wiggle-prob P          chance that a tip turns at each new piece, 0..1 (default 0)\n"
    "  --wiggle-deg D           a turn is uniform in +-D/2 degrees (default 0)\n"
    "  --grid N                 bit bucket cells along each side (default 2048)\n"
    "  --growth-length A_C      crack growth between forks a_c, m (default 0.02)\n"
    "  --seed S                 random seed, a non-negative integer (default 1)\n"
    "  -o, --output FILE        .svg (a picture) or .json (fragment polygons in m)\n";

double flag_number(const ParsedFlags& flags, std::string_view name, double fallback) {
  const auto value = flags.number(name);
  return value ? *value : fallback;
}

fracture::FractureParams parse(const ParsedFlags& flags) {
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  fracture::FractureParams p;
  for (const char* required : {"width", "height"})
    if (!flags.has(required))
      flags.fail("--" + std::string(required) + " is required (see --help)");
  p.width_m = flag_number(flags, "width", 0.0);
  p.height_m = flag_number(flags, "height", 0.0);
  if (!(p.width_m > 0.0) || !(p.height_m > 0.0))
    flags.fail(text::printf("--width and --height must be greater than 0 m, got %g x %g", p.width_m,
                            p.height_m));
  p.initial.length_m = flag_number(flags, "initial-crack", p.initial.length_m);
  p.branch_angle_deg = flag_number(flags, "branch-angle-deg", p.branch_angle_deg);
  p.angle_variance_deg = flag_number(flags, "angle-variance-deg", p.angle_variance_deg);
  p.wiggle_probability = flag_number(flags, "wiggle-prob", p.wiggle_probability);
  p.wiggle_variance_deg = flag_number(flags, "wiggle-deg", p.wiggle_variance_deg);
  p.growth_length_m = flag_number(flags, "growth-length", p.growth_length_m);
  const double grid = flag_number(flags, "grid", 2048.0);
  if (grid != static_cast<double>(static_cast<long>(grid)) || grid < 4 ||
      grid > fracture::FractureParams::kMaxGridCells)
    flags.fail(text::printf("--grid must be a whole number of cells from 4 to %d, got %g",
                            fracture::FractureParams::kMaxGridCells, grid));
  p.grid_x = p.grid_y = static_cast<int>(grid);
  if (const auto seed = flags.value("seed")) {
    std::uint64_t parsed = 0;
    const char* end = seed->data() + seed->size();
    const auto [ptr, ec] = std::from_chars(seed->data(), end, parsed);
    if (ec != std::errc() || ptr != end)
      flags.fail("--seed must be a non-negative integer, got '" + std::string(*seed) + "'");
    p.seed = parsed;
  }
  if (const auto problem = fracture::validate(p)) flags.fail(*problem);
  return p;
}

nlohmann::ordered_json to_json(const fracture::FractureParams& p,
                               const fracture::FracturePattern& pattern) {
  nlohmann::ordered_json out;
  out["width"] = p.width_m;
  out["height"] = p.height_m;
  out["seed"] = p.seed;
  out["grid"] = p.grid_x;
  out["initial_crack"] = p.initial.length_m;
  out["growth_length"] = p.growth_length_m;
  out["branch_angle_deg"] = p.branch_angle_deg;
  out["angle_variance_deg"] = p.angle_variance_deg;
  out["wiggle_prob"] = p.wiggle_probability;
  out["wiggle_deg"] = p.wiggle_variance_deg;
  nlohmann::ordered_json fragments = nlohmann::ordered_json::array();
  for (const fracture::Fragment& f : pattern.fragments) {
    nlohmann::ordered_json polygon = nlohmann::ordered_json::array();
    for (const fracture::Vec2& v : f.polygon_m)
      polygon.push_back({v.x(), v.y()});
    fragments.push_back({{"polygon", std::move(polygon)}, {"area", f.area_m2}});
  }
  out["fragments"] = std::move(fragments);
  return out;
}

// Fragments as filled polygons; SVG's y axis points down, so y is flipped.
std::string to_svg(const fracture::FracturePattern& pattern) {
  const double scale = 1000.0 / std::max(pattern.width_m, pattern.height_m);  // px per m
  std::string svg = text::printf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
      "viewBox=\"0 0 %.3f %.3f\">\n",
      pattern.width_m * scale, pattern.height_m * scale, pattern.width_m * scale,
      pattern.height_m * scale);
  for (std::size_t i = 0; i < pattern.fragments.size(); ++i) {
    // Golden-angle hues keep neighbours apart.
    const double hue = std::fmod(static_cast<double>(i) * 137.508, 360.0);
    svg += text::printf(
        "<polygon fill=\"hsl(%.0f,45%%,78%%)\" stroke=\"#223\" "
        "stroke-width=\"0.6\" points=\"",
        hue);
    for (const fracture::Vec2& v : pattern.fragments[i].polygon_m)
      svg += text::printf("%.2f,%.2f ", v.x() * scale, (pattern.height_m - v.y()) * scale);
    svg += "\"/>\n";
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace

int run_fracture(const Args& args, std::ostream& out) {
  const ParsedFlags flags("fracture", args,
                          {{"width"},
                           {"height"},
                           {"initial-crack"},
                           {"branch-angle-deg"},
                           {"angle-variance-deg"},
                           {"wiggle-prob"},
                           {"wiggle-deg"},
                           {"grid"},
                           {"growth-length"},
                           {"seed"},
                           {"output", true, "o"},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kHelp;
    return kExitOk;
  }
  const auto output = flags.value("output");
  if (!output) flags.fail("-o pattern.svg|pattern.json is required (see --help)");
  const std::string path(*output);
  const bool json = path.ends_with(".json");
  if (!json && !path.ends_with(".svg"))
    flags.fail("-o must end in .svg or .json, got '" + path + "'");
  const fracture::FractureParams params = parse(flags);
  const fracture::FracturePattern pattern = fracture::fracture(params);
  std::ofstream file(path, std::ios::binary);
  if (!file) flags.fail("cannot write '" + path + "'; check the directory exists");
  if (json) {
    file << to_json(params, pattern).dump() << "\n";
  } else {
    file << to_svg(pattern);
  }
  if (!file) throw std::runtime_error("writing '" + path + "' failed");
  out << text::printf("%zu fragments written to %s\n", pattern.fragments.size(), path.c_str());
  return kExitOk;
}

}  // namespace brisance::cli
