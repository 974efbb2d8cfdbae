// sim/blast/blast_point: the full set of blast parameters of a charge at a distance, in SI — what
// `brisance blast` and `GET /v1/blast` print and what the simulator loads panels with.
#pragma once

#include "sim/blast/air.hpp"
#include "sim/blast/kingery_bulmash.hpp"

namespace brisance::blast {

enum class Burst {
  air,      // free-air spherical burst
  surface,  // charge on the ground
};

// How a surface burst is modelled (DESIGN.md decision 1).
enum class SurfaceBurstModel {
  hemispherical,  // the Kingery–Bulmash hemispherical surface-burst curves (default)
  factor_1_8,     // free-air curves with 1.8 times the charge (thesis §2.5.1, the older shortcut)
};

struct Charge {
  double tnt_equivalent_kg = 1.0;  // W = mass * TNT equivalence factor, > 0
  Burst burst = Burst::air;
  SurfaceBurstModel surface_model = SurfaceBurstModel::hemispherical;
  // W for impulses (UFC 3-340-02 eq. 2-5) where the explosive has its own impulse factor;
  // 0: the same as tnt_equivalent_kg.
  double impulse_tnt_equivalent_kg = 0.0;
};

// Everything the curves give at one distance; impulses and times are absolute (not scaled).
struct BlastPoint {
  double scaled_distance_m_kg13 = 0.0;  // Z = R / W^(1/3), with the W the curves are entered with
  double tnt_equivalent_kg = 0.0;       // W of the charge (before the 1.8 surface factor)
  double impulse_tnt_equivalent_kg = 0.0;  // W the impulses are computed with
  double incident_overpressure_pa = 0.0;
  double incident_impulse_pa_s = 0.0;
  double arrival_time_s = 0.0;
  double positive_duration_s = 0.0;
  double reflected_overpressure_pa = 0.0;  // normal incidence
  double reflected_impulse_pa_s = 0.0;     // normal incidence
  double shock_velocity_m_s = 0.0;
  double dynamic_pressure_pa = 0.0;  // q_s, Rankine–Hugoniot (thesis eq. 2.17)
  bool in_validity_range = true;     // Z inside every fitted range
};

// The curve and the charge mass the curves are entered with for this charge: for pressures,
// arrival and duration, and for impulses.
BurstCurve curve_for(const Charge& charge);
double curve_charge_kg(const Charge& charge);
double curve_impulse_charge_kg(const Charge& charge);

// Pressures and times come from the pressure equivalence, impulses (incident and reflected)
// from the impulse equivalence.

// All parameters at distance_m (> 0) from the charge.
BlastPoint blast_point(const Charge& charge, double distance_m, const Ambient& air = {});

// How far the wave has travelled by time_s (> 0) after the detonation, m: a distance whose
// arrival time is at least time_s, within a part in 1e6 of the least such (the arrival time
// grows with the distance). Everything farther is reached only later.
double wave_reach_m(const Charge& charge, double time_s, const Ambient& air = {});

}  // namespace brisance::blast
