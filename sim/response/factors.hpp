// sim/response/factors: equivalent-system transformation factors (load K_L, mass K_M) that turn a
// distributed element into an equivalent SDOF system, in one table with their source.
//
// Equivalent system (Biggs 1964 ch. 5): K_M m y'' + K_L R(y) = K_L F(t), y the peak (midspan)
// displacement, F the total load, R the element's resistance (resistance factor K_R = K_L).
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace brisance::response {

enum class ResponseRange { elastic, elasto_plastic, plastic };

struct TransformationFactors {
  std::string_view element;  // e.g. "one_way_simply_supported"
  ResponseRange range = ResponseRange::elastic;
  double load = 1.0;  // K_L (= K_R)
  double mass = 1.0;  // K_M
  std::string_view source;
  double load_mass() const { return mass / load; }  // K_LM
};

// The whole table (factors.cpp), for the docs and the tests.
std::span<const TransformationFactors> factor_table();

// The factors for an element name and range, if the table has them.
std::optional<TransformationFactors> find_factors(std::string_view element, ResponseRange range);

}  // namespace brisance::response
