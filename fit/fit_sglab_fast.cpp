// `sglab fit sglab-fast`: the coefficients of sglab_fast
// (include/sglab/sglab_fast.hpp)
//   Ê = E(1, κ)·max(0, A + B c + C ρ(V c + ½)),  A, B, C, V = P(κ)/Q(κ),
// numerators of degree 4 over a monic quartic Q, fitted by the rational-shape
// fitter (fit/rational_shape_fit.hpp) in its named steps and certified at the
// fitted Q and V(κ), where the numerators of A, B and C enter linearly:
// docs/models.md#sglab_fast.
// `sglab fit sglab-lite`: the coefficients of sglab_lite
// (include/sglab/sglab_lite.hpp), the same shape with E(1, κ) folded into A,
// B, C (no exp), numerators of degree 4 over a monic quartic: the same per-κ
// floor (step 1, the shape values of sglab_fast) and the same certificate;
// docs/models.md#sglab_lite.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <sglab/sglab.hpp>
#include <sglab/sglab_fast.hpp>
#include <sglab/sglab_lite.hpp>

#include "fit/rational_shape_fit.hpp"

namespace sglab::fit {

namespace {

constexpr std::size_t kFastDegree = 4;  // numerators and the monic denominator
constexpr std::size_t kLiteDegree = 4;

// Step 1 residual: peak_rel of E(1)·max(0, s) at one (κ, c), shape values as parameters.
struct FastShapeResidual {
  double cosine, normalized;  // E(c, κ)/E(1, κ)
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = max0(sglab_fast_shape(T(cosine), p[0][0], p[1][0], p[2][0], p[3][0])) - T(normalized);
    return true;
  }
};

struct FastShape {
  static const RationalLayout& layout() {
    static const RationalLayout l{"sglab-fast", {"a", "b", "c", "v"}, kFastDegree};
    return l;
  }
  template <class T>
  using Params = SglabFastParams<T>;
  template <class T>
  static auto numerators(Params<T>& p) {
    return std::array{p.a, p.b, p.c, p.v};
  }
  static constexpr const char* cpp_type = "SglabFastParams<double>";
  static constexpr const char* form =
      "E = E(1,kappa)*max(0, A + B*c + C*rho(V*c + 1/2)), rho(u) = 0 | u^3(2-u) | 2u-1 on u<=0 | "
      "(0,1) | u>=1; A, B, C, V = P(k)/Q(k) with k = min(kappa, kappa_max), numerators a, b, c, v "
      "of degree 4 and Q = k^4 + q[3]k^3 + ... + q[0] (coefficients lowest order first)";
  // At the fitted Q and V(κ), s' = E1(κ)·(A + B c + C ρ(V c + ½))/E(1, κ) is
  // linear in the numerators of A, B and C (the first in parameter order).
  static constexpr std::size_t certified = 3;
  static constexpr bool floor_from_committed = false;

  // Step 2 fits the shape values themselves.
  static double start_target(std::size_t n, const PerKappaShape& p) { return p.shape[n]; }
  // s changes by about C·δV where V is off by δV: weight V's error by |C|.
  static double start_weight(std::size_t n, const PerKappaShape& p) {
    return n == 3 ? std::max(std::abs(p.shape[2]), 1e-6) : 1.0;
  }

  // Step 1 at one κ: a minimax of the four values from the previous κ's
  // optimum (the first, the largest κ: a ramp of width 1/V around c = 0).
  static PerKappaShape per_kappa_at(double k, const std::vector<double>& cosines,
                                    const std::vector<reference::ReferencePoint>& ref,
                                    const std::optional<PerKappaShape>& previous) {
    const double e1 = irradiance_upper(k);
    std::vector<double> start;
    if (previous) {
      start = previous->shape;
    } else {
      const double v = 0.5 * std::sqrt(k);
      start = {0.0, 0.0, 0.5 / v, v};
    }
    Parameters params{{"A", "B", "C", "V"}, start, {}};
    Residuals residuals;
    for (std::size_t j = 0; j < cosines.size(); ++j)
      residuals.push_back(
          make_residual(FastShapeResidual{ref[j].cosine, ref[j].irradiance / e1}, 4));
    const FitResult f = fit(residuals, params);
    return {k, {f.values.begin(), f.values.begin() + 4}, f.max_abs};
  }
  static auto irradiance(const auto& c, const auto& k, const auto& p) {
    return irradiance_sglab_fast(c, k, p);
  }
};

// sglab_lite: A, B, C carry E(1, κ) over 1 + κ̃ (step 2 fits the shape values
// times E(1, κ)(1 + κ)); V, step 1 and the certificate's free numerators are sglab_fast's.
struct LiteShape {
  static const RationalLayout& layout() {
    static const RationalLayout l{"sglab-lite", {"a", "b", "c", "v"}, kLiteDegree};
    return l;
  }
  template <class T>
  using Params = SglabLiteParams<T>;
  template <class T>
  static auto numerators(Params<T>& p) {
    return std::array{p.a, p.b, p.c, p.v};
  }
  static constexpr const char* cpp_type = "SglabLiteParams<double>";
  static constexpr const char* form =
      "E = max(0, A + B*c + C*rho(V*c + 1/2)), rho(u) = 0 | u^3(2-u) | 2u-1 on u<=0 | (0,1) | "
      "u>=1; A, B, C = P(k)/((1 + k)Q(k)), V = Pv(k)/Q(k) with k = min(kappa, kappa_max), "
      "numerators a, b, c, v of degree 4 and Q = k^4 + q[3]k^3 + ... + q[0] (coefficients "
      "lowest order first); E(1, kappa) folded into A, B, C";
  static constexpr std::size_t certified = 3;
  static constexpr bool floor_from_committed = false;

  static double start_target(std::size_t n, const PerKappaShape& p) {
    return n == 3 ? p.shape[n] : p.shape[n] * irradiance_upper(p.kappa) * (1 + p.kappa);
  }
  // Relative to E(1, κ)(1 + κ), as peak_rel weighs them.
  static double start_weight(std::size_t n, const PerKappaShape& p) {
    return n == 3 ? std::max(std::abs(p.shape[2]), 1e-6)
                  : 1.0 / (irradiance_upper(p.kappa) * (1 + p.kappa));
  }
  static PerKappaShape per_kappa_at(double k, const std::vector<double>& cosines,
                                    const std::vector<reference::ReferencePoint>& ref,
                                    const std::optional<PerKappaShape>& previous) {
    return FastShape::per_kappa_at(k, cosines, ref, previous);
  }
  static auto irradiance(const auto& c, const auto& k, const auto& p) {
    return irradiance_sglab_lite(c, k, p);
  }
};

}  // namespace

FitOutcome fit_sglab_fast(const FitSpec& spec) { return fit_rational_shape<FastShape>(spec); }
FitOutcome fit_sglab_lite(const FitSpec& spec) { return fit_rational_shape<LiteShape>(spec); }

}  // namespace sglab::fit
