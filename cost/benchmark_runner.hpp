// cost/benchmark_runner.hpp — the cost cases (cpu_timing.hpp) timed with
// Google Benchmark, as `sglab bench` records them in the cost table: one
// thread, wall-clock time, the median of the repetitions, the repetitions of
// all cases interleaved in random order (Google Benchmark's
// --benchmark_enable_random_interleaving), so that a drift of the machine's
// speed during the run spreads over every case instead of biasing the cases
// timed last (their ratios are what the tables compare).
#pragma once

#include <vector>

#include "cost/cpu_timing.hpp"

namespace sglab::cost {

// The costs of `cases` (ns per evaluation, in the order of `cases`) and the
// 1-minute load average before and after (−1 when unknown).
struct BenchmarkTimings {
  std::vector<Cost> costs;
  double load_start = 0, load_end = 0;
};

// Times every case, `repetitions` times for at least `min_time` seconds each,
// with a progress line on a terminal. Throws std::runtime_error when a case
// produced no result.
BenchmarkTimings time_with_google_benchmark(const std::vector<CostCase>& cases, int repetitions,
                                            double min_time);

}  // namespace sglab::cost
