// `sglab fit sglab-fast`: the coefficients of sglab_fast
// (include/sglab/sglab_fast.hpp)
//   Ê = E(1, κ)·max(0, A + B c + C ρ(V c + ½)),  A, B, C, V = P(κ)/Q(κ),
// in three named stages, each warm-starting the next:
//   1. per κ of the training grid, the four shape values (A, B, C, V) that
//      minimax the peak_rel error over the training cosines — the family's
//      floor, no model of the κ dependence can do better on those points;
//   2. numerators of degree 4 over a shared monic quartic Q whose roots start
//      log-spaced over the κ range (−Q's roots on the negative axis, so Q > 0),
//      each numerator a linear least-squares fit to the stage-1 values;
//   3. a joint minimax of every coefficient on the peak_rel error of the
//      runtime function itself (Jets through irradiance_sglab_fast);
// then certified (issue 17 §1, certificate_json below): at the fitted Q and
// V(κ) the numerators of A, B and C enter linearly, and an LP bounds how well
// any of their values could do.
// Unless --cold-start, when the committed constant set of the same variant
// and κ range exists (data/constants/sglab-fast-<variant>.json), stages 2 and 3
// start from it instead, with a short polish (a few reweighting rounds and
// penalty decades): that keeps `sglab fit all` fast; a cold start takes about
// 40 s of CPU.
// Training grid: κ at the midpoints of 56 log-spaced cells of [lo, hi] and
// 161 uniform cosines; it shares no (κ, c) point with the standard 29 × 41
// grid or with the held-out grid (fit/model_family.hpp) on which the result is
// measured (float and double) and recorded in the constant set's provenance.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_fast.hpp>

#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "validate/reference.hpp"

namespace sglab::fit {

namespace {

constexpr int kTrainKappas = 56, kTrainCosines = 161;
constexpr std::size_t kDegree = 4;  // numerators and the monic denominator
// The parameters in fit order and the constant set's coefficients object.
const RationalLayout kLayout{"sglab-fast", {"a", "b", "c", "v"}, kDegree};
constexpr std::size_t kNumParams = 4 * (kDegree + 1) + kDegree;

std::vector<validate::ReferencePoint> reference_grid(const std::vector<double>& kappas,
                                                     const std::vector<double>& cosines) {
  return validate::reference_engine().evaluate(product_grid(kappas, cosines));
}

// Stage 1 residual: peak_rel of E(1)·max(0, s) at one (κ, c), shape values as parameters.
struct ShapeResidual {
  double cosine, normalized;  // E(c, κ)/E(1, κ)
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = max0(sglab_fast_shape(T(cosine), p[0][0], p[1][0], p[2][0], p[3][0])) - T(normalized);
    return true;
  }
};

// Stage 3 residual: peak_rel of the runtime function with all coefficients as parameters.
struct ModelResidual {
  double kappa, cosine, reference, peak, kappa_max;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    SglabFastParams<T> params{};
    std::size_t i = 0;
    for (auto* poly : {params.a, params.b, params.c, params.v})
      for (std::size_t j = 0; j <= kDegree; ++j) poly[j] = p[i++][0];
    for (std::size_t j = 0; j < kDegree; ++j) params.q[j] = p[i++][0];
    params.kappa_max = T(kappa_max);
    r[0] = (irradiance_sglab_fast(T(cosine), T(kappa), params) - T(reference)) / T(peak);
    return true;
  }
};

SglabFastParams<double> to_params(const std::vector<double>& v, double kappa_max) {
  SglabFastParams<double> p{};
  std::size_t i = 0;
  for (auto* poly : {p.a, p.b, p.c, p.v})
    for (std::size_t j = 0; j <= kDegree; ++j) poly[j] = v[i++];
  for (std::size_t j = 0; j < kDegree; ++j) p.q[j] = v[i++];
  p.kappa_max = kappa_max;
  return p;
}

struct PerKappa {
  double kappa;
  double A, B, C, V;
  double error;
};

// Stage 1, from the largest κ down, each start the previous optimum.
std::vector<PerKappa> per_kappa_optimum(const std::vector<double>& kappas,
                                        const std::vector<double>& cosines,
                                        const std::vector<validate::ReferencePoint>& ref) {
  std::vector<PerKappa> out(kappas.size());
  std::vector<double> start;
  for (std::size_t ii = kappas.size(); ii-- > 0;) {
    const double k = kappas[ii], e1 = irradiance_upper(k);
    if (start.empty()) {
      const double v = 0.5 * std::sqrt(k);
      start = {0.0, 0.0, 0.5 / v, v};
    }
    Parameters params{{"A", "B", "C", "V"}, start, {}};
    Residuals residuals;
    for (std::size_t j = 0; j < cosines.size(); ++j) {
      const auto& r = ref[ii * cosines.size() + j];
      residuals.push_back(make_residual(ShapeResidual{r.cosine, r.irradiance / e1}, 4));
    }
    const FitResult f = fit(residuals, params);
    out[ii] = {k, f.values[0], f.values[1], f.values[2], f.values[3], f.max_abs};
    start = f.values;
  }
  return out;
}

// Stage 2: Q = Π(κ + r_i) with r log-spaced over the range, then each
// numerator by linear least squares on the stage-1 values (V's residual
// weighted by |C|, the sensitivity of the shape to V).
std::vector<double> rational_start(const std::vector<PerKappa>& per, double lo, double hi) {
  std::vector<double> kappa;
  std::vector<std::vector<double>> targets(4), weights(4);
  for (const PerKappa& p : per) {
    kappa.push_back(p.kappa);
    const double values[] = {p.A, p.B, p.C, p.V};
    for (std::size_t n = 0; n < 4; ++n) {
      targets[n].push_back(values[n]);
      // s changes by about C·δV where V is off by δV: weight V's error by |C|.
      weights[n].push_back(n == 3 ? std::max(std::abs(p.C), 1e-6) : 1.0);
    }
  }
  return kLayout.least_squares_start(kappa, targets, weights, lo, hi);
}

// The certificate (issue 17 §1, clamped_lp_certificate in fit/model_family.hpp):
// at the fitted Q and V(κ), s' = E1(κ)·(A + B c + C ρ(V c + ½))/E(1, κ) is
// linear in the numerators of A, B and C (the first in parameter order).
ordered_json certificate_json(const std::vector<double>& values,
                              const std::vector<validate::ReferencePoint>& train, double hi) {
  return kLayout.lp_certificate<ModelResidual>(
      train, values, 3, hi,
      "lp_at_fitted_denominator_and_v: the numerators of A, B and C free, Q and V(kappa) as "
      "fitted; bound min(LP optimum, L)");
}

// The constant set of a fit: coefficients, form, objective, what it achieved and its certificate.
ordered_json constant_set(const FitSpec& spec, const std::string& variant, bool committed,
                          const ordered_json& coefficients, const ordered_json& achieved,
                          const ordered_json& certificate) {
  FitSpec recorded = spec;
  recorded.kappa_count = kTrainKappas;
  recorded.cosine_count = kTrainCosines;
  ordered_json set = make_constant_set(
      recorded, "sglab-fast", variant, "SglabFastParams<double>",
      "E = E(1,kappa)*max(0, A + B*c + C*rho(V*c + 1/2)), rho(u) = 0 | u^3(2-u) | 2u-1 on u<=0 | "
      "(0,1) | u>=1; A, B, C, V = P(k)/Q(k) with k = min(kappa, kappa_max), numerators a, b, c, v "
      "of degree 4 and Q = k^4 + q[3]k^3 + ... + q[0] (coefficients lowest order first)",
      coefficients,
      fmt::format("minimax of the sglab_fast irradiance peak_rel error (double) over a training "
                  "grid of {} kappa (log-midpoints of {} cells of [{}, {}]) x {} uniform cosines; "
                  "start: {}",
                  kTrainKappas, kTrainKappas, spec.kappa_lo, spec.kappa_hi, kTrainCosines,
                  committed ? "the committed set (polish)"
                            : "per-kappa optimum, then rational least squares"),
      achieved);
  set["provenance"]["certificate"] = certificate;
  return set;
}

}  // namespace

FitOutcome fit_sglab_fast(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "irradiance")
    throw std::invalid_argument(
        fmt::format("sglab-fast has the one objective 'irradiance'; got '{}'", spec.objective));
  const double lo = spec.kappa_lo, hi = spec.kappa_hi;
  const auto train_k = log_midpoints(lo, hi, kTrainKappas);
  const auto train_c = cosine_grid(kTrainCosines);
  const auto train = reference_grid(train_k, train_c);

  // 1. Per-κ floor.
  const std::vector<PerKappa> per = per_kappa_optimum(train_k, train_c, train);
  double floor = 0;
  for (const auto& p : per) floor = std::max(floor, p.error);

  // 2. Rational start (or the committed set).
  const std::string variant = std::string(io::to_string(spec.precision)) +
                              (spec.kappa_range_given ? fmt::format("-k{}-{}", lo, hi) : "");
  Parameters params;
  params.names = kLayout.parameter_names();
  std::optional<std::vector<double>> committed;
  if (!spec.cold_start) committed = kLayout.committed_start(variant, lo, hi);
  params.values = committed ? *committed : rational_start(per, lo, hi);

  // 3. Joint minimax on the runtime function.
  const auto [result, start_error] =
      kLayout.joint_minimax<ModelResidual>(train, params, hi, committed.has_value());
  const MeasuringGrids grids = measuring_grids(spec);
  const auto fitted = to_params(result.values, hi);
  const Measurements m = measure_all(
      [&](auto c, auto k) { return irradiance_sglab_fast(c, k, fitted); }, train, grids);
  const ordered_json coefficients = kLayout.coefficients_json(result.values, hi);
  const ordered_json achieved = achieved_json(result.max_abs, floor, m, grids);

  const ordered_json certificate = certificate_json(result.values, train, hi);

  FitOutcome out;
  out.converged = result.converged;
  out.constant_sets.push_back(
      constant_set(spec, variant, committed.has_value(), coefficients, achieved, certificate));
  out.report = {{"target", "sglab-fast"},
                {"variant", variant},
                {"converged", result.converged},
                {"start", committed ? "committed constant set" : "rational least squares"},
                {"per_kappa_floor", floor},
                {"start_error", start_error},
                {"objective_error", result.max_abs},
                {"achieved", achieved},
                {"certificate", certificate},
                {"coefficients", coefficients}};
  ordered_json table = ordered_json::array();
  for (const auto& p : per) table.push_back({p.kappa, p.A, p.B, p.C, p.V, p.error});
  out.report["per_kappa"] = table;
  out.text = rational_fit_text("sglab-fast", variant, floor, committed.has_value(), start_error,
                               result.max_abs, grids, m, certificate, "A, B, C", "Q and V");
  return out;
}

}  // namespace sglab::fit
