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

// Factors of a deflected shape φ normalised to 1 at the control point, uniform load and mass
// (Biggs 1964 ch. 5): K_L = ∫φ dA / A, K_M = ∫φ² dA / A.
struct ShapeFactors {
  double load = 1.0;
  double mass = 1.0;
};

// A plate simply supported on four sides under uniform load, elastic: the factors of its static
// deflected shape, Navier's double sine series (Timoshenko & Woinowsky-Krieger 1959, "Theory of
// Plates and Shells", §30), summed to 1e-6. The same method gives Biggs's one-way rows exactly
// (tested). `short_over_long` in (0, 1]; smaller ratios tend to the one-way strip (0.64, 0.50).
ShapeFactors two_way_simply_supported_elastic(double short_over_long);

// The same plate, plastic: the yield-line mechanism with hinges from the corners at 45° and a
// ridge along the long axis (the mechanism Biggs table 5.3's plastic rows follow: tested to its
// printed two decimals): K_L = 1/2 − r/6, K_M = 1/3 − r/6, r = short/long.
ShapeFactors two_way_simply_supported_plastic(double short_over_long);

// The whole table (factors.cpp), for the docs and the tests.
std::span<const TransformationFactors> factor_table();

// The factors for an element name and range, if the table has them.
std::optional<TransformationFactors> find_factors(std::string_view element, ResponseRange range);

}  // namespace brisance::response
