#include "fit/minimax.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <numeric>
#include <utility>

namespace sglab::fit {

std::vector<double> evaluate_residuals(const Residuals& residuals,
                                       const std::vector<double>& values) {
  std::vector<const double*> blocks(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  std::vector<double> out(residuals.size());
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    double r = std::numeric_limits<double>::quiet_NaN();
    if (!residuals[i]->Evaluate(blocks.data(), &r, nullptr))
      r = std::numeric_limits<double>::quiet_NaN();
    out[i] = r;
  }
  return out;
}

namespace {

std::atomic<std::size_t> g_nonfinite_evaluations{0};
// The same count for the evaluations made on this thread (a fit solves on
// the thread that runs it: Ceres with one thread).
thread_local std::size_t t_nonfinite_evaluations = 0;

class CheckedResidual final : public ceres::CostFunction {
 public:
  CheckedResidual(std::unique_ptr<ceres::CostFunction> inner, std::atomic<std::size_t>& counter)
      : inner_(std::move(inner)), counter_(counter) {
    set_num_residuals(inner_->num_residuals());
    *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    if (!inner_->Evaluate(p, residuals, jacobians)) return false;
    const std::size_t m = static_cast<std::size_t>(num_residuals());
    bool finite = true;
    for (std::size_t i = 0; i < m; ++i) finite = finite && std::isfinite(residuals[i]);
    const auto& sizes = parameter_block_sizes();
    for (std::size_t b = 0; jacobians && b < sizes.size(); ++b)
      for (std::size_t k = 0; jacobians[b] && k < m * static_cast<std::size_t>(sizes[b]); ++k)
        finite = finite && std::isfinite(jacobians[b][k]);
    if (!finite) {
      counter_.fetch_add(1, std::memory_order_relaxed);
      ++t_nonfinite_evaluations;
    }
    return true;
  }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  std::atomic<std::size_t>& counter_;
};

// The progress of the fit running on this thread (FitProgressScope).
thread_local io::Progress* t_fit_progress = nullptr;

void count_solve() {
  if (t_fit_progress) t_fit_progress->advance();
}

// The box of `params` on the free parameter blocks of `problem`.
void set_bounds(ceres::Problem& problem, const Parameters& params,
                const std::vector<double*>& blocks) {
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (params.is_fixed(i) || !problem.HasParameterBlock(blocks[i])) continue;
    if (i < params.lower.size()) problem.SetParameterLowerBound(blocks[i], 0, params.lower[i]);
    if (i < params.upper.size()) problem.SetParameterUpperBound(blocks[i], 0, params.upper[i]);
  }
}

void summarize(const std::vector<double>& r, FitResult& result) {
  result.max_abs = 0;
  result.worst = 0;
  double sum = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double a = std::abs(r[i]);
    if (!(a <= result.max_abs)) {  // NaN counts as worst
      result.max_abs = std::isnan(a) ? std::numeric_limits<double>::infinity() : a;
      result.worst = i;
    }
    sum += r[i] * r[i];
  }
  result.rms = r.empty() ? 0 : std::sqrt(sum / static_cast<double>(r.size()));
}

// One weighted least-squares solve from `values`; returns Ceres' verdict.
bool solve_weighted(const Residuals& residuals, const Parameters& params,
                    const std::vector<double>& weights, std::vector<double>& values,
                    const FitOptions& options) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<double*> blocks(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    if (weights[i] <= 0) continue;
    problem.AddResidualBlock(residuals[i].get(),
                             new ceres::ScaledLoss(nullptr, weights[i], ceres::TAKE_OWNERSHIP),
                             blocks);
  }
  for (std::size_t i = 0; i < values.size(); ++i)
    if (params.is_fixed(i) && problem.HasParameterBlock(blocks[i]))
      problem.SetParameterBlockConstant(blocks[i]);
  set_bounds(problem, params, blocks);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.solver_iterations;
  solver_options.function_tolerance = options.relative_tolerance;
  solver_options.parameter_tolerance = 1e-15;
  solver_options.gradient_tolerance = 1e-16;
  if (!options.projected_line_search) solver_options.max_num_line_search_step_size_iterations = 0;
  solver_options.num_threads = 1;  // deterministic
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  count_solve();
  return summary.IsSolutionUsable();
}

// Epigraph form of minimax, min E subject to |r_i(p)| ≤ E, by a quadratic
// penalty: ½(wE)² + ½μ Σ max(0, |r_i| − E)², with μ raised step by step. Lawson's
// reweighting alone converges slowly when many residuals are nearly maximal
// (a smooth extremum, or a dense grid); the penalty form reaches the minimax
// point to the precision the schedule allows in either case.
class PenaltyResidual final : public ceres::CostFunction {
 public:
  PenaltyResidual(const ceres::CostFunction* base, std::size_t num_params, double sqrt_mu)
      : base_(base), n_(num_params), sqrt_mu_(sqrt_mu) {
    set_num_residuals(1);
    for (std::size_t i = 0; i <= n_; ++i) mutable_parameter_block_sizes()->push_back(1);
  }
  // The base residual's derivatives only where the constraint is active: near
  // the minimax point most |r_i| are below E, and their row is 0 (the value
  // alone costs one double evaluation instead of the autodiff passes).
  bool Evaluate(double const* const* p, double* residual, double** jacobians) const override {
    double r = 0;
    if (!base_->Evaluate(p, &r, nullptr)) return false;
    const double E = p[n_][0];
    bool active = std::abs(r) - E > 0;
    std::vector<double> jac;
    if (jacobians && active) {
      jac.assign(n_, 0.0);
      std::vector<double*> jac_ptrs(n_);
      for (std::size_t i = 0; i < n_; ++i) jac_ptrs[i] = &jac[i];
      if (!base_->Evaluate(p, &r, jac_ptrs.data())) return false;
      active = std::abs(r) - E > 0;
    }
    const double excess = std::abs(r) - E;
    residual[0] = active ? sqrt_mu_ * excess : 0.0;
    if (jacobians) {
      const double sign = r < 0 ? -1.0 : 1.0;
      for (std::size_t i = 0; i < n_; ++i)
        if (jacobians[i]) jacobians[i][0] = active ? sqrt_mu_ * sign * jac[i] : 0.0;
      if (jacobians[n_]) jacobians[n_][0] = active ? -sqrt_mu_ : 0.0;
    }
    return true;
  }

 private:
  const ceres::CostFunction* base_;
  std::size_t n_;
  double sqrt_mu_;
};

struct ScaledBound {
  double w;
  template <class T>
  bool operator()(const T* E, T* r) const {
    r[0] = T(w) * E[0];
    return true;
  }
};

bool solve_penalty(const Residuals& residuals, const Parameters& params,
                   std::vector<double>& values, double& bound, double mu,
                   const FitOptions& options) {
  ceres::Problem problem;
  std::vector<double*> blocks(values.size() + 1);
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  blocks[values.size()] = &bound;
  const double scale = 1 / std::max(bound, 1e-300);
  for (const auto& r : residuals)
    problem.AddResidualBlock(new PenaltyResidual(r.get(), values.size(), std::sqrt(mu) * scale),
                             nullptr, blocks);
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<ScaledBound, 1, 1>(new ScaledBound{scale}), nullptr, &bound);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (params.is_fixed(i)) problem.SetParameterBlockConstant(blocks[i]);
  set_bounds(problem, params, blocks);
  problem.SetParameterLowerBound(&bound, 0, 0.0);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.solver_iterations;
  solver_options.function_tolerance = 1e-15;
  solver_options.parameter_tolerance = 1e-16;
  solver_options.gradient_tolerance = 1e-20;
  if (!options.projected_line_search) solver_options.max_num_line_search_step_size_iterations = 0;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  count_solve();
  return summary.IsSolutionUsable();
}

}  // namespace

std::unique_ptr<ceres::CostFunction> make_checked_residual(
    std::unique_ptr<ceres::CostFunction> inner, std::atomic<std::size_t>* counter) {
  return std::make_unique<CheckedResidual>(std::move(inner),
                                           counter ? *counter : g_nonfinite_evaluations);
}

std::size_t nonfinite_residual_evaluations() { return g_nonfinite_evaluations.load(); }
std::size_t nonfinite_residual_evaluations_on_this_thread() { return t_nonfinite_evaluations; }

FitProgressScope::FitProgressScope(io::Progress& progress)
    : previous_(std::exchange(t_fit_progress, &progress)) {}
FitProgressScope::~FitProgressScope() { t_fit_progress = previous_; }

void fit_progress_note(std::string status) {
  if (t_fit_progress) t_fit_progress->note(std::move(status));
}

FitResult fit(const Residuals& residuals, const Parameters& params, const FitOptions& options) {
  FitResult best;
  best.values = params.values;
  summarize(evaluate_residuals(residuals, best.values), best);
  const std::size_t n = residuals.size();
  // Scale weights to the start point's residuals so Ceres' tolerances are relative.
  const double scale =
      best.max_abs > 0 && std::isfinite(best.max_abs) ? 1 / (best.max_abs * best.max_abs) : 1.0;
  std::vector<double> weights(n, scale / static_cast<double>(n));
  std::vector<double> values = params.values;
  const int rounds = options.norm == Norm::minimax ? options.lawson_iterations : 1;
  bool any_usable = false;
  for (int round = 0; round < rounds; ++round) {
    if (!solve_weighted(residuals, params, weights, values, options)) break;
    any_usable = true;
    const std::vector<double> r = evaluate_residuals(residuals, values);
    FitResult current;
    current.values = values;
    summarize(r, current);
    current.rounds = round + 1;
    if (current.max_abs < best.max_abs || (round == 0 && options.norm == Norm::least_squares)) {
      current.converged = true;
      best = current;
    }
    if (options.norm != Norm::minimax) break;
    // Lawson's update: w_i ← w_i |r_i| / Σ_j w_j |r_j|, kept away from zero
    // so that a residual can come back.
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) total += weights[i] * std::abs(r[i]);
    if (!(total > 0) || !std::isfinite(total)) break;
    for (std::size_t i = 0; i < n; ++i)
      weights[i] =
          std::max(weights[i] * std::abs(r[i]) / total, 1e-12 / static_cast<double>(n)) * scale;
  }
  if (options.norm == Norm::minimax && any_usable) {
    // Polish with the penalty form of the epigraph problem, μ raised by
    // decades (relative to the current bound): keep the best true max |r|.
    values = best.values;
    double bound = best.max_abs;
    for (int k = 2; k <= options.penalty_decades; ++k) {
      if (!solve_penalty(residuals, params, values, bound, std::pow(10.0, k), options)) break;
      FitResult current;
      current.values = values;
      summarize(evaluate_residuals(residuals, values), current);
      current.rounds = best.rounds + 1;
      if (current.max_abs < best.max_abs) best = current;
      bound = std::max(bound, 0.5 * best.max_abs);
    }
  }
  best.converged = any_usable && std::isfinite(best.max_abs);
  return best;
}

FitResult fit_rounded_to_float(const Residuals& residuals, Parameters params,
                               const FitOptions& options) {
  FitResult result = fit(residuals, params, options);
  params.values = result.values;
  params.fixed.resize(params.size(), false);
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (params.fixed[i]) continue;
    params.values[i] = static_cast<double>(static_cast<float>(params.values[i]));
    params.fixed[i] = true;
    const bool any_free =
        std::find(params.fixed.begin(), params.fixed.end(), false) != params.fixed.end();
    if (any_free) {
      result = fit(residuals, params, options);
      params.values = result.values;
    }
  }
  result.values = params.values;
  summarize(evaluate_residuals(residuals, result.values), result);
  return result;
}

}  // namespace sglab::fit
