// sim/response/resistance: resistance functions of a lumped-mass (SDOF) element — the backbone
// (envelope) each one follows while loading, elastic unloading and reloading inside it, and the
// strain energy along the backbone that the P–I asymptotes are built from.
//
// Every model is piecewise linear, so the SDOF solver can integrate each branch in closed form
// (sdof.hpp). The hysteresis rule is the bounding-envelope one used for SDOF blast analysis in
// Biggs (1964) "Introduction to Structural Dynamics" ch. 2 and UFC 3-340-02 §3-19: load along the
// envelope while the velocity is positive, unload and reload with the initial stiffness, which
// leaves a permanent set.
#pragma once

#include <array>
#include <cstddef>

namespace brisance::response {

enum class ResistanceType {
  elastic,          // R = k x, no limit
  elastic_plastic,  // k up to R_y, then a plateau at +-R_y
  bilinear,         // k up to R_y, then hardening stiffness k_2 (0 <= k_2 < k), both directions
  membrane,         // elastic–plastic, then a tension-membrane branch of stiffness k_m beyond an
                    // onset displacement, in the loading (+) direction only (see resistance.cpp)
};

// The settings of a resistance function, in the real element's terms (the equivalent system's
// factors are applied by the solver). Validated by parse_element (element.hpp).
struct ResistanceSpec {
  ResistanceType type = ResistanceType::elastic;
  double stiffness_n_per_m = 0.0;            // initial (elastic) stiffness k, > 0
  double yield_resistance_n = 0.0;           // R_y, > 0 (all but elastic)
  double hardening_stiffness_n_per_m = 0.0;  // bilinear: k_2 in [0, k)
  double membrane_onset_m = 0.0;             // membrane: displacement where it starts, >= R_y / k
  double membrane_stiffness_n_per_m = 0.0;   // membrane: k_m in (0, k)
};

// One straight piece of an envelope, valid from start_m up to the next segment's start (the first
// segment extends to -infinity so an elastic line from any permanent set meets it).
struct EnvelopeSegment {
  double start_m = 0.0;                // displacement where the segment starts, m
  double resistance_at_start_n = 0.0;  // N
  double slope_n_per_m = 0.0;          // N/m, < initial stiffness
};

// The envelope on one side, written for the loading direction (+); the rebound side is mirrored.
struct Envelope {
  static constexpr std::size_t kMaxSegments = 3;
  std::array<EnvelopeSegment, kMaxSegments> segments{};
  std::size_t count = 0;  // 0: no envelope (elastic)

  // Segment containing x_m (the last one whose start is <= x_m, or the first).
  std::size_t segment_at(double x_m) const;
  double resistance_n(double x_m) const;
  // Where the elastic line R = k (x - set_m) meets the envelope, m (+infinity when count == 0).
  double elastic_meet_m(double stiffness_n_per_m, double set_m) const;
};

// A resistance function ready for the solver.
struct Resistance {
  double stiffness_n_per_m = 0.0;
  Envelope loading;  // + side
  Envelope rebound;  // - side, mirrored: R(-x) = -rebound.resistance_n(x)

  // Strain energy along the loading envelope (elastic line up to the first meet, then the
  // envelope) from 0 to x_m >= 0, J. The energy the impulsive asymptote equates to.
  double backbone_energy_j(double x_m) const;
  // Resistance on the loading backbone at x_m >= 0, N.
  double backbone_resistance_n(double x_m) const;
  // Displacement where the backbone leaves the elastic line, m (+infinity for elastic).
  double elastic_limit_m() const;
};

Resistance make_resistance(const ResistanceSpec& spec);

}  // namespace brisance::response
