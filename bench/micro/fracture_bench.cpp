// Fracture micro-benchmarks: crack growth on a 2048 × 2048 bit bucket and fragment extraction,
// for a pattern of about a thousand fragments (thesis fig. 5.14 style). Goal: under 50 ms total.
//   fracture_bench --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include "sim/fracture/fragments.hpp"

namespace {

using brisance::fracture::FractureParams;

FractureParams thousand_fragments() {
  FractureParams p = brisance::fracture::combined_preset();  // 2048², angle variance and wiggle
  p.growth_length_m = 0.0008;                                // about 1000 fragments on 1 m × 1 m
  p.wiggle_length_m = 0.01;
  return p;
}

void BM_GrowCrackTree(benchmark::State& state) {
  const FractureParams p = thousand_fragments();
  for (auto _ : state)
    benchmark::DoNotOptimize(brisance::fracture::grow_crack_tree(p));
}
BENCHMARK(BM_GrowCrackTree)->Unit(benchmark::kMillisecond);

void BM_ExtractFragments(benchmark::State& state) {
  const FractureParams p = thousand_fragments();
  const auto tree = brisance::fracture::grow_crack_tree(p);
  for (auto _ : state)
    benchmark::DoNotOptimize(brisance::fracture::extract_fragments(tree, p.width_m, p.height_m));
}
BENCHMARK(BM_ExtractFragments)->Unit(benchmark::kMillisecond);

// Growth plus extraction, reporting the fragment count.
void BM_Fracture(benchmark::State& state) {
  const FractureParams p = thousand_fragments();
  std::size_t fragments = 0;
  for (auto _ : state) {
    const auto pattern = brisance::fracture::fracture(p);
    fragments = pattern.fragments.size();
    benchmark::DoNotOptimize(pattern);
  }
  state.counters["fragments"] = static_cast<double>(fragments);
}
BENCHMARK(BM_Fracture)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
