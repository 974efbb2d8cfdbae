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

// 1 / k for k < kInverseCount: the series below multiplies instead of dividing.
constexpr int kInverseCount = 64;
constexpr std::array<double, kInverseCount> kInverse = [] {
  std::array<double, kInverseCount> inverse{};
  for (int k = 1; k < kInverseCount; ++k)
    inverse[k] = 1.0 / k;
  return inverse;
}();

}  // namespace

// G_0..G_4 at once: one power series feeds all orders (the hot path of every loaded panel).
void unit_exp_moments(double x, std::array<double, ExpPolyPiece::kMaxDegree + 2>& g) {
  constexpr int count = ExpPolyPiece::kMaxDegree + 2;
  assert(x >= 2.0 * ExpPolyPiece::kMinRate);
  if (x < kSeriesLimit) {
    // G_j(x) = sum_n (-x)^n / (n! (n + j + 1)); below 2.5 in magnitude (x >= -4 here) the terms
    // fall under 1e-17 well before n = 50.
    double term = 1.0;  // (-x)^n / n!
    for (int j = 0; j < count; ++j)
      g[j] = kInverse[j + 1];
    for (int n = 1; n + count < kInverseCount; ++n) {
      term *= -x * kInverse[n];
      for (int j = 0; j < count; ++j)
        g[j] += term * kInverse[n + j + 1];
      if (std::abs(term) <= 1e-17 * g[count - 1] && n > std::abs(x)) break;
    }
    return;
  }
  // G_j(x) = j! / x^(j+1) * (1 - exp(-x) sum_{m<=j} x^m / m!).
  const double decay = std::exp(-x);
  double partial = 1.0;
  double power = 1.0;
  double factorial = 1.0;
  double inverse_power = 1.0 / x;
  for (int j = 0; j < count; ++j) {
    if (j > 0) {
      power *= x / j;
      partial += power;
      factorial *= j;
      inverse_power /= x;
    }
    g[j] = factorial * inverse_power * (1.0 - decay * partial);
  }
}

double unit_exp_moment(int j, double x) {
  assert(j >= 0 && j <= ExpPolyPiece::kMaxDegree + 1);
  assert(x >= 2.0 * ExpPolyPiece::kMinRate);
  std::array<double, ExpPolyPiece::kMaxDegree + 2> g;
  unit_exp_moments(x, g);
  return g[j];
}

double ExpPolyPiece::pressure_pa(double t_s) const {
  if (t_s < begin_s || t_s >= end_s) return 0.0;
  const double u = (t_s - origin_s) / scale_s;
  double poly = 0.0;
  for (int k = kMaxDegree; k >= 0; --k)
    poly = poly * u + coeff_pa[k];
  return poly * std::exp(-rate * u);
}

namespace {

// The piece restricted to [t0, t1] and re-expanded about the restricted start: p = e^(-rate u0)
// sum_j shifted[j] w^j e^(-rate w) for w = u - u0 in [0, h]. False if the overlap is empty.
struct Restricted {
  double u0;
  double h;
  std::array<double, ExpPolyPiece::kMaxDegree + 1> shifted;
};

bool restrict_piece(const ExpPolyPiece& piece, double t0_s, double t1_s, Restricted& out) {
  const double a = std::max(t0_s, piece.begin_s);
  const double b = std::min(t1_s, piece.end_s);
  if (!(b > a)) return false;
  out.u0 = (a - piece.origin_s) / piece.scale_s;
  out.h = (b - a) / piece.scale_s;
  // Taylor coefficients of the polynomial about u0, so the integral runs over w in [0, h]
  // without cancellation between large antiderivative values.
  out.shifted = piece.coeff_pa;
  constexpr int n = ExpPolyPiece::kMaxDegree;
  for (int i = 0; i < n; ++i)
    for (int k = n - 1; k >= i; --k)
      out.shifted[k] += out.u0 * out.shifted[k + 1];
  return true;
}

}  // namespace

double ExpPolyPiece::impulse_pa_s(double t0_s, double t1_s) const {
  Restricted r;
  if (!restrict_piece(*this, t0_s, t1_s, r)) return 0.0;
  std::array<double, kMaxDegree + 2> g;
  unit_exp_moments(rate * r.h, g);
  double sum = 0.0;
  double h_power = r.h;
  for (int j = 0; j <= kMaxDegree; ++j) {
    sum += r.shifted[j] * h_power * g[j];
    h_power *= r.h;
  }
  return scale_s * std::exp(-rate * r.u0) * sum;
}

double ExpPolyPiece::moment_pa_s2(double t0_s, double t1_s) const {
  Restricted r;
  if (!restrict_piece(*this, t0_s, t1_s, r)) return 0.0;
  // integral_0^h (h - w) w^j e^(-x w / h) dw = h^(j+2) (G_j - G_(j+1)); the factor h - w is
  // measured from the end of the overlap, then shifted to t1 if the piece ends before it.
  std::array<double, kMaxDegree + 2> g;
  unit_exp_moments(rate * r.h, g);
  double sum = 0.0;
  double h_power = r.h * r.h;
  double impulse = 0.0;
  double h_power_impulse = r.h;
  for (int j = 0; j <= kMaxDegree; ++j) {
    sum += r.shifted[j] * h_power * (g[j] - g[j + 1]);
    impulse += r.shifted[j] * h_power_impulse * g[j];
    h_power *= r.h;
    h_power_impulse *= r.h;
  }
  const double decay = std::exp(-rate * r.u0);
  const double overlap_end_s = std::min(t1_s, end_s);
  return decay * (scale_s * scale_s * sum + (t1_s - overlap_end_s) * scale_s * impulse);
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

double PressureHistory::moment_pa_s2(double t0_s, double t1_s) const {
  double moment = 0.0;
  for (std::size_t i = 0; i < count_; ++i)
    moment += pieces_[i].moment_pa_s2(t0_s, t1_s);
  return moment;
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
  std::array<double, ExpPolyPiece::kMaxDegree + 2> g;
  unit_exp_moments(decay, g);
  return g[0] - g[1];
}

double solve_friedlander_decay(double ratio) {
  assert(ratio > 0.0 && ratio <= kEMinus2 * (1.0 + 1e-12));
  // The area ratio G_0 - G_1 falls monotonically with b, with slope -(G_1 - G_2); safeguarded
  // Newton inside the bracket.
  double lo = kMinFriedlanderDecay;
  double hi = kMaxFriedlanderDecay;
  double b = std::clamp(1.0 / ratio - 2.0, lo, hi);
  std::array<double, ExpPolyPiece::kMaxDegree + 2> g;
  for (int iteration = 0; iteration < 100; ++iteration) {
    unit_exp_moments(b, g);
    const double f = g[0] - g[1] - ratio;
    if (std::abs(f) <= 1e-15 * ratio) break;
    if (f > 0.0)
      lo = b;
    else
      hi = b;
    const double slope = -(g[1] - g[2]);
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
