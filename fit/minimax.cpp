#include "minimax.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace sglab::fit {

std::vector<double> evaluate_residuals(const Residuals& residuals, const std::vector<double>& values) {
  std::vector<const double*> blocks(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  std::vector<double> out(residuals.size());
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    double r = std::numeric_limits<double>::quiet_NaN();
    if (!residuals[i]->Evaluate(blocks.data(), &r, nullptr)) r = std::numeric_limits<double>::quiet_NaN();
    out[i] = r;
  }
  return out;
}

namespace {

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
bool solve_weighted(const Residuals& residuals, const Parameters& params, const std::vector<double>& weights,
                    std::vector<double>& values, const FitOptions& options) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  std::vector<double*> blocks(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    if (weights[i] <= 0) continue;
    problem.AddResidualBlock(residuals[i].get(), new ceres::ScaledLoss(nullptr, weights[i], ceres::TAKE_OWNERSHIP),
                             blocks);
  }
  for (std::size_t i = 0; i < values.size(); ++i)
    if (params.is_fixed(i) && problem.HasParameterBlock(blocks[i])) problem.SetParameterBlockConstant(blocks[i]);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.solver_iterations;
  solver_options.function_tolerance = options.relative_tolerance;
  solver_options.parameter_tolerance = 1e-15;
  solver_options.gradient_tolerance = 1e-16;
  solver_options.num_threads = 1;  // deterministic
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  return summary.IsSolutionUsable();
}

}  // namespace

FitResult fit(const Residuals& residuals, const Parameters& params, const FitOptions& options) {
  FitResult best;
  best.values = params.values;
  summarize(evaluate_residuals(residuals, best.values), best);
  const std::size_t n = residuals.size();
  // Scale weights to the start point's residuals so Ceres' tolerances are relative.
  const double scale = best.max_abs > 0 && std::isfinite(best.max_abs) ? 1 / (best.max_abs * best.max_abs) : 1.0;
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
    if (current.max_abs < best.max_abs || round == 0 && options.norm == Norm::least_squares) {
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
      weights[i] = std::max(weights[i] * std::abs(r[i]) / total, 1e-12 / static_cast<double>(n)) * scale;
  }
  best.converged = any_usable && std::isfinite(best.max_abs);
  return best;
}

FitResult fit_rounded_to_float(const Residuals& residuals, Parameters params, const FitOptions& options) {
  FitResult result = fit(residuals, params, options);
  params.values = result.values;
  params.fixed.resize(params.size(), false);
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (params.fixed[i]) continue;
    params.values[i] = static_cast<double>(static_cast<float>(params.values[i]));
    params.fixed[i] = true;
    const bool any_free = std::find(params.fixed.begin(), params.fixed.end(), false) != params.fixed.end();
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
