// sim/blast/panel_load: the pressure histories a blast wave puts on one panel (thesis §2.6.4 and
// fig. 2.16; DESIGN.md decision 5). Time is measured from the wave's arrival at the panel.
#pragma once

#include "sim/blast/pulse.hpp"

namespace brisance::blast {

// The blast wave where it meets a panel: the curves' values at the panel's distance and the
// oblique reflection at its angle of incidence.
struct PanelWave {
  double incident_overpressure_pa = 0.0;   // P_so
  double incident_impulse_pa_s = 0.0;      // i_s
  double positive_duration_s = 0.0;        // t_o
  double shock_velocity_m_s = 0.0;         // U
  double dynamic_pressure_pa = 0.0;        // q_s
  double reflected_overpressure_pa = 0.0;  // P_r at the angle of incidence
  double reflected_impulse_pa_s = 0.0;     // i_r at the angle of incidence
  double cos_incidence = 1.0;              // cosine of the angle between wave direction and normal
};

struct PanelLoadOptions {
  PulseShape shape = PulseShape::friedlander;
  // Relief of the reflected pressure from the panel's edges (thesis eqs. 2.30–2.31).
  bool clearing = true;
  // S: half the smaller frontal dimension of the loaded body, m. t_c = 3 S / U.
  double clearing_distance_m = 0.0;
  // C_D of eq. 2.32; the front face of a block is about 1 (thesis §2.6.4).
  double drag_coefficient = 1.0;
};

// Side-on overpressure p_s(t) (the incident pulse).
PressureHistory side_on_history(const PanelWave& wave, PulseShape shape);
// Drag loading per unit area, C_D q(t) cos^2(alpha) (eq. 2.32 with the blast wind's component
// along the panel normal); q(t) = q_s (p_s(t) / P_so)^2.
PressureHistory drag_history(const PanelWave& wave, const PanelLoadOptions& options);
// Front-face overpressure. Without clearing: the reflected pulse (peak P_r, impulse i_r).
// With clearing: the reflected pulse blends linearly over t_c = 3 S / U into the stagnation
// pressure p_s(t) + C_D q(t) cos^2(alpha) (eqs. 2.30–2.31). As in UFC 3-340-02 §2-15.3, whichever
// of the cleared and the uncleared curve carries less impulse is used.
PressureHistory front_face_history(const PanelWave& wave, const PanelLoadOptions& options);
// Net translatory pressure on a free body's front panel: front face minus the side-on pressure
// that acts on the body from all sides (thesis fig. 2.16). Without clearing its integral is
// exactly i_r - i_s.
PressureHistory net_translatory_history(const PanelWave& wave, const PanelLoadOptions& options);

}  // namespace brisance::blast
