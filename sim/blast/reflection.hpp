// sim/blast/reflection: reflection of the blast wave at an angle (DESIGN.md decision 3).
//
// The reflected pressure coefficient C_R(alpha, P_so) = P_r(alpha) / P_so of UFC 3-340-02
// fig. 2-193 (thesis fig. 3.3), with its rise at the Mach-stem transition, interpolated linearly
// in alpha and in log P_so. alpha is the angle between the direction the wave travels and the
// surface normal: 0 is head-on, 90 degrees is grazing (C_R = 1).
#pragma once

namespace brisance::blast {

struct ChartValue {
  double value = 0.0;
  bool in_range = true;  // P_so inside the chart's pressure range (else clamped to its edge)
};

// C_R straight from the chart. angle_rad in [0, pi/2].
ChartValue chart_reflection_coefficient(double incident_overpressure_pa, double angle_rad);

// i_r(alpha) / i_r(0) straight from UFC 3-340-02 fig. 2-194, interpolated in alpha and log P_so.
ChartValue chart_impulse_ratio(double incident_overpressure_pa, double angle_rad);

struct ObliqueReflection {
  double coefficient = 1.0;      // P_r(alpha) / P_so
  double overpressure_pa = 0.0;  // P_r(alpha)
  double impulse_pa_s = 0.0;     // i_r(alpha)
  bool in_chart_range = true;
};

// Reflected pressure and impulse at angle_rad, given the incident values and the normally
// reflected values of the blast curves. The chart sets the angular shape; it is scaled so that at
// alpha = 0 the result is exactly the curves' P_r, and it falls to P_so at 90 degrees. The
// reflected impulse follows the same reflection factor between i_s and i_r (see reflection.cpp).
ObliqueReflection oblique_reflection(double incident_overpressure_pa, double incident_impulse_pa_s,
                                     double normal_reflected_pa,
                                     double normal_reflected_impulse_pa_s, double angle_rad);

}  // namespace brisance::blast
