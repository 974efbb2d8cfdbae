// `brisance blast`: the blast calculator on the command line.
#include <cmath>
#include <numbers>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/blast/blast_point.hpp"
#include "sim/blast/explosives.hpp"
#include "sim/blast/reflection.hpp"
#include "sim/io/blast_json.hpp"

namespace brisance::cli {

namespace {

constexpr std::string_view kHelp =
    "usage: brisance blast --charge-kg M --distance-m R [--explosive NAME | --tnt-factor F]\n"
    "                      [--burst air|surface] [--surface-model hemispherical|factor_1_8]\n"
    "                      [--angle-deg A] [--json]\n"
    "\n"
    "Blast-wave parameters of a charge at a distance, from the Kingery-Bulmash curves.\n"
    "  --charge-kg M       charge mass in kg (> 0)\n"
    "  --distance-m R      distance from the charge centre in m (> 0)\n"
    "  --explosive NAME    explosive (default TNT); 'brisance blast --list-explosives' lists them\n"
    "  --tnt-factor F      custom TNT equivalence factor instead of a named explosive (> 0)\n"
    "  --burst air|surface free-air spherical (default) or surface (hemispherical) burst\n"
    "  --surface-model M   surface bursts: hemispherical curves (default) or factor_1_8\n"
    "                      (free-air curves with 1.8 x the charge)\n"
    "  --angle-deg A       angle of incidence for the reflected values, 0 (head-on) to 90\n"
    "  --json              one JSON object instead of the table\n";

struct BlastRequest {
  double charge_kg = 0.0;
  double distance_m = 0.0;
  std::string explosive_name = "TNT";
  double tnt_factor = 1.0;
  blast::Charge charge;
  double angle_deg = 0.0;
  bool json = false;
};

double positive(const ParsedFlags& flags, std::string_view name, bool required) {
  const auto value = flags.number(name);
  if (!value) {
    if (required) flags.fail("--" + std::string(name) + " is required (see --help)");
    return 0.0;
  }
  if (!(*value > 0.0))
    flags.fail("--" + std::string(name) + " must be greater than 0, got " +
               text::printf("%g", *value));
  return *value;
}

BlastRequest parse(const ParsedFlags& flags) {
  BlastRequest request;
  if (!flags.positional().empty())
    flags.fail("unexpected argument '" + std::string(flags.positional().front()) + "'");
  request.charge_kg = positive(flags, "charge-kg", true);
  request.distance_m = positive(flags, "distance-m", true);
  if (flags.has("explosive") && flags.has("tnt-factor"))
    flags.fail("give either --explosive or --tnt-factor, not both");
  if (flags.has("tnt-factor")) {
    request.tnt_factor = positive(flags, "tnt-factor", true);
    request.explosive_name = "custom";
  } else if (const auto name = flags.value("explosive")) {
    const auto explosive = blast::find_explosive(*name);
    if (!explosive)
      flags.fail("unknown explosive '" + std::string(*name) +
                 "'; known: " + blast::known_explosive_names() + " (or use --tnt-factor)");
    request.explosive_name = explosive->name;
    request.tnt_factor = explosive->tnt_factor;
  }
  if (const auto burst = flags.value("burst")) {
    if (*burst == "air") {
      request.charge.burst = blast::Burst::air;
    } else if (*burst == "surface") {
      request.charge.burst = blast::Burst::surface;
    } else {
      flags.fail("--burst must be 'air' or 'surface', got '" + std::string(*burst) + "'");
    }
  }
  if (const auto model = flags.value("surface-model")) {
    if (*model == "hemispherical") {
      request.charge.surface_model = blast::SurfaceBurstModel::hemispherical;
    } else if (*model == "factor_1_8") {
      request.charge.surface_model = blast::SurfaceBurstModel::factor_1_8;
    } else {
      flags.fail("--surface-model must be 'hemispherical' or 'factor_1_8', got '" +
                 std::string(*model) + "'");
    }
  }
  if (const auto angle = flags.number("angle-deg")) {
    if (*angle < 0.0 || *angle > 90.0)
      flags.fail("--angle-deg must be between 0 and 90, got " + text::printf("%g", *angle));
    request.angle_deg = *angle;
  }
  request.json = flags.has("json");
  request.charge.tnt_equivalent_kg = request.charge_kg * request.tnt_factor;
  return request;
}

void print_table(std::ostream& out, const BlastRequest& request, const blast::BlastPoint& point,
                 const blast::ObliqueReflection& reflection) {
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
  if (point.in_validity_range && reflection.in_chart_range) {
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
                           {"burst"},
                           {"surface-model"},
                           {"angle-deg"},
                           {"json", false},
                           {"list-explosives", false},
                           {"help", false, "h"}});
  if (flags.has("help")) {
    out << kHelp;
    return kExitOk;
  }
  if (flags.has("list-explosives")) {
    for (const blast::Explosive& explosive : blast::known_explosives())
      out << text::printf("%-20.*s %6.3f  %-9.*s %.*s\n", static_cast<int>(explosive.name.size()),
                          explosive.name.data(), explosive.tnt_factor,
                          static_cast<int>(explosive.basis.size()), explosive.basis.data(),
                          static_cast<int>(explosive.source.size()), explosive.source.data());
    return kExitOk;
  }
  const BlastRequest request = parse(flags);
  const blast::BlastPoint point = blast::blast_point(request.charge, request.distance_m);
  const blast::ObliqueReflection reflection =
      io::reflect(point, request.angle_deg * std::numbers::pi / 180.0);
  if (request.json) {
    out << io::blast_report_json(point, reflection).dump(2) << "\n";
  } else {
    print_table(out, request, point, reflection);
  }
  return kExitOk;
}

}  // namespace brisance::cli
