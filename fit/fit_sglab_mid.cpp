// `sglab fit sglab-mid`: the coefficients of sglab_mid
// (include/sglab/sglab_mid.hpp)
//   Ê = E(1, κ)·max(0, A + B (c + √(c² + e^{S − V c²})) + D c²),
//   A, B, D = P(κ)/Q(κ), S = Ps(κ)/Q(κ) − ln(1 + κ), V = κ Pv(κ)/Q(κ),
// numerators of degree 4 over a monic quartic Q, fitted by the rational-shape
// fitter (fit/rational_shape_fit.hpp) in its named steps and certified at the
// fitted Q, S(κ) and V(κ), where the numerators of A, B and D enter linearly:
// docs/models.md#sglab_mid.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Dense>

#include <sglab/sglab.hpp>
#include <sglab/sglab_mid.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/rational_shape_fit.hpp"

namespace sglab::fit {

namespace {

constexpr std::size_t kMidDegree = 4;  // numerators and the monic denominator
constexpr std::size_t kShapeValues = 5;

// Step 1 residual: peak_rel of E(1)·s at one (κ, c), shape values as parameters (the clamp
// at 0 left out: it can only lower the error, and without it the problem at fixed S, V is an LP).
struct MidShapeResidual {
  double cosine, normalized;  // E(c, κ)/E(1, κ)
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = sglab_mid_shape(T(cosine), p[0][0], p[1][0], p[2][0], p[3][0], p[4][0]) - T(normalized);
    return true;
  }
};

// Step 1 at one κ. At fixed S and V the shape is linear in A, B, D, and
// (without the clamp at 0) their minimax is a linear program (fit/lp_minimax.hpp).
// The problem has many local minima in S and V, so no single start is trusted:
// a joint minimax of all five runs from the previous κ's optimum (`previous`,
// when given) and from the kStarts best (S, V) of the LP over a grid of
// S ∈ [−14, kMaxS] × V/max(κ, 1) ∈ [−2, 3]. The continuation from the previous κ
// is kept unless another start does clearly better (where the shape hardly
// depends on S, at small κ, that keeps the optimum smooth in κ).
constexpr int kStarts = 4;
// S is held at or below kMaxS: for a broad light (small κ) the shape is nearly
// a parabola in c and hardly depends on a large S (A absorbs B e^{S/2}), so a
// free S wanders from κ to κ; held, it stays smooth for stage 2.
constexpr double kMaxS = 4;
PerKappaShape mid_per_kappa_at(double k, const std::vector<double>& cosines,
                               const std::vector<reference::ReferencePoint>& ref,
                               const std::optional<PerKappaShape>& previous) {
  const double e1 = irradiance_upper(k), v_scale = std::max(k, 1.0);
  const auto n = static_cast<Eigen::Index>(cosines.size());
  Eigen::VectorXd y(n), w = Eigen::VectorXd::Ones(n);
  for (Eigen::Index j = 0; j < n; ++j) y(j) = ref[static_cast<std::size_t>(j)].irradiance / e1;
  Eigen::MatrixXd a(n, 3);
  const auto lp_at = [&](double S, double V, Eigen::VectorXd* x) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double c = cosines[static_cast<std::size_t>(j)];
      a(j, 0) = 1, a(j, 1) = detail::sglab_mid_soft_max2(c, S, V), a(j, 2) = c * c;
    }
    const LpMinimaxResult r = lp_minimax(a, y, w);
    if (x) *x = r.x;
    return r.achieved;
  };
  std::vector<std::array<double, 3>> grid;  // error, S, V
  for (int i = 0; i <= 36; ++i)
    for (int j = 0; j <= 50; ++j) {
      const double S = kMaxS - 0.5 * i, V = (-2 + 0.1 * j) * v_scale;
      grid.push_back({lp_at(S, V, nullptr), S, V});
    }
  std::partial_sort(grid.begin(), grid.begin() + kStarts, grid.end());
  Residuals residuals;
  for (std::size_t j = 0; j < cosines.size(); ++j)
    residuals.push_back(
        make_residual(MidShapeResidual{cosines[j], ref[j].irradiance / e1}, kShapeValues));
  const auto polish = [&](const std::vector<double>& start) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const FitResult f = fit(residuals, Parameters{{"A", "B", "D", "S", "V"},
                                                  start,
                                                  {},
                                                  {-inf, -inf, -inf, -inf, -inf},
                                                  {inf, inf, inf, kMaxS, inf}});
    return PerKappaShape{k, {f.values.begin(), f.values.begin() + kShapeValues}, f.max_abs};
  };
  std::optional<PerKappaShape> best;
  if (previous) best = polish({previous->shape.begin(), previous->shape.end()});
  for (int t = 0; t < kStarts; ++t) {
    Eigen::VectorXd x;
    const auto& [err, S, V] = grid[static_cast<std::size_t>(t)];
    lp_at(S, V, &x);
    const PerKappaShape p = polish({x(0), x(1), x(2), S, V});
    // Below 1e−7 (far under any target) the starts tie: keep the continuation.
    if (!best || (p.error < 0.8 * best->error && best->error > 1e-7)) best = p;
  }
  return *best;
}

struct MidShape {
  static const RationalLayout& layout() {
    // The numerators in SglabMidParams order.
    static const RationalLayout l{"sglab-mid", {"a", "b", "d", "s", "v"}, kMidDegree};
    return l;
  }
  template <class T>
  using Params = SglabMidParams<T>;
  template <class T>
  static auto numerators(Params<T>& p) {
    return std::array{p.a, p.b, p.d, p.s, p.v};
  }
  static constexpr const char* cpp_type = "SglabMidParams<double>";
  static constexpr const char* form =
      "E = E(1,kappa)*max(0, A + B*(c + sqrt(c^2 + exp(clamp(S - V*c^2, -80, 80)))) + D*c^2); "
      "A, B, D = P(k)/Q(k), S = Ps(k)/Q(k) - ln(1 + kappa), V = kappa*Pv(k)/Q(k) with k = "
      "min(kappa, kappa_max), numerators a, b, d, s, v of degree 4 and Q = k^4 + q[3]k^3 + ... + "
      "q[0] "
      "(coefficients lowest order first)";
  // At the fitted Q, S(κ) and V(κ), s' = E1(κ)·(A + B (c + √(c² + e^{S − V c²}))
  // + D c²)/E(1, κ) is linear in the numerators of A, B and D (the first in
  // parameter order).
  static constexpr std::size_t certified = 3;
  static constexpr bool floor_from_committed = true;

  // Step 2 fits S + ln(1 + κ) and V/κ for Ps and Pv.
  static double start_target(std::size_t n, const PerKappaShape& p) {
    const auto& sh = p.shape;
    return n == 4 ? sh[4] / p.kappa : n == 3 ? sh[3] + std::log1p(p.kappa) : sh[n];
  }
  static double start_weight(std::size_t, const PerKappaShape&) { return 1.0; }

  // Step 1 at one κ (above).
  static PerKappaShape per_kappa_at(double k, const std::vector<double>& cosines,
                                    const std::vector<reference::ReferencePoint>& ref,
                                    const std::optional<PerKappaShape>& previous) {
    return mid_per_kappa_at(k, cosines, ref, previous);
  }
  static auto irradiance(const auto& c, const auto& k, const auto& p) {
    return irradiance_sglab_mid(c, k, p);
  }
};

}  // namespace

FitOutcome fit_sglab_mid(const FitSpec& spec) { return fit_rational_shape<MidShape>(spec); }

}  // namespace sglab::fit
