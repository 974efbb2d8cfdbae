// `brisance response` and `brisance pi`: the structural-response calculators (issue 16) on the
// command line — an element's SDOF response to a charge or a pulse, and its P–I curve.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/io/response_json.hpp"
#include "sim/response/limits.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kResponseHelp =
    "usage: brisance response --element ELEMENT.json\n"
    "                         (--charge-kg M --distance-m R [--angle-deg A] [--explosive NAME |\n"
    "                          --tnt-factor F] [--burst air|surface] [--surface-model S]\n"
    "                         | --pulse-peak-kpa P --pulse-duration-ms T\n"
    "                          [--pulse-shape triangular|friedlander] [--pulse-impulse-kpa-ms I])\n"
    "                         [--json] [--history-csv FILE]\n"
    "\n"
    "Peak response of a structural element (a lumped-mass SDOF, docs/response.md) to a blast.\n"
    "  --element FILE          the element as JSON (scenes/elements/ has examples)\n"
    "  --charge-kg M, --distance-m R, --angle-deg A, --explosive, --tnt-factor, --burst,\n"
    "  --surface-model         a charge, as for 'brisance blast': the element is loaded by the\n"
    "                          reflected Friedlander pulse at angle A (default 0, head-on)\n"
    "  --pulse-peak-kpa P      or a pulse of peak P kPa (> 0)\n"
    "  --pulse-duration-ms T   and duration T ms (> 0)\n"
    "  --pulse-shape S         triangular (default) or friedlander\n"
    "  --pulse-impulse-kpa-ms I  friedlander only: fit the decay to this impulse (default decay\n"
    "                          coefficient 1)\n"
    "  --json                  one JSON object (the fields of POST /v1/response, no history)\n"
    "  --history-csv FILE      also write the history: time_ms, displacement_m, velocity_m_s,\n"
    "                          resistance_kn\n";

constexpr std::string_view kPiHelp =
    "usage: brisance pi --element ELEMENT.json [--ductility MU | --rotation-deg T]\n"
    "                   [--points N] [--diagram pi|wr] [--min-distance-m A] [--max-distance-m B]\n"
    "                   [--burst air|surface] [--angle-deg A] [-o FILE.svg|FILE.json]\n"
    "\n"
    "Pressure-impulse (P-I) curve of an element for one damage limit: for each of N triangular\n"
    "pulse durations (t_d/T from 0.01 to 100), the peak pressure that just reaches the limit.\n"
    "With --diagram wr, the charge weight-stand-off (W-R) diagram of the same limit instead: for\n"
    "each of N stand-offs log-spaced from A to B m (default 1 to 100), the TNT charge whose\n"
    "reflected Friedlander pulse (at --angle-deg to the normal, default 0) just reaches it.\n"
    "  --element FILE      the element as JSON (scenes/elements/ has examples)\n"
    "  --ductility MU      limit as a ductility ratio, 0 < MU <= 100 (default 1: first yield;\n"
    "                      not for an elastic element)\n"
    "  --rotation-deg T    or as a support rotation, 0 < T <= 45 (needs support.span_m)\n"
    "  --points N          durations in the sweep, 2..100 (default 60)\n"
    "  --diagram D         pi (default) or wr\n"
    "  --min-distance-m A, --max-distance-m B  wr: the stand-offs, 0.1 <= A < B <= 10000\n"
    "  --burst B           wr: air (default) or surface\n"
    "  --angle-deg A       wr: angle of the wave to the element's normal, [0, 90)\n"
    "  -o FILE             write the curve as SVG (log-log; P-I with both asymptotes) or JSON\n"
    "                      (the fields of POST /v1/pi); without -o, print a table\n";

// The charge flags of `brisance response`, spelled as the blast calculator's parameters.
constexpr std::string_view kChargeFlags[] = {
    "charge-kg", "distance-m", "angle-deg", "explosive", "tnt-factor", "surface-model", "burst"};
constexpr std::string_view kPulseFlags[] = {"pulse-peak-kpa", "pulse-duration-ms", "pulse-shape",
                                            "pulse-impulse-kpa-ms"};

std::string dashed(std::string_view name) {
  std::string flag(name);
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

// Every problem at once, on the one line of a usage error (exit code 2).
[[noreturn]] void fail_all(const ParsedFlags& flags, const std::vector<std::string>& messages) {
  std::string message = messages.front();
  for (std::size_t i = 1; i < messages.size(); ++i)
    message += "; " + messages[i];
  flags.fail(message);
}

response::Element load_element(const ParsedFlags& flags) {
  const auto path = flags.value("element");
  if (!path) flags.fail("--element ELEMENT.json is required (see --help)");
  std::ifstream file{std::string(*path), std::ios::binary};
  if (!file) flags.fail("cannot read '" + std::string(*path) + "'");
  std::stringstream text;
  text << file.rdbuf();
  const nlohmann::json json = nlohmann::json::parse(text.str(), nullptr, false);
  if (json.is_discarded()) flags.fail(std::string(*path) + ": not valid JSON");
  const response::ElementParse parsed = response::parse_element(json);
  if (parsed.element) return *parsed.element;
  std::vector<std::string> messages;
  for (const response::FieldError& e : parsed.errors)
    messages.push_back(std::string(*path) + ": " + e.text());
  fail_all(flags, messages);
}

void print_response(std::ostream& out, const nlohmann::ordered_json& r) {
  using text::printf;
  const auto& load = r["load"];
  out << printf("SDOF response (docs/response.md)\n");
  out << printf("  load                 %s, peak %.4g kPa, impulse %.4g kPa*ms, duration %.4g ms",
                load["shape"].get<std::string>().c_str(), load["peak_pressure_kpa"].get<double>(),
                load["impulse_kpa_ms"].get<double>(), load["duration_ms"].get<double>());
  if (load["arrival_time_ms"].get<double>() > 0.0)
    out << printf(", arrival %.4g ms", load["arrival_time_ms"].get<double>());
  out << "\n";
  if (!load["in_validity_range"].get<bool>())
    out << "                       (outside the blast curves' validity range)\n";
  out << printf("  natural period    T  %.4g ms\n", r["natural_period_ms"].get<double>());
  out << printf("  peak displacement    %.4g mm at %.4g ms\n",
                r["peak_displacement_m"].get<double>() * 1e3, r["time_to_peak_ms"].get<double>());
  if (!r["elastic_limit_m"].is_null())
    out << printf("  elastic limit        %.4g mm\n", r["elastic_limit_m"].get<double>() * 1e3);
  if (!r["ductility"].is_null())
    out << printf("  ductility         mu %.4g\n", r["ductility"].get<double>());
  if (!r["support_rotation_deg"].is_null())
    out << printf("  support rotation  th %.4g deg\n", r["support_rotation_deg"].get<double>());
  out << printf("  permanent set        %.4g mm\n", r["permanent_set_m"].get<double>() * 1e3);
  out << printf("  largest rebound      %.4g mm\n", r["min_displacement_m"].get<double>() * 1e3);
  if (!r["damage"].is_null()) {
    const auto limits = response::find_limits(r["limits"].get<std::string>());
    out << printf("  damage               %s (%s, %.*s)\n", r["damage"].get<std::string>().c_str(),
                  r["limits"].get<std::string>().c_str(),
                  static_cast<int>(limits ? limits->source.size() : 0),
                  limits ? limits->source.data() : "");
  } else {
    out << "  damage               (no \"limits\" in the element)\n";
  }
  if (r["warnings"].get<std::size_t>() > 0)
    out << printf("  WARNING: %zu solver warnings; the result may be partial\n",
                  r["warnings"].get<std::size_t>());
}

void write_history_csv(const ParsedFlags& flags, const std::string& path,
                       const nlohmann::ordered_json& history) {
  std::ofstream file(path, std::ios::binary);
  if (!file) flags.fail("cannot write '" + path + "'; check the directory exists");
  file << "time_ms,displacement_m,velocity_m_s,resistance_kn\n";
  const auto& t = history["time_ms"];
  for (std::size_t i = 0; i < t.size(); ++i) {
    file << text::printf(
        "%.9g,%.9g,%.9g,%.9g\n", t[i].get<double>(), history["displacement_m"][i].get<double>(),
        history["velocity_m_s"][i].get<double>(), history["resistance_kn"][i].get<double>());
  }
  if (!file) throw std::runtime_error("writing '" + path + "' failed");
}

// A log-log P–I plot: impulse (kPa*ms) across, peak pressure (kPa) up, the curve and both
// asymptotes dashed.
std::string pi_svg(const nlohmann::ordered_json& pi) {
  constexpr double kWidth = 640, kHeight = 480, kLeft = 80, kRight = 20, kTop = 30, kBottom = 60;
  const double i0 = pi["impulsive_asymptote_kpa_ms"].get<double>();
  const double p0 = pi["quasi_static_asymptote_kpa"].get<double>();
  double imin = i0, imax = i0, pmin = p0, pmax = p0;
  for (const auto& p : pi["points"]) {
    imin = std::min(imin, p["impulse_kpa_ms"].get<double>());
    imax = std::max(imax, p["impulse_kpa_ms"].get<double>());
    pmin = std::min(pmin, p["peak_pressure_kpa"].get<double>());
    pmax = std::max(pmax, p["peak_pressure_kpa"].get<double>());
  }
  const double lx0 = std::floor(std::log10(imin)), lx1 = std::ceil(std::log10(imax) + 1e-9);
  const double ly0 = std::floor(std::log10(pmin)), ly1 = std::ceil(std::log10(pmax) + 1e-9);
  const auto x = [&](double v) {
    return kLeft + (std::log10(v) - lx0) / (lx1 - lx0) * (kWidth - kLeft - kRight);
  };
  const auto y = [&](double v) {
    return kHeight - kBottom - (std::log10(v) - ly0) / (ly1 - ly0) * (kHeight - kTop - kBottom);
  };
  using text::printf;
  std::string s = printf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" "
      "fill=\"white\"/>\n",
      kWidth, kHeight);
  for (double d = lx0; d <= lx1; d += 1.0) {
    const double v = std::pow(10.0, d);
    s += printf("<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>", x(v), kTop,
                x(v), kHeight - kBottom);
    s += printf("<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n", x(v),
                kHeight - kBottom + 16, v);
  }
  for (double d = ly0; d <= ly1; d += 1.0) {
    const double v = std::pow(10.0, d);
    s += printf("<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>", kLeft, y(v),
                kWidth - kRight, y(v));
    s +=
        printf("<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", kLeft - 6, y(v) + 4, v);
  }
  s += printf("<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">impulse, kPa*ms</text>\n",
              (kLeft + kWidth - kRight) / 2, kHeight - 20);
  s += printf(
      "<text x=\"16\" y=\"%g\" text-anchor=\"middle\" transform=\"rotate(-90 16 %g)\">peak "
      "pressure, kPa</text>\n",
      (kTop + kHeight - kBottom) / 2, (kTop + kHeight - kBottom) / 2);
  s += printf(
      "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#888\" "
      "stroke-dasharray=\"6 4\"/>\n",
      x(i0), kTop, x(i0), kHeight - kBottom);
  s += printf(
      "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#888\" "
      "stroke-dasharray=\"6 4\"/>\n",
      kLeft, y(p0), kWidth - kRight, y(p0));
  s += "<polyline fill=\"none\" stroke=\"#c0392b\" stroke-width=\"2\" points=\"";
  for (const auto& p : pi["points"])
    s += printf("%.1f,%.1f ", x(p["impulse_kpa_ms"].get<double>()),
                y(p["peak_pressure_kpa"].get<double>()));
  s += "\"/>\n";
  s += printf("<text x=\"%g\" y=\"%g\">P-I curve, displacement limit %.4g mm</text>\n", kLeft,
              kTop - 10, pi["displacement_limit_m"].get<double>() * 1e3);
  s += "</svg>\n";
  return s;
}

}  // namespace

int run_response(const Args& args, std::ostream& out) {
  const ParsedFlags flags("response", args,
                          {{"element"},
                           {"charge-kg"},
                           {"distance-m"},
                           {"angle-deg"},
                           {"explosive"},
                           {"tnt-factor"},
                           {"burst"},
                           {"surface-model"},
                           {"pulse-peak-kpa"},
                           {"pulse-duration-ms"},
                           {"pulse-shape"},
                           {"pulse-impulse-kpa-ms"},
                           {"json", false},
                           {"history-csv"},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kResponseHelp;
    return kExitOk;
  }
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  bool charge = false, pulse = false;
  for (std::string_view f : kChargeFlags)
    charge = charge || flags.has(f);
  for (std::string_view f : kPulseFlags)
    pulse = pulse || flags.has(f);
  if (charge && pulse)
    flags.fail(
        "give a charge (--charge-kg, --distance-m) or a pulse (--pulse-peak-kpa, "
        "--pulse-duration-ms), not both");
  if (!charge && !pulse)
    flags.fail(
        "give the load: --charge-kg M --distance-m R, or --pulse-peak-kpa P "
        "--pulse-duration-ms T (see --help)");
  const response::Element element = load_element(flags);

  io::LoadQuery query;
  std::vector<io::BlastQueryError> problems;
  std::string cost_flag;
  if (charge) {
    const auto lookup = [&](std::string_view name) -> std::optional<std::string> {
      const auto value = flags.value(dashed(name));
      if (!value) return std::nullopt;
      return std::string(*value);
    };
    const auto spell = [](std::string_view name) { return "--" + dashed(name); };
    io::BlastQuery blast;
    problems = io::parse_blast_query(lookup, spell, blast);
    query.charge = blast;
    cost_flag = "--distance-m";
  } else {
    const auto lookup = [&](std::string_view name) -> std::optional<std::string> {
      const auto value = flags.value("pulse-" + dashed(name));
      if (!value) return std::nullopt;
      return std::string(*value);
    };
    const auto spell = [](std::string_view name) { return "--pulse-" + dashed(name); };
    io::PulseQuery p;
    io::parse_pulse_query(lookup, spell, p, problems);
    query.pulse = p;
    cost_flag = "--pulse-duration-ms";
  }
  if (!problems.empty()) {
    std::vector<std::string> messages;
    for (const auto& p : problems)
      messages.push_back(p.message);
    fail_all(flags, messages);
  }
  const io::LoadAnswer load = io::build_load(query);
  if (const auto cost =
          io::check_load_cost(response::equivalent_system(element), load, cost_flag)) {
    flags.fail(cost->pointer + " " + cost->message);
  }
  const auto csv = flags.value("history-csv");
  const nlohmann::ordered_json result = io::response_json(element, load, csv.has_value());
  if (csv) write_history_csv(flags, std::string(*csv), result["history"]);
  if (flags.has("json")) {
    nlohmann::ordered_json shown = result;
    shown.erase("history");
    out << shown.dump(2) << "\n";
  } else {
    print_response(out, result);
  }
  return kExitOk;
}

// The W–R diagram, log-log: charge (kg) up against stand-off (m) across.
std::string wr_svg(const nlohmann::ordered_json& wr) {
  std::vector<std::pair<double, double>> xy;
  for (const auto& p : wr["points"])
    if (!p["charge_kg"].is_null())
      xy.emplace_back(p["distance_m"].get<double>(), p["charge_kg"].get<double>());
  constexpr double kW = 640, kH = 440, kLeft = 70, kRight = 20, kTop = 30, kBottom = 50;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& [x, y] : xy) {
    x0 = std::min(x0, std::log10(x)), x1 = std::max(x1, std::log10(x));
    y0 = std::min(y0, std::log10(y)), y1 = std::max(y1, std::log10(y));
  }
  if (xy.empty()) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1);
  y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
  const auto px = [&](double x) {
    return kLeft + (std::log10(x) - x0) / (x1 - x0) * (kW - kLeft - kRight);
  };
  const auto py = [&](double y) {
    return kH - kBottom - (std::log10(y) - y0) / (y1 - y0) * (kH - kTop - kBottom);
  };
  std::string svg = text::printf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
      "viewBox=\"0 0 %g %g\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
      kW, kH, kW, kH);
  for (double d = x0; d <= x1; d += 1)
    svg += text::printf("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">1e%g</text>\n",
                        px(std::pow(10.0, d)), kH - kBottom + 18, d);
  for (double d = y0; d <= y1; d += 1)
    svg += text::printf("<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">1e%g</text>\n", kLeft - 6,
                        py(std::pow(10.0, d)) + 4, d);
  svg += text::printf(
      "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">stand-off, m</text>\n"
      "<text x=\"14\" y=\"%.1f\" transform=\"rotate(-90 14 %.1f)\" "
      "text-anchor=\"middle\">TNT charge, kg</text>\n",
      0.5 * (kLeft + kW - kRight), kH - 12, 0.5 * (kTop + kH - kBottom),
      0.5 * (kTop + kH - kBottom));
  svg += text::printf("<text x=\"%.1f\" y=\"%.1f\">W-R, displacement limit %.4g mm</text>\n", kLeft,
                      kTop - 10, wr["displacement_limit_m"].get<double>() * 1e3);
  std::string points;
  for (const auto& [x, y] : xy)
    points += text::printf("%.2f,%.2f ", px(x), py(y));
  svg += "<polyline fill=\"none\" stroke=\"black\" stroke-width=\"2\" points=\"" + points +
         "\"/>\n</svg>\n";
  return svg;
}

void print_wr(std::ostream& out, const nlohmann::ordered_json& wr) {
  using text::printf;
  out << printf("W-R diagram, displacement limit %.4g mm",
                wr["displacement_limit_m"].get<double>() * 1e3);
  if (!wr["ductility"].is_null()) out << printf(", ductility %.4g", wr["ductility"].get<double>());
  if (!wr["rotation_deg"].is_null())
    out << printf(", rotation %.4g deg", wr["rotation_deg"].get<double>());
  out << printf("\n  %s burst, angle %.4g deg, natural period T %.4g ms\n",
                wr["burst"].get<std::string>().c_str(), wr["angle_deg"].get<double>(),
                wr["natural_period_ms"].get<double>());
  out << "  distance_m    charge_kg   scaled_distance   in_range\n";
  for (const auto& p : wr["points"]) {
    if (p["charge_kg"].is_null()) {
      out << printf("  %10.4g   %10s\n", p["distance_m"].get<double>(), "none");
      continue;
    }
    out << printf("  %10.4g   %10.4g   %15.4g   %s\n", p["distance_m"].get<double>(),
                  p["charge_kg"].get<double>(), p["scaled_distance_m_kg13"].get<double>(),
                  p["in_validity_range"].get<bool>() ? "yes" : "no");
  }
  if (wr["warnings"].get<std::size_t>() > 0)
    out << printf(
        "  WARNING: %zu stand-offs with no charge from 1 g to 1000 t reaching the limit\n",
        wr["warnings"].get<std::size_t>());
}

// `brisance pi --diagram wr`: the flags as a POST /v1/pi body, checked by the same reader, so
// every problem is reported at once under its flag's name.
int run_wr(const ParsedFlags& flags, const std::optional<std::string>& output, std::ostream& out) {
  const response::Element element = load_element(flags);
  // The element came from the file: the body has none, and the reader's complaint about its
  // absence is dropped below.
  nlohmann::json body;
  body["diagram"] = "wr";
  std::vector<std::string> messages;
  const auto number = [&](std::string_view flag, const char* key) {
    if (!flags.has(flag)) return;
    if (const auto v = flags.number(flag)) body[key] = *v;
  };
  number("ductility", "ductility");
  number("rotation-deg", "rotation_deg");
  number("points", "points");
  number("angle-deg", "angle_deg");
  if (const auto b = flags.value("burst")) body["burst"] = std::string(*b);
  if (flags.has("min-distance-m") || flags.has("max-distance-m"))
    body["distances_m"] = {flags.number("min-distance-m").value_or(1.0),
                           flags.number("max-distance-m").value_or(100.0)};
  io::PiRequest request;
  std::vector<io::InputError> errors = io::parse_pi_request(body, request);
  std::erase_if(errors, [](const io::InputError& e) { return e.pointer.starts_with("/element"); });
  const auto flag_name = [](const std::string& pointer) -> std::string {
    if (pointer == "/distances_m") return "--min-distance-m/--max-distance-m";
    if (pointer == "/rotation_deg") return "--rotation-deg";
    if (pointer == "/angle_deg") return "--angle-deg";
    return "--" + pointer.substr(1);
  };
  request.element = element;
  if (errors.empty()) {
    // The limit against the element itself (the body had none).
    io::PiLimit limit;
    limit.ductility = flags.number("ductility");
    limit.rotation_deg = flags.number("rotation-deg");
    if (const auto y =
            io::pi_displacement_limit(element, limit, "--ductility", "--rotation-deg", errors)) {
      request.displacement_limit_m = *y;
      if (const auto cost = io::check_wr_cost(response::equivalent_system(element),
                                              request.wr_query, "/distances_m"))
        errors.push_back(*cost);
    }
    for (io::InputError& e : errors)
      if (e.pointer.starts_with("/")) e.pointer = flag_name(e.pointer);
  } else {
    for (io::InputError& e : errors)
      e.pointer = flag_name(e.pointer);
  }
  for (const io::InputError& e : errors)
    messages.push_back(e.pointer + " " + e.message);
  if (!messages.empty()) fail_all(flags, messages);
  const nlohmann::ordered_json wr =
      io::wr_json(element, request.displacement_limit_m, request.points, request.wr_query);
  if (output) {
    std::ofstream file(*output, std::ios::binary);
    if (!file) flags.fail("cannot write '" + *output + "'; check the directory exists");
    if (output->ends_with(".json")) {
      file << wr.dump(1) << "\n";
    } else {
      file << wr_svg(wr);
    }
    if (!file) throw std::runtime_error("writing '" + *output + "' failed");
    out << text::printf("W-R diagram of %zu points written to %s\n", wr["points"].size(),
                        output->c_str());
    return kExitOk;
  }
  print_wr(out, wr);
  return kExitOk;
}

int run_pi(const Args& args, std::ostream& out) {
  const ParsedFlags flags("pi", args,
                          {{"element"},
                           {"ductility"},
                           {"rotation-deg"},
                           {"points"},
                           {"diagram"},
                           {"min-distance-m"},
                           {"max-distance-m"},
                           {"burst"},
                           {"angle-deg"},
                           {"output", true, "o"},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kPiHelp;
    return kExitOk;
  }
  const auto diagram = flags.value("diagram");
  if (diagram && *diagram != "pi" && *diagram != "wr")
    flags.fail("--diagram must be pi or wr, got '" + std::string(*diagram) + "'");
  const bool wr = diagram && *diagram == "wr";
  if (!wr) {
    for (const char* f : {"min-distance-m", "max-distance-m", "burst", "angle-deg"})
      if (flags.has(f)) flags.fail("--" + std::string(f) + " is for --diagram wr only");
  }
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  std::optional<std::string> output;
  if (const auto o = flags.value("output")) {
    output = std::string(*o);
    if (!output->ends_with(".svg") && !output->ends_with(".json"))
      flags.fail("-o must end in .svg or .json, got '" + *output + "'");
  }
  if (wr) return run_wr(flags, output, out);  // checks its flags all at once
  std::size_t points = 60;
  if (const auto n = flags.number("points")) {
    if (!(*n >= io::kMinPiPoints && *n <= io::kMaxPiPoints && std::floor(*n) == *n))
      flags.fail(text::printf("--points must be a whole number from %zu to %zu", io::kMinPiPoints,
                              io::kMaxPiPoints));
    points = static_cast<std::size_t>(*n);
  }
  io::PiLimit limit;
  limit.ductility = flags.number("ductility");
  limit.rotation_deg = flags.number("rotation-deg");
  const response::Element element = load_element(flags);
  std::vector<io::InputError> errors;
  const auto y = io::pi_displacement_limit(element, limit, "--ductility", "--rotation-deg", errors);
  if (!y) flags.fail(errors.front().pointer + " " + errors.front().message);
  const nlohmann::ordered_json pi = io::pi_json(element, *y, points);
  if (output) {
    std::ofstream file(*output, std::ios::binary);
    if (!file) flags.fail("cannot write '" + *output + "'; check the directory exists");
    if (output->ends_with(".json")) {
      file << pi.dump(1) << "\n";
    } else {
      file << pi_svg(pi);
    }
    if (!file) throw std::runtime_error("writing '" + *output + "' failed");
    out << text::printf("P-I curve of %zu points written to %s\n", pi["points"].size(),
                        output->c_str());
    return kExitOk;
  }
  using text::printf;
  out << printf("P-I curve, displacement limit %.4g mm",
                pi["displacement_limit_m"].get<double>() * 1e3);
  if (!pi["ductility"].is_null()) out << printf(", ductility %.4g", pi["ductility"].get<double>());
  if (!pi["rotation_deg"].is_null())
    out << printf(", rotation %.4g deg", pi["rotation_deg"].get<double>());
  out << printf("\n  natural period T %.4g ms\n", pi["natural_period_ms"].get<double>());
  out << printf("  impulsive asymptote    %.4g kPa*ms\n",
                pi["impulsive_asymptote_kpa_ms"].get<double>());
  out << printf("  quasi-static asymptote %.4g kPa\n",
                pi["quasi_static_asymptote_kpa"].get<double>());
  out << "  duration_ms   peak_pressure_kpa   impulse_kpa_ms\n";
  for (const auto& p : pi["points"])
    out << printf("  %11.4g   %17.4g   %14.4g\n", p["duration_ms"].get<double>(),
                  p["peak_pressure_kpa"].get<double>(), p["impulse_kpa_ms"].get<double>());
  if (pi["warnings"].get<std::size_t>() > 0)
    out << printf("  WARNING: %zu durations could not be bracketed\n",
                  pi["warnings"].get<std::size_t>());
  return kExitOk;
}

}  // namespace brisance::cli
