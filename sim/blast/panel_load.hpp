// sim/blast/panel_load: the pressure histories a blast wave puts on one panel, face by face
// (thesis §2.6.4 and fig. 2.13; UFC 3-340-02 §2-15.3 for a closed rectangular body; DESIGN.md
// decision 5). Time is measured from the wave's arrival at the panel. A body's net push is the
// sum of its faces' loads: nothing here assumes which faces a body has.
#pragma once

#include "sim/blast/air.hpp"
#include "sim/blast/blast_point.hpp"
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

// The wave of `point` meeting a panel at `cos_incidence` (clamped to [0, 1]), with the reflected
// peak and impulse at that angle (oblique reflection; 0 where the wave does not strike the face).
PanelWave panel_wave(const BlastPoint& point, double cos_incidence,
                     double reflected_overpressure_pa = 0.0, double reflected_impulse_pa_s = 0.0);

struct PanelLoadOptions {
  PulseShape shape = PulseShape::friedlander;
  // Relief of the reflected pressure from the panel's edges (thesis eqs. 2.30–2.31).
  bool clearing = true;
  // S: half the smaller dimension of the surface the panel lies in, m. A front face clears in
  // t_c = 3 S / U; a rear face fills in 3 S / U (thesis §2.6.4, "Rear Face").
  double clearing_distance_m = 0.0;
  // How much later the wave reaches the edge the relief runs from than this panel, s. Relief
  // starts at an edge only once the wave is there: a far charge's wave meets a face at once (0),
  // a close charge's sweeps out across it from the point nearest the charge, and the panels it
  // reaches first stay reflected that much longer. Added to t_c.
  double clearing_delay_s = 0.0;
  // The panel's own extent, m: a side face's pressure rises while the wave crosses it.
  double panel_extent_m = 0.0;
  // C_D of eq. 2.32 for a front face; the front face of a block is about 1 (thesis §2.6.4).
  double drag_coefficient = 1.0;
};

// How the wave meets a face, from the cosine of its angle of incidence (the angle between the
// wave's direction and the face's inward normal): head-on to grazing from the front, grazing
// (within kSideBand of 90°), or from behind, after wrapping around the body.
enum class FaceKind : unsigned char { front, side, rear };
inline constexpr double kSideBand = 0.1;  // |cos α| ≤ 0.1: within 5.7° of grazing
FaceKind face_kind(double cos_incidence);

// Drag coefficients of the faces the wave does not strike head-on, UFC 3-340-02 table 2-3: side
// walls and roof -0.40 for a peak dynamic pressure up to 25 psi (172 kPa), -0.30 to 50 psi
// (345 kPa), -0.20 beyond; rear wall -0.25 to -0.50, of which Brisance takes the middle.
double side_drag_coefficient(double dynamic_pressure_pa);
inline constexpr double kRearDragCoefficient = -0.375;

// Side-on overpressure p_s(t) (the incident pulse).
PressureHistory side_on_history(const PanelWave& wave, PulseShape shape);
// Drag loading per unit area, C_D q(t) cos^2(alpha) (eq. 2.32 with the blast wind's component
// along the panel normal); q(t) = q_s (p_s(t) / P_so)^2.
PressureHistory drag_history(const PanelWave& wave, const PanelLoadOptions& options);
// Front-face overpressure. Without clearing: the reflected pulse (peak P_r, impulse i_r).
// With clearing: the reflected pulse blends linearly over t_c = 3 S / U (plus the clearing delay)
// into the stagnation
// pressure p_s(t) + C_D q(t) cos^2(alpha) (eqs. 2.30–2.31). As in UFC 3-340-02 §2-15.3, whichever
// of the cleared and the uncleared curve carries less impulse is used.
PressureHistory front_face_history(const PanelWave& wave, const PanelLoadOptions& options);
// A face the wave grazes (thesis fig. 2.13, middle; UFC 3-340-02 §2-15.3.3): the side-on
// pressure plus the side drag, p_s(t) + C_D q(t), rising linearly while the wave crosses the
// panel (panel_extent / U).
PressureHistory side_face_history(const PanelWave& wave, const PanelLoadOptions& options);
// A face the wave reaches from behind (thesis fig. 2.13, bottom; UFC 3-340-02 §2-15.3.4): from
// the wave's arrival at the face (its straight path through the body, which is the length of
// the body it wrapped around), p_s(t) + C_D q(t) with the rear drag coefficient, building up
// linearly over 3 S / U as the wave closes in from the face's edges.
PressureHistory rear_face_history(const PanelWave& wave, const PanelLoadOptions& options);
// PanelLoadOptions::clearing_delay_s of a front panel h off its face's plane and rho along it
// from the charge's foot on that plane, in a surface of clearing distance S: on the line from the
// foot through the panel, the wave reaches the edges S beyond and S before the panel (at
// hypot(h, rho + S) and hypot(h, |rho - S|) from the charge); the relief starts from whichever it
// reaches first, and the delay is that arrival less the panel's (Kingery–Bulmash arrival times),
// never negative. A far charge's wave is nearly planar over the face, and a panel the wave reaches
// after an edge clears as the plane wave's: both give (nearly) 0; a charge close before the face
// gives its middle a delay of the order of t_c.
double clearing_delay_s(const Charge& charge, double h_m, double rho_m, double clearing_distance_m);

// The history of one face kind.
PressureHistory face_history(FaceKind kind, const PanelWave& wave, const PanelLoadOptions& options);

// The blast wind at a point: the air behind the front moves away from the charge with the
// particle velocity of the Rankine–Hugoniot relations (rh_particle_velocity_m_s; for gamma = 1.4
// u_s = (5 P_so / (7 p0)) a0 / sqrt(1 + 6 P_so / (7 p0)), as in G. F. Kinney & K. J. Graham,
// Explosive Shocks in Air, 2nd ed., Springer 1985), decaying over the positive phase as the
// overpressure does, u(t) = u_s p_s(t) / P_so: the decay the drag loads' dynamic pressure
// q(t) = q_s (p_s(t) / P_so)^2 is built from (q = rho u^2 / 2). Zero before the arrival and after
// the positive phase. Times since detonation.
struct BlastWind {
  double arrival_s = 0.0;
  double peak_velocity_m_s = 0.0;  // u_s
  Pulse incident;                  // p_s(t), time since arrival

  double velocity_m_s(double t_s) const;
  double end_s() const { return arrival_s + incident.duration_s; }
};
BlastWind blast_wind(const BlastPoint& point, PulseShape shape, const Ambient& air = {});

}  // namespace brisance::blast
