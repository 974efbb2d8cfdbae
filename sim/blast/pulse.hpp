// sim/blast/pulse: pressure pulses and pressure histories with exact integrals.
//
// Every pressure-time curve in Brisance (Friedlander and triangular pulses, dynamic pressure,
// the cleared front face, the net translatory load) is a short sum of pieces of the form
//     p(t) = sum_k c_k u^k exp(-rate u),   u = (t - origin_s) / scale_s,   t in [begin_s, end_s],
// with t the time since the wave's arrival. Such pieces have closed-form integrals over any
// interval, which is what lets the simulator step impulse-exactly (DESIGN.md decision 6).
#pragma once

#include <array>
#include <cstddef>

namespace brisance::blast {

// One exponential-polynomial piece of a pressure history (see the header comment).
struct ExpPolyPiece {
  static constexpr int kMaxDegree = 3;
  double begin_s = 0.0;   // window start, time since arrival, s
  double end_s = 0.0;     // window end, s (the piece is zero outside [begin_s, end_s])
  double origin_s = 0.0;  // where u = 0, s
  double scale_s = 1.0;   // time per unit of u, s (> 0)
  double rate = 0.0;      // exponential decay per unit of u (>= kMinRate)
  std::array<double, kMaxDegree + 1> coeff_pa{};  // polynomial coefficients in u, Pa

  // Lowest decay rate the integrals are accurate for (a rising exponential, see Friedlander fit).
  static constexpr double kMinRate = -2.0;

  double pressure_pa(double t_s) const;
  // Exact integral of the piece over [t0_s, t1_s] (any interval; clipped to the window), Pa*s.
  double impulse_pa_s(double t0_s, double t1_s) const;
  // Exact first moment about the interval's end, integral of (t1 - t) p(t) dt over [t0, t1],
  // Pa*s^2: how far a load displaces a body within the step, beyond its impulse.
  double moment_pa_s2(double t0_s, double t1_s) const;
};

// A pressure history: a fixed-capacity sum of pieces, so it lives inline in per-panel arrays.
class PressureHistory {
 public:
  static constexpr std::size_t kCapacity = 6;

  void add(const ExpPolyPiece& piece);
  // Multiplies every piece by a constant factor (attenuation, drag coefficient, ...).
  void scale(double factor);

  double pressure_pa(double t_s) const;
  // Exact integral over [t0_s, t1_s], Pa*s; t is time since arrival (negative times give zero).
  double impulse_pa_s(double t0_s, double t1_s) const;
  // Exact integral of (t1 - t) p(t) over [t0_s, t1_s], Pa*s^2.
  double moment_pa_s2(double t0_s, double t1_s) const;
  double total_impulse_pa_s() const;
  // Time after which the history is zero, s.
  double end_s() const;

  std::size_t size() const { return count_; }
  const ExpPolyPiece& piece(std::size_t i) const { return pieces_[i]; }

 private:
  std::array<ExpPolyPiece, kCapacity> pieces_{};
  std::size_t count_ = 0;
};

// The shapes a positive phase can take.
enum class PulseShape {
  friedlander,            // p(t) = P (1 - t/T) exp(-b t/T), b solved so the area is the impulse
  triangle_same_impulse,  // thesis fig. 2.9 line II: peak P, area = impulse, duration 2 i / P
  triangle_same_period,   // thesis fig. 2.9 line I: peak P, duration T (area P T / 2)
};

// How a Friedlander pulse met its targets.
enum class PulseFit {
  exact,       // peak, duration and impulse all kept
  lengthened,  // impulse > (e - 2) P T: no monotone Friedlander exists; duration lengthened
  shortened,   // impulse < P T / kMaxDecay (about): decay capped, duration shortened
};

// A positive-phase pulse, time measured from arrival.
struct Pulse {
  PulseShape shape = PulseShape::friedlander;
  double peak_pa = 0.0;
  double duration_s = 0.0;
  double decay = 0.0;  // Friedlander decay coefficient b (0 for triangles)
  PulseFit fit = PulseFit::exact;

  double pressure_pa(double t_s) const;
  double impulse_pa_s(double t0_s, double t1_s) const;
  double total_impulse_pa_s() const;
  // The pulse as one exponential-polynomial piece.
  ExpPolyPiece piece() const;
  // The pulse's shape squared times peak_q_pa: the dynamic-pressure history that goes with this
  // overpressure pulse, q(t) = q_s (p(t) / P)^2 (particle velocity follows the overpressure).
  ExpPolyPiece squared_piece(double peak_q_pa) const;
};

// Largest Friedlander decay coefficient used; beyond it the duration is shortened instead.
inline constexpr double kMaxFriedlanderDecay = 400.0;
// Smallest decay coefficient: b = -1 is the fullest pulse that still decays monotonically from its
// peak; its area is (e - 2) P T.
inline constexpr double kMinFriedlanderDecay = -1.0;

// Builds a pulse of the given shape from the blast curves' peak, duration and impulse
// (all > 0). For a Friedlander pulse the decay coefficient b is solved so that the pulse integrates
// to the impulse; see PulseFit for what happens where no such b exists.
Pulse make_pulse(PulseShape shape, double peak_pa, double duration_s, double impulse_pa_s);

// Area of the unit Friedlander pulse, integral_0^1 (1 - u) exp(-b u) du.
double friedlander_area_ratio(double decay);
// The decay b with friedlander_area_ratio(b) = ratio, for ratio in
// [friedlander_area_ratio(kMaxFriedlanderDecay), e - 2].
double solve_friedlander_decay(double ratio);

// G_j(x) = integral_0^1 w^j exp(-x w) dw for j = 0..4, accurate for x >= 2 kMinRate.
double unit_exp_moment(int j, double x);
// All of G_0..G_4 at once, for the cost of one.
void unit_exp_moments(double x, std::array<double, ExpPolyPiece::kMaxDegree + 2>& g);

}  // namespace brisance::blast
