// cost/cpu_timing.hpp — how long each registered method takes per evaluation
// (the "speed" half of speed against accuracy).
//
// Workload (fixed, reproducible): kCostInputs = 2^20 (1,048,576) inputs,
// κ log-uniform in [1e−3, 1e4] (log10 κ uniform in [−3, 4]) and c uniform in
// [−1, 1] (std::mt19937_64, seed kCostSeed); the erf variants get x uniform in
// [0, 4]. Inputs are generated in double and rounded to float for the float
// cases, so both precisions see the same (rounded) values. So many distinct
// inputs keep the branch predictor from learning a short repeated sequence
// (which flatters branchy methods); cost_input_description() states this.
//
// Modes:
//   scalar — a loop over the inputs calling the registry's f32/f64
//            function pointer once per element (so it includes an indirect
//            call per evaluation and no cross-element vectorization: the cost
//            of calling one method through the registry);
//   batch  — one call of the registry's batch32/batch64 pointer over the
//            inputs (the inlined loop of sglab/batch.hpp or a method's own
//            vectorizing kernel). The erf variants have no batch pointer in
//            the registry; their batch mode is the same inlined loop over the
//            variant's functor (ErfListing5, ErfAS7125, ErfStd).
//   light_setup — float methods with the per-light split only: the registry's
//            light_setup32 once per κ of the inputs (ns per light);
//   light_eval  — light_eval32 as a renderer calls it: kCostLights lights
//            (the first κ of the inputs) each evaluated at a contiguous
//            1/kCostLights of the cosines (ns per shading point).
// One thread. ns_per_eval = wall time of a pass / evaluations per pass, the
// median over the repetitions.
//
// `sglab bench` times these same cases with Google Benchmark
// (cost/benchmark_runner.hpp)
// and writes the cost table (cost_table.hpp) that `sglab pareto` and
// `sglab recommend` read; `measure_costs` times them with
// std::chrono::steady_clock (no Google Benchmark dependency) for their
// --live-timing option.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/vocabulary.hpp"

namespace sglab::cost {

inline constexpr std::size_t kCostInputs = std::size_t{1} << 20;
inline constexpr std::size_t kCostLights = 256;

// The input distribution, as stated in the bench output and the cost table.
std::string cost_input_description(std::size_t n = kCostInputs);
inline constexpr std::uint64_t kCostSeed = 20261121;

enum class CostKind { irradiance, hemispherical, erf };
enum class CostMode { scalar, batch, light_setup, light_eval };
constexpr std::array<io::EnumName<CostKind>, 3> names_of(CostKind) {
  return {{{CostKind::irradiance, "irradiance"},
           {CostKind::hemispherical, "hemispherical"},
           {CostKind::erf, "erf"}}};
}
constexpr std::array<io::EnumName<CostMode>, 4> names_of(CostMode) {
  return {{{CostMode::scalar, "scalar"},
           {CostMode::batch, "batch"},
           {CostMode::light_setup, "light_setup"},
           {CostMode::light_eval, "light_eval"}}};
}
using io::to_string;

// The inputs and output buffers shared by every case.
struct CostWorkload {
  std::vector<float> cosine32, kappa32, x32, out32;
  std::vector<double> cosine64, kappa64, x64, out64;
};
std::shared_ptr<CostWorkload> make_cost_workload(std::uint64_t seed = kCostSeed,
                                                 std::size_t n = kCostInputs);

// What a cost is of: a method of one kind, in one precision and mode.
struct CostOf {
  CostKind kind = CostKind::irradiance;
  std::string method;
  bool refit = false;
  io::Precision precision = io::Precision::float32;
  CostMode mode = CostMode::scalar;
};

// One timed case: `run()` evaluates the method once per input (one pass of
// `evaluations` evaluations).
struct CostCase : CostOf {
  std::size_t evaluations = kCostInputs;
  std::function<void()> run;
  // "kind/method/precision/mode", what --filter matches.
  std::string name() const;
};

// Every case over the registry: irradiance_methods, hemispherical_methods,
// erf_variants × {float, double} × {scalar, batch}, plus float light_setup
// and light_eval for methods with the per-light split, in registry order.
std::vector<CostCase> cost_cases(const std::shared_ptr<CostWorkload>& workload);

struct Cost : CostOf {
  double ns_per_eval = 0;  // median over the repetitions
};

struct CostOptions {
  int repetitions = 5;
  double min_time = 0.01;  // seconds per repetition (5 × 0.01 s = the ~0.05 s quick mode)
  std::vector<CostKind> kinds{CostKind::irradiance, CostKind::hemispherical, CostKind::erf};
  std::vector<io::Precision> precisions{io::Precision::float32, io::Precision::float64};
  std::vector<CostMode> modes{CostMode::scalar, CostMode::batch, CostMode::light_setup,
                              CostMode::light_eval};
  std::string filter;  // ECMAScript regex searched in CostCase::name(); empty = all
};

// Times one case: `repetitions` times, run passes until `min_time` has
// elapsed (after one warm-up pass), ns per evaluation of that repetition;
// returns the median. Throws std::invalid_argument on repetitions < 1.
double time_case(const CostCase& c, int repetitions, double min_time);

// The quick measurement used by pareto/recommend (steady_clock, one thread).
// Throws std::invalid_argument on repetitions < 1 or a bad filter regex.
std::vector<Cost> measure_costs(const CostOptions& options = {});

}  // namespace sglab::cost
