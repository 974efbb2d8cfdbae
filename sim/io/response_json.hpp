// sim/io/response_json: the structural-response calculators (issue 16) as inputs and JSON — an
// element under a charge or a given pulse gives its SDOF response; an element and a damage limit
// give its P–I curve. Shared by `brisance response`, `brisance pi`, `POST /v1/response` and
// `POST /v1/pi`, so all four check the same things with the same messages and answer the same
// fields. Inputs are checked completely (every problem at once, each with a JSON pointer), and
// the work a request may ask for is bounded (see kMaxLoadPeriods).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/blast_json.hpp"
#include "sim/response/element.hpp"
#include "sim/response/pi_diagram.hpp"
#include "sim/response/sdof.hpp"

namespace brisance::io {

// One bad input: where (a JSON pointer into the request body, or the name of a flag) and the fix.
struct InputError {
  std::string pointer;
  std::string message;
};

// A pulse given directly: peak pressure and duration, triangular (linear decay, the default) or
// Friedlander. A Friedlander pulse takes its decay from impulse_kpa_ms when given, else uses the
// decay coefficient b = 1.
struct PulseQuery {
  double peak_kpa = 0.0;
  double duration_ms = 0.0;
  bool friedlander = false;
  std::optional<double> impulse_kpa_ms;
};

// The load of a response: a charge (its reflected pulse at the element) or a pulse.
struct LoadQuery {
  std::optional<BlastQuery> charge;
  std::optional<PulseQuery> pulse;
};

// Reads a pulse's parameters — peak_kpa, duration_ms, shape, impulse_kpa_ms — through `lookup`
// (the text given, or nullopt); `spell` names a parameter in messages. Appends every problem.
void parse_pulse_query(const std::function<std::optional<std::string>(std::string_view)>& lookup,
                       const std::function<std::string(std::string_view)>& spell, PulseQuery& pulse,
                       std::vector<BlastQueryError>& problems);

// The longest run a request may ask for, in natural periods of the element: the load's end (its
// arrival plus its duration) may be at most this many periods, so one solve is at most about
// 32 x (kMaxLoadPeriods + 3) steps (the solver steps at T/32 once the pulse is over).
inline constexpr double kMaxLoadPeriods = 2000;
// Points of a P–I curve a request may ask for.
inline constexpr std::size_t kMinPiPoints = 2;
inline constexpr std::size_t kMaxPiPoints = 100;
// History samples in a response answer (evenly thinned from the solver's steps; the peak kept).
inline constexpr std::size_t kMaxHistorySamples = 1000;

// The pressure history of a load and what it is, in engineering units.
struct LoadAnswer {
  response::PressureLoad load;
  double peak_pressure_kpa = 0.0;
  double impulse_kpa_ms = 0.0;
  double duration_ms = 0.0;
  double arrival_time_ms = 0.0;
  std::string shape;  // "triangular" or "friedlander"
  bool in_validity_range = true;
};
LoadAnswer build_load(const LoadQuery& query);

// The run-length bound: an error naming `pointer` when the load ends more than kMaxLoadPeriods
// natural periods after detonation.
std::optional<InputError> check_load_cost(const response::SdofSystem& system,
                                          const LoadAnswer& load, std::string_view pointer);

// The SDOF response of an element to a load, as JSON: peak_displacement_m, time_to_peak_ms,
// ductility (null for an elastic model), support_rotation_deg (null without a span), damage
// (null without limits), limits, permanent_set_m, max_rebound_m, natural_period_ms,
// elastic_limit_m (null for elastic), load {...}, warnings, and with `history` the thinned time
// history {time_ms[], displacement_m[], velocity_m_s[], resistance_kn[]}.
nlohmann::ordered_json response_json(const response::Element& element, const LoadAnswer& load,
                                     bool history);

// What limits a P–I curve: a ductility ratio or a support rotation.
struct PiLimit {
  std::optional<double> ductility;
  std::optional<double> rotation_deg;
};
// Checks a limit against an element and gives its displacement, m; errors are named by
// `ductility_name` / `rotation_name` (a pointer or a flag). With neither given, a plastic element
// takes ductility 1 (first yield); an elastic one needs a rotation.
std::optional<double> pi_displacement_limit(const response::Element& element, const PiLimit& limit,
                                            std::string_view ductility_name,
                                            std::string_view rotation_name,
                                            std::vector<InputError>& errors);

// The P–I curve as JSON: displacement_limit_m, ductility, rotation_deg (of that limit, null when
// not defined), natural_period_ms, impulsive_asymptote_kpa_ms, quasi_static_asymptote_kpa, points
// [{duration_ms, peak_pressure_kpa, impulse_kpa_ms}], solves, warnings.
nlohmann::ordered_json pi_json(const response::Element& element, double displacement_limit_m,
                               std::size_t points);

// The W–R (charge weight against stand-off) diagram of the same damage limit: for each of
// `points` stand-offs log-spaced over [min_distance_m, max_distance_m], the TNT-equivalent charge
// whose reflected Friedlander pulse (at angle_deg to the element's normal) just reaches the limit
// (response::wr_curve; bisection in log mass over [kMinWrChargeKg, kMaxWrChargeKg]).
inline constexpr double kMinWrChargeKg = 1e-3;
inline constexpr double kMaxWrChargeKg = 1e6;
inline constexpr double kMinWrDistanceM = 0.1;
inline constexpr double kMaxWrDistanceM = 10000.0;
struct WrQuery {
  double min_distance_m = 1.0;
  double max_distance_m = 100.0;
  blast::Burst burst = blast::Burst::air;
  double angle_deg = 0.0;
};
// The run-length bound for a W–R diagram: the largest charge's pulse at the largest stand-off
// (the longest load searched) must end within kMaxLoadPeriods natural periods.
std::optional<InputError> check_wr_cost(const response::SdofSystem& system, const WrQuery& query,
                                        std::string_view pointer);
// The W–R diagram as JSON: diagram "wr", displacement_limit_m, ductility, rotation_deg,
// natural_period_ms, burst, angle_deg, points [{distance_m, charge_kg (null: no charge in
// [1 g, 1000 t] reaches the limit), scaled_distance_m_kg13 (null likewise), in_validity_range}],
// warnings (stand-offs without a charge).
nlohmann::ordered_json wr_json(const response::Element& element, double displacement_limit_m,
                               std::size_t points, const WrQuery& query);

// A whole POST /v1/response body: {"element": {...}, "charge": {...} | "pulse": {...},
// "history": bool (default true)}; a POST /v1/pi body: {"element", "ductility" |
// "rotation_deg", "points", "diagram": "pi" | "wr", and for "wr" "distances_m": [min, max],
// "burst", "angle_deg"}. Every problem is returned with its pointer.
struct ResponseRequest {
  response::Element element;
  LoadQuery load;
  bool history = true;
};
std::vector<InputError> parse_response_request(const nlohmann::json& body,
                                               ResponseRequest& request);
struct PiRequest {
  response::Element element;
  double displacement_limit_m = 0.0;
  std::size_t points = 60;
  bool wr = false;  // the W–R diagram instead of the P–I curve
  WrQuery wr_query;
};
std::vector<InputError> parse_pi_request(const nlohmann::json& body, PiRequest& request);

}  // namespace brisance::io
