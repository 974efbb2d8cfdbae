// sim/blast/kingery_bulmash: the Kingery–Bulmash blast curves for TNT (DESIGN.md decision 2).
//
// Polynomial fits of Kingery & Bulmash (1984), "Airblast Parameters from TNT Spherical Air Burst
// and Hemispherical Surface Burst", in the form used by UFC 3-340-02 and ConWep:
//     U = K0 + K1 log10(Z),   log10(Y) = sum_i C_i U^i,
// with Z = R / W^(1/3) in m/kg^(1/3). Time and impulse come scaled by W^(1/3).
#pragma once

namespace brisance::blast {

enum class BurstCurve {
  spherical_free_air,     // charge in free air, no ground reflection
  hemispherical_surface,  // charge on the ground
};

enum class KbParameter {
  incident_overpressure,
  incident_impulse,
  arrival_time,
  positive_duration,
  reflected_overpressure,
  reflected_impulse,
  shock_velocity,
};
inline constexpr int kKbParameterCount = 7;

// Scaled curve values at one scaled distance, SI units.
struct ScaledBlast {
  double incident_overpressure_pa = 0.0;     // P_so
  double incident_impulse_pa_s_kg13 = 0.0;   // i_s / W^(1/3)
  double arrival_time_s_kg13 = 0.0;          // t_a / W^(1/3)
  double positive_duration_s_kg13 = 0.0;     // t_o / W^(1/3)
  double reflected_overpressure_pa = 0.0;    // P_r, normal incidence
  double reflected_impulse_pa_s_kg13 = 0.0;  // i_r / W^(1/3), normal incidence
  double shock_velocity_m_s = 0.0;           // U
  // False if Z lies outside the fitted range of any parameter; see kingery_bulmash().
  bool in_validity_range = true;
};

struct ScaledRange {
  double min_m_kg13;
  double max_m_kg13;
};

// The fitted range of one parameter.
ScaledRange kingery_bulmash_range(BurstCurve curve, KbParameter parameter);

// All seven parameters at scaled distance z (m/kg^(1/3), > 0).
//
// Outside a parameter's fitted range the value is flagged (in_validity_range = false) and
// continued without running the polynomial past its data:
//  - closer than the range: pressures, impulses, duration and velocity keep their value at the
//    range's near end (an underestimate near the charge); arrival time shrinks in proportion to Z;
//  - farther than the range: overpressures, impulses and the duration continue as the power law
//    through the last octave of the fit (pressures fall about as Z^-1.37, impulses as Z^-1.02,
//    duration grows as Z^0.27 between Z = 20 and 40); arrival time grows at the far-end shock
//    velocity (about the speed of sound) and the velocity keeps its far-end value.
ScaledBlast kingery_bulmash(BurstCurve curve, double z);

// One parameter, in the units of ScaledBlast; `in_range` (optional) tells whether z was inside.
double kingery_bulmash_value(BurstCurve curve, KbParameter parameter, double z,
                             bool* in_range = nullptr);

}  // namespace brisance::blast
