// The certified fit of one sglab-acc member: Ceres on the training grid
// alternating with the exact LP of the numerators on the dense grid, then
// measured and certified (the LP bound and the per-κ floor).
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_acc.hpp>

#include "fit/fit_sglab_acc_family.hpp"
#include "fit/lp_minimax.hpp"
#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit {

namespace acc {

void bound(Parameters& p) {
  p.lower.clear();
  p.upper.clear();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool log = p.names[i].rfind("log", 0) == 0;
    p.lower.push_back(log ? kLogLower : -kLinearBound);
    p.upper.push_back(log ? kLogUpper : kLinearBound);
    p.values[i] = std::clamp(p.values[i], p.lower[i], p.upper[i]);
  }
}

namespace {

// The errors of member (N, D) with coefficients p on `ref` (model_family.hpp).
template <std::size_t N, std::size_t D, std::size_t M>
Measured measure(const SglabAccParams<double, N, D, M>& p,
                 const std::vector<reference::ReferencePoint>& ref) {
  return fit::measure([&](auto c, auto k) { return irradiance_sglab_acc(c, k, p); }, ref);
}

// The residuals of member (N, D, M) on `samples`, of the parameters log steep[2M + 1], num, log
// scale.
template <std::size_t N, std::size_t D, std::size_t M>
Residuals member_residuals(const std::vector<SglabAccSample>& samples) {
  Residuals residuals;
  for (const auto& r : samples)
    residuals.push_back(make_residual(PeakRelResidual<N, D, M>{r.kappa, r.cosine, r.irradiance,
                                                               irradiance_upper(r.kappa), r.weight},
                                      steep_count(M) + N * (D + 1) + 1));
  return residuals;
}

template <std::size_t N, std::size_t D, std::size_t M>
SglabAccFit fit_coefficients(const std::vector<double>& start,
                             const std::vector<SglabAccSample>& samples, bool polish_only) {
  constexpr std::size_t K = steep_count(M);
  Parameters params;
  for (std::size_t i = 0; i < K; ++i) params.names.push_back(fmt::format("log_steep{}", i));
  for (std::size_t i = 0; i < N * (D + 1); ++i) params.names.push_back(fmt::format("num{}", i));
  params.names.push_back("log_scale");
  for (std::size_t i = 0; i < K; ++i) params.values.push_back(std::log(start[i]));
  params.values.insert(params.values.end(), start.begin() + K, start.begin() + K + N * (D + 1));
  params.values.push_back(std::log(start[K + N * (D + 1)]));
  bound(params);
  const Residuals residuals = member_residuals<N, D, M>(samples);
  // Fewer rounds than the defaults: the training grid is large and the
  // staged start is close. From a converged set (the committed JSON) a short
  // polish: the full schedule there takes minutes and moves the error < 2%.
  FitOptions options;
  options.lawson_iterations = polish_only ? 2 : 12;
  options.penalty_decades = polish_only ? 4 : 8;
  options.solver_iterations = polish_only ? 30 : 200;
  const FitResult f = fit(residuals, params, options);
  SglabAccFit out;
  for (std::size_t i = 0; i < K; ++i) out.values.push_back(std::exp(f.values[i]));
  out.values.insert(out.values.end(), f.values.begin() + K, f.values.begin() + K + N * (D + 1));
  out.values.push_back(std::exp(f.values[K + N * (D + 1)]));
  out.max_abs = f.max_abs;
  out.converged = f.converged;
  return out;
}

// The parameters of member_residuals (log steep, num, log scale) of values (steep, num, scale),
// `k` steepness coefficients.
std::vector<double> log_parameters(std::vector<double> v, std::size_t k) {
  for (std::size_t i = 0; i < k; ++i) v[i] = std::log(v[i]);
  v.back() = std::log(v.back());
  return v;
}

// The best numerators at the steepness and scale of `values` on `samples`:
// at fixed t(κ) and s, f̂ and so Ê is linear in the coefficients of every P_j,
// so the minimax is the LP of fit/lp_minimax.hpp (exchange from a subset of
// the rows). Returns `values` with those numerators, and the LP's answer
// with `achieved` taken on the model itself (the clamp of f̂ to [0, 1] lies
// outside the linear part).
template <std::size_t N, std::size_t D, std::size_t M>
std::pair<std::vector<double>, LpMinimaxResult> best_numerators(
    const std::vector<double>& values, const std::vector<SglabAccSample>& samples) {
  constexpr std::size_t K = steep_count(M);
  const Residuals residuals = member_residuals<N, D, M>(samples);
  std::vector<std::size_t> linear(N * (D + 1));
  std::iota(linear.begin(), linear.end(), K);
  const LinearSubproblem sub = linear_subproblem(residuals, log_parameters(values, K), linear);
  LpMinimaxResult lp = lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  std::vector<double> out = values;
  for (std::size_t k = 0; k < linear.size(); ++k) out[K + k] += lp.x[Eigen::Index(k)];  // x₀ + δ
  lp.achieved = max_abs_residual(evaluate_residuals(residuals, log_parameters(out, K)));
  return {out, lp};
}

// The per-κ floor at the steepness steep[2M + 1]: at each κ of `samples` (grouped
// by κ) the LP optimum over its cosines with b_0 … b_{N−1} free (PerKappaResidual),
// t(κ) fixed; no member with that t(κ) does better at that κ, whatever its
// fade, scale or degree. Returns the max over κ weighted (÷ w(κ)) and plain.
template <std::size_t N, std::size_t M>
std::pair<double, double> per_kappa_floor(const std::vector<double>& steep,
                                          const std::vector<SglabAccSample>& samples) {
  SglabAccParams<double, 1, 0, M> own{};
  std::copy(steep.begin(), steep.begin() + long(steep_count(M)), own.steep);
  const auto sp = detail::sglab_acc_steepness(own);
  double weighted = 0, plain = 0;
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    while (end < samples.size() && samples[end].kappa == samples[i].kappa) ++end;
    const double k = samples[i].kappa, t = steepness(k, sp);
    Residuals residuals;
    std::vector<std::size_t> rows;
    for (std::size_t s = i; s < end; ++s, rows.push_back(rows.size()))
      residuals.push_back(make_residual(
          PerKappaResidual<N>{t, samples[s].cosine, samples[s].irradiance, irradiance_upper(k),
                              irradiance_lower_over_two_pi(k), irradiance_upper_over_two_pi(k)},
          N));
    std::vector<std::size_t> linear(N);
    std::iota(linear.begin(), linear.end(), std::size_t(0));
    const LinearSubproblem sub = linear_subproblem(residuals, std::vector<double>(N, 0.0), linear);
    const double f =
        lp_minimax_on(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()), rows).lower_bound;
    plain = std::max(plain, f);
    weighted = std::max(weighted, f / samples[i].weight);
    i = end;
  }
  return {weighted, plain};
}

// Alternations of the LP (exact numerators at fixed t, s) with a Ceres polish
// of every parameter (t, s move), each round kept only if it lowers the LP's achieved max.
constexpr int kAlternations = 3;

SglabAccFit fit_coefficients_any(Member m, const std::vector<double>& start,
                                 const std::vector<SglabAccSample>& samples,
                                 bool polish_only = false) {
  return with_member(m, [&](auto N, auto D, auto M) {
    return fit_coefficients<N(), D(), M()>(start, samples, polish_only);
  });
}

template <std::size_t N, std::size_t D, std::size_t M>
MemberFit measure_member(const SglabAccFit& f,
                         const std::vector<reference::ReferencePoint>& standard,
                         const std::vector<reference::ReferencePoint>& held_out) {
  MemberFit out;
  out.member = {N, D, M};
  out.values = f.values;
  out.train = f.max_abs;
  out.converged = f.converged;
  const auto p = params_of<N, D, M>(out.values);
  out.standard = measure(p, standard);
  out.held_out = measure(p, held_out);
  return out;
}

// Member (N, D) from `start`: Ceres (fit_coefficients) on the training grid,
// then the LP on the dense grid at its t(κ) and s, alternating with Ceres
// polishes; measured on the standard and held-out grids, and certified.
template <std::size_t N, std::size_t D, std::size_t M>
MemberFit certified_fit(const std::vector<double>& start, const std::vector<SglabAccSample>& train,
                        const std::vector<SglabAccSample>& dense,
                        const std::vector<reference::ReferencePoint>& standard,
                        const std::vector<reference::ReferencePoint>& held_out, bool polish_only) {
  // Round 0: the LP at the start's t(κ) and s (a refit from a committed set
  // is never worse than it); then Ceres and the LP in turn while they gain.
  constexpr std::size_t K = steep_count(M);
  auto [values, lp] = best_numerators<N, D, M>(start, dense);
  SglabAccFit f = fit_coefficients<N, D, M>(values, train, polish_only);
  for (int round = 1; round <= kAlternations; ++round) {
    const SglabAccFit g = round == 1 ? f : fit_coefficients<N, D, M>(values, train, true);
    auto [next, next_lp] = best_numerators<N, D, M>(g.values, dense);
    if (!(next_lp.achieved < lp.achieved)) break;
    values = std::move(next), lp = next_lp;
  }
  f.values = values;
  f.max_abs = max_abs_residual(
      evaluate_residuals(member_residuals<N, D, M>(train), log_parameters(values, K)));
  MemberFit out = measure_member<N, D, M>(f, standard, held_out);
  const auto [floor_weighted, floor_plain] = per_kappa_floor<N, M>(values, dense);
  std::size_t kappas = 0;
  for (std::size_t i = 0; i < dense.size(); ++i)
    kappas += i == 0 || dense[i].kappa != dense[i - 1].kappa;
  out.certificate = {lp.achieved, lp.lower_bound,  floor_weighted, floor_plain, dense.size(),
                     kappas,      lp.working_rows, lp.rounds,      lp.converged};
  return out;
}

}  // namespace

MemberFit fit_any(Member m, const std::vector<double>& start,
                  const std::vector<SglabAccSample>& train,
                  const std::vector<SglabAccSample>& dense, const MeasuringGrids& measuring,
                  bool polish_only) {
  return with_member(m, [&](auto N, auto D, auto M) {
    return certified_fit<N(), D(), M()>(start, train, dense, measuring.standard, measuring.held_out,
                                        polish_only);
  });
}

}  // namespace acc

SglabAccFit fit_sglab_acc_coefficients(std::size_t terms, std::size_t degree,
                                       const std::vector<double>& start,
                                       const std::vector<SglabAccSample>& samples) {
  return acc::fit_coefficients_any({terms, degree}, start, samples);
}

}  // namespace sglab::fit
