// sim/response/plate: the large-deflection plate SDOF (see plate.hpp for the model and sources).
//
// Integration: the cubic resistance has no closed form under a general pulse, so the equation is
// integrated with the Dormand–Prince 5(4) embedded Runge–Kutta pair (J. R. Dormand, P. J. Prince
// (1980) J. Comput. Appl. Math. 6(1)) with local error control on (w / t, v / (t omega)). Each
// smooth stretch of the load (between arrivals and the ends of its pieces) is integrated on its
// own, so no step straddles a kink. Rejected: the piecewise-linear closed form of sdof.cpp on a
// dense multilinear fit of R(w) — its error depends on the fit's knots, which a check then has
// to chase; the adaptive pair's error is controlled directly.
#include "sim/response/plate.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sim/response/factors.hpp"

namespace brisance::response {

namespace {

constexpr double kPi = std::numbers::pi;

// The kinks of the load: arrivals and the windows of every piece, sorted, within [from, to].
std::vector<double> load_breakpoints(const PressureLoad& load, double from_s, double to_s) {
  std::vector<double> t = {from_s, to_s};
  for (const LoadComponent& c : load.components) {
    t.push_back(c.arrival_s);
    for (std::size_t i = 0; i < c.history.size(); ++i) {
      t.push_back(c.arrival_s + c.history.piece(i).begin_s);
      t.push_back(c.arrival_s + c.history.piece(i).end_s);
    }
  }
  std::erase_if(t, [&](double x) { return !(x >= from_s && x <= to_s); });
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

// Largest |w| of the cubic Hermite interpolant of one step (ends included), and where, as a
// fraction of the step.
std::pair<double, double> hermite_peak(double w0, double v0, double w1, double v1, double h) {
  double best = std::abs(w0), at = 0.0;
  if (std::abs(w1) > best) best = std::abs(w1), at = 1.0;
  // dw/ds = A s^2 + B s + C on s in [0, 1].
  const double a = 6.0 * w0 + 3.0 * h * v0 - 6.0 * w1 + 3.0 * h * v1;
  const double b = -6.0 * w0 - 4.0 * h * v0 + 6.0 * w1 - 2.0 * h * v1;
  const double c = h * v0;
  const auto value = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * w0 + (s3 - 2 * s2 + s) * h * v0 + (-2 * s3 + 3 * s2) * w1 +
           (s3 - s2) * h * v1;
  };
  const auto consider = [&](double s) {
    if (!(s > 0.0 && s < 1.0)) return;
    const double w = std::abs(value(s));
    if (w > best) best = w, at = s;
  };
  if (std::abs(a) < 1e-300) {
    if (b != 0.0) consider(-c / b);
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      consider(q / a);
      if (q != 0.0) consider(c / q);
    }
  }
  return {best, at};
}

// The first s in [0, s_peak] where the step's cubic Hermite interpolant's |w| reaches `level`
// (|w(s_peak)| >= level), and dw/dt there: 64 samples, then bisection on the bracketing pair.
std::pair<double, double> hermite_first_reach(double w0, double v0, double w1, double v1, double h,
                                              double level, double s_peak) {
  const auto value = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * w0 + (s3 - 2 * s2 + s) * h * v0 + (-2 * s3 + 3 * s2) * w1 +
           (s3 - s2) * h * v1;
  };
  const auto rate = [&](double s) {  // dw/dt = (dw/ds) / h
    const double s2 = s * s;
    return ((6 * s2 - 6 * s) * w0 + (3 * s2 - 4 * s + 1) * h * v0 + (-6 * s2 + 6 * s) * w1 +
            (3 * s2 - 2 * s) * h * v1) /
           h;
  };
  double lo = 0.0, hi = s_peak;
  if (std::abs(value(0.0)) >= level) return {0.0, v0};
  constexpr int kSamples = 64;
  for (int k = 1; k <= kSamples; ++k) {
    const double s = s_peak * k / kSamples;
    if (std::abs(value(s)) >= level) {
      hi = s;
      break;
    }
    lo = s;
  }
  for (int i = 0; i < 60 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::abs(value(mid)) >= level ? hi : lo) = mid;
  }
  return {hi, rate(hi)};
}

}  // namespace

double PlateModel::resistance_n(double w) const {
  return linear_stiffness_n_per_m * w + cubic_stiffness_n_per_m3 * w * w * w;
}

double PlateModel::centre_stress_pa(double w) const {
  return bending_stress_pa_per_m * std::abs(w) + membrane_stress_pa_per_m2 * w * w;
}

double PlateModel::static_deflection_m(double pressure_pa) const {
  const double load = area_m2 * std::max(pressure_pa, 0.0);
  if (load <= 0.0) return 0.0;
  // Newton on the convex, increasing R(w) - load from a start right of the root (both guesses
  // are: each drops one positive term), so the iterates fall monotonically onto it.
  double w = load / linear_stiffness_n_per_m;
  if (cubic_stiffness_n_per_m3 > 0.0) w = std::min(w, std::cbrt(load / cubic_stiffness_n_per_m3));
  for (int i = 0; i < 100; ++i) {
    const double f = resistance_n(w) - load;
    const double df = linear_stiffness_n_per_m + 3.0 * cubic_stiffness_n_per_m3 * w * w;
    const double next = w - f / df;
    if (!(next < w)) break;
    w = next;
  }
  return w;
}

double PlateModel::natural_period_s() const {
  return 2.0 * kPi * std::sqrt(mass_factor * mass_kg / (load_factor * linear_stiffness_n_per_m));
}

PlateModel plate_model(const PlateSpec& spec) {
  assert(spec.width_m > 0.0 && spec.height_m > 0.0 && spec.thickness_m > 0.0);
  assert(spec.youngs_modulus_pa > 0.0 && spec.density_kg_m3 > 0.0);
  assert(spec.small_deflection_alpha > 0.0 && spec.small_deflection_beta > 0.0);
  assert(spec.poissons_ratio >= 0.0 && spec.poissons_ratio < 0.5);
  const double a = std::max(spec.width_m, spec.height_m);
  const double b = std::min(spec.width_m, spec.height_m);
  const double t = spec.thickness_m;
  const double e = spec.youngs_modulus_pa;
  const double nu = spec.poissons_ratio;
  PlateModel m;
  m.area_m2 = a * b;
  m.mass_kg = spec.density_kg_m3 * a * b * t;
  // Elastic factors of the plate's static shape (Navier series; at b/a -> 0 the one-way strip).
  const ShapeFactors f = two_way_simply_supported_elastic(b / a);
  m.load_factor = f.load;
  m.mass_factor = f.mass;
  m.linear_stiffness_n_per_m =
      m.area_m2 * e * t * t * t / (spec.small_deflection_alpha * b * b * b * b);
  const double a2 = a * a, b2 = b * b;
  const double c3 =
      std::pow(kPi, 4) * e * t *
      ((1.0 / (a2 * a2) + 1.0 / (b2 * b2)) / 16.0 +
       (1.0 / (a2 * a2) + 2.0 * nu / (a2 * b2) + 1.0 / (b2 * b2)) / (8.0 * (1.0 - nu * nu)));
  m.cubic_stiffness_n_per_m3 = m.area_m2 * kPi * kPi / 16.0 * c3;
  m.bending_stress_pa_per_m = spec.small_deflection_beta / spec.small_deflection_alpha * e * t / b2;
  m.membrane_stress_pa_per_m2 =
      kPi * kPi * e / 8.0 * ((1.0 / b2 + nu / a2) / (1.0 - nu * nu) + 1.0 / b2);
  return m;
}

PlateSdofResult solve_plate(const PlateModel& model, const PressureLoad& load,
                            const PlateSolveOptions& options) {
  assert(model.mass_kg > 0.0 && model.linear_stiffness_n_per_m > 0.0);
  PlateSdofResult result;
  if (load.components.empty()) return result;
  const double period = model.natural_period_s();
  const double omega = 2.0 * kPi / period;
  double start = INFINITY;
  for (const LoadComponent& c : load.components)
    start = std::min(start, c.arrival_s);
  // After the load the plate vibrates freely; with no damping its largest |w| comes within one
  // period, which the small-deflection period bounds (stiffening only shortens it).
  const double end = options.end_time_s > 0.0 ? options.end_time_s : load.end_s() + period;
  if (!(end > start)) return result;

  const double equivalent_mass = model.mass_factor * model.mass_kg;
  const double force_per_pa = model.load_factor * model.area_m2 * options.load_scale;
  const auto acceleration = [&](double t, double w) {
    return (force_per_pa * load.pressure_pa(t) - model.load_factor * model.resistance_n(w)) /
           equivalent_mass;
  };
  // Dormand–Prince 5(4) tableau.
  constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  constexpr double a21 = 1.0 / 5;
  constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                   a54 = -212.0 / 729;
  constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                   a65 = -5103.0 / 18656;
  constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784,
                   b6 = 11.0 / 84;
  constexpr double e1 = b1 - 5179.0 / 57600, e3 = b3 - 7571.0 / 16695, e4 = b4 - 393.0 / 640,
                   e5 = b5 + 92097.0 / 339200, e6 = b6 - 187.0 / 2100, e7 = -1.0 / 40;

  // The break: |w| reaching the deflection at which the centre stress is the break stress
  // (the stress grows with |w|: a quadratic b |w| + m w^2 = sigma).
  double break_deflection = INFINITY;
  if (std::isfinite(options.break_stress_pa) && options.break_stress_pa >= 0.0) {
    const double bb = model.bending_stress_pa_per_m, mm = model.membrane_stress_pa_per_m2;
    break_deflection = mm > 0.0 ? 2.0 * options.break_stress_pa /
                                      (bb + std::sqrt(bb * bb + 4.0 * mm * options.break_stress_pa))
                                : options.break_stress_pa / bb;
  }
  double w = 0.0, v = 0.0;
  double h = period / 64.0;
  const double max_step = period / 16.0;
  const std::vector<double> stops = load_breakpoints(load, start, end);
  std::size_t total = 0;
  for (std::size_t seg = 0; seg + 1 < stops.size(); ++seg) {
    double t = stops[seg];
    const double seg_end = stops[seg + 1];
    while (t < seg_end) {
      if (total >= options.max_steps) {
        ++result.warnings;
        result.peak_stress_pa = model.centre_stress_pa(result.peak_deflection_m);
        return result;
      }
      bool last = false;
      double step = std::min(h, max_step);
      if (t + step >= seg_end) step = seg_end - t, last = true;
      // Stages of y' = (v, acc(t, w)).
      const double kw1 = v, kv1 = acceleration(t, w);
      const double kw2 = v + step * a21 * kv1;
      const double kv2 = acceleration(t + c2 * step, w + step * a21 * kw1);
      const double kw3 = v + step * (a31 * kv1 + a32 * kv2);
      const double kv3 = acceleration(t + c3 * step, w + step * (a31 * kw1 + a32 * kw2));
      const double kw4 = v + step * (a41 * kv1 + a42 * kv2 + a43 * kv3);
      const double kv4 =
          acceleration(t + c4 * step, w + step * (a41 * kw1 + a42 * kw2 + a43 * kw3));
      const double kw5 = v + step * (a51 * kv1 + a52 * kv2 + a53 * kv3 + a54 * kv4);
      const double kv5 =
          acceleration(t + c5 * step, w + step * (a51 * kw1 + a52 * kw2 + a53 * kw3 + a54 * kw4));
      const double kw6 = v + step * (a61 * kv1 + a62 * kv2 + a63 * kv3 + a64 * kv4 + a65 * kv5);
      const double kv6 = acceleration(
          t + step, w + step * (a61 * kw1 + a62 * kw2 + a63 * kw3 + a64 * kw4 + a65 * kw5));
      const double w_new = w + step * (b1 * kw1 + b3 * kw3 + b4 * kw4 + b5 * kw5 + b6 * kw6);
      const double v_new = v + step * (b1 * kv1 + b3 * kv3 + b4 * kv4 + b5 * kv5 + b6 * kv6);
      const double kw7 = v_new, kv7 = acceleration(t + step, w_new);
      const double err_w = step * (e1 * kw1 + e3 * kw3 + e4 * kw4 + e5 * kw5 + e6 * kw6 + e7 * kw7);
      const double err_v = step * (e1 * kv1 + e3 * kv3 + e4 * kv4 + e5 * kv5 + e6 * kv6 + e7 * kv7);
      // Error relative to the larger of the state's own size and the motion so far.
      const double size = std::max({std::abs(w_new), result.peak_deflection_m, 1e-9});
      const double err = std::max(std::abs(err_w) / (options.tolerance * size),
                                  std::abs(err_v) / (options.tolerance * size * omega));
      ++total;
      if (!std::isfinite(w_new) || !std::isfinite(v_new)) {
        ++result.warnings;
        result.peak_stress_pa = model.centre_stress_pa(result.peak_deflection_m);
        return result;
      }
      const double grow = err > 0.0 ? 0.9 * std::pow(err, -0.2) : 5.0;
      if (err > 1.0) {
        ++result.rejected_steps;
        h = step * std::max(0.2, grow);
        continue;
      }
      const auto [peak, at] = hermite_peak(w, v, w_new, v_new, step);
      if (result.break_time_s < 0.0 && peak >= break_deflection) {
        const auto [s_break, v_break] =
            hermite_first_reach(w, v, w_new, v_new, step, break_deflection, at);
        result.break_time_s = t + s_break * step;
        result.break_velocity_m_s = v_break;
      }
      if (peak > result.peak_deflection_m) {
        result.peak_deflection_m = peak;
        result.time_to_peak_s = t + at * step;
      }
      ++result.steps;
      w = w_new, v = v_new;
      t = last ? seg_end : t + step;
      if (!last) h = step * std::clamp(grow, 0.2, 5.0);
    }
  }
  result.peak_stress_pa = model.centre_stress_pa(result.peak_deflection_m);
  return result;
}

}  // namespace brisance::response
