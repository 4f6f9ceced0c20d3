// Throughput of the erf checker: the variant inlined as a functor versus
// called through the registry's function pointer, and the checker alone.
// Each iteration checks every 64th float bit pattern in [0, 4) plus the tail
// sample (single run, both cores); items/s counts checked points.
#include <cmath>

#include <benchmark/benchmark.h>

#include <sglab/erf.hpp>
#include <sglab/registry.hpp>

#include "validate/erf_check.hpp"

namespace {

sglab::validate::ErfFloatOptions options() {
  sglab::validate::ErfFloatOptions o;
  o.stride = 64;
  o.grid_log2 = 0;
  o.tail_stride = 4099;
  o.odd_stride = 1u << 20;
  return o;
}

template <class F>
void run(benchmark::State& state, F f) {
  std::uint64_t points = 0;
  for (auto _ : state) {
    const auto r = sglab::validate::check_erf_float(f, options());
    benchmark::DoNotOptimize(r.stats.max_ulp);
    points += r.stats.count + r.stats.nonfinite;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(points));
}

const sglab::ErfVariant& variant(const char* id) { return *sglab::find_erf_variant(id); }

void BM_CheckerOnly(benchmark::State& s) {
  run(s, [](float x) { return x < 1.0f ? x : 1.0f; });
}
void BM_Listing5Functor(benchmark::State& s) { run(s, sglab::ErfListing5{}); }
void BM_Listing5Pointer(benchmark::State& s) { run(s, variant("listing5").f32); }
void BM_AS7125Functor(benchmark::State& s) { run(s, sglab::ErfAS7125{}); }
void BM_AS7125Pointer(benchmark::State& s) { run(s, variant("as7125").f32); }
void BM_StdFunctor(benchmark::State& s) { run(s, sglab::ErfStd{}); }
void BM_StdPointer(benchmark::State& s) { run(s, variant("std").f32); }

}  // namespace

BENCHMARK(BM_CheckerOnly)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Listing5Functor)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Listing5Pointer)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AS7125Functor)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AS7125Pointer)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StdFunctor)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StdPointer)->Unit(benchmark::kMillisecond)->UseRealTime();
