// Tests of sim/blast/panel_load: the front face with clearing, the net translatory load, drag.
#include "sim/blast/panel_load.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/blast/air.hpp"
#include "tests/support/quadrature.hpp"

namespace brisance::blast {
namespace {

// A wave of 60 kPa side-on, with its reflected values from the ideal-gas relations and an impulse
// that fits a Friedlander pulse.
PanelWave typical_wave() {
  PanelWave wave;
  wave.incident_overpressure_pa = 60e3;
  wave.incident_impulse_pa_s = 110.0;
  wave.positive_duration_s = 8e-3;
  wave.shock_velocity_m_s = rh_shock_velocity_m_s(60e3);
  wave.dynamic_pressure_pa = rh_dynamic_pressure_pa(60e3);
  wave.reflected_overpressure_pa = rh_reflected_overpressure_pa(60e3);
  wave.reflected_impulse_pa_s = 290.0;
  return wave;
}

using testing::simpson;

TEST(NetTranslatory, WithoutClearingCarriesExactlyReflectedMinusIncidentImpulse) {
  const PanelWave wave = typical_wave();
  for (PulseShape shape : {PulseShape::friedlander, PulseShape::triangle_same_impulse}) {
    PanelLoadOptions options;
    options.shape = shape;
    options.clearing = false;
    const PressureHistory net = net_translatory_history(wave, options);
    const double expected = wave.reflected_impulse_pa_s - wave.incident_impulse_pa_s;
    EXPECT_NEAR(net.total_impulse_pa_s(), expected, 1e-9 * expected);
    EXPECT_NEAR(net.pressure_pa(0.0),
                wave.reflected_overpressure_pa - wave.incident_overpressure_pa, 1e-6);
  }
}

TEST(FrontFace, ClearingStartsAtReflectedPressureAndEndsOnStagnation) {
  const PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.clearing_distance_m = 0.5;  // t_c = 1.5 / U, about 3.5 ms
  const double t_c = 3.0 * 0.5 / wave.shock_velocity_m_s;
  const PressureHistory front = front_face_history(wave, options);
  EXPECT_NEAR(front.pressure_pa(0.0), wave.reflected_overpressure_pa, 1e-6);
  // After t_c the face sees the stagnation pressure p_s(t) + C_D q(t) (eq. 2.30).
  const PressureHistory side_on = side_on_history(wave, options.shape);
  const PressureHistory drag = drag_history(wave, options);
  for (double t : {1.01 * t_c, 5e-3, 7.9e-3}) {
    EXPECT_NEAR(front.pressure_pa(t), side_on.pressure_pa(t) + drag.pressure_pa(t), 1e-6);
  }
  // Clearing only ever removes impulse.
  options.clearing = false;
  EXPECT_LT(front.total_impulse_pa_s(), front_face_history(wave, options).total_impulse_pa_s());
  // The exact integral matches quadrature of the piecewise curve.
  const double quad = simpson([&](double t) { return front.pressure_pa(t); }, 0.0,
                              wave.positive_duration_s * (1 - 1e-12));
  EXPECT_NEAR(front.total_impulse_pa_s(), quad, 1e-6 * quad);
}

TEST(FrontFace, ClearingOfATinyPanelLeavesTheStagnationImpulse) {
  const PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.clearing_distance_m = 1e-6;
  const PressureHistory front = front_face_history(wave, options);
  const double stagnation = side_on_history(wave, options.shape).total_impulse_pa_s() +
                            drag_history(wave, options).total_impulse_pa_s();
  EXPECT_NEAR(front.total_impulse_pa_s(), stagnation, 1e-3 * stagnation);
}

TEST(FrontFace, SlowClearingOfAHugeFaceFallsBackToTheReflectedPulse) {
  PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.clearing_distance_m = 500.0;  // t_c far beyond the pulse
  const PressureHistory front = front_face_history(wave, options);
  EXPECT_LE(front.total_impulse_pa_s(), wave.reflected_impulse_pa_s * (1 + 1e-9));
}

TEST(DragLoading, FollowsEquation2_32AndTheNormalComponent) {
  PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.drag_coefficient = 1.2;
  const PressureHistory drag = drag_history(wave, options);
  EXPECT_NEAR(drag.pressure_pa(0.0), 1.2 * wave.dynamic_pressure_pa, 1e-9);
  wave.cos_incidence = 0.5;
  EXPECT_NEAR(drag_history(wave, options).total_impulse_pa_s(), 0.25 * drag.total_impulse_pa_s(),
              1e-12 * drag.total_impulse_pa_s());
  // q(t) = q_s (p_s(t) / P_so)^2 at every time.
  wave.cos_incidence = 1.0;
  const PressureHistory side_on = side_on_history(wave, options.shape);
  for (double t : {0.0, 1e-3, 4e-3}) {
    const double shape = side_on.pressure_pa(t) / wave.incident_overpressure_pa;
    EXPECT_NEAR(drag.pressure_pa(t), 1.2 * wave.dynamic_pressure_pa * shape * shape, 1e-6);
  }
}

}  // namespace
}  // namespace brisance::blast
