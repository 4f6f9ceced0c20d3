// validate/cost.hpp — how long each registered method takes per evaluation
// (the "speed" half of speed against accuracy).
//
// Workload (fixed, reproducible): 4096 inputs, κ log-uniform in [1e−3, 1e4]
// and c uniform in [−1, 1] (std::mt19937_64, seed kCostSeed); the erf
// variants get x uniform in [0, 4]. Inputs are generated in double and
// rounded to float for the float cases, so both precisions see the same
// (rounded) values.
//
// Modes:
//   scalar — a loop over the 4096 inputs calling the registry's f32/f64
//            function pointer once per element (so it includes an indirect
//            call per evaluation and no cross-element vectorization: the cost
//            of calling one method through the registry);
//   batch  — one call of the registry's batch32/batch64 pointer over the 4096
//            inputs (the inlined loop of sglab/batch.hpp, vectorizable). The
//            erf variants have no batch pointer in the registry; their batch
//            mode is the same inlined loop over the variant's functor
//            (ErfListing5, ErfAS7125, ErfStd).
// One thread. ns_per_eval = wall time of a pass / 4096, the median over the
// repetitions.
//
// `sglab bench` times these same cases with Google Benchmark (app/cmd_bench.cpp);
// `measure_costs` times them with std::chrono::steady_clock (no Google
// Benchmark dependency, so the validate library and its tests stay free of it)
// and is what `sglab pareto` and `sglab recommend` use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sweep.hpp"
#include "table.hpp"

namespace sglab::validate {

inline constexpr std::size_t kCostInputs = 4096;
inline constexpr std::uint64_t kCostSeed = 20261121;

enum class CostKind { irradiance, hemispherical, erf };
enum class CostMode { scalar, batch };
std::string_view to_string(CostKind k);  // "irradiance", "hemispherical", "erf"
std::string_view to_string(CostMode m);  // "scalar", "batch"

// The inputs and output buffers shared by every case.
struct CostWorkload {
  std::vector<float> cosine32, kappa32, x32, out32;
  std::vector<double> cosine64, kappa64, x64, out64;
};
std::shared_ptr<CostWorkload> make_cost_workload(std::uint64_t seed = kCostSeed, std::size_t n = kCostInputs);

// One timed case: `run()` evaluates the method once per input (one pass of
// `evaluations` evaluations).
struct CostCase {
  CostKind kind = CostKind::irradiance;
  std::string method;
  bool refit = false;
  FloatFormat precision = FloatFormat::binary32;
  CostMode mode = CostMode::scalar;
  std::size_t evaluations = kCostInputs;
  std::function<void()> run;
  // "kind/method/precision/mode", what --filter matches.
  std::string name() const;
};

// Every case over the registry: irradiance_methods, hemispherical_methods,
// erf_variants × {float, double} × {scalar, batch}, in registry order.
std::vector<CostCase> cost_cases(const std::shared_ptr<CostWorkload>& workload);

struct Cost {
  CostKind kind = CostKind::irradiance;
  std::string method;
  bool refit = false;
  FloatFormat precision = FloatFormat::binary32;
  CostMode mode = CostMode::scalar;
  double ns_per_eval = 0;  // median over the repetitions
};

struct CostOptions {
  int repetitions = 5;
  double min_time = 0.01;  // seconds per repetition (5 × 0.01 s = the ~0.05 s quick mode)
  std::vector<CostKind> kinds{CostKind::irradiance, CostKind::hemispherical, CostKind::erf};
  std::vector<FloatFormat> precisions{FloatFormat::binary32, FloatFormat::binary64};
  std::vector<CostMode> modes{CostMode::scalar, CostMode::batch};
  std::string filter;  // ECMAScript regex searched in CostCase::name(); empty = all
};

// Times one case: `repetitions` times, run passes until `min_time` has
// elapsed (after one warm-up pass), ns per evaluation of that repetition;
// returns the median. Throws std::invalid_argument on repetitions < 1.
double time_case(const CostCase& c, int repetitions, double min_time);

// The quick measurement used by pareto/recommend (steady_clock, one thread).
// Throws std::invalid_argument on repetitions < 1 or a bad filter regex.
std::vector<Cost> measure_costs(const CostOptions& options = {});

// kind, method, precision, mode, ns_per_eval.
Table cost_table(const std::vector<Cost>& costs, std::string title = "Cost per evaluation (median of repetitions)");

}  // namespace sglab::validate
