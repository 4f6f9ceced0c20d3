// sglab/sglab_mid.hpp — sglab's model `sglab_mid`:
//   Ê(c, κ) = E(1, κ) · max(0, A + B (c + √(c² + e^{S − V c²})) + D c²),
// the exact E(1, κ) times a smoothed max(c, 0) of varying width; A, B, D rational in κ,
// S = Ps/Q − ln(1 + κ), V = κ Pv/Q (SglabMidParams). Why κ itself in S and V keeps the
// error bounded to κ = FLT_MAX, the fit, error and cost: docs/models.md#sglab_mid.
//
// Never NaN for finite κ ≥ 0 and c ∈ [−1, 1]: E(1, κ) is formed as in
// sglab_fast (no κ², a Taylor series below κ = ¼); Q(κ̃) ≥ kappa_max⁴ is
// finite, so A, B, D and the rational parts of S and V are finite, and V =
// V(kappa_max)·κ/kappa_max beyond kappa_max stays finite to the largest float
// as long as V(kappa_max) < kappa_max (5.9e3 for the shipped set;
// tests/test_methods.cpp evaluates κ = FLT_MAX); the exponent
// S − V c² is clamped to [−80, 80], so e^{…} lies in [1.8e−35, 5.6e34], finite
// and positive in float, and the square root takes a positive finite argument.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "branch_free.hpp"
#include "closed_forms.hpp"
#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"
#include "sglab_fast.hpp"

namespace sglab {

namespace detail {

// The exponent bound of e^{S − V c²} (see the top of this file).
inline constexpr double kSglabMidExponentBound = 80.0;

// ln x for finite x ≥ 1 without branches or library calls, for the batch's
// ln(1 + κ̃): x = m 2^e with m ∈ [√½, √2) from the bits, ln m = 2 atanh(t),
// t = (m − 1)/(m + 1) ∈ (−0.172, 0.172), by its series to t⁹ (truncation
// below 1e−8); within a few ulp of std::log.
SGLAB_FORCE_INLINE float log_bf(float x) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
  const std::int32_t e = static_cast<std::int32_t>(bits - 0x3f3504f3u) >> 23;
  const float m = std::bit_cast<float>(bits - (static_cast<std::uint32_t>(e) << 23));
  const float t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
  const float series =
      1.0f + t2 * (1.0f / 3.0f + t2 * (1.0f / 5.0f + t2 * (1.0f / 7.0f + t2 * (1.0f / 9.0f))));
  return static_cast<float>(e) * 0.693147181f + 2.0f * t * series;
}

// c + √(c² + e^{clamp(S − V c², −80, 80)}): a smoothed 2 max(c, 0).
template <class T>
T sglab_mid_soft_max2(const T& cosine, const T& s, const T& v) {
  using std::exp;
  using std::sqrt;
  const T c2 = cosine * cosine;
  const T x = min_of(max_of(s - v * c2, T(-kSglabMidExponentBound)), T(kSglabMidExponentBound));
  return cosine + sqrt(c2 + exp(x));
}

}  // namespace detail

// Everything of `sglab_mid` that depends on κ alone, with E(1, κ) folded into
// a, b, d: Ê = max(0, a + b (c + √(c² + e^{s − v c²})) + d c²).
template <class T>
struct SglabMidLight {
  T a, b, d, s, v;
};

// The normalized shape A + B (c + √(c² + e^{S − V c²})) + D c², unclamped (the
// fitter's per-κ stage).
template <class T>
T sglab_mid_shape(const T& cosine, const T& A, const T& B, const T& D, const T& S, const T& V) {
  return A + B * detail::sglab_mid_soft_max2(cosine, S, V) + D * (cosine * cosine);
}

// Per-light setup: one exp and two divisions.
template <class T, class S = double>
SglabMidLight<T> sglab_mid_light(const T& kappa,
                                 const SglabMidParams<S>& p = constants::sglab_mid_float) {
  const T k = detail::min_of(kappa, T(p.kappa_max));
  const T inv_q = T(1) / (horner(k, p.q) + k * k * k * k);
  // A, B, D are O(1) after the division; E(1, κ) ≈ 2π/κ is applied last, so
  // nothing underflows before it even at κ near the largest float.
  using std::log;
  const T e1 = two_pi_v<T>() * detail::upper_over_two_pi_fast(kappa);
  // κ·Pv(κ̃)/Q(κ̃) written as κ̃·Pv/Q·max(1, κ/kappa_max): the factor is exactly 1 on the
  // fitted range, and κ̃·Pv/Q < kappa_max, so the product stays finite to FLT_MAX.
  const T grow = detail::max_of(T(1), kappa / T(p.kappa_max));
  return {horner(k, p.a) * inv_q * e1, horner(k, p.b) * inv_q * e1, horner(k, p.d) * inv_q * e1,
          horner(k, p.s) * inv_q - log(T(1) + kappa), k * horner(k, p.v) * inv_q * grow};
}

// Per-shading-point evaluation.
template <class T>
T sglab_mid_eval(const SglabMidLight<T>& light, const T& cosine) {
  return detail::max0_branchless(light.a +
                                 light.b * detail::sglab_mid_soft_max2(cosine, light.s, light.v) +
                                 light.d * (cosine * cosine));
}

// The same setup in float without branches or library calls (branch_free.hpp),
// so that a batch loop vectorizes. Identical algebra to sglab_mid_light.
template <class S>
SGLAB_FORCE_INLINE SglabMidLight<float> sglab_mid_light_branch_free(float kappa,
                                                                    const SglabMidParams<S>& p) {
  namespace bf = branch_free;
  const float k = bf::min(kappa, float(p.kappa_max));
  const float inv_q = 1.0f / (horner(k, p.q) + k * k * k * k);
  const float e1 = two_pi_v<float>() * detail::upper_over_two_pi_branch_free(kappa);
  const float grow = bf::max(1.0f, kappa / float(p.kappa_max));
  return {horner(k, p.a) * inv_q * e1, horner(k, p.b) * inv_q * e1, horner(k, p.d) * inv_q * e1,
          horner(k, p.s) * inv_q - detail::log_bf(1.0f + kappa), k * horner(k, p.v) * inv_q * grow};
}

// The per-shading-point evaluation without library calls (exp_bf, sqrt_bf),
// for the batch below.
SGLAB_FORCE_INLINE float sglab_mid_eval_branch_free(const SglabMidLight<float>& light,
                                                    float cosine) {
  namespace bf = branch_free;
  constexpr float bound = static_cast<float>(detail::kSglabMidExponentBound);
  const float c2 = cosine * cosine;
  const float x = bf::clamp(light.s - light.v * c2, -bound, bound);
  const float shape = light.a + light.b * (cosine + bf::sqrt_bf(c2 + bf::exp_bf(x))) + light.d * c2;
  return detail::max0_branchless(shape);
}

// Float batch of `sglab_mid` that vectorizes (tests/test_sglab_mid.cpp
// compares it with the scalar path).
template <class S = double>
SGLAB_FLATTEN void irradiance_sglab_mid_batch(
    const float* __restrict cosine, const float* __restrict kappa, float* __restrict out,
    std::size_t n, const SglabMidParams<S>& p = constants::sglab_mid_float) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = sglab_mid_eval_branch_free(sglab_mid_light_branch_free(kappa[i], p), cosine[i]);
}

// `sglab_mid`: Ê(c, κ), the two steps above in one call.
template <class T, class S = double>
T irradiance_sglab_mid(const T& cosine, const T& kappa,
                       const SglabMidParams<S>& p = constants::sglab_mid_float) {
  return sglab_mid_eval(sglab_mid_light(kappa, p), cosine);
}

}  // namespace sglab
