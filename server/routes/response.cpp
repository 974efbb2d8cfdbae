// server/routes/response: POST /v1/response (an element's SDOF response to a charge or a pulse)
// and POST /v1/pi (its P–I curve), synchronous like GET /v1/blast. sim/io/response_json checks
// the body completely and bounds the work (a load of at most 2000 natural periods, at most 100
// P–I points, ductility <= 100, rotation <= 45 deg), so each answer costs milliseconds.
#include <nlohmann/json.hpp>

#include "server/routes/routes.hpp"
#include "sim/io/response_json.hpp"

namespace brisance::server::routes {

namespace {

// The body as JSON, or the problem that answers it instead.
std::optional<HttpResponse> read_body(const Context& c, nlohmann::json& body) {
  const std::string_view content_type = c.request.header("content-type");
  if (!content_type.empty() && content_type.find("json") == std::string_view::npos) {
    return problem(415, "unsupported-media-type", "Unsupported media type",
                   "send the request as application/json")
        .response();
  }
  body = nlohmann::json::parse(c.request.body, nullptr, false);
  if (body.is_discarded()) {
    return problem(400, "malformed-json", "Malformed JSON",
                   "the request body is not valid JSON; send an object such as "
                   "{\"element\": {...}, \"pulse\": {...}}")
        .response();
  }
  return std::nullopt;
}

HttpResponse invalid(const std::vector<io::InputError>& errors) {
  Problem p = problem(422, "invalid-input", "Invalid input",
                      std::to_string(errors.size()) +
                          " problem(s) in the request; each is listed in 'errors' with a JSON "
                          "pointer into the request body");
  for (const io::InputError& e : errors)
    p.error("pointer", e.pointer, e.message);
  return p.response();
}

}  // namespace

HttpResponse element_response(const Context& c) {
  nlohmann::json body;
  if (auto answer = read_body(c, body)) return std::move(*answer);
  io::ResponseRequest request;
  const auto errors = io::parse_response_request(body, request);
  if (!errors.empty()) return invalid(errors);
  HttpResponse r;
  r.body = io::response_json(request.element, io::build_load(request.load), request.history).dump();
  return r;
}

HttpResponse pressure_impulse(const Context& c) {
  nlohmann::json body;
  if (auto answer = read_body(c, body)) return std::move(*answer);
  io::PiRequest request;
  const auto errors = io::parse_pi_request(body, request);
  if (!errors.empty()) return invalid(errors);
  HttpResponse r;
  r.body = request.wr
               ? io::wr_json(request.element, request.displacement_limit_m, request.points,
                             request.wr_query)
                     .dump()
               : io::pi_json(request.element, request.displacement_limit_m, request.points).dump();
  return r;
}

}  // namespace brisance::server::routes
