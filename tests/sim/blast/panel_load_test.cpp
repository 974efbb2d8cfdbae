// Tests of sim/blast/panel_load: front, side and rear faces (thesis fig. 2.13, UFC 3-340-02
// §2-15.3) against hand-computed histories, clearing, drag.
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

// The history's exact integral agrees with quadrature of the piecewise curve.
void expect_exact_integral(const PressureHistory& history, double duration_s) {
  const double quad =
      simpson([&](double t) { return history.pressure_pa(t); }, 0.0, duration_s * (1 - 1e-12));
  EXPECT_NEAR(history.total_impulse_pa_s(), quad, 1e-6 * quad);
}

TEST(FrontFace, WithoutClearingIsTheReflectedPulse) {
  const PanelWave wave = typical_wave();
  for (PulseShape shape : {PulseShape::friedlander, PulseShape::triangle_same_impulse}) {
    PanelLoadOptions options;
    options.shape = shape;
    options.clearing = false;
    const PressureHistory front = front_face_history(wave, options);
    EXPECT_NEAR(front.total_impulse_pa_s(), wave.reflected_impulse_pa_s,
                1e-9 * wave.reflected_impulse_pa_s);
    EXPECT_NEAR(front.pressure_pa(0.0), wave.reflected_overpressure_pa, 1e-6);
  }
}

TEST(FaceKind, FrontSideAndRearByTheAngleOfIncidence) {
  EXPECT_EQ(face_kind(1.0), FaceKind::front);
  EXPECT_EQ(face_kind(0.11), FaceKind::front);
  EXPECT_EQ(face_kind(0.1), FaceKind::side);
  EXPECT_EQ(face_kind(0.0), FaceKind::side);
  EXPECT_EQ(face_kind(-0.1), FaceKind::side);
  EXPECT_EQ(face_kind(-0.11), FaceKind::rear);
  EXPECT_EQ(face_kind(-1.0), FaceKind::rear);
}

TEST(SideDrag, UfcTable2_3ByDynamicPressure) {
  constexpr double psi = 6894.757;
  EXPECT_EQ(side_drag_coefficient(1e3), -0.40);
  EXPECT_EQ(side_drag_coefficient(24.9 * psi), -0.40);
  EXPECT_EQ(side_drag_coefficient(25.1 * psi), -0.30);
  EXPECT_EQ(side_drag_coefficient(49.9 * psi), -0.30);
  EXPECT_EQ(side_drag_coefficient(50.1 * psi), -0.20);
}

// A triangular wave, where every face's history can be written down by hand:
// p_s(t) = P (1 - t/T), q(t) = q_s (1 - t/T)^2 for t < T.
struct HandWave {
  double P = 60e3, T = 2.0 * 110.0 / 60e3, q = 0.0, U = 0.0;
  double pressure(double t, double drag, double rise) const {
    if (t < 0.0 || t >= T) return 0.0;
    const double u = 1.0 - t / T;
    return (P * u + drag * q * u * u) * std::min(1.0, t / rise);
  }
  // Integral of pressure over [0, T]: the ramped part by its closed form.
  double impulse(double drag, double rise) const {
    // With r = rise / T <= 1: integral_0^r (x/r)(P(1-x) + C q (1-x)^2) T dx + integral_r^1 ...
    const double r = rise / T;
    const double c = drag * q;
    const double full = T * (P * (1 - r) * (1 - r) / 2 + c * std::pow(1 - r, 3) / 3);
    const double ramp =
        T / r *
        (P * (r * r / 2 - r * r * r / 3) + c * (r * r / 2 - 2 * r * r * r / 3 + r * r * r * r / 4));
    return full + ramp;
  }
};

PanelWave triangle_wave(const HandWave& hand) {
  PanelWave wave = typical_wave();
  wave.incident_overpressure_pa = hand.P;
  wave.incident_impulse_pa_s = 0.5 * hand.P * hand.T;
  wave.positive_duration_s = hand.T;
  wave.shock_velocity_m_s = hand.U;
  wave.dynamic_pressure_pa = hand.q;
  return wave;
}

TEST(SideFace, SideOnPlusSideDragRisingWhileTheWaveCrossesThePanel) {
  HandWave hand;
  hand.q = rh_dynamic_pressure_pa(hand.P);
  hand.U = rh_shock_velocity_m_s(hand.P);
  const PanelWave wave = triangle_wave(hand);
  PanelLoadOptions options;
  options.shape = PulseShape::triangle_same_impulse;
  options.panel_extent_m = 0.3;  // crossed in 0.3 / U, about 0.7 ms
  const double rise = 0.3 / hand.U;
  const PressureHistory side = side_face_history(wave, options);
  for (double t : {0.0, 0.25 * rise, rise, 1.5e-3, 3e-3})
    EXPECT_NEAR(side.pressure_pa(t), hand.pressure(t, -0.40, rise), 1e-6 * hand.P) << t;
  const double expected = hand.impulse(-0.40, rise);
  EXPECT_NEAR(side.total_impulse_pa_s(), expected, 1e-9 * expected);
}

TEST(RearFace, SideOnPlusRearDragBuildingUpOverThreeSOverU) {
  HandWave hand;
  hand.q = rh_dynamic_pressure_pa(hand.P);
  hand.U = rh_shock_velocity_m_s(hand.P);
  const PanelWave wave = triangle_wave(hand);
  PanelLoadOptions options;
  options.shape = PulseShape::triangle_same_impulse;
  options.clearing_distance_m = 0.2;
  const double rise = 3.0 * 0.2 / hand.U;
  const PressureHistory rear = rear_face_history(wave, options);
  EXPECT_EQ(rear.pressure_pa(0.0), 0.0);  // no jump: it builds up from the edges
  for (double t : {0.1 * rise, rise, 2e-3, 3.5e-3})
    EXPECT_NEAR(rear.pressure_pa(t), hand.pressure(t, kRearDragCoefficient, rise), 1e-6 * hand.P)
        << t;
  const double expected = hand.impulse(kRearDragCoefficient, rise);
  EXPECT_NEAR(rear.total_impulse_pa_s(), expected, 1e-9 * expected);
  // The same wave on the Friedlander pulse: the exact integral agrees with quadrature.
  options.shape = PulseShape::friedlander;
  const PanelWave smooth = typical_wave();
  expect_exact_integral(rear_face_history(smooth, options), smooth.positive_duration_s);
}

TEST(FaceHistory, DispatchesOnTheFaceKind) {
  const PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.clearing_distance_m = 0.3;
  options.panel_extent_m = 0.1;
  EXPECT_EQ(face_history(FaceKind::front, wave, options).total_impulse_pa_s(),
            front_face_history(wave, options).total_impulse_pa_s());
  EXPECT_EQ(face_history(FaceKind::side, wave, options).total_impulse_pa_s(),
            side_face_history(wave, options).total_impulse_pa_s());
  EXPECT_EQ(face_history(FaceKind::rear, wave, options).total_impulse_pa_s(),
            rear_face_history(wave, options).total_impulse_pa_s());
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
  expect_exact_integral(front, wave.positive_duration_s);
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

TEST(FrontFace, RelievedOnlyOnceTheWaveHasReachedTheEdge) {
  // The clearing delay lengthens t_c: the face keeps more of its reflected impulse, never more
  // than all of it, and the stagnation pressure still follows once the relief is through.
  const PanelWave wave = typical_wave();
  PanelLoadOptions options;
  options.clearing_distance_m = 0.5;
  const double prompt = front_face_history(wave, options).total_impulse_pa_s();
  options.clearing_delay_s = 1e-3;
  const PressureHistory delayed = front_face_history(wave, options);
  EXPECT_GT(delayed.total_impulse_pa_s(), prompt);
  EXPECT_LE(delayed.total_impulse_pa_s(), wave.reflected_impulse_pa_s * (1 + 1e-9));
  const double t_c = 3.0 * 0.5 / wave.shock_velocity_m_s + 1e-3;
  const PressureHistory side_on = side_on_history(wave, options.shape);
  const PressureHistory drag = drag_history(wave, options);
  EXPECT_NEAR(delayed.pressure_pa(1.01 * t_c),
              side_on.pressure_pa(1.01 * t_c) + drag.pressure_pa(1.01 * t_c), 1e-6);
}

TEST(ClearingDelay, TheWavesSweepFromTheChargesFootToTheEdge) {
  // Kingery–Bulmash arrival times: at the nearer (in time) of the edges S beyond and S before the
  // panel, less at the panel. A far
  // charge's wave is nearly planar over a face: the delay is a small part of t_c = 3 S / U
  // (100 kg at 50 m, S = 0.5 m: 0.2 %); a close charge's sweeps out across it (at 0.5 m: 9 %).
  Charge charge;
  charge.tnt_equivalent_kg = 100.0;
  const double s = 0.5;
  const auto share_of_t_c = [&](double h, double rho) {
    const double t_c = 3.0 * s / blast_point(charge, std::hypot(h, rho)).shock_velocity_m_s;
    return clearing_delay_s(charge, h, rho, s) / t_c;
  };
  EXPECT_LT(share_of_t_c(50.0, 0.0), 0.005);
  EXPECT_GT(share_of_t_c(0.5, 0.0), 0.05);
  EXPECT_NEAR(clearing_delay_s(charge, 0.5, 0.0, s),
              blast_point(charge, std::hypot(0.5, s)).arrival_time_s -
                  blast_point(charge, 0.5).arrival_time_s,
              1e-12);
  // A panel the wave reaches after the edge before it (on the line from the charge's foot)
  // clears from that edge as a plane wave's would: no delay. Between, the nearer of the two
  // edges counts: at rho = S/4 the edge before, 3S/4 from the foot.
  EXPECT_EQ(clearing_delay_s(charge, 0.5, 2.0, s), 0.0);
  EXPECT_NEAR(clearing_delay_s(charge, 0.5, 0.25 * s, s),
              blast_point(charge, std::hypot(0.5, 0.75 * s)).arrival_time_s -
                  blast_point(charge, std::hypot(0.5, 0.25 * s)).arrival_time_s,
              1e-12);
  EXPECT_EQ(clearing_delay_s(charge, 0.5, 0.0, 0.0), 0.0);
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

TEST(BlastWind, ParticleVelocityDecayingAsTheOverpressureOverThePositivePhase) {
  // 10 kg TNT at 10 m: the wind arrives with the front at u_s (Rankine–Hugoniot), falls as
  // p_s(t) / P_so, and stops at the end of the positive phase; rho_s u^2 / 2 is the dynamic
  // pressure q(t) = q_s (p_s(t) / P_so)^2 the drag loads use.
  Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  const BlastPoint point = blast_point(charge, 10.0);
  const BlastWind wind = blast_wind(point, PulseShape::friedlander);
  const double u_s = rh_particle_velocity_m_s(point.incident_overpressure_pa);
  EXPECT_GT(u_s, 40.0);
  EXPECT_EQ(wind.velocity_m_s(point.arrival_time_s - 1e-6), 0.0);
  EXPECT_NEAR(wind.velocity_m_s(point.arrival_time_s), u_s, 1e-9 * u_s);
  EXPECT_EQ(wind.velocity_m_s(point.arrival_time_s + point.positive_duration_s + 1e-6), 0.0);
  const PressureHistory side_on = side_on_history(
      PanelWave{point.incident_overpressure_pa, point.incident_impulse_pa_s,
                point.positive_duration_s, point.shock_velocity_m_s, point.dynamic_pressure_pa},
      PulseShape::friedlander);
  PanelWave wave;
  wave.incident_overpressure_pa = point.incident_overpressure_pa;
  wave.incident_impulse_pa_s = point.incident_impulse_pa_s;
  wave.positive_duration_s = point.positive_duration_s;
  wave.dynamic_pressure_pa = point.dynamic_pressure_pa;
  const PressureHistory q = drag_history(wave, PanelLoadOptions{});
  const double rho_s = rh_density_behind_kg_m3(point.incident_overpressure_pa);
  for (double f : {0.0, 0.1, 0.3, 0.6, 0.9}) {
    const double t = f * point.positive_duration_s;
    const double u = wind.velocity_m_s(point.arrival_time_s + t);
    EXPECT_NEAR(u, u_s * side_on.pressure_pa(t) / point.incident_overpressure_pa, 1e-9 * u_s);
    EXPECT_NEAR(0.5 * rho_s * u * u,
                q.pressure_pa(t) * rh_dynamic_pressure_pa(point.incident_overpressure_pa) /
                    point.dynamic_pressure_pa,
                3e-3 * point.dynamic_pressure_pa)
        << f;
  }
}

}  // namespace
}  // namespace brisance::blast
