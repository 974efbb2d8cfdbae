// `brisance blast`: the blast calculator on the command line.
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/blast/explosives.hpp"
#include "sim/io/blast_json.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kHelp =
    "usage: brisance blast --charge-kg M --distance-m R\n"
    "                      [--explosive NAME | --tnt-factor F [--impulse-tnt-factor G]]\n"
    "                      [--burst air|surface] [--surface-model hemispherical|factor_1_8]\n"
    "                      [--angle-deg A] [--json] [--pulse-csv FILE]\n"
    "\n"
    "Blast-wave parameters of a charge at a distance, from the Kingery-Bulmash curves.\n"
    "  --charge-kg M       charge mass in kg (> 0)\n"
    "  --distance-m R      distance from the charge centre in m (> 0)\n"
    "  --explosive NAME    explosive (default TNT); 'brisance blast --list-explosives' lists them\n"
    "  --tnt-factor F      custom TNT equivalence factor instead of a named explosive (> 0)\n"
    "  --impulse-tnt-factor G\n"
    "                      with --tnt-factor: a separate equivalence for impulses (UFC 3-340-02\n"
    "                      eq. 2-5; default F); named explosives bring their own\n"
    "  --burst air|surface free-air spherical (default) or surface (hemispherical) burst\n"
    "  --surface-model M   surface bursts: hemispherical curves (default) or factor_1_8\n"
    "                      (free-air curves with 1.8 x the charge)\n"
    "  --angle-deg A       angle of incidence for the reflected values, 0 (head-on) to 90\n"
    "  --json              one JSON object instead of the table (with the pulses and the inputs)\n"
    "  --pulse-csv FILE    also write the incident and reflected pressure-time pulses as CSV:\n"
    "                      time_ms since detonation, incident_kpa (Friedlander positive phase,\n"
    "                      then the cubic negative phase), reflected_kpa (positive phase only);\n"
    "                      200 rows from arrival to the end of the negative phase\n";

constexpr std::size_t kPulseCsvSamples = 200;

struct BlastRequest {
  io::BlastQuery query;
  bool json = false;
  std::optional<std::string> pulse_csv;
};

// The calculator's parameters are spelled with dashes on the command line (--charge-kg).
std::string dashed(std::string_view name) {
  std::string flag(name);
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

BlastRequest parse(const ParsedFlags& flags) {
  BlastRequest request;
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  const auto lookup = [&](std::string_view name) -> std::optional<std::string> {
    const auto value = flags.value(dashed(name));
    if (!value) return std::nullopt;
    return std::string(*value);
  };
  const auto spell = [](std::string_view name) { return "--" + dashed(name); };
  const auto problems = io::parse_blast_query(lookup, spell, request.query);
  if (!problems.empty()) {
    // Every bad flag at once, on the one line of a usage error.
    std::string message = problems.front().message;
    for (std::size_t i = 1; i < problems.size(); ++i)
      message += "; " + problems[i].message;
    flags.fail(message);
  }
  request.json = flags.has("json");
  if (const auto csv = flags.value("pulse-csv")) request.pulse_csv = std::string(*csv);
  return request;
}

void print_table(std::ostream& out, const io::BlastQuery& request, const io::BlastAnswer& answer) {
  const blast::BlastPoint& point = answer.point;
  const blast::ObliqueReflection& reflection = answer.reflection;
  const blast::NegativePhase& negative = answer.negative_phase;
  const bool surface = request.charge.burst == blast::Burst::surface;
  const char* model = !surface ? "free-air spherical burst"
                      : request.charge.surface_model == blast::SurfaceBurstModel::hemispherical
                          ? "hemispherical surface burst"
                          : "surface burst, free-air curves x 1.8";
  using text::printf;
  out << printf("Blast parameters, Kingery-Bulmash, %s\n", model);
  out << printf("  charge                     %g kg %s (TNT factor %.3f)\n", request.charge_kg,
                request.explosive_name.c_str(), request.tnt_factor);
  out << printf("  TNT equivalent         W   %.4g kg\n", point.tnt_equivalent_kg);
  if (point.impulse_tnt_equivalent_kg != point.tnt_equivalent_kg)
    out << printf("  ... for impulses       Wi  %.4g kg (impulse factor %.3f)\n",
                  point.impulse_tnt_equivalent_kg, request.impulse_tnt_factor);
  out << printf("  distance               R   %g m\n", request.distance_m);
  out << printf("  scaled distance        Z   %.4g m/kg^(1/3)\n", point.scaled_distance_m_kg13);
  out << printf("  incident overpressure  Pso %.4g kPa\n", point.incident_overpressure_pa * 1e-3);
  out << printf("  incident impulse       is  %.4g kPa*ms\n", point.incident_impulse_pa_s);
  out << printf("  arrival time           ta  %.4g ms\n", point.arrival_time_s * 1e3);
  out << printf("  positive duration      to  %.4g ms\n", point.positive_duration_s * 1e3);
  out << printf("  shock front velocity   U   %.4g m/s\n", point.shock_velocity_m_s);
  out << printf("  dynamic pressure       qs  %.4g kPa\n", point.dynamic_pressure_pa * 1e-3);
  out << printf("  reflected overpressure Pr  %.4g kPa   at %g deg incidence\n",
                reflection.overpressure_pa * 1e-3, request.angle_deg);
  out << printf("  reflected impulse      ir  %.4g kPa*ms\n", reflection.impulse_pa_s);
  out << printf("  reflection coefficient Cr  %.4g\n", reflection.coefficient);
  out << printf("  negative phase: peak underpressure %.4g kPa, impulse %.4g kPa*ms, %.4g ms\n",
                negative.underpressure_pa * 1e-3, negative.impulse_pa_s, negative.duration_s * 1e3);
  if (point.in_validity_range && reflection.in_chart_range && negative.in_validity_range) {
    out << "  in validity range          yes\n";
  } else {
    out << "  in validity range          NO: outside the fitted range, values are continued\n"
           "                             (clamped near the charge, 1/Z decay far away)\n";
  }
}

}  // namespace

int run_blast(const Args& args, std::ostream& out) {
  const ParsedFlags flags("blast", args,
                          {{"charge-kg"},
                           {"distance-m"},
                           {"explosive"},
                           {"tnt-factor"},
                           {"impulse-tnt-factor"},
                           {"burst"},
                           {"surface-model"},
                           {"angle-deg"},
                           {"json", false},
                           {"pulse-csv"},
                           {"list-explosives", false},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kHelp;
    return kExitOk;
  }
  if (flags.has("list-explosives")) {
    for (const blast::Explosive& explosive : blast::known_explosives())
      out << text::printf("%-20.*s %6.3f %6.3f  %-9.*s %.*s\n",
                          static_cast<int>(explosive.name.size()), explosive.name.data(),
                          explosive.tnt_factor, explosive.impulse_factor(),
                          static_cast<int>(explosive.basis.size()), explosive.basis.data(),
                          static_cast<int>(explosive.source.size()), explosive.source.data());
    return kExitOk;
  }
  const BlastRequest request = parse(flags);
  const io::BlastAnswer answer = io::calculate_blast(request.query);
  if (request.pulse_csv) {
    std::ofstream file(*request.pulse_csv, std::ios::binary);
    if (!file) flags.fail("cannot write '" + *request.pulse_csv + "'; check the directory exists");
    file << io::blast_pulse_csv(answer, kPulseCsvSamples);
    if (!file) throw std::runtime_error("writing '" + *request.pulse_csv + "' failed");
  }
  if (request.json) {
    out << io::blast_answer_json(request.query, answer).dump(2) << "\n";
  } else {
    print_table(out, request.query, answer);
  }
  return kExitOk;
}

}  // namespace brisance::cli
