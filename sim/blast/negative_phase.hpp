// sim/blast/negative_phase: the suction that follows a blast wave's positive phase.
//
// Peak underpressure and negative impulse are the curves of UFC 3-340-02 (2008) for the negative
// phase of spherical free-air and hemispherical surface bursts of TNT, as fitted piecewise in
// Z = R / W^(1/3) by Rigby, Tyas, Bennett, Clarke & Fay (2014), "The negative phase of the blast
// load", Int. J. Protective Structures 5(1) 1-19. The pressure follows the cubic of NAVFAC DM-2.08
// eq. 14a (Granström 1956),
//     p(t) = -P (27/4) (t/T) (1 - t/T)^2,   0 <= t <= T,
// whose area is 9/16 P T; T is taken as 16/9 i / P so that the peak and the impulse are the
// curves' own (the charts' separate duration curve is returned beside it for comparison).
#pragma once

#include "sim/blast/blast_point.hpp"

namespace brisance::blast {

struct NegativePhase {
  double underpressure_pa = 0.0;  // peak suction below ambient, > 0
  double impulse_pa_s = 0.0;      // area of the suction, > 0
  double duration_s = 0.0;        // of the cubic: 16/9 impulse / underpressure
  double chart_duration_s = 0.0;  // the UFC chart's own duration curve (Rigby et al. fit)
  bool in_validity_range = true;  // Z within the charts (up to 40 m/kg^(1/3))

  // Gauge pressure (negative) at time t_s after the positive phase ends; 0 outside the phase.
  double pressure_pa(double t_s) const;
};

// The incident negative phase of a charge at distance_m (> 0). Peak underpressure and duration
// use the charge's pressure equivalence, the impulse its impulse equivalence (UFC eqs. 2-4, 2-5).
NegativePhase negative_phase(const Charge& charge, double distance_m);

}  // namespace brisance::blast
