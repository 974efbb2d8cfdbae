// sim/response/sdof: piecewise closed-form integration of the equivalent SDOF system.
//
// Within a step the resistance is one straight branch (R = k_b y + r_0) and the force is the
// straight line with the same impulse and first moment as the true pressure over the step (both
// exact, sim/blast/pulse). The linear ODE m y'' + c y' + k_b y = f_0 + f_1 s then has a closed form
// (particular line + matrix exponential of the homogeneous part), exact for triangular pulses and
// second order in the step for curved ones. Branch changes (yield, reversal, a new envelope
// segment) are located inside the step by a bracketed root search on the closed form, so elastic
// unloading and the permanent set come out exactly. Rejected: average-acceleration Newmark (thesis
// §2.7) — it needs a small step everywhere to place the yield point.
#include "sim/response/sdof.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "sim/blast/reflection.hpp"

namespace brisance::response {

double PressureLoad::pressure_pa(double t_s) const {
  double p = 0.0;
  for (const LoadComponent& c : components) {
    if (t_s >= c.arrival_s) p += c.history.pressure_pa(t_s - c.arrival_s);
  }
  return p;
}

double PressureLoad::impulse_pa_s(double t0_s, double t1_s) const {
  double i = 0.0;
  for (const LoadComponent& c : components) {
    i += c.history.impulse_pa_s(t0_s - c.arrival_s, t1_s - c.arrival_s);
  }
  return i;
}

double PressureLoad::moment_pa_s2(double t0_s, double t1_s) const {
  double m = 0.0;
  for (const LoadComponent& c : components) {
    m += c.history.moment_pa_s2(t0_s - c.arrival_s, t1_s - c.arrival_s);
  }
  return m;
}

double PressureLoad::end_s() const {
  double end = 0.0;
  for (const LoadComponent& c : components)
    end = std::max(end, c.arrival_s + c.history.end_s());
  return end;
}

LoadComponent pulse_component(const blast::Pulse& pulse, double arrival_s) {
  LoadComponent c;
  c.arrival_s = arrival_s;
  c.history.add(pulse.piece());
  return c;
}

LoadComponent charge_component(const blast::Charge& charge, double distance_m, double angle_rad,
                               blast::PulseShape shape, const blast::Ambient& air) {
  const blast::BlastPoint bp = blast::blast_point(charge, distance_m, air);
  const blast::ObliqueReflection r =
      blast::oblique_reflection(bp.incident_overpressure_pa, bp.incident_impulse_pa_s,
                                bp.reflected_overpressure_pa, bp.reflected_impulse_pa_s, angle_rad);
  return pulse_component(
      blast::make_pulse(shape, r.overpressure_pa, bp.positive_duration_s, r.impulse_pa_s),
      bp.arrival_time_s);
}

double SdofSystem::natural_period_s() const {
  return 2.0 * std::numbers::pi * std::sqrt(mass_kg / resistance.stiffness_n_per_m);
}

SdofSystem equivalent_system(const Element& e) {
  SdofSystem s;
  s.mass_kg = e.mass_factor * e.mass_kg;
  s.force_per_pa_m2 = e.load_factor * e.loaded_area_m2;
  s.load_factor = e.load_factor;
  s.span_m = e.span_m;
  s.resistance = make_resistance(e.resistance);
  // The resistance factor equals the load factor (Biggs 1964 §5.3).
  auto scale = [&](Envelope& env) {
    for (std::size_t i = 0; i < env.count; ++i) {
      env.segments[i].resistance_at_start_n *= e.load_factor;
      env.segments[i].slope_n_per_m *= e.load_factor;
    }
  };
  s.resistance.stiffness_n_per_m *= e.load_factor;
  scale(s.resistance.loading);
  scale(s.resistance.rebound);
  s.damping_n_s_per_m =
      2.0 * e.damping_ratio * std::sqrt(s.resistance.stiffness_n_per_m * s.mass_kg);
  return s;
}

namespace {

enum class Branch { elastic, loading, rebound };

// Where the motion is on the resistance function.
struct Phase {
  Branch branch = Branch::elastic;
  double set_m = 0.0;       // elastic branch: displacement at zero resistance
  std::size_t segment = 0;  // envelope branches: which segment
};

struct Line {
  double stiffness_n_per_m = 0.0;  // k_b
  double offset_n = 0.0;           // r_0: R = k_b y + r_0
};

Line branch_line(const Resistance& r, const Phase& ph) {
  switch (ph.branch) {
    case Branch::elastic:
      return {r.stiffness_n_per_m, -r.stiffness_n_per_m * ph.set_m};
    case Branch::loading: {
      const EnvelopeSegment& s = r.loading.segments[ph.segment];
      return {s.slope_n_per_m, s.resistance_at_start_n - s.slope_n_per_m * s.start_m};
    }
    case Branch::rebound: {
      // Mirrored: R(y) = -E(-y).
      const EnvelopeSegment& s = r.rebound.segments[ph.segment];
      return {s.slope_n_per_m, -s.resistance_at_start_n + s.slope_n_per_m * s.start_m};
    }
  }
  return {};
}

// The closed-form motion on one branch under the force f_0 + f_1 s, from (y0, v0) at s = 0.
class BranchMotion {
 public:
  BranchMotion(double mass_kg, double damping, const Line& line, double f0, double f1, double y0,
               double v0)
      : m_(mass_kg), c_(damping), k_(line.stiffness_n_per_m), f1_(f1), g0_(f0 - line.offset_n) {
    sigma_ = -0.5 * c_ / m_;
    delta_ = k_ / m_;
    const double mu2 = sigma_ * sigma_ - delta_;
    oscillating_ = mu2 < 0.0;
    rate_ = std::sqrt(std::abs(mu2));
    double yp0 = 0.0;
    double vp0 = 0.0;
    particular(0.0, yp0, vp0);
    yh0_ = y0 - yp0;
    vh0_ = v0 - vp0;
  }

  void at(double s, double& y, double& v) const {
    double yp = 0.0;
    double vp = 0.0;
    particular(s, yp, vp);
    double cs = 1.0;
    double sn = s;  // S(s) = sin(w s) / w, sinh(mu s) / mu, or s when w = mu = 0
    if (rate_ > 0.0) {
      if (oscillating_) {
        cs = std::cos(rate_ * s);
        sn = std::sin(rate_ * s) / rate_;
      } else {
        cs = std::cosh(rate_ * s);
        sn = std::sinh(rate_ * s) / rate_;
      }
    }
    const double decay = sigma_ == 0.0 ? 1.0 : std::exp(sigma_ * s);
    // exp(A s) = exp(sigma s) [C I + S (A - sigma I)], A = [[0, 1], [-k/m, -c/m]].
    y = yp + decay * (cs * yh0_ + sn * (vh0_ - sigma_ * yh0_));
    v = vp + decay * (cs * vh0_ + sn * (sigma_ * vh0_ - delta_ * yh0_));
  }

 private:
  // A particular solution of m y'' + c y' + k y = g0 + f1 s.
  void particular(double s, double& y, double& v) const {
    if (k_ > 0.0) {
      const double b = f1_ / k_;
      y = (g0_ - c_ * b) / k_ + b * s;
      v = b;
    } else if (c_ > 0.0) {
      const double p1 = f1_ / c_;
      const double p0 = (g0_ - m_ * p1) / c_;
      y = p0 * s + 0.5 * p1 * s * s;
      v = p0 + p1 * s;
    } else {
      y = (g0_ / 2.0 + f1_ * s / 6.0) * s * s / m_;
      v = (g0_ + 0.5 * f1_ * s) * s / m_;
    }
  }

  double m_, c_, k_, f1_, g0_;
  double sigma_ = 0.0, delta_ = 0.0, rate_ = 0.0;
  bool oscillating_ = false;
  double yh0_ = 0.0, vh0_ = 0.0;
};

// First root of f in (0, h] given f(0) and f(h) of opposite signs (Illinois false position).
template <typename F>
double first_root(F f, double h, double f0, double fh) {
  double a = 0.0, b = h, fa = f0, fb = fh;
  int side = 0;
  for (int i = 0; i < 100 && b - a > 1e-14 * h; ++i) {
    const double x = (a * fb - b * fa) / (fb - fa);
    const double s = std::clamp(x, a + 1e-3 * (b - a), b - 1e-3 * (b - a));
    const double fs = f(s);
    if ((fs > 0.0) == (fb > 0.0)) {
      b = s;
      fb = fs;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = s;
      fa = fs;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
  }
  return b;
}

// Where a curved piece is linearised over a step, the longest step its shape allows.
struct StepWindow {
  double begin_s = 0.0;
  double end_s = 0.0;
  double max_step_s = 0.0;
};

std::vector<StepWindow> load_step_windows(const PressureLoad& load) {
  std::vector<StepWindow> windows;
  for (const LoadComponent& c : load.components) {
    for (std::size_t i = 0; i < c.history.size(); ++i) {
      const blast::ExpPolyPiece& p = c.history.piece(i);
      const bool straight = p.rate == 0.0 && p.coeff_pa[2] == 0.0 && p.coeff_pa[3] == 0.0;
      if (straight) continue;
      double scale = p.end_s - p.begin_s;
      if (std::abs(p.rate) > 1.0) scale = std::min(scale, p.scale_s / std::abs(p.rate));
      windows.push_back({c.arrival_s + p.begin_s, c.arrival_s + p.end_s, scale / 16.0});
    }
  }
  return windows;
}

// Times where the load's slope may jump: step boundaries, so straight pieces are exact.
std::vector<double> load_breakpoints(const PressureLoad& load) {
  std::vector<double> t;
  for (const LoadComponent& c : load.components) {
    t.push_back(c.arrival_s);
    for (std::size_t i = 0; i < c.history.size(); ++i) {
      t.push_back(c.arrival_s + c.history.piece(i).begin_s);
      t.push_back(c.arrival_s + c.history.piece(i).end_s);
    }
  }
  std::sort(t.begin(), t.end());
  return t;
}

}  // namespace

SdofResult solve_sdof(const SdofSystem& sys, const PressureLoad& load, const SolveOptions& opt) {
  assert(sys.mass_kg > 0.0 && sys.resistance.stiffness_n_per_m > 0.0);
  const Resistance& res = sys.resistance;
  const double k = res.stiffness_n_per_m;
  const double period_s = sys.natural_period_s();
  const double load_end_s = load.end_s();
  const double end_s = opt.end_time_s > 0.0  ? opt.end_time_s
                       : opt.stop_after_peak ? load_end_s + 4.0 * period_s
                                             : load_end_s + 3.0 * period_s;
  // T / 32 keeps every velocity reversal inside a step findable (at most one per half period);
  // curved pieces of the load get a finer step only while they act.
  double free_step_s = period_s / 32.0;
  if (opt.max_step_s > 0.0) free_step_s = std::min(free_step_s, opt.max_step_s);
  const std::vector<StepWindow> windows = load_step_windows(load);
  const std::vector<double> breaks = load_breakpoints(load);
  const double force_scale = sys.force_per_pa_m2 * opt.load_scale;

  SdofResult out;
  double t = 0.0;
  double y = opt.initial_displacement_m;
  double v = opt.initial_velocity_m_s;
  Phase ph;
  // Start on the branch the initial displacement lies on (elastic about zero unless beyond).
  out.peak_displacement_m = y;
  out.min_displacement_m = y;
  auto resistance_of = [&](double y_m) {
    const Line l = branch_line(res, ph);
    return l.stiffness_n_per_m * y_m + l.offset_n;
  };
  auto record = [&] {
    if (opt.record_history) {
      out.history.push_back({t, y, v, resistance_of(y) / sys.load_factor});
    }
  };
  record();
  std::size_t next_break = 0;
  constexpr std::size_t kMaxSteps = 10'000'000;
  bool done = false;
  while (!done && t < end_s) {
    if (out.steps++ >= kMaxSteps) {
      ++out.warnings;
      break;
    }
    while (next_break < breaks.size() && breaks[next_break] <= t * (1.0 + 1e-15))
      ++next_break;
    double max_step_s = free_step_s;
    for (const StepWindow& w : windows) {
      if (t >= w.begin_s && t < w.end_s) max_step_s = std::min(max_step_s, w.max_step_s);
    }
    double t1 = std::min(t + max_step_s, end_s);
    if (next_break < breaks.size()) t1 = std::min(t1, breaks[next_break]);
    const double h = t1 - t;
    // The straight force with the step's exact impulse and first moment.
    const double impulse = force_scale * load.impulse_pa_s(t, t1);
    const double moment = force_scale * load.moment_pa_s2(t, t1);
    const double f1 = (6.0 * impulse * h - 12.0 * moment) / (h * h * h);
    const double f0 = impulse / h - 0.5 * f1 * h;
    const BranchMotion motion(sys.mass_kg, sys.damping_n_s_per_m, branch_line(res, ph), f0, f1, y,
                              v);
    double y1 = 0.0;
    double v1 = 0.0;
    motion.at(h, y1, v1);
    if (!std::isfinite(y1) || !std::isfinite(v1)) {
      ++out.warnings;
      break;
    }

    // Events: a velocity reversal first (at most one per step, as h <= T / 32), then the branch's
    // boundaries up to that reversal — y is monotone there, so a boundary crossed and re-crossed
    // around a peak inside one step is still found.
    enum class Event { none, leave_up, leave_down, next_segment, stop_up, stop_down };
    Event event = Event::none;
    double s_event = h;
    auto y_at = [&](double s) {
      double ys = 0.0, vs = 0.0;
      motion.at(s, ys, vs);
      return ys;
    };
    auto v_at = [&](double s) {
      double ys = 0.0, vs = 0.0;
      motion.at(s, ys, vs);
      return vs;
    };
    if ((v > 0.0 && v1 <= 0.0) || (v < 0.0 && v1 >= 0.0)) {
      s_event = first_root(v_at, h, v, v1);
      event = v > 0.0 ? Event::stop_up : Event::stop_down;
    }
    const double y_end = event == Event::none ? y1 : y_at(s_event);
    auto boundary = [&](Event e, double edge_m) {
      const double s = first_root([&](double q) { return y_at(q) - edge_m; }, s_event, y - edge_m,
                                  y_end - edge_m);
      s_event = s;
      event = e;
    };
    if (ph.branch == Branch::elastic) {
      const double hi = res.loading.elastic_meet_m(k, ph.set_m);
      const double lo = -res.rebound.elastic_meet_m(k, -ph.set_m);
      if (y_end > hi) boundary(Event::leave_up, hi);
      if (y_end < lo) boundary(Event::leave_down, lo);
    } else {
      const Envelope& env = ph.branch == Branch::loading ? res.loading : res.rebound;
      if (ph.segment + 1 < env.count) {
        const double sign = ph.branch == Branch::loading ? 1.0 : -1.0;
        const double edge = sign * env.segments[ph.segment + 1].start_m;
        if (sign * (y_end - edge) > 0.0) boundary(Event::next_segment, edge);
      }
    }
    if (event != Event::none) {
      motion.at(s_event, y1, v1);
      t1 = t + s_event;
      ++out.events;
    }
    t = t1;
    y = y1;
    v = v1;
    // The time to peak is when the peak is first reached: an undamped element repeats its peak
    // every period, and round-off must not move the time to a later, equal one.
    if (y > out.peak_displacement_m) {
      if (y > out.peak_displacement_m + 1e-9 * std::abs(out.peak_displacement_m))
        out.time_to_peak_s = t;
      out.peak_displacement_m = y;
    }
    out.min_displacement_m = std::min(out.min_displacement_m, y);
    switch (event) {
      case Event::none:
        break;
      case Event::stop_up:
      case Event::stop_down: {
        const double r = resistance_of(y);
        v = 0.0;
        if (ph.branch != Branch::elastic) ph = {Branch::elastic, y - r / k, 0};
        if (event == Event::stop_up && opt.stop_after_peak && t >= load_end_s) done = true;
        break;
      }
      case Event::leave_up:
        ph = {Branch::loading, 0.0, res.loading.segment_at(y)};
        break;
      case Event::leave_down:
        ph = {Branch::rebound, 0.0, res.rebound.segment_at(-y)};
        break;
      case Event::next_segment:
        ++ph.segment;
        break;
    }
    record();
    if (opt.stop_above_m && y > *opt.stop_above_m) done = true;
  }

  out.end_time_s = t;
  out.permanent_set_m = y - resistance_of(y) / k;
  const double limit_m = res.elastic_limit_m();
  if (std::isfinite(limit_m)) out.ductility = out.peak_displacement_m / limit_m;
  if (sys.span_m) {
    out.support_rotation_deg =
        std::atan(out.peak_displacement_m / (0.5 * *sys.span_m)) * 180.0 / std::numbers::pi;
  }
  return out;
}

}  // namespace brisance::response
