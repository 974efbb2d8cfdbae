// Tests of sim/blast/pulse: exact integrals, the Friedlander fit and its limits.
#include "sim/blast/pulse.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "tests/support/quadrature.hpp"

namespace brisance::blast {
namespace {

using testing::simpson;

TEST(UnitExpMoment, MatchesQuadratureOnBothSidesOfTheSeriesSwitch) {
  for (int j = 0; j <= 4; ++j) {
    for (double x : {-4.0, -1.0, -1e-9, 0.0, 1e-6, 0.5, 2.4999, 2.5001, 7.0, 40.0, 400.0}) {
      const double quad =
          simpson([&](double w) { return std::pow(w, j) * std::exp(-x * w); }, 0.0, 1.0, 200000);
      EXPECT_NEAR(unit_exp_moment(j, x), quad, 1e-12 * std::abs(quad) + 1e-15)
          << "j=" << j << " x=" << x;
    }
  }
}

TEST(UnitExpMoment, ClosedFormsAtZero) {
  EXPECT_DOUBLE_EQ(unit_exp_moment(0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(unit_exp_moment(1, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(unit_exp_moment(2, 0.0), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(unit_exp_moment(3, 0.0), 0.25);
}

TEST(FriedlanderFit, IntegratesToTheImpulseTo1e9) {
  // Peaks, durations and impulses spanning what the blast curves produce, from nearly triangular
  // (ratio close to 1/2) to sharply decaying (ratio 0.003) pulses, plus the concave range above
  // 1/2.
  const double peak = 250e3;
  const double duration = 4e-3;
  for (double ratio : {0.003, 0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.49, 0.4999999, 0.5, 0.50000001,
                       0.55, 0.6, 0.7, 0.718}) {
    const double impulse = ratio * peak * duration;
    const Pulse pulse = make_pulse(PulseShape::friedlander, peak, duration, impulse);
    ASSERT_EQ(pulse.fit, PulseFit::exact) << ratio;
    EXPECT_DOUBLE_EQ(pulse.duration_s, duration);
    EXPECT_NEAR(pulse.total_impulse_pa_s(), impulse, 1e-9 * impulse) << ratio;
    EXPECT_NEAR(pulse.impulse_pa_s(0.0, duration), impulse, 1e-9 * impulse) << ratio;
    // Independent quadrature of the pressure function itself.
    const double quad =
        simpson([&](double t) { return pulse.pressure_pa(t); }, 0.0, duration * (1.0 - 1e-12));
    EXPECT_NEAR(quad, impulse, 1e-7 * impulse) << ratio;
    EXPECT_DOUBLE_EQ(pulse.pressure_pa(0.0), peak);
  }
}

TEST(FriedlanderFit, DecayCoefficientHasKnownLimits) {
  EXPECT_NEAR(solve_friedlander_decay(0.5), 0.0, 1e-12);  // triangle
  EXPECT_NEAR(solve_friedlander_decay(std::numbers::e - 2.0), -1.0, 1e-9);
  // Large b: area ratio = 1/b - (1 - e^-b)/b^2.
  const double b = 50.0;
  const double ratio = 1.0 / b - (1.0 - std::exp(-b)) / (b * b);
  EXPECT_NEAR(solve_friedlander_decay(ratio), b, 1e-9 * b);
}

TEST(FriedlanderFit, TooMuchImpulseLengthensThePulseButKeepsPeakAndImpulse) {
  const double peak = 100e3, duration = 10e-3;
  const double impulse = 0.9 * peak * duration;  // above (e - 2) P T
  const Pulse pulse = make_pulse(PulseShape::friedlander, peak, duration, impulse);
  EXPECT_EQ(pulse.fit, PulseFit::lengthened);
  EXPECT_GT(pulse.duration_s, duration);
  EXPECT_DOUBLE_EQ(pulse.decay, kMinFriedlanderDecay);
  EXPECT_NEAR(pulse.total_impulse_pa_s(), impulse, 1e-12 * impulse);
  // Still decays monotonically from its peak.
  double previous = pulse.pressure_pa(0.0);
  EXPECT_DOUBLE_EQ(previous, peak);
  for (int i = 1; i <= 100; ++i) {
    const double p = pulse.pressure_pa(pulse.duration_s * i / 101.0);
    EXPECT_LT(p, previous);
    previous = p;
  }
}

TEST(FriedlanderFit, VanishingImpulseShortensThePulse) {
  const double peak = 1e6, duration = 1e-2;
  const double impulse = 1e-5 * peak * duration;
  const Pulse pulse = make_pulse(PulseShape::friedlander, peak, duration, impulse);
  EXPECT_EQ(pulse.fit, PulseFit::shortened);
  EXPECT_LT(pulse.duration_s, duration);
  EXPECT_NEAR(pulse.total_impulse_pa_s(), impulse, 1e-12 * impulse);
}

TEST(TrianglePulses, FollowThesisFigure2_9) {
  const double peak = 80e3, duration = 6e-3, impulse = 150.0;
  const Pulse same_impulse = make_pulse(PulseShape::triangle_same_impulse, peak, duration, impulse);
  EXPECT_DOUBLE_EQ(same_impulse.duration_s, 2.0 * impulse / peak);
  EXPECT_NEAR(same_impulse.total_impulse_pa_s(), impulse, 1e-12 * impulse);
  const Pulse same_period = make_pulse(PulseShape::triangle_same_period, peak, duration, impulse);
  EXPECT_DOUBLE_EQ(same_period.duration_s, duration);
  EXPECT_NEAR(same_period.total_impulse_pa_s(), 0.5 * peak * duration, 1e-9);
  EXPECT_NEAR(same_period.pressure_pa(0.5 * duration), 0.5 * peak, 1e-9);
}

TEST(PulseIntegral, PartialIntervalsAddUpWhateverTheStep) {
  const Pulse pulse = make_pulse(PulseShape::friedlander, 300e3, 3e-3, 0.15 * 300e3 * 3e-3);
  const double total = pulse.total_impulse_pa_s();
  for (double step : {1e-7, 3.3e-6, 1e-4, 7e-4, 1e-2}) {
    double sum = 0.0;
    // Start before arrival, end after the pulse: the integral is zero outside the window.
    for (double t = -0.5e-3; t < 5e-3; t += step)
      sum += pulse.impulse_pa_s(t, t + step);
    EXPECT_NEAR(sum, total, 1e-9 * total) << "step " << step;
  }
  // One sub-interval against quadrature.
  const double a = 0.4e-3, b = 1.9e-3;
  const double quad = simpson([&](double t) { return pulse.pressure_pa(t); }, a, b);
  EXPECT_NEAR(pulse.impulse_pa_s(a, b), quad, 1e-9 * quad);
  EXPECT_EQ(pulse.impulse_pa_s(b, a), 0.0);
}

TEST(PressureHistory, SumsPiecesAndScales) {
  const Pulse pulse = make_pulse(PulseShape::friedlander, 100e3, 2e-3, 60.0);
  PressureHistory history;
  history.add(pulse.piece());
  history.add(pulse.squared_piece(20e3));
  EXPECT_DOUBLE_EQ(history.pressure_pa(0.0), 120e3);
  EXPECT_DOUBLE_EQ(history.end_s(), 2e-3);
  const double quad =
      simpson([&](double t) { return history.pressure_pa(t); }, 0.0, 2e-3 * (1.0 - 1e-12));
  EXPECT_NEAR(history.total_impulse_pa_s(), quad, 1e-7 * quad);
  const double before = history.total_impulse_pa_s();
  history.scale(0.25);
  EXPECT_NEAR(history.total_impulse_pa_s(), 0.25 * before, 1e-12 * before);
}

TEST(ExpPolyPiece, CubicWithShiftedOriginMatchesQuadrature) {
  ExpPolyPiece piece;
  piece.begin_s = 0.3e-3;
  piece.end_s = 2.0e-3;
  piece.origin_s = 0.0;
  piece.scale_s = 2.0e-3;
  piece.rate = 3.7;
  piece.coeff_pa = {5e4, -2e4, 7e4, -4e4};
  const double quad =
      simpson([&](double t) { return piece.pressure_pa(t); }, 0.3e-3, 2.0e-3 * (1.0 - 1e-13));
  EXPECT_NEAR(piece.impulse_pa_s(0.0, 1.0), quad, 1e-8 * std::abs(quad));
  const double mid = simpson([&](double t) { return piece.pressure_pa(t); }, 0.5e-3, 0.6e-3);
  EXPECT_NEAR(piece.impulse_pa_s(0.5e-3, 0.6e-3), mid, 1e-10 * std::abs(mid));
}

}  // namespace
}  // namespace brisance::blast

namespace brisance::blast {
namespace {

TEST(PressureHistory, FirstMomentMatchesQuadratureAndIsConsistentWithImpulses) {
  const Pulse pulse = make_pulse(PulseShape::friedlander, 2e5, 4e-3, 0.12 * 2e5 * 4e-3);
  PressureHistory history;
  history.add(pulse.piece());
  history.add(pulse.squared_piece(5e4));
  for (auto [a, b] :
       {std::pair{0.0, 4e-3}, {1e-3, 1.5e-3}, {-1e-3, 2e-3}, {3e-3, 6e-3}, {2e-3, 2e-3 + 1e-9}}) {
    const double quad = simpson([&](double t) { return (b - t) * history.pressure_pa(t); },
                                std::max(a, 0.0), std::min(b, 4e-3 * (1 - 1e-12)), 200000);
    EXPECT_NEAR(history.moment_pa_s2(a, b), quad, 1e-8 * std::abs(quad) + 1e-20) << a << " " << b;
  }
  // Splitting [a, c] at b: M(a, c) = M(a, b) + (c - b) I(a, b) + M(b, c).
  const double a = 0.3e-3, b = 1.7e-3, c = 3.1e-3;
  EXPECT_NEAR(history.moment_pa_s2(a, c),
              history.moment_pa_s2(a, b) + (c - b) * history.impulse_pa_s(a, b) +
                  history.moment_pa_s2(b, c),
              1e-12 * history.moment_pa_s2(a, c));
}

}  // namespace
}  // namespace brisance::blast
