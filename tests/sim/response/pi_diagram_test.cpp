// Tests of sim/response/pi_diagram: asymptotes against their closed forms, the swept curve
// against the asymptotes, monotonicity, and the W–R curve against direct SDOF runs.
#include "sim/response/pi_diagram.hpp"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

namespace brisance::response {
namespace {

Element element(ResistanceType type) {
  Element e;
  e.mass_kg = 500.0;
  e.loaded_area_m2 = 2.0;
  e.resistance.type = type;
  e.resistance.stiffness_n_per_m = 2.0e6;
  e.resistance.yield_resistance_n = type == ResistanceType::elastic ? 0.0 : 1.0e5;
  e.load_factor = 0.64;  // simply supported, elastic (Biggs 1964 table 5.1)
  e.mass_factor = 0.50;
  e.span_m = 3.0;
  return e;
}

TEST(PiAsymptotes, MatchHandFormulas) {
  const SdofSystem el = equivalent_system(element(ResistanceType::elastic));
  const double y = 0.02;
  // Elastic: i = y sqrt(K_L k K_M m) / (K_L A), p = k y / (2 A).
  EXPECT_NEAR(impulsive_asymptote_pa_s(el, y),
              y * std::sqrt(0.64 * 2e6 * 0.5 * 500.0) / (0.64 * 2.0), 1e-9);
  EXPECT_NEAR(quasi_static_asymptote_pa(el, y), 2e6 * y / (2.0 * 2.0), 1e-6);
  // Elastic–plastic at mu = 4: i = sqrt(2 K_M m K_L R_y (y - y_el / 2)) / (K_L A),
  // p = R_y (1 - 1 / (2 mu)) / A.
  const SdofSystem ep = equivalent_system(element(ResistanceType::elastic_plastic));
  const double yel = 1e5 / 2e6;
  const double ym = 4.0 * yel;
  EXPECT_NEAR(displacement_for_ductility(ep, 4.0), ym, 1e-15);
  EXPECT_NEAR(impulsive_asymptote_pa_s(ep, ym),
              std::sqrt(2.0 * 0.5 * 500.0 * 0.64 * 1e5 * (ym - 0.5 * yel)) / (0.64 * 2.0), 1e-9);
  EXPECT_NEAR(quasi_static_asymptote_pa(ep, ym), 1e5 * (1.0 - 1.0 / 8.0) / 2.0, 1e-6);
  EXPECT_NEAR(displacement_for_rotation(ep, 2.0), 1.5 * std::tan(2.0 * std::numbers::pi / 180.0),
              1e-15);
}

void check_curve(const SdofSystem& sys, double limit_m) {
  PiOptions opt;
  opt.points = 50;
  opt.min_duration_ratio = 1e-3;
  opt.max_duration_ratio = 1e3;
  const PiCurve c = pi_curve(sys, limit_m, opt);
  ASSERT_EQ(c.points.size(), 50u);
  EXPECT_EQ(c.warnings, 0u);
  // Ends of the sweep against the closed-form asymptotes, within 1 %.
  const double imp_err = c.points.front().impulse_pa_s / c.impulsive_asymptote_pa_s - 1.0;
  const double qs_err = c.points.back().peak_pressure_pa / c.quasi_static_asymptote_pa - 1.0;
  std::printf("impulsive end %.3e, quasi-static end %.3e\n", imp_err, qs_err);
  EXPECT_NEAR(imp_err, 0.0, 0.01);
  EXPECT_NEAR(qs_err, 0.0, 0.01);
  for (std::size_t i = 1; i < c.points.size(); ++i) {
    EXPECT_LE(c.points[i].peak_pressure_pa, c.points[i - 1].peak_pressure_pa * (1.0 + 1e-4));
    EXPECT_GE(c.points[i].impulse_pa_s, c.points[i - 1].impulse_pa_s * (1.0 - 1e-4));
    // Undamped: above both asymptotes (up to the bisection tolerance).
    EXPECT_GE(c.points[i].peak_pressure_pa, c.quasi_static_asymptote_pa * (1.0 - 1e-4));
    EXPECT_GE(c.points[i].impulse_pa_s, c.impulsive_asymptote_pa_s * (1.0 - 1e-4));
  }
  // A middle point really sits on the limit.
  const PiPoint& mid = c.points[25];
  SolveOptions so;
  so.stop_after_peak = true;
  const PressureLoad load{
      {pulse_component(blast::make_pulse(blast::PulseShape::triangle_same_period,
                                         mid.peak_pressure_pa, mid.duration_s, mid.impulse_pa_s))}};
  EXPECT_NEAR(solve_sdof(sys, load, so).peak_displacement_m / limit_m, 1.0, 2e-4);
}

TEST(PiCurve, ElasticApproachesAsymptotesAndIsMonotone) {
  const SdofSystem sys = equivalent_system(element(ResistanceType::elastic));
  check_curve(sys, 0.03);
}

TEST(PiCurve, ElasticPlasticApproachesAsymptotesAndIsMonotone) {
  const SdofSystem sys = equivalent_system(element(ResistanceType::elastic_plastic));
  check_curve(sys, displacement_for_ductility(sys, 5.0));
}

TEST(WrCurve, ChargeGrowsWithStandOffAndSitsOnTheLimit) {
  const SdofSystem sys = equivalent_system(element(ResistanceType::elastic_plastic));
  const double limit = displacement_for_ductility(sys, 3.0);
  const std::vector<WrPoint> wr = wr_curve(sys, limit, {5.0, 10.0, 20.0, 40.0});
  ASSERT_EQ(wr.size(), 4u);
  for (std::size_t i = 0; i < wr.size(); ++i) {
    ASSERT_GT(wr[i].charge_kg, 0.0) << i;
    if (i > 0) {
      EXPECT_GT(wr[i].charge_kg, wr[i - 1].charge_kg);
    }
  }
  blast::Charge charge;
  charge.tnt_equivalent_kg = wr[1].charge_kg;
  SolveOptions so;
  so.stop_after_peak = true;
  const double y = solve_sdof(sys, {{charge_component(charge, 10.0, 0.0)}}, so).peak_displacement_m;
  EXPECT_NEAR(y / limit, 1.0, 0.01);
}

}  // namespace
}  // namespace brisance::response
