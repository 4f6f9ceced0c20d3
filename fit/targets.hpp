// fit/targets.hpp — the `sglab fit` targets. Each target builds its
// residuals from the runtime templates, fits with fit/minimax, evaluates the
// published constants on the same objective, and returns constant sets to
// write plus a report.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/vocabulary.hpp"
#include "reference/reference.hpp"

namespace sglab::io {
class Progress;
}

namespace sglab::fit {

using ordered_json = nlohmann::ordered_json;

// Float scalar costs of runtime methods (ns per evaluation) from the cost
// table that `sglab bench` wrote (cost/cost_table.hpp), read by the caller:
// a fit that compares costs takes them from here and never times anything,
// so that its report is the same for the same inputs.
// The costs of the runtime methods from a cost table (cost/cost_table.hpp),
// in one source (cost/cost_source.hpp): by default ACO's inverse throughput
// of the float GLSL export on navi21 (cycles), else CPU batch ns/eval.
struct MethodCosts {
  std::string what;    // which cost, e.g. "GPU inverse throughput on navi21 (cycles per wave)"
  std::string source;  // the table's file and how it was made; empty: no table
  std::map<std::string, double> per_method;  // method id → cost in that source's unit
};

struct FitSpec {
  std::string target;  // a name of fit_targets()
  io::Precision precision = io::Precision::float32;
  std::string objective;    // target-specific; empty = the target's default
  bool alpha_free = false;  // clamped-cosine: α free instead of tied by energy conservation
  double kappa_lo = 1e-3, kappa_hi = 1e4;
  int kappa_count = 29, cosine_count = 41;
  bool kappa_range_given = false;   // --kappa was given: the variant name records the range
  std::optional<double> max_error;  // model order: the error budget
  bool cold_start = false;  // sglab-fast, sglab-mid: ignore the committed set as a warm start
  std::string command;      // the command line, recorded in provenance
  MethodCosts costs;        // sglab-acc: the cost column of its report
};

struct FitOutcome {
  std::vector<ordered_json> constant_sets;  // data/constants/<target>-<variant>.json contents
  ordered_json report;                      // what --json prints
  std::string text;                         // human-readable summary
  bool converged = true;
};

// Machine epsilon (spacing of 1) of the working precision: 2^−10, 2^−23, 2^−52.
double machine_epsilon(io::Precision p);

// Log-spaced κ grid of `count` values over [lo, hi] (io::log_spaced; count 1: lo) and
// cosine grid c_i = −1 + 2i/(count − 1).
std::vector<double> kappa_grid(double lo, double hi, int count);
std::vector<double> cosine_grid(int count);

// `text` as a C++ identifier: every character but letters and digits as '_'.
std::string cpp_identifier(std::string text);

// A constant set with provenance; `coefficients` in parameter-struct order;
// its cpp_name is cpp_identifier(target + "_" + variant).
ordered_json make_constant_set(const FitSpec& spec, const std::string& target,
                               const std::string& variant, const std::string& cpp_type,
                               const std::string& form, ordered_json coefficients,
                               ordered_json objective, ordered_json achieved);

FitOutcome fit_clamped_cosine(const FitSpec& spec);
// steepness2022 / steepness2024, objective optimal-t | irradiance
FitOutcome fit_steepness(const FitSpec& spec);
FitOutcome fit_lambda_d(const FitSpec& spec);
FitOutcome fit_erf(const FitSpec& spec);
FitOutcome fit_sglab_fast(const FitSpec& spec);  // sglab_fast (fit/fit_sglab_fast.cpp)
FitOutcome fit_sglab_mid(const FitSpec& spec);   // sglab_mid (fit/fit_sglab_mid.cpp)
FitOutcome fit_sglab_lite(const FitSpec& spec);  // sglab_lite (fit/fit_sglab_fast.cpp)
FitOutcome fit_sglab_min(const FitSpec& spec);   // sglab_min (fit/fit_sglab_min.cpp)
FitOutcome fit_sglab_tab(const FitSpec& spec);   // sglab_tab (fit/fit_sglab_tab.cpp)
// sglab_acc<N> ladder, or its model order with max_error
FitOutcome fit_sglab_acc(const FitSpec& spec);

// The dense training grid of sglab-acc's certificate and LP exchange over [lo, hi]
// (fit/fit_sglab_acc_grids.cpp): κ log-spaced at half-step offsets (twice as dense in [0.5, 200])
// plus the ends; per κ, c = 0, 64 uniform cosines at half-step offsets and c = ±z_k/t(κ), z_k =
// 0.05 … 3.15 where |c| < 1, sorted by c: symmetric about 0 and distinct.
std::vector<reference::Query> sglab_acc_dense_grid(double lo, double hi);

// The core of the sglab-acc fit, exposed for tests: minimax of the
// peak_rel error of SglabAccParams<double, terms, degree> on `samples`, each
// divided by its weight, from `start` = steep[5], num[terms(degree+1)], scale (> 0).
struct SglabAccSample {
  double kappa, cosine, irradiance;
  double weight = 1;  // the residual is peak_rel/weight (fit/fit_sglab_acc.cpp: w(κ))
};
struct SglabAccFit {
  std::vector<double> values;  // same layout as start
  double max_abs = 0;          // max peak_rel on the samples
  bool converged = false;
};
SglabAccFit fit_sglab_acc_coefficients(std::size_t terms, std::size_t degree,
                                       const std::vector<double>& start,
                                       const std::vector<SglabAccSample>& samples);

// t*(κ) at each κ: the steepness that minimaxes, over 201 cosines, the 2022
// s̃ − s (target "steepness2022") or the 2024 f − (E − E(−1))/(E(1) − E(−1))
// ("steepness2024") — the dots of [Tokuyoshi2022] supplementary Fig. 2.
std::vector<double> optimal_steepness(const std::string& target, const std::vector<double>& kappas);

// One `fit all` run of a target: its objective (empty: the default), α
// tie and working precision.
struct FitAllRun {
  std::string_view objective;
  bool alpha_free;
  std::string_view precision;
};

// The `sglab fit` targets, one row each: every place that lists targets (the
// dispatch, the CLI's help and option checks, `fit all`) reads this table.
struct FitTarget {
  std::string_view name;
  FitOutcome (*fit)(const FitSpec&);
  std::string_view help;  // one line for `sglab fit --help`
  // The options the target takes; any other is refused, never ignored.
  bool precision = false, objective = false, kappa = false, max_error = false, alpha_free = false,
       cold_start = false, costs = false;
  std::span<const FitAllRun> all;  // the runs of `fit all`, in order
};
std::span<const FitTarget> fit_targets();
// The row of `name`, nullptr when there is none.
const FitTarget* find_fit_target(std::string_view name);
// "clamped-cosine, steepness2022, …" for messages and help.
std::string fit_target_names();

// Dispatch by spec.target; throws std::invalid_argument for an unknown target or objective.
FitOutcome run_fit(const FitSpec& spec);

// Runs every spec (run_fit), up to `jobs` of them at once, each on one thread
// (a fit is serial inside, so its outcome is the same whatever `jobs`),
// started from the last spec to the first (fit all's longest fits are last). To
// each outcome's report "diagnostics" is added: the residual evaluations of
// the fit that were not finite (nonfinite_residual_evaluations) and the
// messages its solver logged (solver_messages), both 0 in a sound fit, with a
// warning line in its text otherwise. `done(i, outcome)` is called for every
// spec in order, one call at a time, as soon as fits 0..i have finished;
// `finished` advances as each fit finishes. With one job at a time each fit
// shows its solves on a progress line of its own (FitProgressScope). A fit
// that throws stops new ones from starting; once the running ones have
// finished, the first exception in spec order is rethrown.
void run_fits(const std::vector<FitSpec>& specs, std::size_t jobs, io::Progress& finished,
              const std::function<void(std::size_t, FitOutcome&)>& done);

}  // namespace sglab::fit
