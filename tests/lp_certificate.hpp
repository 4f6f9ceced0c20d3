// The check of a certificate made by sglab::fit::clamped_lp_certificate
// (fit/model_family.hpp) for a model E(1, κ)·max(0, s') at its committed
// coefficients, shared by tests/test_sglab_fast.cpp and tests/test_sglab_mid.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::test {

// The fitters' training grid (fit/fit_sglab_fast.cpp, fit/fit_sglab_mid.cpp): 56
// log-midpoints of [1e−3, 1e4] × 161 uniform cosines, then the κ of `extra`
// (sglab-min's κ beyond the range, fit/fit_sglab_min.cpp) × the same cosines.
inline std::vector<reference::ReferencePoint> certificate_training_grid(
    const std::vector<double>& extra = {}) {
  std::vector<double> kappas = fit::log_midpoints(1e-3, 1e4, 56);
  kappas.insert(kappas.end(), extra.begin(), extra.end());
  return reference::reference_engine().evaluate(fit::product_grid(kappas, fit::cosine_grid(161)));
}

// `residual(r)`: the fit's residual at r (all `values.size()` parameters);
// `error(values, r)`: the runtime's peak_rel at r with the coefficients
// `values`, computed without Ceres; the first `linear_count` parameters are the
// numerators the certificate frees. Checks: the bound is positive and at most
// the achieved max, which is the committed coefficients' max on the points
// with E/E(1) ≥ L (recomputed from the runtime); and the bound is right: the
// LP's best numerators (solved here again) err in the runtime by the LP's
// value (so the model is linear in them: a wrong index or a nonlinear one
// shows here), no less than the bound; random changes of the numerators do
// no better than the bound. `extra_kappas`: as certificate_training_grid.
// Returns the certificate.
inline fit::ordered_json check_clamped_lp_certificate(
    const std::vector<double>& values, std::size_t linear_count,
    const std::function<std::unique_ptr<ceres::CostFunction>(const reference::ReferencePoint&)>&
        residual,
    const std::function<double(const std::vector<double>&, const reference::ReferencePoint&)>&
        error,
    const std::vector<double>& extra_kappas = {}) {
  const auto train = certificate_training_grid(extra_kappas);
  std::vector<std::size_t> linear(linear_count);
  std::iota(linear.begin(), linear.end(), 0);
  const fit::ordered_json c = fit::clamped_lp_certificate(train, values, linear, residual, "test");
  const double achieved = c["achieved"].get<double>(), bound = c["lower_bound"].get<double>();
  EXPECT_GT(bound, 0) << c;
  EXPECT_LE(bound, achieved) << c;
  EXPECT_TRUE(c["lp"]["converged"].get<bool>()) << c;

  std::vector<reference::ReferencePoint> rows;
  for (const auto& r : train)
    if (r.irradiance >= fit::kCertificateLevel * irradiance_upper(r.kappa)) rows.push_back(r);
  const auto max_error = [&](const std::vector<double>& v) {
    double m = 0;
    for (const auto& r : rows) m = std::max(m, error(v, r));
    return m;
  };
  EXPECT_NEAR(max_error(values), achieved, 1e-12 * achieved);

  fit::Residuals residuals;
  for (const auto& r : rows) residuals.push_back(residual(r));
  const fit::LinearSubproblem sub = fit::linear_subproblem(residuals, values, linear);
  const fit::LpMinimaxResult lp =
      fit::lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  std::vector<double> best = values;
  for (std::size_t i = 0; i < linear_count; ++i)
    best[i] = sub.x0(Eigen::Index(i)) + lp.x(Eigen::Index(i));
  const double at_best = max_error(best);
  EXPECT_NEAR(at_best, lp.achieved, 1e-6 * lp.achieved);
  EXPECT_GE(at_best, bound * (1 - 1e-9));
  EXPECT_LE(at_best, achieved * (1 + 1e-9));  // the committed numerators are one choice

  std::mt19937 rng(1717);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<double> v = best;
    const double scale = std::pow(10.0, -6 + trial % 5);
    for (std::size_t i = 0; i < linear_count; ++i) v[i] += scale * normal(rng) * std::abs(v[i]);
    EXPECT_GE(max_error(v), bound * (1 - 1e-9)) << "trial " << trial;
  }
  return c;
}

}  // namespace sglab::test
