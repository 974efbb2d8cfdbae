// sim/response/pi_diagram: bisections on the SDOF for the P–I and W–R diagrams.
#include "sim/response/pi_diagram.hpp"

#include <cassert>
#include <cmath>
#include <numbers>

namespace brisance::response {

double displacement_for_ductility(const SdofSystem& system, double ductility) {
  assert(std::isfinite(system.elastic_limit_m()));
  return ductility * system.elastic_limit_m();
}

double displacement_for_rotation(const SdofSystem& system, double rotation_deg) {
  assert(system.span_m);
  return 0.5 * *system.span_m * std::tan(rotation_deg * std::numbers::pi / 180.0);
}

double impulsive_asymptote_pa_s(const SdofSystem& system, double displacement_limit_m) {
  const double energy_j = system.resistance.backbone_energy_j(displacement_limit_m);
  return std::sqrt(2.0 * system.mass_kg * energy_j) / system.force_per_pa_m2;
}

double quasi_static_asymptote_pa(const SdofSystem& system, double displacement_limit_m) {
  const double energy_j = system.resistance.backbone_energy_j(displacement_limit_m);
  return energy_j / (displacement_limit_m * system.force_per_pa_m2);
}

namespace {

// Bisection in log space on a positive parameter x with reaches(x) monotone: returns the
// geometric middle of the last bracket, or 0 when no bracket was found in [floor, ceil].
template <typename F>
double bisect_log(F reaches, double guess, double floor, double ceil, double tol, bool& ok) {
  double lo = guess;
  double hi = guess;
  ok = true;
  while (reaches(lo)) {
    hi = lo;
    lo *= 0.5;
    if (lo < floor) {
      ok = false;
      return 0.0;
    }
  }
  if (hi == lo) {
    hi = lo * 2.0;
    while (!reaches(hi)) {
      lo = hi;
      hi *= 2.0;
      if (hi > ceil) {
        ok = false;
        return 0.0;
      }
    }
  }
  while (hi / lo - 1.0 > tol) {
    const double mid = std::sqrt(lo * hi);
    (reaches(mid) ? hi : lo) = mid;
  }
  return std::sqrt(lo * hi);
}

}  // namespace

PiCurve pi_curve(const SdofSystem& system, double displacement_limit_m, const PiOptions& options) {
  assert(options.points >= 2 && displacement_limit_m > 0.0);
  PiCurve curve;
  curve.displacement_limit_m = displacement_limit_m;
  curve.impulsive_asymptote_pa_s = impulsive_asymptote_pa_s(system, displacement_limit_m);
  curve.quasi_static_asymptote_pa = quasi_static_asymptote_pa(system, displacement_limit_m);
  const double period_s = system.natural_period_s();
  SolveOptions solve;
  solve.record_history = false;
  solve.stop_after_peak = true;
  solve.stop_above_m = displacement_limit_m;
  const double step = std::log(options.max_duration_ratio / options.min_duration_ratio) /
                      static_cast<double>(options.points - 1);
  for (std::size_t i = 0; i < options.points; ++i) {
    const double duration_s =
        period_s * options.min_duration_ratio * std::exp(step * static_cast<double>(i));
    // A unit-peak triangle; the bisection scales it.
    const PressureLoad load{{pulse_component(blast::make_pulse(
        blast::PulseShape::triangle_same_period, 1.0, duration_s, 0.5 * duration_s))}};
    auto reaches = [&](double peak_pa) {
      solve.load_scale = peak_pa;
      ++curve.solves;
      return solve_sdof(system, load, solve).peak_displacement_m >= displacement_limit_m;
    };
    // Start just under both asymptotes (the curve lies above them when undamped).
    const double guess = 0.99 * std::max(curve.quasi_static_asymptote_pa,
                                         2.0 * curve.impulsive_asymptote_pa_s / duration_s);
    bool ok = true;
    const double peak_pa =
        bisect_log(reaches, guess, guess * 1e-6, guess * 1e6, options.relative_tolerance, ok);
    if (!ok) {
      ++curve.warnings;
      continue;
    }
    curve.points.push_back({duration_s, peak_pa, 0.5 * peak_pa * duration_s});
  }
  return curve;
}

std::vector<WrPoint> wr_curve(const SdofSystem& system, double displacement_limit_m,
                              const std::vector<double>& distances_m, const WrOptions& options) {
  std::vector<WrPoint> out;
  SolveOptions solve;
  solve.record_history = false;
  solve.stop_after_peak = true;
  solve.stop_above_m = displacement_limit_m;
  for (double distance_m : distances_m) {
    blast::Charge charge = options.charge;
    auto reaches = [&](double mass_kg) {
      charge.tnt_equivalent_kg = mass_kg;
      const PressureLoad load{
          {charge_component(charge, distance_m, options.angle_rad, options.shape)}};
      return solve_sdof(system, load, solve).peak_displacement_m >= displacement_limit_m;
    };
    bool ok = true;
    const double guess = std::sqrt(options.min_charge_kg * options.max_charge_kg);
    const double mass_kg = bisect_log(reaches, guess, options.min_charge_kg, options.max_charge_kg,
                                      options.relative_tolerance, ok);
    WrPoint p{distance_m, ok ? mass_kg : 0.0, ok};
    if (ok) {
      charge.tnt_equivalent_kg = mass_kg;
      p.in_validity_range = blast::blast_point(charge, distance_m).in_validity_range;
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace brisance::response
