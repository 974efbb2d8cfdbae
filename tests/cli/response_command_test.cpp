// Tests of `brisance response` and `brisance pi` in-process: results against closed forms
// (impulsive limit, dynamic load factor, elastic–plastic energy balance, P–I asymptotes), the
// damage level against the PDC-TR 06-08 bounds, and the input errors.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/text.hpp"
#include "sim/blast/blast_point.hpp"

namespace brisance::cli {
namespace {

// Writes an element file in the test's temporary folder and returns its path.
std::string element_file(const std::string& name, const nlohmann::json& element) {
  const std::string path = testing::TempDir() + "/" + name + ".json";
  std::ofstream(path) << element.dump();
  return path;
}

// Elastic, already an equivalent SDOF: m = 100 kg, k = 1e6 N/m (omega = 100 rad/s), A = 1 m^2.
nlohmann::json elastic() {
  return {{"mass_kg", 100},
          {"loaded_area_m2", 1},
          {"resistance", {{"type", "elastic"}, {"stiffness_n_per_m", 1e6}}}};
}

// Elastic–plastic: y_el = R_y / k = 1 mm, span 2 m, judged against the RC flexure limits.
nlohmann::json elastic_plastic() {
  return {{"mass_kg", 100},
          {"loaded_area_m2", 1},
          {"resistance",
           {{"type", "elastic_plastic"}, {"stiffness_n_per_m", 1e6}, {"yield_resistance_n", 1e3}}},
          {"support", {{"span_m", 2}}},
          {"limits", "rc_flexure"}};
}

nlohmann::json run_json(int (*command)(const Args&, std::ostream&), const Args& args) {
  std::ostringstream out;
  EXPECT_EQ(command(args, out), kExitOk);
  return nlohmann::json::parse(out.str());
}

std::string usage_error(int (*command)(const Args&, std::ostream&), const Args& args) {
  std::ostringstream out;
  try {
    command(args, out);
  } catch (const UsageError& error) {
    EXPECT_EQ(error.message.find('\n'), std::string::npos) << error.message;
    return error.message;
  }
  ADD_FAILURE() << "no usage error";
  return {};
}

TEST(ResponseCommand, ShortPulseGivesTheImpulsiveLimit) {
  const std::string path = element_file("elastic", elastic());
  // Triangle of 1000 kPa for 0.05 ms: I = 25 Pa*s, t_d / T = 8e-4; y = I A / (m omega) = 2.5 mm.
  const auto r = run_json(run_response, {"--element", path, "--pulse-peak-kpa", "1000",
                                         "--pulse-duration-ms", "0.05", "--json"});
  EXPECT_NEAR(r["peak_displacement_m"].get<double>(), 25.0 / (100.0 * 100.0), 2.5e-3 * 1e-3);
  // The peak comes a quarter period after the (short) load: T / 4 = pi / 200 s.
  EXPECT_NEAR(r["time_to_peak_ms"].get<double>(), 1e3 * std::numbers::pi / 200.0, 0.05);
  EXPECT_NEAR(r["natural_period_ms"].get<double>(), 1e3 * 2.0 * std::numbers::pi / 100.0, 1e-9);
  EXPECT_TRUE(r["ductility"].is_null());
  EXPECT_TRUE(r["support_rotation_deg"].is_null());
  EXPECT_TRUE(r["damage"].is_null());
  EXPECT_NEAR(r["load"]["impulse_kpa_ms"].get<double>(), 25.0, 1e-9);
}

TEST(ResponseCommand, LongTriangleMatchesTheClosedFormLoadFactor) {
  const std::string path = element_file("elastic", elastic());
  // t_d = 2 s = 31.8 T. Closed form for a triangular pulse while it acts (Biggs 1964 ch. 2):
  // y / y_st = 1 - cos(wt) - t / t_d + sin(wt) / (w t_d); its maximum, sampled densely here.
  const double w = 100.0, td = 2.0;
  double dlf = 0.0;
  for (int i = 1; i <= 200000; ++i) {
    const double t = td * i / 200000.0;
    dlf = std::max(dlf, 1.0 - std::cos(w * t) - t / td + std::sin(w * t) / (w * td));
  }
  const auto r = run_json(run_response, {"--element", path, "--pulse-peak-kpa", "10",
                                         "--pulse-duration-ms", "2000", "--json"});
  const double static_m = 10e3 * 1.0 / 1e6;
  EXPECT_NEAR(r["peak_displacement_m"].get<double>() / static_m, dlf, 5e-3 * dlf);
  EXPECT_GT(dlf, 1.9);
}

TEST(ResponseCommand, ElasticPlasticImpulseMatchesTheEnergyBalance) {
  const std::string path = element_file("ep", elastic_plastic());
  // I = 30 Pa*s on 1 m^2 in 0.05 ms: I^2 / (2m) = R_y (y_m - y_el / 2) gives y_m = 5 mm, mu = 5.
  const auto r = run_json(run_response, {"--element", path, "--pulse-peak-kpa", "1200",
                                         "--pulse-duration-ms", "0.05", "--json"});
  EXPECT_NEAR(r["ductility"].get<double>(), 5.0, 5e-3);
  EXPECT_NEAR(r["elastic_limit_m"].get<double>(), 1e-3, 1e-12);
  // Permanent set y_m - y_el (no reverse yield).
  EXPECT_NEAR(r["permanent_set_m"].get<double>(), 4e-3, 1e-5);
  // theta = atan(y / (L / 2)), L = 2 m.
  const double theta =
      std::atan(r["peak_displacement_m"].get<double>() / 1.0) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(r["support_rotation_deg"].get<double>(), theta, 1e-12);
  // PDC-TR 06-08 RC flexure: mu > 1 (B1) and theta = 0.29 deg < 2 (B2): moderate.
  EXPECT_EQ(r["damage"].get<std::string>(), "moderate");
  EXPECT_EQ(r["limits"].get<std::string>(), "rc_flexure");
}

TEST(ResponseCommand, ChargeLoadsWithTheReflectedPulse) {
  const std::string path = element_file("ep", elastic_plastic());
  const auto r = run_json(
      run_response, {"--element", path, "--charge-kg", "100", "--distance-m", "15", "--json"});
  std::ostringstream blast_out;
  ASSERT_EQ(run_blast({"--charge-kg", "100", "--distance-m", "15", "--json"}, blast_out), 0);
  const auto blast = nlohmann::json::parse(blast_out.str());
  EXPECT_NEAR(r["load"]["peak_pressure_kpa"].get<double>(),
              blast["reflected_overpressure_kpa"].get<double>(), 1e-9);
  EXPECT_NEAR(r["load"]["impulse_kpa_ms"].get<double>(),
              blast["reflected_impulse_kpa_ms"].get<double>(),
              1e-6 * blast["reflected_impulse_kpa_ms"].get<double>());
  EXPECT_NEAR(r["load"]["arrival_time_ms"].get<double>(), blast["arrival_time_ms"].get<double>(),
              1e-9);
  EXPECT_GT(r["time_to_peak_ms"].get<double>(), blast["arrival_time_ms"].get<double>());
}

TEST(ResponseCommand, HistoryCsvHasTheColumnsAndThePeak) {
  const std::string path = element_file("ep", elastic_plastic());
  const std::string csv = testing::TempDir() + "/history.csv";
  const auto r =
      run_json(run_response, {"--element", path, "--pulse-peak-kpa", "1200", "--pulse-duration-ms",
                              "0.05", "--json", "--history-csv", csv});
  std::ifstream file(csv);
  std::string line;
  std::getline(file, line);
  EXPECT_EQ(line, "time_ms,displacement_m,velocity_m_s,resistance_kn");
  double peak = 0.0;
  int rows = 0;
  while (std::getline(file, line)) {
    double t = 0, y = 0, v = 0, res = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &t, &y, &v, &res), 4) << line;
    peak = std::max(peak, y);
    ++rows;
  }
  EXPECT_GT(rows, 10);
  EXPECT_NEAR(peak, r["peak_displacement_m"].get<double>(), 1e-9);
  std::remove(csv.c_str());
}

TEST(ResponseCommand, BadInputIsOneLineNamingEveryProblem) {
  const std::string good = element_file("ep", elastic_plastic());
  EXPECT_NE(usage_error(run_response, {"--element", good}).find("give the load"),
            std::string::npos);
  EXPECT_NE(
      usage_error(run_response, {"--element", good, "--charge-kg", "1", "--pulse-peak-kpa", "5"})
          .find("not both"),
      std::string::npos);
  EXPECT_NE(usage_error(run_response, {"--pulse-peak-kpa", "5", "--pulse-duration-ms", "1"})
                .find("--element ELEMENT.json is required"),
            std::string::npos);
  nlohmann::json bad = elastic_plastic();
  bad["resistance"]["stiffness_n_per_m"] = -1;
  bad["colour"] = "grey";
  const std::string message = usage_error(
      run_response,
      {"--element", element_file("bad", bad), "--pulse-peak-kpa", "5", "--pulse-duration-ms", "1"});
  EXPECT_NE(message.find("/resistance/stiffness_n_per_m must be > 0"), std::string::npos);
  EXPECT_NE(message.find("/colour is not a known field"), std::string::npos);
  const std::string pulse =
      usage_error(run_response, {"--element", good, "--pulse-peak-kpa", "-5", "--pulse-duration-ms",
                                 "x", "--pulse-shape", "square"});
  for (const char* flag : {"--pulse-peak-kpa", "--pulse-duration-ms", "--pulse-shape"})
    EXPECT_NE(pulse.find(flag), std::string::npos) << flag << " in " << pulse;
  // Bounded cost: a load lasting more than 2000 natural periods (T = 63 ms here) is refused.
  EXPECT_NE(usage_error(run_response,
                        {"--element", good, "--pulse-peak-kpa", "1", "--pulse-duration-ms", "1e6"})
                .find("natural periods"),
            std::string::npos);
}

TEST(PiCommand, AsymptotesAreTheClosedForms) {
  const std::string path = element_file("ep", elastic_plastic());
  const std::string out = testing::TempDir() + "/pi.json";
  std::ostringstream text;
  ASSERT_EQ(run_pi({"--element", path, "--ductility", "5", "--points", "20", "-o", out}, text), 0);
  std::ifstream file(out);
  const auto pi = nlohmann::json::parse(file);
  // mu = 5, y = 5 mm: impulsive sqrt(2 m R_y (y - y_el / 2)) / A = 30 Pa*s (= kPa*ms);
  // quasi-static R_y (1 - 1 / (2 mu)) / A = 900 Pa (Baker et al. 1983 ch. 5).
  EXPECT_NEAR(pi["displacement_limit_m"].get<double>(), 5e-3, 1e-12);
  EXPECT_NEAR(pi["impulsive_asymptote_kpa_ms"].get<double>(), 30.0, 30.0 * 1e-9);
  EXPECT_NEAR(pi["quasi_static_asymptote_kpa"].get<double>(), 0.9, 0.9 * 1e-9);
  ASSERT_EQ(pi["points"].size(), 20u);
  // The sweep's ends approach the asymptotes (t_d / T = 0.01 and 100).
  EXPECT_NEAR(pi["points"][0]["impulse_kpa_ms"].get<double>(), 30.0, 30.0 * 0.03);
  EXPECT_NEAR(pi["points"][19]["peak_pressure_kpa"].get<double>(), 0.9, 0.9 * 0.03);
  EXPECT_NEAR(pi["rotation_deg"].get<double>(), std::atan(5e-3) * 180.0 / std::numbers::pi, 1e-12);
  std::remove(out.c_str());
}

TEST(PiCommand, ElasticRotationLimitAndSvg) {
  nlohmann::json e = elastic();
  e["support"] = {{"span_m", 2}};
  const std::string path = element_file("elastic_span", e);
  const std::string out = testing::TempDir() + "/pi.svg";
  std::ostringstream text;
  ASSERT_EQ(run_pi({"--element", path, "--rotation-deg", "1", "--points", "10", "-o", out}, text),
            0);
  std::ifstream file(out);
  std::stringstream svg;
  svg << file.rdbuf();
  EXPECT_EQ(svg.str().rfind("<svg", 0), 0u);
  EXPECT_NE(svg.str().find("<polyline"), std::string::npos);
  std::remove(out.c_str());
  // Table on stdout: elastic asymptotes y sqrt(k m) / A and k y / (2A), y = tan(1 deg) m.
  std::ostringstream table;
  ASSERT_EQ(run_pi({"--element", path, "--rotation-deg", "1", "--points", "5"}, table), 0);
  const double y = std::tan(std::numbers::pi / 180.0);
  char expected[64];
  std::snprintf(expected, sizeof expected, "impulsive asymptote    %.4g kPa*ms", y * 1e4);
  EXPECT_NE(table.str().find(expected), std::string::npos) << table.str();
  std::snprintf(expected, sizeof expected, "quasi-static asymptote %.4g kPa", 1e6 * y / 2 * 1e-3);
  EXPECT_NE(table.str().find(expected), std::string::npos) << table.str();
}

TEST(PiCommand, BadLimitsAreUsageErrors) {
  const std::string el = element_file("elastic", elastic());
  const std::string ep = element_file("ep", elastic_plastic());
  EXPECT_NE(usage_error(run_pi, {"--element", el}).find("--rotation-deg is required"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", el, "--rotation-deg", "2"}).find("span"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "--ductility", "2", "--rotation-deg", "2"})
                .find("give one"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "--ductility", "1000"}).find("<= 100"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "--points", "1"}).find("2 to 100"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "-o", "pi.png"}).find(".svg or .json"),
            std::string::npos);
}

TEST(PiCommand, WrDiagramMeetsTheImpulsiveAsymptoteAndItsPointsSitOnTheLimit) {
  // The elastic-plastic element at mu = 5 (T = 63 ms): close-in charges give reflected pulses
  // of about 1 ms, impulsive for it, so the charge found at each stand-off carries the impulsive
  // asymptote's 30 Pa*s (Baker et al. 1983 ch. 5) as its Kingery-Bulmash reflected impulse.
  const std::string path = element_file("ep_wr", elastic_plastic());
  const std::string out = testing::TempDir() + "/wr.json";
  std::ostringstream text;
  ASSERT_EQ(run_pi({"--element", path, "--ductility", "5", "--diagram", "wr", "--min-distance-m",
                    "1", "--max-distance-m", "4", "--points", "3", "-o", out},
                   text),
            0);
  std::ifstream file(out);
  const auto wr = nlohmann::json::parse(file);
  EXPECT_EQ(wr["diagram"], "wr");
  ASSERT_EQ(wr["points"].size(), 3u);
  EXPECT_NEAR(wr["points"][1]["distance_m"].get<double>(), 2.0, 1e-12);
  double previous = 0.0;
  for (const auto& p : wr["points"]) {
    const double charge_kg = p["charge_kg"].get<double>();
    const double distance_m = p["distance_m"].get<double>();
    EXPECT_GT(charge_kg, previous);
    previous = charge_kg;
    blast::Charge charge;
    charge.tnt_equivalent_kg = charge_kg;
    const blast::BlastPoint point = blast::blast_point(charge, distance_m);
    EXPECT_LT(point.positive_duration_s, 0.05 * 2.0 * std::numbers::pi / 100.0);
    EXPECT_NEAR(point.reflected_impulse_pa_s / 30.0, 1.0, 0.03) << distance_m << " m";
    // The response command at that charge and stand-off reaches the limit.
    const nlohmann::json r =
        run_json(run_response, {"--element", path, "--charge-kg", text::printf("%.17g", charge_kg),
                                "--distance-m", text::printf("%.17g", distance_m), "--json"});
    EXPECT_NEAR(r["ductility"].get<double>(), 5.0, 5.0 * 0.005) << distance_m << " m";
  }
  std::remove(out.c_str());
  // Table and SVG.
  std::ostringstream table;
  ASSERT_EQ(
      run_pi({"--element", path, "--ductility", "5", "--diagram", "wr", "--points", "4"}, table),
      0);
  EXPECT_NE(table.str().find("W-R diagram"), std::string::npos) << table.str();
  const std::string svg_path = testing::TempDir() + "/wr.svg";
  ASSERT_EQ(run_pi({"--element", path, "--ductility", "5", "--diagram", "wr", "--points", "4", "-o",
                    svg_path},
                   table),
            0);
  std::ifstream svg_file(svg_path);
  std::stringstream svg;
  svg << svg_file.rdbuf();
  EXPECT_EQ(svg.str().rfind("<svg", 0), 0u);
  EXPECT_NE(svg.str().find("<polyline"), std::string::npos);
  std::remove(svg_path.c_str());
}

TEST(PiCommand, WrBadFlagsAreReportedAtOnce) {
  const std::string ep = element_file("ep", elastic_plastic());
  const std::string all = usage_error(
      run_pi, {"--element", ep, "--diagram", "wr", "--min-distance-m", "50", "--max-distance-m",
               "5", "--burst", "ground", "--angle-deg", "95", "--points", "200"});
  for (const char* part : {"--points must be", "--min-distance-m/--max-distance-m must be",
                           "--burst must be", "--angle-deg must be"})
    EXPECT_NE(all.find(part), std::string::npos) << all;
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "--diagram", "xy"}).find("pi or wr"),
            std::string::npos);
  EXPECT_NE(usage_error(run_pi, {"--element", ep, "--burst", "air"}).find("--diagram wr only"),
            std::string::npos);
  // Bounded cost: a stiff element (T = 0.63 ms) and a 10 km stand-off, where the largest charge
  // searched gives a load lasting beyond 2000 periods.
  nlohmann::json stiff = elastic_plastic();
  stiff["resistance"]["stiffness_n_per_m"] = 1e10;
  stiff["resistance"]["yield_resistance_n"] = 1e7;
  const std::string st = element_file("stiff", stiff);
  EXPECT_NE(usage_error(run_pi, {"--element", st, "--diagram", "wr", "--max-distance-m", "10000"})
                .find("natural periods"),
            std::string::npos);
}

}  // namespace
}  // namespace brisance::cli
