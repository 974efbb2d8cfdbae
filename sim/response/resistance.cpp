// sim/response/resistance: envelopes of the resistance functions and their strain energy.
#include "sim/response/resistance.hpp"

#include <cassert>
#include <limits>

namespace brisance::response {

std::size_t Envelope::segment_at(double x_m) const {
  std::size_t i = 0;
  while (i + 1 < count && segments[i + 1].start_m <= x_m)
    ++i;
  return i;
}

double Envelope::resistance_n(double x_m) const {
  const EnvelopeSegment& s = segments[segment_at(x_m)];
  return s.resistance_at_start_n + s.slope_n_per_m * (x_m - s.start_m);
}

double Envelope::elastic_meet_m(double stiffness_n_per_m, double set_m) const {
  if (count == 0) return std::numeric_limits<double>::infinity();
  // D(x) = envelope(x) - k (x - set) falls strictly (every slope < k), so the meet is unique: it
  // lies on the first segment whose line meets the elastic line before the next segment starts.
  for (std::size_t i = 0; i < count; ++i) {
    const EnvelopeSegment& s = segments[i];
    const double meet_m =
        (s.resistance_at_start_n - s.slope_n_per_m * s.start_m + stiffness_n_per_m * set_m) /
        (stiffness_n_per_m - s.slope_n_per_m);
    if (i + 1 == count || meet_m < segments[i + 1].start_m) return meet_m;
  }
  return std::numeric_limits<double>::infinity();
}

double Resistance::elastic_limit_m() const {
  return loading.elastic_meet_m(stiffness_n_per_m, 0.0);
}

double Resistance::backbone_resistance_n(double x_m) const {
  const double limit_m = elastic_limit_m();
  return x_m <= limit_m ? stiffness_n_per_m * x_m : loading.resistance_n(x_m);
}

double Resistance::backbone_energy_j(double x_m) const {
  const double limit_m = elastic_limit_m();
  if (x_m <= limit_m) return 0.5 * stiffness_n_per_m * x_m * x_m;
  double energy_j = 0.5 * stiffness_n_per_m * limit_m * limit_m;
  // Trapezoids are exact on each straight piece between the elastic limit and x_m.
  double from_m = limit_m;
  for (std::size_t i = loading.segment_at(limit_m); i < loading.count; ++i) {
    const double end_m = (i + 1 < loading.count) ? loading.segments[i + 1].start_m : x_m;
    const double to_m = end_m < x_m ? end_m : x_m;
    if (to_m > from_m) {
      energy_j +=
          0.5 * (loading.resistance_n(from_m) + loading.resistance_n(to_m)) * (to_m - from_m);
      from_m = to_m;
    }
    if (to_m >= x_m) break;
  }
  return energy_j;
}

Resistance make_resistance(const ResistanceSpec& spec) {
  assert(spec.stiffness_n_per_m > 0.0);
  Resistance r;
  r.stiffness_n_per_m = spec.stiffness_n_per_m;
  if (spec.type == ResistanceType::elastic) return r;
  const double yield_m = spec.yield_resistance_n / spec.stiffness_n_per_m;
  const double k2 = spec.type == ResistanceType::bilinear ? spec.hardening_stiffness_n_per_m : 0.0;
  r.loading.segments[0] = {yield_m, spec.yield_resistance_n, k2};
  r.loading.count = 1;
  r.rebound = r.loading;
  if (spec.type == ResistanceType::membrane) {
    // Tension-membrane stiffening: beyond the onset displacement a laterally restrained element
    // carries load as a membrane in tension. Idealised here as one straight rising branch after the
    // plastic plateau — the trilinear shape UFC 3-340-02 ch. 4 draws for the tension-membrane
    // region of restrained slabs; the onset and k_m are inputs, not derived from the section. The
    // membrane is in tension only in the loading direction, so the rebound side stays
    // elastic–perfectly-plastic. (Rejected: a cubic string law R ~ x^3, which is not piecewise
    // linear and would cost the closed-form integration.)
    r.loading.segments[1] = {spec.membrane_onset_m, spec.yield_resistance_n,
                             spec.membrane_stiffness_n_per_m};
    r.loading.count = 2;
  }
  return r;
}

}  // namespace brisance::response
