// Micro-benchmarks of the blast model: the full parameter set at one point (goal: under 200 ns),
// the oblique reflection, the Friedlander fit and the analytic pulse integral the simulator
// calls every step. Run: make bench (Release build).
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/panel_load.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/blast/reflection.hpp"

namespace {

using namespace brisance::blast;

// Distances cycle through the near, middle and far field so branch prediction and the piece
// lookup see realistic variety.
std::vector<double> distances() {
  std::vector<double> r;
  for (int i = 0; i < 64; ++i)
    r.push_back(0.5 * std::pow(1.08, i));  // 0.5 m .. 63 m
  return r;
}

void BM_BlastPoint(benchmark::State& state) {
  const Charge charge{100.0, state.range(0) ? Burst::surface : Burst::air};
  const std::vector<double> r = distances();
  std::size_t i = 0;
  for (auto _ : state) {
    BlastPoint p = blast_point(charge, r[i++ & 63]);
    benchmark::DoNotOptimize(p);
  }
}
BENCHMARK(BM_BlastPoint)->Arg(0)->Arg(1)->ArgName("surface");

void BM_ObliqueReflection(benchmark::State& state) {
  const BlastPoint p = blast_point(Charge{100.0}, 12.0);
  double angle = 0.0;
  for (auto _ : state) {
    ObliqueReflection o =
        oblique_reflection(p.incident_overpressure_pa, p.incident_impulse_pa_s,
                           p.reflected_overpressure_pa, p.reflected_impulse_pa_s, angle);
    benchmark::DoNotOptimize(o);
    angle = angle > 1.5 ? 0.0 : angle + 0.037;
  }
}
BENCHMARK(BM_ObliqueReflection);

void BM_FriedlanderFit(benchmark::State& state) {
  double ratio = 0.05;
  for (auto _ : state) {
    Pulse pulse = make_pulse(PulseShape::friedlander, 1e5, 1e-2, ratio * 1e5 * 1e-2);
    benchmark::DoNotOptimize(pulse);
    ratio = ratio > 0.7 ? 0.05 : ratio + 0.013;
  }
}
BENCHMARK(BM_FriedlanderFit);

void BM_PulseIntegral(benchmark::State& state) {
  const Pulse pulse = make_pulse(PulseShape::friedlander, 2e5, 5e-3, 0.2 * 2e5 * 5e-3);
  const double dt = 1e-4;
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pulse.impulse_pa_s(t, t + dt));
    t = t > 5e-3 ? 0.0 : t + dt;
  }
}
BENCHMARK(BM_PulseIntegral);

void BM_NetPanelHistoryIntegral(benchmark::State& state) {
  // The cleared front-face history (five pieces): what one loaded panel costs per step.
  const BlastPoint p = blast_point(Charge{100.0}, 12.0);
  PanelWave wave{p.incident_overpressure_pa, p.incident_impulse_pa_s,
                 p.positive_duration_s,      p.shock_velocity_m_s,
                 p.dynamic_pressure_pa,      p.reflected_overpressure_pa,
                 p.reflected_impulse_pa_s,   1.0};
  PanelLoadOptions options;
  options.clearing_distance_m = 0.5;
  const PressureHistory net = front_face_history(wave, options);
  const double dt = 1e-4;
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(net.impulse_pa_s(t, t + dt));
    t = t > p.positive_duration_s ? 0.0 : t + dt;
  }
}
BENCHMARK(BM_NetPanelHistoryIntegral);

}  // namespace

BENCHMARK_MAIN();
