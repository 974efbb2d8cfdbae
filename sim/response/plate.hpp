// sim/response/plate: a rectangular plate simply supported on four edges (a window pane) as a
// nonlinear lumped-mass (SDOF) system with membrane stiffening, and the peak centre stress it
// reaches under a pressure history. What a glazing tool does instead of a static plate formula.
//
// Resistance (total load on the plate against its centre deflection w), large deflections:
//     R(w) = k1 w + k3 w^3
// * k1 from the small-deflection solution the caller supplies (Roark's Formulas, 7th ed., table
//   11.4 case 1a: w = alpha q b^4 / (E t^3)), so the small-deflection end is that table's exact
//   series solution: k1 = A E t^3 / (alpha b^4), A = a b.
// * k3 from the one-term Galerkin solution of von Kármán's plate equations, edges simply supported
//   and held (in-plane displacement zero on average along each edge): the Duffing coefficient of
//   N. Yamaki (1961) "Influence of large amplitudes on flexural vibrations of elastic plates",
//   ZAMM 41, as used for blast loading by V. R. Feldgun, D. Z. Yankelevsky, Y. S. Karinski (2016)
//   "A nonlinear SDOF model for blast response simulation of elastic thin rectangular plates",
//   Int. J. Impact Eng. 88. With w = W sin(pi x/a) sin(pi y/b) the membrane term is
//     C3 W^3,  C3 = pi^4 E t [ (1/a^4 + 1/b^4) / 16 + (1/a^4 + 2 nu/(a^2 b^2) + 1/b^4) / (8 (1 -
//     nu^2)) ]
//   per unit area, against (16/pi^2) q of the load: k3 = A (pi^2/16) C3.
// Centre stress along the short span (where the small-deflection stress is largest):
//     sigma(w) = (beta/alpha) E t |w| / b^2                                         (bending)
//              + (pi^2 E w^2 / 8) [ (1/b^2 + nu/a^2) / (1 - nu^2) + 1/b^2 ]          (membrane)
// the bending part is Roark's beta/alpha (exact at small deflection), the membrane part the
// one-term solution's mid-surface stress at the centre (its Airy function plus the edge tension
// that holds the edges).
// Equivalent system (Biggs 1964 ch. 5, sim/response/factors): K_M m w'' + K_L R(w) = K_L A p(t),
// with the elastic factors of the plate's static deflected shape at its own b/a (Navier series,
// factors.hpp; towards the one-way strip as b/a -> 0). One set of factors throughout: the mode
// shape's change under membrane action is not modelled.
#pragma once

#include <cmath>
#include <cstddef>

#include "sim/response/sdof.hpp"

namespace brisance::response {

struct PlateSpec {
  double width_m = 1.0;
  double height_m = 1.0;
  double thickness_m = 0.006;
  double youngs_modulus_pa = 70e9;
  // Roark's table is for nu = 0.3; the membrane term takes the same value (glass: 0.22).
  double poissons_ratio = 0.3;
  double density_kg_m3 = 2500.0;
  // The small-deflection coefficients at this plate's aspect ratio: w = alpha q b^4 / (E t^3),
  // sigma = beta q b^2 / t^2, b the shorter side (Roark table 11.4 case 1a, fracture::roark_*).
  double small_deflection_alpha = 0.0444;
  double small_deflection_beta = 0.2874;
};

// The plate's lumped model (real-element terms; the solver applies K_L and K_M).
struct PlateModel {
  double area_m2 = 0.0;
  double mass_kg = 0.0;
  double load_factor = 1.0;                // K_L
  double mass_factor = 1.0;                // K_M
  double linear_stiffness_n_per_m = 0.0;   // k1
  double cubic_stiffness_n_per_m3 = 0.0;   // k3
  double bending_stress_pa_per_m = 0.0;    // sigma_b / |w|
  double membrane_stress_pa_per_m2 = 0.0;  // sigma_m / w^2

  double resistance_n(double deflection_m) const;
  // Largest principal stress at the centre (bending + membrane, tension face), Pa.
  double centre_stress_pa(double deflection_m) const;
  // The static large-deflection solution: R(w) = A p, solved for w >= 0, m.
  double static_deflection_m(double pressure_pa) const;
  // Of the small-deflection stiffness, s.
  double natural_period_s() const;
};

PlateModel plate_model(const PlateSpec& spec);

struct PlateSolveOptions {
  double end_time_s = 0.0;  // 0: the load's end plus one small-deflection period
  double load_scale = 1.0;  // multiplies the pressure (breaking-pressure bisections)
  double tolerance = 1e-9;  // local error per step, relative to the largest |w| so far (v: x omega)
  std::size_t max_steps = 2000000;  // a cap; reaching it is a warning, the result partial
  // The stress at which the plate breaks (a pane's strength), Pa: the result gives when the
  // centre stress first reaches it and the centre velocity then. Infinite: not looked for.
  double break_stress_pa = INFINITY;
};

struct PlateSdofResult {
  double peak_deflection_m = 0.0;  // largest |w| over the history
  double time_to_peak_s = 0.0;
  double peak_stress_pa = 0.0;  // centre_stress_pa(peak_deflection_m)
  std::size_t steps = 0;
  std::size_t rejected_steps = 0;
  std::size_t warnings = 0;  // non-finite state or the step cap
  // The first time the centre stress reaches options.break_stress_pa (-1: never), s, on the
  // load's clock, and the centre velocity dw/dt then, m/s (from the step's cubic Hermite
  // interpolant, as the peak).
  double break_time_s = -1.0;
  double break_velocity_m_s = 0.0;
};

// Integrates K_M m w'' + K_L R(w) = K_L A s p(t) from rest with an error-controlled
// Dormand–Prince 5(4) Runge–Kutta scheme, restarting at every kink of the load (arrivals, piece
// ends); the peak |w| inside a step comes from the step's cubic Hermite interpolant.
PlateSdofResult solve_plate(const PlateModel& model, const PressureLoad& load,
                            const PlateSolveOptions& options = {});

}  // namespace brisance::response
