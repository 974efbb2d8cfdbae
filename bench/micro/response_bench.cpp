// bench/micro/response_bench: speed of sim/response — one SDOF history and one full P–I curve on
// one core (goals: under 20 us and under 20 ms, issue 16), and the large-deflection pane model a
// job runs once per breakable pane (a breaking-pressure search runs it about 30 times). A
// program, not a test (STYLE.md §12).
#include <benchmark/benchmark.h>

#include "sim/response/pi_diagram.hpp"
#include "sim/response/plate.hpp"
#include "sim/response/sdof.hpp"

namespace {

using namespace brisance;

// An RC slab strip-like element: 500 kg, 2 m^2, k = 2 MN/m, R_y = 100 kN, simply supported.
response::Element slab() {
  response::Element e;
  e.mass_kg = 500.0;
  e.loaded_area_m2 = 2.0;
  e.resistance.type = response::ResistanceType::elastic_plastic;
  e.resistance.stiffness_n_per_m = 2.0e6;
  e.resistance.yield_resistance_n = 1.0e5;
  e.load_factor = 0.64;
  e.mass_factor = 0.50;
  e.span_m = 3.0;
  return e;
}

// One history: 100 kg TNT at 15 m, head-on Friedlander pulse, to three periods after the load.
void BM_SdofHistory(benchmark::State& state) {
  const response::SdofSystem sys = response::equivalent_system(slab());
  blast::Charge charge;
  charge.tnt_equivalent_kg = 100.0;
  const response::PressureLoad load{{response::charge_component(charge, 15.0, 0.0)}};
  response::SolveOptions opt;
  opt.record_history = state.range(0) != 0;
  std::size_t steps = 0;
  for (auto _ : state) {
    const response::SdofResult r = response::solve_sdof(sys, load, opt);
    benchmark::DoNotOptimize(r.peak_displacement_m);
    steps = r.steps;
  }
  state.counters["steps"] = static_cast<double>(steps);
}
BENCHMARK(BM_SdofHistory)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

// One P–I curve: 60 durations from t_d / T = 0.01 to 100, ductility 5.
void BM_PiCurve(benchmark::State& state) {
  const response::SdofSystem sys = response::equivalent_system(slab());
  response::PiOptions opt;
  opt.points = static_cast<std::size_t>(state.range(0));
  const double limit = response::displacement_for_ductility(sys, 5.0);
  std::size_t solves = 0;
  for (auto _ : state) {
    const response::PiCurve c = response::pi_curve(sys, limit, opt);
    benchmark::DoNotOptimize(c.points.data());
    solves = c.solves;
  }
  state.counters["solves"] = static_cast<double>(solves);
}
BENCHMARK(BM_PiCurve)->Arg(60)->Unit(benchmark::kMillisecond);

// window.json's pane (1.2 x 0.9 m, 6 mm glass, Roark alpha/beta at a/b = 4/3 interpolated
// between the rows 1.2 and 1.4) under its reflected pulse: 10 kg TNT at 10 m head-on.
void BM_PlatePane(benchmark::State& state) {
  response::PlateSpec spec;
  spec.width_m = 1.2;
  spec.height_m = 0.9;
  spec.thickness_m = 0.006;
  const double s = (4.0 / 3.0 - 1.2) / 0.2;
  spec.small_deflection_alpha = 0.0616 + s * (0.0770 - 0.0616);
  spec.small_deflection_beta = 0.3762 + s * (0.4530 - 0.3762);
  const response::PlateModel model = response::plate_model(spec);
  blast::Charge charge;
  charge.tnt_equivalent_kg = 10.0;
  const response::PressureLoad load{{response::charge_component(charge, 10.0, 0.0)}};
  std::size_t steps = 0;
  double stress = 0.0;
  for (auto _ : state) {
    const response::PlateSdofResult r = response::solve_plate(model, load);
    benchmark::DoNotOptimize(r.peak_stress_pa);
    steps = r.steps + r.rejected_steps;
    stress = r.peak_stress_pa;
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["stress_MPa"] = stress / 1e6;
}
BENCHMARK(BM_PlatePane)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
