// sim/response/pi_diagram: iso-damage curves of an element — the pressure–impulse (P–I) diagram
// for triangular pulses, its closed-form asymptotes, and the charge-weight/stand-off (W–R)
// diagram built on the Kingery–Bulmash reflected parameters of sim/blast.
//
// Method (thesis §2.8; Baker et al. 1983 ch. 5 for the asymptotes): for each pulse duration of a
// log-spaced sweep, bisect on the peak pressure until the SDOF's peak displacement reaches the
// damage limit. The curve lies above both asymptotes for an undamped system.
#pragma once

#include <cstddef>
#include <vector>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/response/sdof.hpp"

namespace brisance::response {

// The displacement limit for a ductility ratio mu (> 0): mu times the elastic limit.
double displacement_for_ductility(const SdofSystem& system, double ductility);
// The displacement limit for a support rotation: (span / 2) tan(theta). Needs system.span_m.
double displacement_for_rotation(const SdofSystem& system, double rotation_deg);

// Impulsive asymptote, Pa*s: the impulse whose kinetic energy (K_L A i)^2 / (2 K_M m) equals the
// strain energy K_L * integral_0^y R dy to the limit y (elastic: i = y sqrt(k K_M m / K_L) / A;
// elastic–plastic: sqrt(2 K_M m K_L R_y (y - y_el / 2) / K_L^2) / A; rigid–plastic: drop y_el).
double impulsive_asymptote_pa_s(const SdofSystem& system, double displacement_limit_m);
// Quasi-static asymptote, Pa: the constant pressure whose work to the limit equals the strain
// energy, p = integral_0^y R dy / (A y) (elastic: k y / (2 A); elastic–plastic:
// R_y (1 - 1 / (2 mu)) / A).
double quasi_static_asymptote_pa(const SdofSystem& system, double displacement_limit_m);

struct PiOptions {
  std::size_t points = 60;            // durations in the sweep (>= 2)
  double min_duration_ratio = 0.01;   // shortest t_d / T
  double max_duration_ratio = 100.0;  // longest t_d / T
  double relative_tolerance = 1e-4;   // of the bisection on pressure
};

struct PiPoint {
  double duration_s = 0.0;
  double peak_pressure_pa = 0.0;  // of the triangular pulse just reaching the limit
  double impulse_pa_s = 0.0;      // P t_d / 2
};

struct PiCurve {
  std::vector<PiPoint> points;  // increasing duration: pressure falls, impulse rises
  double displacement_limit_m = 0.0;
  double impulsive_asymptote_pa_s = 0.0;
  double quasi_static_asymptote_pa = 0.0;
  std::size_t solves = 0;    // SDOF runs used
  std::size_t warnings = 0;  // durations where the bisection could not bracket the limit
};

PiCurve pi_curve(const SdofSystem& system, double displacement_limit_m,
                 const PiOptions& options = {});

struct WrOptions {
  blast::Charge charge;    // burst type and model; its mass is what is searched
  double angle_rad = 0.0;  // of the wave to the element's normal
  blast::PulseShape shape = blast::PulseShape::friedlander;
  double relative_tolerance = 1e-3;
  double min_charge_kg = 1e-3;
  double max_charge_kg = 1e6;
};

struct WrPoint {
  double distance_m = 0.0;
  double charge_kg = 0.0;         // TNT-equivalent mass just reaching the limit (0: none in range)
  bool in_validity_range = true;  // the curves' scaled distance range at that mass
};

// The W–R curve: for each stand-off, the charge that just reaches the damage limit.
std::vector<WrPoint> wr_curve(const SdofSystem& system, double displacement_limit_m,
                              const std::vector<double>& distances_m,
                              const WrOptions& options = {});

}  // namespace brisance::response
