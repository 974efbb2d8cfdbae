#include "sim/blast/panel_load.hpp"

#include <algorithm>
#include <cassert>

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

// Front-face history minus `side_on_weight` times the side-on pulse.
PressureHistory front_minus_side_on(const PanelWave& wave, const PanelLoadOptions& options,
                                    double side_on_weight) {
  const Pulse incident = incident_pulse(wave, options.shape);
  const Pulse reflected = reflected_pulse(wave, options.shape);
  ExpPolyPiece side_on = incident.piece();

  PressureHistory uncleared;
  uncleared.add(reflected.piece());
  if (side_on_weight != 0.0) uncleared.add(weighted(side_on, -side_on_weight, 0.0, 0.0, 1e300));
  if (!options.clearing || options.clearing_distance_m <= 0.0) return uncleared;

  const double clearing_time_s = 3.0 * options.clearing_distance_m / wave.shock_velocity_m_s;
  const double q_scale = drag_factor(wave, options) * wave.dynamic_pressure_pa;
  const ExpPolyPiece drag = incident.squared_piece(q_scale);
  const double blend_end_s = clearing_time_s;
  const double ramp = 1.0 / clearing_time_s;  // weight of the stagnation curve grows as t / t_c

  PressureHistory cleared;
  // Reflected pulse fading out over [0, t_c].
  cleared.add(weighted(reflected.piece(), 1.0, -ramp, 0.0, blend_end_s));
  // Stagnation pressure p_s + C_D q fading in over [0, t_c], then alone.
  cleared.add(weighted(side_on, 0.0, ramp, 0.0, blend_end_s));
  cleared.add(weighted(drag, 0.0, ramp, 0.0, blend_end_s));
  cleared.add(weighted(side_on, 1.0, 0.0, blend_end_s, 1e300));
  cleared.add(weighted(drag, 1.0, 0.0, blend_end_s, 1e300));
  if (cleared.total_impulse_pa_s() >= reflected.total_impulse_pa_s()) return uncleared;
  if (side_on_weight != 0.0) cleared.add(weighted(side_on, -side_on_weight, 0.0, 0.0, 1e300));
  return cleared;
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
  return front_minus_side_on(wave, options, 0.0);
}

PressureHistory net_translatory_history(const PanelWave& wave, const PanelLoadOptions& options) {
  return front_minus_side_on(wave, options, 1.0);
}

}  // namespace brisance::blast
