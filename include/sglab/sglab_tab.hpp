// sglab/sglab_tab.hpp — sglab's model `sglab_tab`, the accurate end at a low price:
//   Ê(c, κ) = E(1, κ) · max(0, A + B (c + √(c² + g)) + D c² + (G + H c²) g),
//   g = e^{S − V c²},  S = s − ln(1 + κ),  V = κ v,
// sglab_mid's shape (a smoothed max(c, 0) of varying width, sglab_mid.hpp) with two terms in
// its exp, whose seven values A, B, D, G, H, s, v are tabulated: piecewise cubics in
// u = √κ/(1 + √κ) ∈ [0, 1) over N equal cells (SglabTabParams). u maps every κ ≥ 0 into
// [0, 1], so the last cell reaches κ = ∞ (there 1 − u = 1/(1 + √κ)), and one
// square root, one division and a table read are the whole cost of the cell; form,
// fit, error and cost: docs/models.md#sglab_tab.
//
// Never NaN for finite κ ≥ 0 and c ∈ [−1, 1]: √κ ≤ 1.9e19, so u ∈ [0, 1] and
// the cell index is in [0, N − 1]; E(1, κ) is formed as in sglab_fast; the
// exponent S − V c² is the difference of finite values as long as every
// cubic v stays below 1 on its cell (then κ v ≤ FLT_MAX; the fit's tests
// check it at κ = FLT_MAX), and it is clamped to [−80, 80], so g lies in
// [1.8e−35, 5.6e34] and the square root takes a positive finite argument.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"
#include "sglab_fast.hpp"

namespace sglab {

// Everything of `sglab_tab` that depends on κ alone, E(1, κ) folded into
// a, b, d, g, h: Ê = max(0, a + b (c + √(c² + e)) + d c² + (g + h c²) e),
// e = e^{clamp(s − v c², −80, 80)}.
template <class T>
struct SglabTabLight {
  T a, b, d, g, h, s, v;
};

namespace detail {

// The exponent bound of e^{S − V c²} (see the top of this file).
inline constexpr double kSglabTabExponentBound = 80.0;

// The cell of κ and the cell's local coordinate t ∈ [−1, 1]: u N = j + (t + 1)/2.
template <class T>
struct SglabTabCell {
  std::size_t index;
  T t;
};
template <std::size_t N, class T>
SglabTabCell<T> sglab_tab_cell(const T& kappa) {
  using std::floor;
  using std::sqrt;
  const T r = sqrt(kappa);
  const T x = r / (T(1) + r) * T(N);  // u N ∈ [0, N]
  const T j = min_of(floor(x), T(N - 1));
  // The index from the value (a Ceres Jet's value member `a`: its cell does not move with it),
  // cell 0 for a NaN (κ NaN, negative or +inf, outside the domain: no float-to-integer
  // conversion of a value out of range).
  double value = 0;
  if constexpr (requires { j.a; })
    value = static_cast<double>(j.a);
  else
    value = static_cast<double>(j);
  const std::size_t index = value >= 0 ? static_cast<std::size_t>(value) : 0;
  return {index, T(2) * (x - j) - T(1)};
}

// The normalized shape A + B (c + √(c² + g)) + D c² + (G + H c²) g, g = e^{clamp(S − V c²)},
// unclamped (the fitter's per-cell stage).
template <class T>
T sglab_tab_shape(const T& cosine, const T& A, const T& B, const T& D, const T& G, const T& H,
                  const T& S, const T& V) {
  using std::exp;
  using std::sqrt;
  const T c2 = cosine * cosine;
  const T g =
      exp(min_of(max_of(S - V * c2, T(-kSglabTabExponentBound)), T(kSglabTabExponentBound)));
  return A + B * (cosine + sqrt(c2 + g)) + D * c2 + (G + H * c2) * g;
}

}  // namespace detail

// Per-light setup: one square root and one division for the cell, seven cubics
// from the table, one logarithm, and E(1, κ) (one exp).
template <class T, class S, std::size_t N, std::size_t D>
SglabTabLight<T> sglab_tab_light(const T& kappa, const SglabTabParams<S, N, D>& p) {
  using std::log;
  const auto [j, t] = detail::sglab_tab_cell<N>(kappa);
  const S* c = p.coef + j * kSglabTabValues * (D + 1);
  T value[kSglabTabValues];
  for (std::size_t m = 0; m < kSglabTabValues; ++m) {
    const S* poly = c + m * (D + 1);
    T acc = T(poly[D]);
    for (std::size_t i = D; i-- > 0;) acc = acc * t + T(poly[i]);
    value[m] = acc;
  }
  const T e1 = two_pi_v<T>() * detail::upper_over_two_pi_fast(kappa);
  return {value[0] * e1,   value[1] * e1, value[2] * e1,
          value[3] * e1,   value[4] * e1, value[5] - log(T(1) + kappa),
          kappa * value[6]};
}
template <class T>
SglabTabLight<T> sglab_tab_light(const T& kappa) {
  return sglab_tab_light(kappa, constants::sglab_tab_float);
}

// Per-shading-point evaluation: one exp, one square root.
template <class T>
T sglab_tab_eval(const SglabTabLight<T>& l, const T& cosine) {
  return detail::max0_branchless(
      detail::sglab_tab_shape(cosine, l.a, l.b, l.d, l.g, l.h, l.s, l.v));
}

// `sglab_tab`: Ê(c, κ), the two steps above in one call.
template <class T, class S, std::size_t N, std::size_t D>
T irradiance_sglab_tab(const T& cosine, const T& kappa, const SglabTabParams<S, N, D>& p) {
  return sglab_tab_eval(sglab_tab_light(kappa, p), cosine);
}
template <class T>
T irradiance_sglab_tab(const T& cosine, const T& kappa) {
  return irradiance_sglab_tab(cosine, kappa, constants::sglab_tab_float);
}

// Float batch of `sglab_tab` (a loop of the scalar call: the table read is a gather).
inline void irradiance_sglab_tab_batch(const float* __restrict cosine,
                                       const float* __restrict kappa, float* __restrict out,
                                       std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = irradiance_sglab_tab(cosine[i], kappa[i]);
}

}  // namespace sglab
