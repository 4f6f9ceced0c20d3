// fit/minimax.hpp — the one fitting engine behind every target: Ceres
// least squares, and minimax (smallest maximum residual) on top of it by
// Lawson's iteratively reweighted least squares as a warm start, polished
// by a quadratic-penalty solve of the epigraph form min E, |r_i| ≤ E.
//
// A problem is a list of scalar residual functions r_i(p) of the same N
// scalar parameters (each its own size-1 parameter block, so any of them can
// be held fixed, e.g. after rounding it to float). Residuals are built from
// small functors with a templated operator() so Ceres can differentiate the
// runtime code itself (STYLE.md, Ceres examples).
#pragma once

#include <atomic>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "common/io.hpp"

namespace sglab::fit {

struct Parameters {
  std::vector<std::string> names;
  std::vector<double> values;
  std::vector<bool> fixed;  // empty = none fixed
  // Box of the search space (Ceres keeps every trial point inside it): empty = unbounded.
  std::vector<double> lower = {}, upper = {};

  std::size_t size() const { return values.size(); }
  bool is_fixed(std::size_t i) const { return i < fixed.size() && fixed[i]; }
};

enum class Norm { least_squares, minimax };

struct FitOptions {
  Norm norm = Norm::minimax;
  int lawson_iterations = 20;         // reweighting rounds for minimax (the warm start)
  int penalty_decades = 12;           // then penalty weights 10^2 … 10^this (relative)
  int solver_iterations = 200;        // Ceres iterations per round
  double relative_tolerance = 1e-12;  // Ceres function tolerance
  // On a problem with bounds Ceres follows every trust-region step with a
  // projected line search (Solver::Options::max_num_line_search_step_size_iterations),
  // several residual and Jacobian evaluations per iteration. Where the box only
  // keeps trial points finite and the optimum lies far inside it, that search
  // changes nothing but the time: turn it off (the steps are still clamped to
  // the box).
  bool projected_line_search = true;
};

struct FitResult {
  std::vector<double> values;
  double max_abs = 0;     // max |r_i| at `values`
  std::size_t worst = 0;  // index of that residual
  double rms = 0;
  bool converged = false;
  int rounds = 0;
};

// `inner` with the same parameter blocks and residuals, counting each
// evaluation whose residual or Jacobian entry is NaN or ±inf in `counter`
// (null: the process-wide count below).
std::unique_ptr<ceres::CostFunction> make_checked_residual(
    std::unique_ptr<ceres::CostFunction> inner, std::atomic<std::size_t>* counter = nullptr);

// Residual evaluations in this process so far (every fit, every solve, the
// trial steps Ceres rejects included) that gave a NaN or ±inf residual or
// derivative. A residual must stay finite over the whole search space: such
// an evaluation is a defect of the model or of its parameterization (Ceres
// rejects the step and logs "Error in evaluating the ResidualBlock"). `sglab
// fit` reports the count of each fit; tests require it to stay 0.
std::size_t nonfinite_residual_evaluations();
// The non-finite evaluations made on the calling thread, of every checked
// residual (whatever its counter): a fit makes all of its evaluations on the
// thread that runs it, so this attributes them to the fit (run_fits,
// fit/targets.hpp).
std::size_t nonfinite_residual_evaluations_on_this_thread();

// A residual functor F has `template <class T> bool operator()(T const* const* p, T* r) const`
// writing one residual from the N scalar parameters p[0][0] … p[N−1][0].
// Every residual is wrapped so that an evaluation giving a non-finite value
// or derivative is counted (nonfinite_residual_evaluations below).
template <class F>
std::unique_ptr<ceres::CostFunction> make_residual(F functor, std::size_t num_parameters) {
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<F, 4>>(new F(std::move(functor)));
  for (std::size_t i = 0; i < num_parameters; ++i) cost->AddParameterBlock(1);
  cost->SetNumResiduals(1);
  return make_checked_residual(std::move(cost));
}

using Residuals = std::vector<std::unique_ptr<ceres::CostFunction>>;

// Residual values at `values` (NaN where a residual cannot be evaluated).
std::vector<double> evaluate_residuals(const Residuals& residuals,
                                       const std::vector<double>& values);

// Least squares or minimax fit from params.values (the start point). Fixed
// parameters stay at their values. Deterministic: same inputs, same digits.
// For minimax, the result is the best iterate on the true max |r|.
FitResult fit(const Residuals& residuals, const Parameters& params, const FitOptions& options = {});

// Rounds every free parameter to float, one at a time in order, re-fitting
// the remaining free ones after each rounding (for coefficients that a float
// shader will store).
FitResult fit_rounded_to_float(const Residuals& residuals, Parameters params,
                               const FitOptions& options = {});

// Progress of a long fit. While a FitProgressScope is alive, every solve that
// fit() makes on the same thread advances its Progress, and
// fit_progress_note() on that thread sets the text shown after the count (the
// model being fitted). `sglab fit` opens one per target when it runs one fit
// at a time; the Progress draws only when stderr is a terminal.
class FitProgressScope {
 public:
  explicit FitProgressScope(io::Progress& progress);
  ~FitProgressScope();
  FitProgressScope(const FitProgressScope&) = delete;
  FitProgressScope& operator=(const FitProgressScope&) = delete;

 private:
  io::Progress* previous_;
};
// No-op without a scope on the calling thread.
void fit_progress_note(std::string status);

}  // namespace sglab::fit
