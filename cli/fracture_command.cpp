// `brisance fracture`: grow a crack pattern on a pane and write its fragments (thesis ch. 5.4).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/engine/pane_pattern.hpp"
#include "sim/fracture/fragments.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kHelp =
    "usage: brisance fracture --width W --height H [--thickness T]\n"
    "                         [--pressure-kpa P | --growth-length A_C] [--duration-ms D]\n"
    "                         [--impulse-kpa-ms I] [--charge-kg M --distance-m R]\n"
    "                         [--breakage dynamic|static] [--branch-angle-deg A]\n"
    "                         [--angle-variance-deg V] [--wiggle-prob P] [--wiggle-deg D]\n"
    "                         [--grid N] [--initial-crack L] [--seed S]\n"
    "                         -o pattern.svg|pattern.json\n"
    "\n"
    "Grows the crack pattern a job grows for a breakable pane and writes the fragments it cuts\n"
    "the pane into. Every default is the scene's 'fracture' default (annealed glass:\n"
    "radial cracks from the centre and rings, docs/fracture.md), so the same pane,\n"
    "pressure and seed give the job's pattern.\n"
    "  --width W, --height H    pane size in m (> 0)\n"
    "  --thickness T            pane thickness, m (default 0.006)\n"
    "  --pressure-kpa P         peak pressure on the pane, kPa (a job's fracture report gives "
    "it):\n"
    "                           the radial cracks follow from the pane's stress, the rings\n"
    "                           from the pressure;\n"
    "                           default: the pressure that just breaks the pane (coarsest "
    "pattern)\n"
    "  --duration-ms D          positive duration of the reflected pulse, ms: the dynamic plate\n"
    "                           model (fracture.breakage \"dynamic\", the default) needs the "
    "pulse,\n"
    "                           not only its peak ('brisance blast' gives all three numbers)\n"
    "  --impulse-kpa-ms I       its impulse, kPa ms: a Friedlander pulse fitted to it; without it\n"
    "                           a triangle of duration D. These pulses are not cleared: a job\n"
    "                           with simulation.clearing false loads its pane this way\n"
    "  --charge-kg M, --distance-m R\n"
    "                           instead of the pulse flags: M kg of TNT in the air R m in front\n"
    "                           of the pane (head-on), and the pane's front face loaded as a job\n"
    "                           loads it: the reflected Friedlander pulse cleared from the pane's\n"
    "                           edges (S = half its shorter side, C_D 1) over 3 S / U\n"
    "  --breakage MODEL         dynamic (default: large-deflection plate SDOF under the pulse) or\n"
    "                           static (Roark's small-deflection stress under the peak pressure)\n"
    "  --growth-length A_C      grow the thesis's crack tree with this growth between forks,\n"
    "                           m, instead (fracture.growth_length)\n"
    "  --branch-angle-deg A     angle between the two branches of a fork (default 25)\n"
    "  --angle-variance-deg V   forks open A +- V/2, uniform (default 34.5)\n"
    "  --wiggle-prob P          chance that a tip turns at each new piece, 0..1 (default 0.3)\n"
    "  --wiggle-deg D           a turn is uniform in +-D/2 degrees (default 30)\n"
    "  --grid N                 bit bucket cells along the longer side (default 2048; refined\n"
    "                           to 4 cells per growth length, up to 4096)\n"
    "  --initial-crack L        length of the initial cross at the centre, m (default: as a job,\n"
    "                           2 A_C, at most a quarter of the shorter side)\n"
    "  --seed S                 random seed, a non-negative integer (default 1; a job's pane uses\n"
    "                           fracture.seed, else one mixed from simulation.seed)\n"
    "  -o, --output FILE        .svg (a picture) or .json (fragment polygons in m)\n";

double flag_number(const ParsedFlags& flags, std::string_view name, double fallback) {
  const auto value = flags.number(name);
  return value ? *value : fallback;
}

struct Plan {
  double thickness_m = 0.006;
  double pressure_pa = 0.0;
  bool pressure_given = false;
  bool dynamic = true;  // the breakage model the stress came from
  engine::PanePattern pattern;
};

Plan parse(const ParsedFlags& flags) {
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  for (const char* required : {"width", "height"})
    if (!flags.has(required))
      flags.fail("--" + std::string(required) + " is required (see --help)");
  const double width = flag_number(flags, "width", 0.0);
  const double height = flag_number(flags, "height", 0.0);
  if (!(width > 0.0) || !(height > 0.0) || width > scene::kMaxPaneSide_m ||
      height > scene::kMaxPaneSide_m)
    flags.fail(
        text::printf("--width and --height must be greater than 0 m and at most %g m (a "
                     "pane), got %g x %g",
                     scene::kMaxPaneSide_m, width, height));
  Plan plan;
  plan.thickness_m = flag_number(flags, "thickness", plan.thickness_m);
  if (!(plan.thickness_m >= scene::kMinPaneThickness_m) ||
      plan.thickness_m > std::min(width, height))
    flags.fail(
        text::printf("--thickness must be at least %g m (0.1 mm) and at most the pane's "
                     "shorter side, got %g",
                     scene::kMinPaneThickness_m, plan.thickness_m));
  if (flags.has("pressure-kpa") && flags.has("growth-length"))
    flags.fail("give --pressure-kpa or --growth-length, not both");

  // The scene's defaults, with the flags given in their place.
  scene::FractureSpec spec;
  spec.trigger = scene::FractureSpec::Trigger::always;  // a preview always shows a pattern
  spec.branch_angle_deg = flag_number(flags, "branch-angle-deg", spec.branch_angle_deg);
  spec.angle_variance_deg = flag_number(flags, "angle-variance-deg", spec.angle_variance_deg);
  spec.wiggle_probability = flag_number(flags, "wiggle-prob", spec.wiggle_probability);
  spec.wiggle_variance_deg = flag_number(flags, "wiggle-deg", spec.wiggle_variance_deg);
  if (flags.has("growth-length")) {
    spec.growth_length_m = flag_number(flags, "growth-length", 0.0);
    if (!(*spec.growth_length_m > 0.0))
      flags.fail(
          text::printf("--growth-length must be greater than 0 m, got %g", *spec.growth_length_m));
  }
  const double grid = flag_number(flags, "grid", spec.grid);
  if (grid != static_cast<double>(static_cast<long>(grid)) || grid < 4 ||
      grid > fracture::FractureParams::kMaxGridCells)
    flags.fail(text::printf("--grid must be a whole number of cells from 4 to %d, got %g",
                            fracture::FractureParams::kMaxGridCells, grid));
  spec.grid = static_cast<int>(grid);
  if (const auto model = flags.value("breakage")) {
    if (*model == "static")
      spec.breakage = scene::FractureSpec::Breakage::static_plate;
    else if (*model != "dynamic")
      flags.fail("--breakage must be dynamic or static, got '" + std::string(*model) + "'");
  }
  // The reflected pulse: a triangle of --duration-ms, or the Friedlander pulse fitted to
  // --impulse-kpa-ms (what a job builds, blast::make_pulse with the same three numbers).
  std::optional<double> duration_s;
  if (flags.has("duration-ms")) {
    duration_s = 1e-3 * flag_number(flags, "duration-ms", 0.0);
    if (!(*duration_s > 0.0) || !std::isfinite(*duration_s) || *duration_s > 10.0)
      flags.fail(text::printf("--duration-ms must be greater than 0 and at most 10000, got %g",
                              *duration_s * 1e3));
  }
  std::optional<double> impulse_pa_s;
  if (flags.has("impulse-kpa-ms")) {
    impulse_pa_s = flag_number(flags, "impulse-kpa-ms", 0.0);  // kPa ms = Pa s
    if (!(*impulse_pa_s > 0.0) || !std::isfinite(*impulse_pa_s))
      flags.fail(text::printf("--impulse-kpa-ms must be greater than 0, got %g", *impulse_pa_s));
    if (!duration_s) flags.fail("--impulse-kpa-ms needs --duration-ms");
    if (!flags.has("pressure-kpa"))
      flags.fail("--impulse-kpa-ms needs --pressure-kpa (the pulse's peak)");
  }
  // A charge instead of a pulse: the job's cleared front-face history (pane_face_load).
  std::optional<blast::Charge> charge;
  double charge_distance_m = 0.0;
  if (flags.has("charge-kg") || flags.has("distance-m")) {
    if (!flags.has("charge-kg") || !flags.has("distance-m"))
      flags.fail("--charge-kg and --distance-m go together");
    for (const char* pulse_flag :
         {"pressure-kpa", "duration-ms", "impulse-kpa-ms", "growth-length"})
      if (flags.has(pulse_flag))
        flags.fail("give --charge-kg and --distance-m or --" + std::string(pulse_flag) +
                   ", not both");
    const double kg = flag_number(flags, "charge-kg", 0.0);
    charge_distance_m = flag_number(flags, "distance-m", 0.0);
    if (!(kg > 0.0) || !(kg <= 1e6))
      flags.fail(text::printf("--charge-kg must be greater than 0 and at most 1e6, got %g", kg));
    if (!(charge_distance_m > 0.0) || !(charge_distance_m <= 1e4))
      flags.fail(text::printf("--distance-m must be greater than 0 and at most 10000, got %g",
                              charge_distance_m));
    charge = blast::Charge{};
    charge->tnt_equivalent_kg = kg;
    charge->impulse_tnt_equivalent_kg = kg;
  }
  std::uint64_t seed = 1;
  if (const auto text = flags.value("seed")) {
    const char* end = text->data() + text->size();
    const auto [ptr, ec] = std::from_chars(text->data(), end, seed);
    if (ec != std::errc() || ptr != end)
      flags.fail("--seed must be a non-negative integer, got '" + std::string(*text) + "'");
  }
  if (flags.has("pressure-kpa")) {
    plan.pressure_pa = 1e3 * flag_number(flags, "pressure-kpa", 0.0);
    plan.pressure_given = true;
    if (!(plan.pressure_pa > 0.0) || !std::isfinite(plan.pressure_pa))
      flags.fail(
          text::printf("--pressure-kpa must be greater than 0, got %g", plan.pressure_pa / 1e3));
  }
  // The dynamic model needs the pulse, not only its peak; a given growth length needs no stress
  // (the one reported is then the static one). Reported after the other flags are checked.
  const bool missing_pulse = spec.breakage == scene::FractureSpec::Breakage::dynamic &&
                             !duration_s && !charge && !flags.has("growth-length");
  if (!duration_s && !charge) spec.breakage = scene::FractureSpec::Breakage::static_plate;
  plan.dynamic = spec.breakage == scene::FractureSpec::Breakage::dynamic;
  const auto load_at = [&](double peak_pa) {
    engine::PaneLoad load;
    load.peak_pressure_pa = peak_pa;
    if (duration_s)
      load.history.components.push_back(response::pulse_component(
          impulse_pa_s ? blast::make_pulse(blast::PulseShape::friedlander, peak_pa, *duration_s,
                                           *impulse_pa_s)
                       : blast::make_pulse(blast::PulseShape::triangle_same_period, peak_pa,
                                           *duration_s, 0.5 * peak_pa * *duration_s)));
    return load;
  };
  const engine::PaneSize pane{width, height, plan.thickness_m, 2500.0};  // annealed glass
  if (charge) {
    // The scene's defaults: Friedlander pulse, clearing on, C_D 1, the pane's own edges.
    blast::PanelLoadOptions options;
    options.clearing_distance_m = engine::pane_clearing_distance_m(pane);
    const engine::PaneFaceLoad face =
        engine::pane_face_load(*charge, charge_distance_m, 1.0, options);
    engine::PaneLoad load;
    load.peak_pressure_pa = face.peak_pressure_pa;
    if (face.component.history.size() > 0) {
      load.history.components.push_back(face.component);
      load.history.components.back().arrival_s = 0.0;  // the pane's clock, as a job's
    }
    plan.pressure_pa = load.peak_pressure_pa;
    plan.pressure_given = true;
    plan.pattern = engine::pane_pattern(spec, pane, load, seed);
  } else if (!plan.pressure_given) {
    scene::FractureSpec by_stress = spec;
    by_stress.trigger = scene::FractureSpec::Trigger::automatic;
    plan.pressure_pa = engine::breaking_pressure_pa(by_stress, pane, load_at(1e3));
  }
  if (!charge) plan.pattern = engine::pane_pattern(spec, pane, load_at(plan.pressure_pa), seed);
  fracture::FractureParams& p = plan.pattern.params;
  p.initial.length_m = flag_number(flags, "initial-crack", p.initial.length_m);
  if (const auto problem = fracture::validate(p)) flags.fail(*problem);
  if (missing_pulse)
    flags.fail(
        "--duration-ms is required with --breakage dynamic (the reflected pulse's positive "
        "duration; 'brisance blast' gives it), or use --breakage static");
  return plan;
}

nlohmann::ordered_json to_json(const Plan& plan, const fracture::FracturePattern& pattern) {
  const fracture::FractureParams& p = plan.pattern.params;
  nlohmann::ordered_json out;
  out["width"] = p.width_m;
  out["height"] = p.height_m;
  out["thickness"] = plan.thickness_m;
  out["pressure_kpa"] = plan.pressure_pa / 1e3;
  out["stress_mpa"] = plan.pattern.response.plate.stress_pa / 1e6;
  out["breakage"] = plan.dynamic ? "dynamic" : "static";
  out["seed"] = p.seed;
  out["grid"] = p.grid_x;
  out["initial_crack"] = p.initial.length_m;
  out["growth_length"] = p.growth_length_m;
  out["branch_angle_deg"] = p.branch_angle_deg;
  out["angle_variance_deg"] = p.angle_variance_deg;
  out["wiggle_prob"] = p.wiggle_probability;
  out["wiggle_deg"] = p.wiggle_variance_deg;
  using Kind = fracture::FractureParams::Kind;
  out["pattern"] = p.kind == Kind::radial_ring ? "radial_ring"
                   : p.kind == Kind::dice      ? "dice"
                                               : "crack_tree";
  if (p.kind == Kind::radial_ring) {
    out["radial_cracks"] = p.radial.count;
    out["ring_radii"] = p.radial.ring_radii_m;
  } else if (p.kind == Kind::dice) {
    out["dice_cell"] = p.dice_cell_m;
  }
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
                           {"thickness"},
                           {"pressure-kpa"},
                           {"duration-ms"},
                           {"impulse-kpa-ms"},
                           {"charge-kg"},
                           {"distance-m"},
                           {"breakage"},
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
  const Plan plan = parse(flags);
  const fracture::FracturePattern pattern = fracture::fracture(plan.pattern.params);
  std::ofstream file(path, std::ios::binary);
  if (!file) flags.fail("cannot write '" + path + "'; check the directory exists");
  if (json) {
    file << to_json(plan, pattern).dump() << "\n";
  } else {
    file << to_svg(pattern);
  }
  if (!file) throw std::runtime_error("writing '" + path + "' failed");
  using Kind = fracture::FractureParams::Kind;
  const fracture::FractureParams& p = plan.pattern.params;
  std::string what;
  if (p.kind == Kind::radial_ring)
    what =
        text::printf("%d radial cracks%s, %zu rings", p.radial.count,
                     plan.pattern.radial_capped ? " (capped)" : "", p.radial.ring_radii_m.size());
  else if (p.kind == Kind::dice)
    what = text::printf("tempered dice %.3g mm", p.dice_cell_m * 1e3);
  else
    what = text::printf("growth length %.3g m%s", plan.pattern.growth_length_m,
                        plan.pattern.growth_length_given     ? ", given"
                        : plan.pattern.growth_length_clamped ? ", clamped"
                                                             : "");
  out << text::printf("%zu fragments written to %s (%s; stress %.3g MPa at %.4g kPa%s)\n",
                      pattern.fragments.size(), path.c_str(), what.c_str(),
                      plan.pattern.response.plate.stress_pa / 1e6, plan.pressure_pa / 1e3,
                      plan.pressure_given ? "" : ", the pressure that just breaks it");
  return kExitOk;
}

}  // namespace brisance::cli
