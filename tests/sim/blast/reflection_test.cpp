// Tests of sim/blast/reflection: the UFC 3-340-02 charts and the oblique reflection built on them.
#include "sim/blast/reflection.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "sim/blast/kingery_bulmash.hpp"

namespace brisance::blast {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Largest C_R beyond 20 degrees, and where it is.
std::pair<double, double> mach_stem_peak(double pressure_pa) {
  double best = 0.0, where = 0.0;
  for (double a = 20.0; a <= 90.0; a += 0.25) {
    const double c = chart_reflection_coefficient(pressure_pa, a * kDeg).value;
    if (c > best) {
      best = c;
      where = a;
    }
  }
  return {best, where};
}

TEST(ReflectionChart, NormalIncidenceAgreesWithTheKingeryBulmashRatio) {
  // Two independent public sources: the chart's C_R(0) (fig. 2-193) against P_r / P_so of the
  // fits, from 1.4 kPa to the chart's top curve (34.5 MPa). Measured worst deviation 3.4 %.
  for (BurstCurve curve : {BurstCurve::spherical_free_air, BurstCurve::hemispherical_surface}) {
    for (double z = 0.1; z <= 40.0; z *= 1.1) {
      const ScaledBlast s = kingery_bulmash(curve, z);
      const double fits = s.reflected_overpressure_pa / s.incident_overpressure_pa;
      const ChartValue chart = chart_reflection_coefficient(s.incident_overpressure_pa, 0.0);
      if (s.incident_overpressure_pa > 34.4e6) {
        EXPECT_FALSE(chart.in_range) << z;
        continue;
      }
      EXPECT_TRUE(chart.in_range) << z;
      EXPECT_NEAR(chart.value, fits, 0.04 * fits) << "Z " << z;
    }
  }
}

TEST(ReflectionChart, GrazingIncidenceIsSideOn) {
  for (double p : {1.4e3, 1e4, 2e5, 3e6, 3e7})
    EXPECT_NEAR(chart_reflection_coefficient(p, 90.0 * kDeg).value, 1.0, 1e-12) << p;
}

TEST(ReflectionChart, MachStemPeakIsKeptBetweenCurvesAndMovesWithPressure) {
  // Thesis §3.4 / fig. 3.3: at low pressure C_R rises above its normal value near the Mach-stem
  // transition; the peak angle falls from about 80 degrees (1.4 kPa) to about 40 (300 kPa).
  // Between two chart curves the interpolated peak must stay as high as the curves' own peaks
  // (about 3.0-3.3), not be averaged down.
  double previous_angle = 90.0;
  for (double p : {2e3, 5e3, 1e4, 2e4, 5e4, 1e5, 3e5}) {
    const auto [peak, angle] = mach_stem_peak(p);
    const double normal = chart_reflection_coefficient(p, 0.0).value;
    EXPECT_GT(peak, 3.0) << p;
    if (p <= 1e5) {
      EXPECT_GT(peak, 1.15 * normal) << p;
    }
    EXPECT_LT(angle, previous_angle) << p;
    previous_angle = angle;
  }
  EXPECT_NEAR(mach_stem_peak(2e3).second, 78.0, 3.0);
  EXPECT_NEAR(mach_stem_peak(3e5).second, 40.5, 2.0);
}

TEST(ReflectionChart, ContinuousInPressure) {
  // No jumps when the pressure crosses from one chart curve to the next.
  for (double a : {0.0, 30.0, 45.0, 60.0, 75.0}) {
    double previous = chart_reflection_coefficient(1.4e3, a * kDeg).value;
    for (double p = 1.4e3; p < 3e7; p *= 1.01) {
      const double c = chart_reflection_coefficient(p, a * kDeg).value;
      EXPECT_NEAR(c, previous, 0.12 * previous) << "P " << p << " angle " << a;
      previous = c;
    }
  }
}

TEST(ReflectionChart, OutsideThePressureRangeIsFlagged) {
  EXPECT_FALSE(chart_reflection_coefficient(500.0, 0.0).in_range);
  EXPECT_FALSE(chart_reflection_coefficient(1e8, 0.0).in_range);
  EXPECT_TRUE(chart_reflection_coefficient(1e5, 0.0).in_range);
  // Clamped to the edge curve, still a valid coefficient.
  EXPECT_NEAR(chart_reflection_coefficient(500.0, 0.0).value,
              chart_reflection_coefficient(1378.95, 0.0).value, 1e-12);
}

TEST(ImpulseChart, GrazingRatioMatchesTheFitsSideOnOverReflectedImpulse) {
  // Fig. 2-194 at 90 degrees against i_s / i_r of the fits: another cross-check of two sources
  // (measured within 6 %).
  for (double z = 0.3; z <= 40.0; z *= 1.2) {
    const ScaledBlast s = kingery_bulmash(BurstCurve::spherical_free_air, z);
    const double fits = s.incident_impulse_pa_s_kg13 / s.reflected_impulse_pa_s_kg13;
    const double chart = chart_impulse_ratio(s.incident_overpressure_pa, 90.0 * kDeg).value;
    EXPECT_NEAR(chart, fits, 0.15 * fits) << "Z " << z;
  }
}

TEST(ObliqueReflection, EndsAreExactlyTheCurvesValues) {
  for (double z : {0.3, 1.0, 3.0, 10.0, 30.0}) {
    const ScaledBlast s = kingery_bulmash(BurstCurve::spherical_free_air, z);
    const auto reflect = [&](double angle_deg) {
      return oblique_reflection(s.incident_overpressure_pa, s.incident_impulse_pa_s_kg13,
                                s.reflected_overpressure_pa, s.reflected_impulse_pa_s_kg13,
                                angle_deg * kDeg);
    };
    const ObliqueReflection normal = reflect(0.0);
    EXPECT_NEAR(normal.overpressure_pa, s.reflected_overpressure_pa,
                1e-9 * s.reflected_overpressure_pa);
    EXPECT_NEAR(normal.impulse_pa_s, s.reflected_impulse_pa_s_kg13,
                1e-9 * s.reflected_impulse_pa_s_kg13);
    const ObliqueReflection grazing = reflect(90.0);
    EXPECT_NEAR(grazing.overpressure_pa, s.incident_overpressure_pa,
                1e-9 * s.incident_overpressure_pa);
    EXPECT_NEAR(grazing.impulse_pa_s, s.incident_impulse_pa_s_kg13,
                1e-9 * s.incident_impulse_pa_s_kg13);
    // The impulse falls steadily with angle (fig. 2-194 has no Mach-stem bump), never below i_s.
    double previous = normal.impulse_pa_s;
    for (double a = 5.0; a <= 90.0; a += 5.0) {
      const ObliqueReflection o = reflect(a);
      EXPECT_LE(o.impulse_pa_s, previous * (1 + 1e-3)) << z << " " << a;
      EXPECT_GE(o.impulse_pa_s, s.incident_impulse_pa_s_kg13 * (1 - 1e-12));
      EXPECT_GE(o.coefficient, 1.0 - 1e-12);
      EXPECT_NEAR(o.overpressure_pa, o.coefficient * s.incident_overpressure_pa, 1e-6);
      previous = o.impulse_pa_s;
    }
  }
}

TEST(ObliqueReflection, FollowsTheChartShapeIncludingTheMachStemRise) {
  // At Z = 8 (about 15 kPa), the reflected pressure at the Mach-stem peak exceeds the normal one.
  const ScaledBlast s = kingery_bulmash(BurstCurve::spherical_free_air, 8.0);
  const auto [peak_c, peak_angle] = mach_stem_peak(s.incident_overpressure_pa);
  const ObliqueReflection at_peak = oblique_reflection(
      s.incident_overpressure_pa, s.incident_impulse_pa_s_kg13, s.reflected_overpressure_pa,
      s.reflected_impulse_pa_s_kg13, peak_angle * kDeg);
  EXPECT_GT(at_peak.overpressure_pa, 1.3 * s.reflected_overpressure_pa);
  EXPECT_GT(peak_c, 3.0);
}

}  // namespace
}  // namespace brisance::blast
