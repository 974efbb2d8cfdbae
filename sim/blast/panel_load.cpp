#include "sim/blast/panel_load.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace brisance::blast {

namespace {

Pulse incident_pulse(const PanelWave& wave, PulseShape shape) {
  return make_pulse(shape, wave.incident_overpressure_pa, wave.positive_duration_s,
                    wave.incident_impulse_pa_s);
}

// The reflected pulse keeps the positive duration of the incident wave; its decay carries i_r.
Pulse reflected_pulse(const PanelWave& wave, PulseShape shape) {
  return make_pulse(shape, wave.reflected_overpressure_pa, wave.positive_duration_s,
                    wave.reflected_impulse_pa_s);
}

// A piece multiplied by the linear weight (w0 + w1 * t) and restricted to [begin_s, end_s].
ExpPolyPiece weighted(ExpPolyPiece piece, double w0, double w1_per_s, double begin_s,
                      double end_s) {
  // In the piece's variable u, t = origin + scale u, so the weight is a + b u.
  const double a = w0 + w1_per_s * piece.origin_s;
  const double b = w1_per_s * piece.scale_s;
  assert(piece.coeff_pa[ExpPolyPiece::kMaxDegree] == 0.0);  // room for one more degree
  std::array<double, ExpPolyPiece::kMaxDegree + 1> product{};
  for (int k = 0; k < ExpPolyPiece::kMaxDegree; ++k) {
    product[k] += a * piece.coeff_pa[k];
    product[k + 1] += b * piece.coeff_pa[k];
  }
  piece.coeff_pa = product;
  piece.begin_s = std::max(piece.begin_s, begin_s);
  piece.end_s = std::min(piece.end_s, end_s);
  return piece;
}

double drag_factor(const PanelWave& wave, const PanelLoadOptions& options) {
  return options.drag_coefficient * wave.cos_incidence * wave.cos_incidence;
}

// The pieces of `piece` rising linearly from 0 at t = 0 to full weight at rise_s, then full.
void add_ramped(PressureHistory& history, const ExpPolyPiece& piece, double rise_s) {
  if (rise_s <= 0.0) {
    history.add(piece);
    return;
  }
  history.add(weighted(piece, 0.0, 1.0 / rise_s, 0.0, rise_s));
  history.add(weighted(piece, 1.0, 0.0, rise_s, 1e300));
}

// p_s(t) + C_D q(t), ramped in over rise_s.
PressureHistory ramped_side_on_plus_drag(const PanelWave& wave, PulseShape shape,
                                         double drag_coefficient, double rise_s) {
  const Pulse incident = incident_pulse(wave, shape);
  PressureHistory history;
  add_ramped(history, incident.piece(), rise_s);
  add_ramped(history, incident.squared_piece(drag_coefficient * wave.dynamic_pressure_pa), rise_s);
  return history;
}

}  // namespace

PressureHistory side_on_history(const PanelWave& wave, PulseShape shape) {
  PressureHistory history;
  history.add(incident_pulse(wave, shape).piece());
  return history;
}

PressureHistory drag_history(const PanelWave& wave, const PanelLoadOptions& options) {
  PressureHistory history;
  history.add(incident_pulse(wave, options.shape)
                  .squared_piece(drag_factor(wave, options) * wave.dynamic_pressure_pa));
  return history;
}

PressureHistory front_face_history(const PanelWave& wave, const PanelLoadOptions& options) {
  const Pulse incident = incident_pulse(wave, options.shape);
  const Pulse reflected = reflected_pulse(wave, options.shape);
  PressureHistory uncleared;
  uncleared.add(reflected.piece());
  if (!options.clearing || options.clearing_distance_m <= 0.0) return uncleared;

  const double clearing_time_s = 3.0 * options.clearing_distance_m / wave.shock_velocity_m_s +
                                 std::max(options.clearing_delay_s, 0.0);
  const ExpPolyPiece side_on = incident.piece();
  const ExpPolyPiece drag =
      incident.squared_piece(drag_factor(wave, options) * wave.dynamic_pressure_pa);
  const double ramp = 1.0 / clearing_time_s;  // weight of the stagnation curve grows as t / t_c

  PressureHistory cleared;
  // Reflected pulse fading out over [0, t_c].
  cleared.add(weighted(reflected.piece(), 1.0, -ramp, 0.0, clearing_time_s));
  // Stagnation pressure p_s + C_D q fading in over [0, t_c], then alone.
  add_ramped(cleared, side_on, clearing_time_s);
  add_ramped(cleared, drag, clearing_time_s);
  return cleared.total_impulse_pa_s() < reflected.total_impulse_pa_s() ? cleared : uncleared;
}

double clearing_delay_s(const Charge& charge, double h_m, double rho_m,
                        double clearing_distance_m) {
  if (clearing_distance_m <= 0.0) return 0.0;
  const auto arrival = [&](double along_m) {
    return blast_point(charge, std::max(std::hypot(h_m, along_m), 1e-3)).arrival_time_s;
  };
  // The edges S beyond the panel and S before it on the line from the charge's foot: the relief
  // starts from whichever the wave reaches first.
  const double edge = std::min(arrival(rho_m + clearing_distance_m),
                               arrival(std::abs(rho_m - clearing_distance_m)));
  return std::max(edge - arrival(rho_m), 0.0);
}

PanelWave panel_wave(const BlastPoint& point, double cos_incidence,
                     double reflected_overpressure_pa, double reflected_impulse_pa_s) {
  PanelWave wave;
  wave.incident_overpressure_pa = point.incident_overpressure_pa;
  wave.incident_impulse_pa_s = point.incident_impulse_pa_s;
  wave.positive_duration_s = point.positive_duration_s;
  wave.shock_velocity_m_s = point.shock_velocity_m_s;
  wave.dynamic_pressure_pa = point.dynamic_pressure_pa;
  wave.cos_incidence = std::clamp(cos_incidence, 0.0, 1.0);
  wave.reflected_overpressure_pa = reflected_overpressure_pa;
  wave.reflected_impulse_pa_s = reflected_impulse_pa_s;
  return wave;
}

FaceKind face_kind(double cos_incidence) {
  if (cos_incidence > kSideBand) return FaceKind::front;
  if (cos_incidence < -kSideBand) return FaceKind::rear;
  return FaceKind::side;
}

double side_drag_coefficient(double dynamic_pressure_pa) {
  constexpr double kPsi = 6894.757;  // Pa
  if (dynamic_pressure_pa <= 25.0 * kPsi) return -0.40;
  if (dynamic_pressure_pa <= 50.0 * kPsi) return -0.30;
  return -0.20;
}

PressureHistory side_face_history(const PanelWave& wave, const PanelLoadOptions& options) {
  return ramped_side_on_plus_drag(wave, options.shape,
                                  side_drag_coefficient(wave.dynamic_pressure_pa),
                                  options.panel_extent_m / wave.shock_velocity_m_s);
}

PressureHistory rear_face_history(const PanelWave& wave, const PanelLoadOptions& options) {
  return ramped_side_on_plus_drag(wave, options.shape, kRearDragCoefficient,
                                  3.0 * options.clearing_distance_m / wave.shock_velocity_m_s);
}

PressureHistory face_history(FaceKind kind, const PanelWave& wave,
                             const PanelLoadOptions& options) {
  switch (kind) {
    case FaceKind::front:
      return front_face_history(wave, options);
    case FaceKind::side:
      return side_face_history(wave, options);
    case FaceKind::rear:
      return rear_face_history(wave, options);
  }
  return front_face_history(wave, options);
}

double BlastWind::velocity_m_s(double t_s) const {
  const double since = t_s - arrival_s;
  if (!(since >= 0.0) || !(since < incident.duration_s) || incident.peak_pa <= 0.0) return 0.0;
  return peak_velocity_m_s * std::max(0.0, incident.pressure_pa(since)) / incident.peak_pa;
}

BlastWind blast_wind(const BlastPoint& point, PulseShape shape, const Ambient& air) {
  BlastWind wind;
  wind.arrival_s = point.arrival_time_s;
  if (!(point.incident_overpressure_pa > 0.0 && point.positive_duration_s > 0.0 &&
        point.incident_impulse_pa_s > 0.0))
    return wind;
  wind.peak_velocity_m_s = rh_particle_velocity_m_s(point.incident_overpressure_pa, air);
  wind.incident = make_pulse(shape, point.incident_overpressure_pa, point.positive_duration_s,
                             point.incident_impulse_pa_s);
  return wind;
}

}  // namespace brisance::blast
