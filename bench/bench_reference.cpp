// Reference engine throughput: (κ, c) points per second, H and E together
// (s included), on fresh random points (κ log-uniform in [1e−3, 1e4], c
// uniform in [−1, 1]) so that nothing is served from the cache. Read
// `items_per_second`. The batch benchmark uses every core (TBB) and is timed
// in wall-clock time; the single benchmark is one thread.
// Then the irradiance table (reference/irradiance_table.hpp), E alone to 1e−10
// of the peak, on the same kind of points, one thread: a point at a time
// (a slice per point), many cosines per κ (the slice of a scene's lobe), and
// the build at first use.
//
//   build-ref/bench/bench_reference --benchmark_min_time=2
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "reference/irradiance_table.hpp"
#include "reference/reference.hpp"

namespace {

using sglab::reference::irradiance_table;
using sglab::reference::IrradianceTable;
using sglab::reference::Quadrature;
using sglab::reference::Query;
using sglab::reference::ReferenceEngine;

std::vector<Query> random_points(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Query> q(n);
  for (auto& p : q) p = {std::pow(10.0, -3 + 7 * unit(rng)), -1 + 2 * unit(rng)};
  return q;
}

// The batch API: TBB over all cores.
void BM_ReferenceBatch(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  std::mt19937_64 rng(1);
  ReferenceEngine engine;
  for (auto _ : state) {
    state.PauseTiming();
    const auto points = random_points(rng, n);
    engine.clear_cache();
    state.ResumeTiming();
    benchmark::DoNotOptimize(engine.evaluate(points));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}
BENCHMARK(BM_ReferenceBatch)->Arg(4096)->UseRealTime()->Unit(benchmark::kMillisecond);

// One point at a time on one thread.
void BM_ReferenceSingle(benchmark::State& state) {
  std::mt19937_64 rng(2);
  ReferenceEngine engine;
  auto points = random_points(rng, 1 << 16);
  std::size_t i = 0;
  for (auto _ : state) {
    if (i == points.size()) {
      state.PauseTiming();
      points = random_points(rng, points.size());
      engine.clear_cache();
      i = 0;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(engine.evaluate(points[i].kappa, points[i].cosine));
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ReferenceSingle)->Unit(benchmark::kMicrosecond);

// Cache hits (a sweep revisiting its grid).
void BM_ReferenceCached(benchmark::State& state) {
  std::mt19937_64 rng(3);
  ReferenceEngine engine;
  const auto points = random_points(rng, 1024);
  engine.evaluate(points);
  for (auto _ : state) benchmark::DoNotOptimize(engine.evaluate(points));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}
BENCHMARK(BM_ReferenceCached)->UseRealTime()->Unit(benchmark::kMicrosecond);

// The 50-digit mode, for the ratio (slow: a small batch).
void BM_ReferenceHighBatch(benchmark::State& state) {
  std::mt19937_64 rng(4);
  ReferenceEngine engine;
  for (auto _ : state) {
    state.PauseTiming();
    const auto points = random_points(rng, 32);
    engine.clear_cache();
    state.ResumeTiming();
    benchmark::DoNotOptimize(engine.evaluate(points, Quadrature::high));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 32));
}
BENCHMARK(BM_ReferenceHighBatch)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(3);

// The irradiance table, one point at a time: a slice of its κ, then E.
void BM_IrradianceTableSingle(benchmark::State& state) {
  std::mt19937_64 rng(5);
  const auto points = random_points(rng, 1 << 16);
  const IrradianceTable& table = irradiance_table();  // built outside the timing
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(table.irradiance(points[i].kappa, points[i].cosine));
    i = (i + 1) & (points.size() - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_IrradianceTableSingle)->Unit(benchmark::kNanosecond);

// The irradiance table, 4096 cosines per slice (a scene's lobe at every normal).
void BM_IrradianceTableSlice(benchmark::State& state) {
  std::mt19937_64 rng(6);
  const auto points = random_points(rng, 4096);
  const IrradianceTable& table = irradiance_table();
  std::size_t k = 0;
  for (auto _ : state) {
    const IrradianceTable::Slice slice = table.slice(points[k].kappa);
    double sum = 0;
    for (const auto& p : points) sum += slice(p.cosine);
    benchmark::DoNotOptimize(sum);
    k = (k + 1) % points.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}
BENCHMARK(BM_IrradianceTableSlice)->Unit(benchmark::kMicrosecond);

// Building the table: one quadrature per node, on every core (wall-clock).
void BM_IrradianceTableBuild(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(IrradianceTable().pieces().size());
}
BENCHMARK(BM_IrradianceTableBuild)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
