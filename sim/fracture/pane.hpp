// sim/fracture/pane: coupling a pane to the blast (DESIGN.md decision 9) — the bending stress of
// a rectangular plate under the peak reflected pressure, whether it breaks, and the crack
// pattern's scale from the critical crack length (thesis eq. 5.5). Standalone: no engine or scene.
// Units: SI (m, Pa).
#pragma once

#include <cstdint>

namespace brisance::fracture {

// Roark's Formulas for Stress and Strain (Young & Budynas, 7th ed., 2002), table 11.4, case 1a:
// a rectangular plate, all edges simply supported, uniform pressure q, Poisson's ratio 0.3.
// With a the longer and b the shorter side and t the thickness,
//   sigma_max = beta(a/b) q b^2 / t^2   (at the centre, along the short span),
//   y_max     = alpha(a/b) q b^4 / (E t^3).
// beta and alpha are interpolated linearly in a/b between the table's rows (1, 1.2, ..., 5, inf).
// Small-deflection theory: it holds while y_max stays below about half the thickness; beyond it
// membrane action carries part of the load and the true stress is lower (Roark §11.11).
double roark_beta(double aspect_ratio);
double roark_alpha(double aspect_ratio);

// The terminal speed of a running crack in soda-lime (window) glass, m/s: about 1 500 m/s, the
// limiting velocity H. Schardin measured with high-speed photography of cracks in plate glass
// ("Velocity effects in fracture", in B. L. Averbach et al. (eds.), Fracture, 1959). A broken
// pane's cracks run out from their nucleation points at this speed (engine::break_pane).
inline constexpr double kTerminalCrackSpeed_m_s = 1500.0;

struct PlateResponse {
  double stress_pa = 0.0;        // sigma_max
  double deflection_m = 0.0;     // y_max
  bool small_deflection = true;  // y_max <= t / 2: the table's theory applies
  // A dynamic model's break: when the stress first reached the strength (s on the load's clock;
  // -1: never, or a static model) and the plate's centre velocity then, m/s.
  double break_time_s = -1.0;
  double break_velocity_m_s = 0.0;
};
PlateResponse simply_supported_plate(double width_m, double height_m, double thickness_m,
                                     double pressure_pa, double youngs_modulus_pa);

// What the blast does to a pane: does it break, and at what pattern scale.
struct PaneFractureInput {
  double width_m = 1.0;
  double height_m = 1.0;
  double thickness_m = 0.006;
  double youngs_modulus_pa = 70e9;
  double fracture_toughness_pa_sqrt_m = 0.75e6;  // K_c
  double strength_pa = 45e6;                     // bending strength
  double pressure_pa = 0.0;                      // peak reflected overpressure on the pane
  // The pattern's growth length is pattern_scale x a_c (see PaneFracture::growth_length_m).
  double pattern_scale = 5000.0;
  // Clamp of the growth length, m (the bit bucket's resolution below, the pane's size above).
  double min_growth_length_m = 0.0;
  double max_growth_length_m = 1.0;
};

struct PaneFracture {
  PlateResponse plate;
  bool breaks = false;  // stress above strength
  // a_c = (1/pi) (K_c / sigma)^2 (thesis eq. 5.5): the critical flaw length at that stress, m.
  // For glass it is micrometres; 0 if the pane does not break.
  double critical_crack_length_m = 0.0;
  // The crack pattern's growth length between forks, m: pattern_scale x a_c, clamped. It keeps
  // eq. 5.5's law (proportional to sigma^-2: higher pressure, smaller fragments) at a scale the
  // bit bucket and a renderer can hold.
  double growth_length_m = 0.0;
  bool clamped = false;  // the growth length hit a clamp: the pressure no longer changes it
};
// Judged by the static small-deflection plate above under input.pressure_pa.
PaneFracture pane_fracture(const PaneFractureInput& input);
// Judged by a plate response found elsewhere (the engine's dynamic plate model): its stress
// against the strength, and eq. 5.5's scale at that stress.
PaneFracture pane_fracture(const PaneFractureInput& input, const PlateResponse& plate);

// Empirical glass fragments of window panes (thesis §2.11, cited from [4]), SI units:
// mean frontal area A' (eq. 2.45), m^2, and mean velocity v (eq. 2.46), m/s, for the peak
// pressure P_e on the pane (P_r for a window facing the charge), Pa, and the thickness h, m.
// Eq. 2.46 is stated for h >= 0.762 mm and 690 Pa <= P_e <= 689 kPa.
double empirical_fragment_area_m2(double peak_pressure_pa);
double empirical_fragment_velocity_m_s(double peak_pressure_pa, double thickness_m);

}  // namespace brisance::fracture
