// The calculators of the HTTP API end to end (GET /v1/blast, POST /v1/response and /v1/pi):
// a real server, a real HTTP client. They read no store, so unlike the Api suite they are not
// run again on PostgreSQL.
#include <gtest/gtest.h>

#include "tests/server/test_server.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;

TEST(CalculatorApi, BlastCalculatorAndExplosivesMatchTheCli) {
  TestServer server(with_workers(0));
  const json blast = server.get_json("/v1/blast?charge_kg=100&distance_m=15");
  // DESIGN.md's twelve fields, the impulse equivalence, the two pulses, the negative phase and
  // the inputs.
  EXPECT_EQ(blast.size(), 17u);
  EXPECT_DOUBLE_EQ(blast.at("impulse_tnt_equivalent_kg").get<double>(), 100.0);
  EXPECT_GT(blast.at("negative_phase").at("underpressure_kpa").get<double>(), 0.0);
  EXPECT_EQ(blast.at("inputs").at("explosive"), "TNT");
  EXPECT_EQ(blast.at("inputs").at("distance_m"), 15.0);
  EXPECT_NEAR(blast.at("scaled_distance_m_kg13").get<double>(), 15.0 / std::cbrt(100.0), 1e-12);
  EXPECT_TRUE(blast.at("in_validity_range").get<bool>());
  const json comp_b = server.get_json("/v1/blast?charge_kg=100&distance_m=15&explosive=comp-b");
  EXPECT_GT(comp_b.at("tnt_equivalent_kg").get<double>(), 100.0);
  const json explosives = server.get_json("/v1/explosives");
  EXPECT_EQ(explosives.at("explosives")[0].at("name"), "TNT");
  for (const json& e : explosives.at("explosives")) {
    if (e.at("name") == "H-6") {
      EXPECT_EQ(e.at("tnt_factor").get<double>(), 1.38);
      EXPECT_EQ(e.at("impulse_tnt_factor").get<double>(), 1.15);
    } else if (e.at("name") == "TNT") {
      EXPECT_EQ(e.at("impulse_tnt_factor").get<double>(), 1.0);
    }
  }
}

// Every bad parameter of one request is named at once.
TEST(CalculatorApi, BlastNamesEveryBadParameter) {
  TestServer server(with_workers(0));
  const ClientResponse r =
      server.request("GET", "/v1/blast?charge_kg=-1&distance_m=x&burst=sea&angle_deg=95");
  EXPECT_EQ(r.status, 400);
  std::vector<std::string> named;
  const json problem = json::parse(r.body);
  for (const json& e : problem.at("errors"))
    named.push_back(e.at("parameter"));
  EXPECT_EQ(named, (std::vector<std::string>{"charge_kg", "distance_m", "burst", "angle_deg"}));
}

json elastic_element() {
  return {{"mass_kg", 100},
          {"loaded_area_m2", 1},
          {"resistance", {{"type", "elastic"}, {"stiffness_n_per_m", 1e6}}}};
}

std::vector<std::string> pointers(const ClientResponse& r) {
  std::vector<std::string> out;
  const json problem = json::parse(r.body);
  for (const json& e : problem.at("errors"))
    out.push_back(e.at("pointer"));
  return out;
}

// POST /v1/response and /v1/pi: results against closed forms, and every bad field named by its
// pointer in one 422.
TEST(CalculatorApi, ResponseAndPiAnswerWithClosedFormsAndPointers) {
  TestServer server(with_workers(0));
  // m = 100 kg, k = 1e6 N/m, omega = 100 rad/s; a 0.05 ms triangle of 1000 kPa carries 25 Pa*s:
  // the impulsive response y = I A / (m omega) = 2.5 mm.
  const json body = {{"element", elastic_element()},
                     {"pulse", {{"peak_kpa", 1000}, {"duration_ms", 0.05}}}};
  const ClientResponse ok =
      server.request("POST", "/v1/response", body.dump(), {{"Content-Type", "application/json"}});
  ASSERT_EQ(ok.status, 200) << ok.body;
  const json r = json::parse(ok.body);
  EXPECT_NEAR(r.at("peak_displacement_m").get<double>(), 2.5e-3, 2.5e-6);
  const auto& history = r.at("history");
  ASSERT_GT(history.at("time_ms").size(), 10u);
  EXPECT_LE(history.at("time_ms").size(), 1002u);
  EXPECT_EQ(history.at("time_ms").size(), history.at("displacement_m").size());

  // P–I of the elastic element with a span of 2 m at 1 degree: y = tan(1 deg) m, impulsive
  // asymptote y sqrt(k m) / A, quasi-static k y / (2 A).
  json element = elastic_element();
  element["support"] = {{"span_m", 2}};
  const ClientResponse pi = server.request(
      "POST", "/v1/pi", json{{"element", element}, {"rotation_deg", 1}, {"points", 8}}.dump());
  ASSERT_EQ(pi.status, 200) << pi.body;
  const json curve = json::parse(pi.body);
  const double y = std::tan(std::acos(-1.0) / 180.0);
  EXPECT_NEAR(curve.at("impulsive_asymptote_kpa_ms").get<double>(), y * 1e4, 1e-9);
  EXPECT_NEAR(curve.at("quasi_static_asymptote_kpa").get<double>(), 1e6 * y / 2 * 1e-3, 1e-9);
  EXPECT_EQ(curve.at("points").size(), 8u);

  json bad = body;
  bad["element"]["resistance"]["stiffness_n_per_m"] = 0;
  bad["element"]["paint"] = "red";
  bad["pulse"]["shape"] = "square";
  bad["extra"] = 1;
  const ClientResponse invalid = server.request("POST", "/v1/response", bad.dump());
  EXPECT_EQ(invalid.status, 422);
  EXPECT_EQ(json::parse(invalid.body).at("type"), "urn:brisance:problem:invalid-input");
  EXPECT_EQ(pointers(invalid),
            (std::vector<std::string>{"/extra", "/element/paint",
                                      "/element/resistance/stiffness_n_per_m", "/pulse/shape"}));
  // Both loads, or none.
  json both = body;
  both["charge"] = {{"charge_kg", 1}, {"distance_m", 5}};
  EXPECT_EQ(pointers(server.request("POST", "/v1/response", both.dump())),
            std::vector<std::string>{"/pulse"});
  EXPECT_EQ(
      pointers(server.request("POST", "/v1/response", json{{"element", elastic_element()}}.dump())),
      std::vector<std::string>{"/charge"});
  json charge = {{"element", elastic_element()},
                 {"charge", {{"charge_kg", -1}, {"distance_m", "far"}, {"explosive", "x"}}}};
  EXPECT_EQ(
      pointers(server.request("POST", "/v1/response", charge.dump())),
      (std::vector<std::string>{"/charge/charge_kg", "/charge/distance_m", "/charge/explosive"}));
  // Bounded cost: a load lasting beyond 2000 natural periods (T = 63 ms) is refused.
  json long_pulse = body;
  long_pulse["pulse"]["duration_ms"] = 1e7;
  EXPECT_EQ(pointers(server.request("POST", "/v1/response", long_pulse.dump())),
            std::vector<std::string>{"/pulse/duration_ms"});
  EXPECT_EQ(pointers(server.request("POST", "/v1/pi",
                                    json{{"element", elastic_element()}, {"points", 1000}}.dump())),
            std::vector<std::string>{"/points"});
  EXPECT_EQ(pointers(server.request("POST", "/v1/pi", json{{"element", elastic_element()}}.dump())),
            std::vector<std::string>{"/rotation_deg"});
  // The W–R diagram of the same limit: charges growing with stand-off, every bad field at once.
  json elastic_plastic = elastic_element();
  elastic_plastic["resistance"] = {
      {"type", "elastic_plastic"}, {"stiffness_n_per_m", 1e6}, {"yield_resistance_n", 1e3}};
  const ClientResponse wr = server.request("POST", "/v1/pi",
                                           json{{"element", elastic_plastic},
                                                {"ductility", 5},
                                                {"points", 4},
                                                {"diagram", "wr"},
                                                {"distances_m", {2, 16}},
                                                {"burst", "surface"},
                                                {"angle_deg", 10}}
                                               .dump());
  ASSERT_EQ(wr.status, 200) << wr.body;
  const json diagram = json::parse(wr.body);
  EXPECT_EQ(diagram.at("diagram"), "wr");
  EXPECT_EQ(diagram.at("burst"), "surface");
  ASSERT_EQ(diagram.at("points").size(), 4u);
  EXPECT_NEAR(diagram.at("points")[3].at("distance_m").get<double>(), 16.0, 1e-12);
  for (std::size_t k = 1; k < 4; ++k)
    EXPECT_GT(diagram.at("points")[k].at("charge_kg").get<double>(),
              diagram.at("points")[k - 1].at("charge_kg").get<double>());
  EXPECT_EQ(pointers(server.request("POST", "/v1/pi",
                                    json{{"element", elastic_plastic},
                                         {"diagram", "wr"},
                                         {"distances_m", {5, 1}},
                                         {"burst", "ground"},
                                         {"angle_deg", 90},
                                         {"points", 0}}
                                        .dump())),
            (std::vector<std::string>{"/points", "/distances_m", "/burst", "/angle_deg"}));
  EXPECT_EQ(pointers(server.request(
                "POST", "/v1/pi",
                json{{"element", elastic_plastic}, {"diagram", "xy"}, {"burst", "air"}}.dump())),
            (std::vector<std::string>{"/diagram", "/burst"}));
  EXPECT_EQ(server.request("POST", "/v1/pi", "{not json").status, 400);
  EXPECT_EQ(server.request("POST", "/v1/pi", "x", {{"Content-Type", "text/plain"}}).status, 415);
  EXPECT_EQ(server.request("GET", "/v1/pi").status, 405);
}

// GET /v1/blast and `brisance blast` read their parameters with one parser: the TNT factor and
// the surface-burst model are query parameters too, with the CLI's meaning.
TEST(CalculatorApi, BlastTakesTheCliParametersWithTheirMeaning) {
  TestServer server(with_workers(0));
  const json factor = server.get_json("/v1/blast?charge_kg=10&distance_m=8&tnt_factor=1.37");
  EXPECT_DOUBLE_EQ(factor.at("tnt_equivalent_kg").get<double>(), 13.7);
  const json c4 = server.get_json("/v1/blast?charge_kg=10&distance_m=8&explosive=C4");
  EXPECT_DOUBLE_EQ(c4.at("tnt_equivalent_kg").get<double>(), 13.7);
  EXPECT_EQ(c4.at("incident_overpressure_kpa"), factor.at("incident_overpressure_kpa"));
  const json hemi = server.get_json("/v1/blast?charge_kg=10&distance_m=8&burst=surface");
  const json shortcut =
      server.get_json("/v1/blast?charge_kg=10&distance_m=8&burst=surface&surface_model=factor_1_8");
  const json free_air_18 = server.get_json("/v1/blast?charge_kg=18&distance_m=8");
  EXPECT_NE(hemi.at("incident_overpressure_kpa"), shortcut.at("incident_overpressure_kpa"));
  EXPECT_EQ(shortcut.at("incident_overpressure_kpa"), free_air_18.at("incident_overpressure_kpa"));
  for (const auto& [query, parameter] : std::vector<std::pair<std::string, std::string>>{
           {"charge_kg=1&distance_m=5&tnt_factor=0", "tnt_factor"},
           {"charge_kg=1&distance_m=5&tnt_factor=1.2&explosive=RDX", "tnt_factor"},
           {"charge_kg=1&distance_m=5&burst=surface&surface_model=flat", "surface_model"}}) {
    const ClientResponse r = server.request("GET", "/v1/blast?" + query);
    EXPECT_EQ(r.status, 400) << query;
    EXPECT_EQ(json::parse(r.body).at("errors")[0].at("parameter"), parameter) << query;
  }
}

// No bytes a client sends can end the process or break a problem body: what a detail echoes is
// repaired to valid UTF-8.

}  // namespace
}  // namespace brisance::testing
