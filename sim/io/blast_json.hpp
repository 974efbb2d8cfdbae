// sim/io/blast_json: the blast calculator — its parameters and its JSON object (DESIGN.md "The
// blast calculator's JSON fields") — shared by `brisance blast` and `GET /v1/blast`, so both take
// the same parameters, check them with the same messages and answer with the same fields.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/negative_phase.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/blast/reflection.hpp"

namespace brisance::io {

// What the calculator is asked: a charge at a distance, seen at an angle of incidence.
struct BlastQuery {
  double charge_kg = 0.0;
  double distance_m = 0.0;
  std::string explosive_name = "TNT";  // "custom" when a TNT factor was given
  double tnt_factor = 1.0;
  double impulse_tnt_factor = 1.0;  // for impulses (UFC 3-340-02 eq. 2-5); = tnt_factor if none
  blast::Charge charge;             // burst, surface model and TNT equivalent
  double angle_deg = 0.0;
};

// A parameter the calculator cannot use: its name (as the caller spells it) and what to fix.
struct BlastQueryError {
  std::string parameter;
  std::string message;
};

// Reads the calculator's parameters — charge_kg, distance_m, explosive or tnt_factor (with an
// optional impulse_tnt_factor), burst, surface_model, angle_deg — through `lookup` (the text given
// for a parameter, or nullopt), and checks them. `spell` turns a parameter's name into the caller's
// spelling for messages
// ("--charge-kg" on the command line, "'charge_kg'" over HTTP). Returns every problem, in the
// order above; when there is none, `query` is filled in.
std::vector<BlastQueryError> parse_blast_query(
    const std::function<std::optional<std::string>(std::string_view name)>& lookup,
    const std::function<std::string(std::string_view name)>& spell, BlastQuery& query);

// The blast point of the query, its reflection at the query's angle, and the positive-phase
// pulses (Friedlander, decay solved so each integrates to its impulse; sim/blast/pulse) that go
// with them, time from arrival.
struct BlastAnswer {
  blast::BlastPoint point;
  blast::ObliqueReflection reflection;
  blast::Pulse incident_pulse;
  blast::Pulse reflected_pulse;
  blast::NegativePhase negative_phase;  // incident; follows the positive phase
};
BlastAnswer calculate_blast(const BlastQuery& query);

// The blast point and its reflection at the given angle of incidence, in engineering units.
nlohmann::ordered_json blast_report_json(const blast::BlastPoint& point,
                                         const blast::ObliqueReflection& reflection);

// The query as the calculator understood it (explosive by its canonical name, defaults filled
// in): charge_kg, distance_m, explosive, tnt_factor, impulse_tnt_factor, burst, surface_model,
// angle_deg.
nlohmann::ordered_json blast_inputs_json(const BlastQuery& query);

// The whole answer of `brisance blast --json` and GET /v1/blast: the report, the two pulses as
// {peak_kpa, duration_ms, impulse_kpa_ms, decay}, the incident negative phase and the echoed
// inputs.
nlohmann::ordered_json blast_answer_json(const BlastQuery& query, const BlastAnswer& answer);

// The incident and reflected pulses sampled at `samples` (>= 2) evenly spaced times from arrival
// to the end of the incident negative phase, as CSV: time_ms (since detonation), incident_kpa
// (with its negative phase), reflected_kpa (positive phase only: the reflected negative phase is
// not modelled).
std::string blast_pulse_csv(const BlastAnswer& answer, std::size_t samples);

// Reflection of `point` at `angle_rad` of incidence (0: head-on).
blast::ObliqueReflection reflect(const blast::BlastPoint& point, double angle_rad);

}  // namespace brisance::io
