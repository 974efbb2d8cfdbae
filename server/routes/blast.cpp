// server/routes/blast: GET /v1/blast (the blast calculator, the same parameters as `brisance
// blast`) and GET /v1/explosives.
#include <nlohmann/json.hpp>

#include "server/routes/routes.hpp"
#include "sim/blast/explosives.hpp"
#include "sim/io/blast_json.hpp"

namespace brisance::server::routes {

using nlohmann::json;

HttpResponse blast_calculator(const Context& c) {
  const auto lookup = [&](std::string_view name) -> std::optional<std::string> {
    const auto value = c.target.get(name);
    if (!value) return std::nullopt;
    return std::string(*value);
  };
  const auto spell = [](std::string_view name) { return "'" + std::string(name) + "'"; };
  io::BlastQuery query;
  const auto problems = io::parse_blast_query(lookup, spell, query);
  if (!problems.empty()) {
    // Every bad parameter at once, each named in errors[].
    Problem p = problem(400, "invalid-parameter", "Invalid query parameter",
                        problems.size() == 1 ? problems.front().message
                                             : std::to_string(problems.size()) +
                                                   " parameters are invalid; each is listed in "
                                                   "'errors'");
    for (const io::BlastQueryError& e : problems)
      p.error("parameter", e.parameter, e.message);
    return p.response();
  }
  const io::BlastAnswer answer = io::calculate_blast(query);
  HttpResponse r;
  r.body = io::blast_answer_json(query, answer).dump();
  return r;
}

HttpResponse explosives(const Context& c) {
  json list = json::array();
  for (const blast::Explosive& e : blast::known_explosives()) {
    list.push_back(json{{"name", e.name},
                        {"tnt_factor", e.tnt_factor},
                        {"impulse_tnt_factor", e.impulse_factor()},
                        {"basis", e.basis},
                        {"source", e.source}});
  }
  return etagged(c.request, json{{"explosives", list}}.dump());
}

}  // namespace brisance::server::routes
