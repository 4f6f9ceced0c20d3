// sglab/sglab_fast.hpp — sglab's model `sglab_fast`:
//   Ê(c, κ) = E(1, κ) · max(0, A + B c + C ρ(V c + ½)),
// the exact E(1, κ) times a line plus the C² ramp ρ(u) = 0 | u³(2 − u) | 2u − 1 on
// u ≤ 0 | (0, 1) | u ≥ 1, A, B, C, V rational in κ (SglabFastParams); form, fit, error and
// cost: docs/models.md#sglab_fast.
//
// Never NaN for finite κ ≥ 0 and c ∈ [−1, 1]: E(1, κ) is formed without
// overflow (no κ²) and by a Taylor series below κ = ¼, and the rational
// functions are evaluated at κ̃ = min(κ, kappa_max), where Q ≥ kappa_max⁴ is
// finite; beyond kappa_max the shape stays that of kappa_max.
#pragma once

#include <cmath>
#include <cstddef>
#include <type_traits>

#include "branch_free.hpp"
#include "closed_forms.hpp"
#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"

namespace sglab {

namespace detail {

template <class T>
T min_of(const T& a, const T& b) {
  return b < a ? b : a;
}
template <class T>
T max_of(const T& a, const T& b) {
  return a < b ? b : a;
}

// Ē(1, κ) = E(1, κ)/2π = (κ − 1 + e^{−κ})/κ² with as many Taylor terms
// below κ = ¼ as the precision needs: Σ_{m≥0} (−κ)^m/(m + 2)!, whose first
// omitted term at κ = ¼ is 1.2e−8 of the sum after 6 terms (float) and 1.4e−18
// after 12 (double). From ¼ on: (1 − (1 − e^{−κ})/κ)/κ, one division and no
// κ²; the difference loses at most a factor 9 (κ = ¼). Both are evaluated —
// the series at min(κ, ¼), the closed form at max(κ, ¼), so both are finite —
// and blended by a 0/1 weight (exact: the other term is 0).
template <class T>
T upper_over_two_pi_fast(const T& kappa) {
  using std::exp;
  constexpr std::size_t terms = std::is_same_v<T, float> ? 6 : 12;
  const T ks = min_of(kappa, T(0.25)), kc = max_of(kappa, T(0.25));
  // closed_forms.hpp: Σ_{m<terms} (−κ)^m/(m + 2)!, Horner unrolled at compile time.
  const T series = sglab::detail::pole_series<false>(ks, std::make_index_sequence<terms - 1>{});
  const T r = T(1) / kc;
  // e^{−κ} < 2e−35 beyond κ = 80, far below the precision of 1 − e^{−κ}: the
  // argument stops there, so exp never underflows to a denormal or takes its
  // slow underflow path.
  const T closed = (T(1) - (T(1) - exp(-min_of(kc, T(80)))) * r) * r;
  const T use_series = T(kappa < T(0.25));
  return use_series * series + (T(1) - use_series) * closed;
}

// upper_over_two_pi_fast in float without branches or library calls
// (branch_free.hpp's exp_bf, a select), for the vectorizing setups of
// sglab_fast and sglab_mid: the same series below ¼ and closed form above.
SGLAB_FORCE_INLINE float upper_over_two_pi_branch_free(float kappa) {
  namespace bf = branch_free;
  const float ks = bf::min(kappa, 0.25f), kc = bf::max(kappa, 0.25f);
  const float series = sglab::detail::pole_series<false>(ks, std::make_index_sequence<5>{});
  const float r = 1.0f / kc;
  const float closed = (1.0f - (1.0f - bf::exp_bf(-bf::min(kc, 80.0f))) * r) * r;
  return bf::select(kappa < 0.25f, series, closed);
}

// The C² ramp ρ(u) above, without branches (the cosine varies from one
// shading point to the next, so a branch on it would be mispredicted): with
// v = clamp(u, 0, 1) = (|u| − |u − 1| + 1)/2 and max(u − 1, 0) = (u − 1 + |u − 1|)/2,
// ρ = v³(2 − v) + 2 max(u − 1, 0). For the |u| ≲ 10² of the model the
// rounding of these identities stays below 1e−6 of ρ's scale.
template <class T>
T sglab_ramp(const T& u) {
  using std::abs;
  const T over = abs(u - T(1));
  const T v = T(0.5) * (abs(u) - over + T(1));
  return v * v * v * (T(2) - v) + (u - T(1) + over);
}

// max(x, 0) = (x + |x|)/2 without a branch (exact in binary floating point).
template <class T>
T max0_branchless(const T& x) {
  using std::abs;
  return T(0.5) * (x + abs(x));
}

}  // namespace detail

// Everything of `sglab_fast` that depends on κ alone, with E(1, κ) folded
// in: Ê = max(0, a + b c + c_ramp ρ(v c + ½)).
template <class T>
struct SglabFastLight {
  T a, b, c_ramp, v;
};

// The normalized shape s(c) = A + B c + C ρ(V c + ½), unclamped (the fitter's per-κ stage).
template <class T>
T sglab_fast_shape(const T& cosine, const T& A, const T& B, const T& C, const T& V) {
  return A + B * cosine + C * detail::sglab_ramp(V * cosine + T(0.5));
}

// Per-light setup: one exp and two divisions.
template <class T, class S = double>
SglabFastLight<T> sglab_fast_light(const T& kappa,
                                   const SglabFastParams<S>& p = constants::sglab_fast_float) {
  const T k = detail::min_of(kappa, T(p.kappa_max));
  const T inv_q = T(1) / (horner(k, p.q) + k * k * k * k);
  // A, B, C are O(1) after the division; E(1, κ) ≈ 2π/κ is applied last, so
  // nothing underflows before it even at κ near the largest float.
  const T e1 = two_pi_v<T>() * detail::upper_over_two_pi_fast(kappa);
  return {horner(k, p.a) * inv_q * e1, horner(k, p.b) * inv_q * e1, horner(k, p.c) * inv_q * e1,
          horner(k, p.v) * inv_q};
}

// Per-shading-point evaluation.
template <class T>
T sglab_fast_eval(const SglabFastLight<T>& light, const T& cosine) {
  return detail::max0_branchless(light.a + light.b * cosine +
                                 light.c_ramp * detail::sglab_ramp(light.v * cosine + T(0.5)));
}

// The same setup in float without branches or library calls (branch_free.hpp:
// exp_bf within 2 ulp of expf, selects instead of comparisons), so that a batch
// loop vectorizes. Identical algebra to sglab_fast_light.
template <class S>
SGLAB_FORCE_INLINE SglabFastLight<float> sglab_fast_light_branch_free(float kappa,
                                                                      const SglabFastParams<S>& p) {
  namespace bf = branch_free;
  const float k = bf::min(kappa, float(p.kappa_max));
  const float inv_q = 1.0f / (horner(k, p.q) + k * k * k * k);
  const float e1 = two_pi_v<float>() * detail::upper_over_two_pi_branch_free(kappa);
  return {horner(k, p.a) * inv_q * e1, horner(k, p.b) * inv_q * e1, horner(k, p.c) * inv_q * e1,
          horner(k, p.v) * inv_q};
}

// Float batch of `sglab_fast` that vectorizes (tests/test_sglab_fast.cpp
// compares it with the scalar path).
template <class S = double>
SGLAB_FLATTEN void irradiance_sglab_fast_batch(
    const float* __restrict cosine, const float* __restrict kappa, float* __restrict out,
    std::size_t n, const SglabFastParams<S>& p = constants::sglab_fast_float) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = sglab_fast_eval(sglab_fast_light_branch_free(kappa[i], p), cosine[i]);
}

// `sglab_fast`: Ê(c, κ), the two steps above in one call.
template <class T, class S = double>
T irradiance_sglab_fast(const T& cosine, const T& kappa,
                        const SglabFastParams<S>& p = constants::sglab_fast_float) {
  return sglab_fast_eval(sglab_fast_light(kappa, p), cosine);
}

}  // namespace sglab
