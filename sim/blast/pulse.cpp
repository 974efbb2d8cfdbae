#include "sim/blast/pulse.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace brisance::blast {

namespace {

constexpr double kEMinus2 = std::numbers::e - 2.0;  // area ratio of the b = -1 Friedlander pulse

// Below this |x| (and for every negative x, where all terms share a sign) the power series of
// G_j is used; above it the closed form, whose cancellation is then at most a factor of four.
constexpr double kSeriesLimit = 2.5;

}  // namespace

double unit_exp_moment(int j, double x) {
  assert(j >= 0 && j <= ExpPolyPiece::kMaxDegree);
  assert(x >= 2.0 * ExpPolyPiece::kMinRate);
  if (x < kSeriesLimit) {
    // G_j(x) = sum_n (-x)^n / (n! (n + j + 1)).
    double term = 1.0;  // (-x)^n / n!
    double sum = 1.0 / (j + 1);
    for (int n = 1; n < 200; ++n) {
      term *= -x / n;
      const double add = term / (n + j + 1);
      sum += add;
      if (std::abs(add) <= 1e-17 * std::abs(sum) && n > std::abs(x)) break;
    }
    return sum;
  }
  // G_j(x) = j! / x^(j+1) * (1 - exp(-x) sum_{m<=j} x^m / m!).
  double partial = 1.0;
  double power = 1.0;
  double factorial = 1.0;
  for (int m = 1; m <= j; ++m) {
    power *= x / m;
    partial += power;
    factorial *= m;
  }
  return factorial / std::pow(x, j + 1) * (1.0 - std::exp(-x) * partial);
}

double ExpPolyPiece::pressure_pa(double t_s) const {
  if (t_s < begin_s || t_s >= end_s) return 0.0;
  const double u = (t_s - origin_s) / scale_s;
  double poly = 0.0;
  for (int k = kMaxDegree; k >= 0; --k)
    poly = poly * u + coeff_pa[k];
  return poly * std::exp(-rate * u);
}

double ExpPolyPiece::impulse_pa_s(double t0_s, double t1_s) const {
  const double a = std::max(t0_s, begin_s);
  const double b = std::min(t1_s, end_s);
  if (!(b > a)) return 0.0;
  const double u0 = (a - origin_s) / scale_s;
  const double h = (b - a) / scale_s;
  // Taylor coefficients of the polynomial about u0, so the integral runs over w = u - u0 in [0, h]
  // without cancellation between large antiderivative values.
  std::array<double, kMaxDegree + 1> shifted = coeff_pa;
  for (int i = 0; i < kMaxDegree; ++i)
    for (int k = kMaxDegree - 1; k >= i; --k)
      shifted[k] += u0 * shifted[k + 1];
  double sum = 0.0;
  double h_power = h;
  const double x = rate * h;
  for (int j = 0; j <= kMaxDegree; ++j) {
    if (shifted[j] != 0.0) sum += shifted[j] * h_power * unit_exp_moment(j, x);
    h_power *= h;
  }
  return scale_s * std::exp(-rate * u0) * sum;
}

void PressureHistory::add(const ExpPolyPiece& piece) {
  assert(count_ < kCapacity);
  assert(piece.scale_s > 0.0 && piece.rate >= ExpPolyPiece::kMinRate);
  if (!(piece.end_s > piece.begin_s)) return;  // empty window: nothing to add
  pieces_[count_++] = piece;
}

void PressureHistory::scale(double factor) {
  for (std::size_t i = 0; i < count_; ++i)
    for (double& c : pieces_[i].coeff_pa)
      c *= factor;
}

double PressureHistory::pressure_pa(double t_s) const {
  double p = 0.0;
  for (std::size_t i = 0; i < count_; ++i)
    p += pieces_[i].pressure_pa(t_s);
  return p;
}

double PressureHistory::impulse_pa_s(double t0_s, double t1_s) const {
  double impulse = 0.0;
  for (std::size_t i = 0; i < count_; ++i)
    impulse += pieces_[i].impulse_pa_s(t0_s, t1_s);
  return impulse;
}

double PressureHistory::total_impulse_pa_s() const {
  return impulse_pa_s(0.0, end_s());
}

double PressureHistory::end_s() const {
  double end = 0.0;
  for (std::size_t i = 0; i < count_; ++i)
    end = std::max(end, pieces_[i].end_s);
  return end;
}

double friedlander_area_ratio(double decay) {
  return unit_exp_moment(0, decay) - unit_exp_moment(1, decay);
}

double solve_friedlander_decay(double ratio) {
  assert(ratio > 0.0 && ratio <= kEMinus2 * (1.0 + 1e-12));
  // The area ratio falls monotonically with b; safeguarded Newton inside the bracket.
  double lo = kMinFriedlanderDecay;
  double hi = kMaxFriedlanderDecay;
  double b = std::clamp(1.0 / ratio - 2.0, lo, hi);
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double f = friedlander_area_ratio(b) - ratio;
    if (std::abs(f) <= 1e-15 * ratio) break;
    if (f > 0.0)
      lo = b;
    else
      hi = b;
    // d/db of the area ratio is -integral_0^1 u (1 - u) exp(-b u) du.
    const double slope = -(unit_exp_moment(1, b) - unit_exp_moment(2, b));
    double next = b - f / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == b || hi - lo <= 1e-15 * std::max(1.0, std::abs(b))) break;
    b = next;
  }
  return b;
}

Pulse make_pulse(PulseShape shape, double peak_pa, double duration_s, double impulse_pa_s) {
  assert(peak_pa > 0.0 && duration_s > 0.0 && impulse_pa_s > 0.0);
  Pulse pulse;
  pulse.shape = shape;
  pulse.peak_pa = peak_pa;
  pulse.duration_s = duration_s;
  switch (shape) {
    case PulseShape::friedlander: {
      static const double min_ratio = friedlander_area_ratio(kMaxFriedlanderDecay);
      const double ratio = impulse_pa_s / (peak_pa * duration_s);
      if (ratio >= kEMinus2) {
        // No Friedlander pulse with this peak and duration carries so much impulse while decaying
        // monotonically; keep peak and impulse, stretch the duration at the fullest shape.
        pulse.decay = kMinFriedlanderDecay;
        pulse.duration_s = impulse_pa_s / (peak_pa * friedlander_area_ratio(pulse.decay));
        pulse.fit = PulseFit::lengthened;
      } else if (ratio < min_ratio) {
        // A vanishing impulse for its peak: cap the decay (exp(-b) would underflow) and shorten.
        pulse.decay = kMaxFriedlanderDecay;
        pulse.duration_s = impulse_pa_s / (peak_pa * min_ratio);
        pulse.fit = PulseFit::shortened;
      } else {
        pulse.decay = solve_friedlander_decay(ratio);
      }
      break;
    }
    case PulseShape::triangle_same_impulse:
      pulse.duration_s = 2.0 * impulse_pa_s / peak_pa;
      break;
    case PulseShape::triangle_same_period:
      break;
  }
  return pulse;
}

ExpPolyPiece Pulse::piece() const {
  ExpPolyPiece piece;
  piece.begin_s = 0.0;
  piece.end_s = duration_s;
  piece.origin_s = 0.0;
  piece.scale_s = duration_s;
  piece.rate = decay;
  piece.coeff_pa = {peak_pa, -peak_pa, 0.0, 0.0};
  return piece;
}

ExpPolyPiece Pulse::squared_piece(double peak_q_pa) const {
  ExpPolyPiece piece = this->piece();
  piece.rate = 2.0 * decay;
  piece.coeff_pa = {peak_q_pa, -2.0 * peak_q_pa, peak_q_pa, 0.0};
  return piece;
}

double Pulse::pressure_pa(double t_s) const {
  return piece().pressure_pa(t_s);
}

double Pulse::impulse_pa_s(double t0_s, double t1_s) const {
  return piece().impulse_pa_s(t0_s, t1_s);
}

double Pulse::total_impulse_pa_s() const {
  return peak_pa * duration_s * friedlander_area_ratio(decay);
}

}  // namespace brisance::blast
