// Tests of `brisance blast` in-process: the JSON contract of DESIGN.md and the input errors.
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "sim/blast/blast_point.hpp"

namespace brisance::cli {
namespace {

std::string run(const Args& args) {
  std::ostringstream out;
  EXPECT_EQ(run_blast(args, out), kExitOk);
  return out.str();
}

std::string usage_error(const Args& args) {
  std::ostringstream out;
  try {
    run_blast(args, out);
  } catch (const UsageError& error) {
    return error.message;
  }
  ADD_FAILURE() << "no usage error";
  return {};
}

TEST(BlastCommand, JsonHasExactlyTheContractFields) {
  const auto json =
      nlohmann::json::parse(run({"--charge-kg", "100", "--distance-m", "15", "--json"}));
  const std::set<std::string> expected = {
      "scaled_distance_m_kg13",     "tnt_equivalent_kg",        "incident_overpressure_kpa",
      "incident_impulse_kpa_ms",    "arrival_time_ms",          "positive_duration_ms",
      "reflected_overpressure_kpa", "reflected_impulse_kpa_ms", "shock_velocity_m_s",
      "dynamic_pressure_kpa",       "reflection_coefficient",   "in_validity_range"};
  std::set<std::string> keys;
  for (const auto& [key, value] : json.items())
    keys.insert(key);
  EXPECT_EQ(keys, expected);
  // Engineering units over the SI calculator.
  const blast::BlastPoint point = blast::blast_point(blast::Charge{100.0}, 15.0);
  EXPECT_DOUBLE_EQ(json["incident_overpressure_kpa"].get<double>(),
                   point.incident_overpressure_pa * 1e-3);
  EXPECT_DOUBLE_EQ(json["arrival_time_ms"].get<double>(), point.arrival_time_s * 1e3);
  EXPECT_DOUBLE_EQ(json["incident_impulse_kpa_ms"].get<double>(), point.incident_impulse_pa_s);
  EXPECT_NEAR(json["reflection_coefficient"].get<double>(),
              point.reflected_overpressure_pa / point.incident_overpressure_pa, 1e-12);
  EXPECT_TRUE(json["in_validity_range"].get<bool>());
}

TEST(BlastCommand, ExplosiveSurfaceAndAngleOptions) {
  const auto tnt = nlohmann::json::parse(run({"--charge-kg=10", "--distance-m=5", "--json"}));
  const auto rdx = nlohmann::json::parse(
      run({"--charge-kg", "10", "--distance-m", "5", "--explosive", "rdx", "--json"}));
  EXPECT_DOUBLE_EQ(rdx["tnt_equivalent_kg"].get<double>(), 11.85);
  EXPECT_GT(rdx["incident_overpressure_kpa"].get<double>(),
            tnt["incident_overpressure_kpa"].get<double>());
  const auto custom = nlohmann::json::parse(
      run({"--charge-kg", "10", "--distance-m", "5", "--tnt-factor", "2", "--json"}));
  EXPECT_DOUBLE_EQ(custom["tnt_equivalent_kg"].get<double>(), 20.0);
  const auto surface = nlohmann::json::parse(
      run({"--charge-kg", "10", "--distance-m", "5", "--burst", "surface", "--json"}));
  EXPECT_GT(surface["incident_overpressure_kpa"].get<double>(),
            tnt["incident_overpressure_kpa"].get<double>());
  const auto grazing = nlohmann::json::parse(
      run({"--charge-kg", "10", "--distance-m", "5", "--angle-deg", "90", "--json"}));
  EXPECT_NEAR(grazing["reflection_coefficient"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(grazing["reflected_overpressure_kpa"].get<double>(),
              grazing["incident_overpressure_kpa"].get<double>(), 1e-9);
}

TEST(BlastCommand, OutOfRangeIsFlaggedInJsonAndTable) {
  const auto far =
      nlohmann::json::parse(run({"--charge-kg", "1", "--distance-m", "500", "--json"}));
  EXPECT_FALSE(far["in_validity_range"].get<bool>());
  EXPECT_NE(run({"--charge-kg", "1", "--distance-m", "500"}).find("NO: outside"),
            std::string::npos);
}

TEST(BlastCommand, TableNamesEveryQuantityWithItsUnit) {
  const std::string table = run({"--charge-kg", "100", "--distance-m", "15"});
  for (const char* text : {"Pso", "kPa*ms", "m/kg^(1/3)", "m/s", "ms", "in validity range"})
    EXPECT_NE(table.find(text), std::string::npos) << text;
}

TEST(BlastCommand, BadInputIsOneClearMessage) {
  EXPECT_NE(usage_error({"--distance-m", "5"}).find("--charge-kg is required"), std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "-1", "--distance-m", "5"}).find("greater than 0"),
            std::string::npos);
  EXPECT_NE(
      usage_error({"--charge-kg", "abc", "--distance-m", "5"}).find("must be a finite number"),
      std::string::npos);
  EXPECT_NE(
      usage_error({"--charge-kg", "nan", "--distance-m", "5"}).find("must be a finite number"),
      std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--distance-m", "5", "--explosive", "semtex-x"})
                .find("known: TNT"),
            std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--distance-m", "5", "--burst", "water"})
                .find("'air' or 'surface'"),
            std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--distance-m", "5", "--angle-deg", "120"})
                .find("between 0 and 90"),
            std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--distance-m", "5", "--frobnicate"})
                .find("unknown option '--frobnicate'"),
            std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--charge-kg", "2", "--distance-m", "5"})
                .find("given twice"),
            std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg"}).find("needs a value"), std::string::npos);
  EXPECT_NE(usage_error({"--charge-kg", "1", "--distance-m", "5", "--explosive", "RDX",
                         "--tnt-factor", "1.2"})
                .find("not both"),
            std::string::npos);
  for (const std::string& message : {usage_error({"--distance-m", "5"}),
                                     usage_error({"--charge-kg", "0", "--distance-m", "1"})}) {
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind("brisance blast: ", 0), 0u) << message;
  }
}

}  // namespace
}  // namespace brisance::cli
