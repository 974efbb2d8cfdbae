// sim/response/sdof: the lumped-mass (SDOF) solver — an element's equivalent system under a sum of
// blast pressure histories, integrated piecewise in closed form.
//
// Equation (thesis eq. 2.36 with the equivalent-system factors of Biggs 1964 ch. 5):
//     K_M m y'' + c y' + K_L R(y) = K_L A p(t),   c = 2 zeta sqrt(K_L k K_M m),
// y the displacement of the element's control point (midspan), p the summed pressure.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/response/element.hpp"

namespace brisance::response {

// One pressure history arriving at arrival_s (time since detonation of the first charge, s).
struct LoadComponent {
  double arrival_s = 0.0;
  blast::PressureHistory history;
};

// The pressure on the element: a sum of histories (several charges, or pieces of one).
struct PressureLoad {
  std::vector<LoadComponent> components;

  double pressure_pa(double t_s) const;
  double impulse_pa_s(double t0_s, double t1_s) const;  // exact
  double moment_pa_s2(double t0_s, double t1_s) const;  // exact, integral of (t1 - t) p(t) dt
  double end_s() const;                                 // time after which p = 0
};

// A pulse (sim/blast/pulse) arriving at arrival_s.
LoadComponent pulse_component(const blast::Pulse& pulse, double arrival_s = 0.0);

// The reflected pulse of a charge at distance_m, the wave meeting the element at angle_rad from
// its normal (0: head-on): Kingery–Bulmash parameters (sim/blast/blast_point), oblique reflection
// (sim/blast/reflection), arriving at the curves' arrival time.
LoadComponent charge_component(const blast::Charge& charge, double distance_m, double angle_rad,
                               blast::PulseShape shape = blast::PulseShape::friedlander,
                               const blast::Ambient& air = {});

// The equivalent system of an element (what the solver integrates).
struct SdofSystem {
  double mass_kg = 0.0;            // K_M m
  double damping_n_s_per_m = 0.0;  // c
  double force_per_pa_m2 = 0.0;    // K_L A: equivalent force per unit pressure, m^2
  double load_factor = 1.0;        // K_L, to report the real element's resistance
  Resistance resistance;           // K_L R
  std::optional<double> span_m;

  double natural_period_s() const;  // of the initial stiffness, undamped
  double elastic_limit_m() const { return resistance.elastic_limit_m(); }
};

SdofSystem equivalent_system(const Element& element);

struct SolveOptions {
  double end_time_s = 0.0;  // 0: the load's end plus three natural periods
  double max_step_s = 0.0;  // 0: automatic (T/32 and the pulses' own time scales)
  double load_scale = 1.0;  // multiplies the pressure (used by the P–I bisections)
  bool record_history = true;
  // Stop at the first local maximum of displacement once the load is over (peak response).
  bool stop_after_peak = false;
  // Stop as soon as the displacement exceeds this, m (a P–I bisection only needs "exceeded").
  std::optional<double> stop_above_m;
  double initial_displacement_m = 0.0;
  double initial_velocity_m_s = 0.0;
};

struct HistorySample {
  double time_s = 0.0;
  double displacement_m = 0.0;
  double velocity_m_s = 0.0;
  double resistance_n = 0.0;  // of the real element (R, not K_L R)
};

struct SdofResult {
  std::vector<HistorySample> history;  // at every step end and every event
  double peak_displacement_m = 0.0;    // largest displacement (in the load's direction)
  double time_to_peak_s = 0.0;
  double min_displacement_m = 0.0;             // largest rebound (most negative displacement)
  double permanent_set_m = 0.0;                // centre of the final elastic vibration
  std::optional<double> ductility;             // peak / elastic limit; none for an elastic model
  std::optional<double> support_rotation_deg;  // atan(peak / (span / 2)) when a span is given
  double end_time_s = 0.0;
  std::size_t steps = 0;
  std::size_t events = 0;    // yield, reversal and segment changes located
  std::size_t warnings = 0;  // non-finite state or the step cap reached (result then partial)
};

SdofResult solve_sdof(const SdofSystem& system, const PressureLoad& load,
                      const SolveOptions& options = {});

}  // namespace brisance::response
