// sim/blast/air: the ambient air the blast curves assume and the Rankine–Hugoniot relations for a
// shock in it (thesis §2.4, eqs. 2.15–2.17 and 2.28–2.29; ideal gas, gamma = 1.4).
#pragma once

namespace brisance::blast {

// Ambient conditions. The Kingery–Bulmash fits are for sea level; these defaults match them
// (ICAO standard atmosphere at sea level: 101.325 kPa, 288.15 K, 1.225 kg/m^3, 340.3 m/s).
struct Ambient {
  double pressure_pa = 101325.0;
  double density_kg_m3 = 1.225;
  double sound_speed_m_s = 340.29;
  double gamma = 1.4;
};

// Shock front velocity for a peak overpressure, thesis eq. 2.15 (m/s).
double rh_shock_velocity_m_s(double overpressure_pa, const Ambient& air = {});
// Air density right behind the front, thesis eq. 2.16 (kg/m^3).
double rh_density_behind_kg_m3(double overpressure_pa, const Ambient& air = {});
// Peak dynamic pressure q_s = rho u^2 / 2 behind the front, thesis eq. 2.17 (Pa).
double rh_dynamic_pressure_pa(double overpressure_pa, const Ambient& air = {});
// Particle velocity behind the front, from mass and momentum conservation (eqs. 2.1–2.2), m/s.
double rh_particle_velocity_m_s(double overpressure_pa, const Ambient& air = {});
// Normally reflected overpressure of an ideal-gas shock, thesis eq. 2.29 (Pa). Real air at high
// pressure reflects more strongly (C_R well above 8); the Kingery–Bulmash P_r fit has that.
double rh_reflected_overpressure_pa(double overpressure_pa, const Ambient& air = {});

// Alternative peak-overpressure equations kept for comparison (thesis §2.4.2). Both take the
// scaled distance Z = R / W^(1/3) in m/kg^(1/3) and return Pa; `in_range` says whether the
// result lies inside the range the equation was published for.
struct EmpiricalOverpressure {
  double overpressure_pa = 0.0;
  bool in_range = false;
};
// Brode: eq. 2.20 above 10 bar, eq. 2.21 between 0.1 and 10 bar.
EmpiricalOverpressure brode_overpressure(double scaled_distance_m_kg13);
// Henrych: eqs. 2.22–2.24 for 0.05 <= Z <= 10 (near, middle and far field).
EmpiricalOverpressure henrych_overpressure(double scaled_distance_m_kg13);

}  // namespace brisance::blast
