// sim/io/blast_json: the blast calculator's JSON object (DESIGN.md "The blast calculator's JSON
// fields"), shared by `brisance blast --json` and `GET /v1/blast` so both give the same fields.
#pragma once

#include <nlohmann/json.hpp>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/reflection.hpp"

namespace brisance::io {

// The blast point and its reflection at the given angle of incidence, in engineering units.
nlohmann::ordered_json blast_report_json(const blast::BlastPoint& point,
                                         const blast::ObliqueReflection& reflection);

// Reflection of `point` at `angle_rad` of incidence (0: head-on).
blast::ObliqueReflection reflect(const blast::BlastPoint& point, double angle_rad);

}  // namespace brisance::io
