// sim/response/factors: the table of transformation factors.
//
// Source: J. M. Biggs (1964) "Introduction to Structural Dynamics", McGraw-Hill, table 5.1
// (simply supported beams and one-way slabs), table 5.2 (fixed-end), table 5.3 (two-way slabs
// simply supported on four sides); the same factors are reprinted in UFC 3-340-02 (2008) tables
// 3-12 and 3-13. Uniformly distributed load only. Values are K_L and K_M; K_LM = K_M / K_L.
// The one-way rows were cross-checked against the table Ingeania publishes from the same source
// (ingeania.com/Reference/SDOF_Transformation_Factors); the two-way rows were not cross-checked
// against a second copy: verify them against the printed table before design use.
// Not in the table (missing): concentrated and third-point loads, cantilevers, the fixed-edge
// two-way slabs of Biggs table 5.4 / UFC table 3-13's fixed cases.
#include "sim/response/factors.hpp"

#include <array>

namespace brisance::response {
namespace {

constexpr std::string_view kTable51 = "Biggs 1964 table 5.1; UFC 3-340-02 table 3-12";
constexpr std::string_view kTable52 = "Biggs 1964 table 5.2; UFC 3-340-02 table 3-12";
constexpr std::string_view kTable53 = "Biggs 1964 table 5.3; UFC 3-340-02 table 3-13";

using R = ResponseRange;
constexpr std::array kFactors = {
    // One-way, simply supported, uniform load.
    TransformationFactors{"one_way_simply_supported", R::elastic, 0.64, 0.50, kTable51},
    TransformationFactors{"one_way_simply_supported", R::plastic, 0.50, 0.33, kTable51},
    // One-way, fixed both ends, uniform load (elasto-plastic: ends hinged, midspan elastic).
    TransformationFactors{"one_way_fixed", R::elastic, 0.53, 0.41, kTable52},
    TransformationFactors{"one_way_fixed", R::elasto_plastic, 0.64, 0.50, kTable52},
    TransformationFactors{"one_way_fixed", R::plastic, 0.50, 0.33, kTable52},
    // Two-way slab simply supported on four sides, uniform load; the suffix is the side ratio
    // a/b (short/long).
    TransformationFactors{"two_way_simply_supported_1.0", R::elastic, 0.45, 0.31, kTable53},
    TransformationFactors{"two_way_simply_supported_1.0", R::plastic, 0.33, 0.17, kTable53},
    TransformationFactors{"two_way_simply_supported_0.9", R::elastic, 0.47, 0.33, kTable53},
    TransformationFactors{"two_way_simply_supported_0.9", R::plastic, 0.35, 0.18, kTable53},
    TransformationFactors{"two_way_simply_supported_0.8", R::elastic, 0.49, 0.35, kTable53},
    TransformationFactors{"two_way_simply_supported_0.8", R::plastic, 0.37, 0.20, kTable53},
    TransformationFactors{"two_way_simply_supported_0.7", R::elastic, 0.51, 0.37, kTable53},
    TransformationFactors{"two_way_simply_supported_0.7", R::plastic, 0.38, 0.22, kTable53},
    TransformationFactors{"two_way_simply_supported_0.6", R::elastic, 0.53, 0.39, kTable53},
    TransformationFactors{"two_way_simply_supported_0.6", R::plastic, 0.40, 0.23, kTable53},
    TransformationFactors{"two_way_simply_supported_0.5", R::elastic, 0.55, 0.41, kTable53},
    TransformationFactors{"two_way_simply_supported_0.5", R::plastic, 0.42, 0.25, kTable53},
};

}  // namespace

std::span<const TransformationFactors> factor_table() {
  return kFactors;
}

std::optional<TransformationFactors> find_factors(std::string_view element, ResponseRange range) {
  for (const TransformationFactors& f : kFactors) {
    if (f.element == element && f.range == range) return f;
  }
  return std::nullopt;
}

}  // namespace brisance::response
