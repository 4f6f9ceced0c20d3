// sglab/sglab_acc.hpp — sglab's own irradiance models (origin "sglab").
//
// `sglab_acc<N>`: the [Tokuyoshi2024] interpolation form with a fitted
// correction of its lerp factor,
//
//   Ê(c, κ) = 2π lerp(Ē(−1, κ), Ē(1, κ), f̂),
//   f̂ = f₂₀₂₄(c, t) + (1 − c²) e^{−z²} (b₀(κ) + b₁(κ) z² + … + b_{N−1}(κ) z^{2(N−1)}),  z = t c,
//
// where f₂₀₂₄ = ½(c erfc(−z) + erfc(t)) − e^{−z²} expm1(t²(c² − 1))/(2√π t) is
// the factor of [Tokuyoshi2024] supplementary Listing 7, t(κ) its steepness
// (same rational form, coefficients refitted jointly with the correction),
// and every b_j(κ) = u(1 − u)³ P_j(u), u = t/(t + s), P_j a polynomial of
// degree D (sglab_acc_fade): the correction fades where the 2024 form is
// already exact (like κ as κ → 0, like κ^{−3/2} as κ → ∞). The residual of
// the 2024 form is even in c; the correction is even, reuses the e^{−z²} the
// form already computes (no extra exp/erfc call), and vanishes at c = ±1, so
// the poles E(±1, κ) stay exact.
//
// Everything that depends on κ alone (t, erfc(t), 1/t, the poles, the b_j)
// is computed once per light by `sglab_acc_light`; `sglab_acc_eval` is the
// per-shading-point part. The plain function is exactly eval(setup(κ), c).
// Fitted by `sglab fit sglab-acc` (fit/sglab_acc.cpp), each
// residual divided by min(T, max(e₂₀₂₄(κ), 8e−7)) so that at every κ the
// error stays at or below tokuyoshi2024's (or 1e−6); the measured errors of
// the shipped sets are in their provenance (sglab/constants.hpp). Max
// peak_rel |Ê − E|/E(1, κ), float, κ ∈ [1e−3, 1e4], on a held-out 200 κ ×
// 401 c grid never used in fitting:
//   sglab_acc1 (N = 1, D = 3) 1.93e−4,  sglab_acc2 (N = 2, D = 3) 5.51e−5,
//   sglab_acc3 (N = 3, D = 4) 2.12e−5  (tokuyoshi2024: 1.44e−3 refitted).
// Cost (callgrind, float, instructions per evaluation, bench/method_cost.cpp):
// scalar 454, 465, 477 and batch 125, 127, 133 against tokuyoshi2024's 423
// and 115 (1.07×, 1.10×, 1.13× scalar; 1.09×, 1.10×, 1.16× batch): the same
// erfc/exp/expm1 calls, one extra division per light.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "closed_forms.hpp"
#include "constants.hpp"
#include "hemispherical.hpp"
#include "irradiance.hpp"
#include "math.hpp"
#include "params.hpp"

namespace sglab {

// The κ-only part of `sglab_acc<N>` (the per-light state).
template <class T, std::size_t N> struct SglabAccLight {
  T t;             // steepness t(κ)
  T half_erfc_t;   // ½ erfc(t)
  T tail_scale;    // 1/(2√π max(t, ε)) (detail::sglab_acc_tail_scale)
  T t2;            // t²
  T lower, upper;  // Ē(−1, κ), Ē(1, κ) (closed_forms.hpp)
  T b[N];          // correction coefficients b_j(κ)
};

namespace detail {

// b_j(κ) = u(1 − u)³ P_j(u), u = t/(t + s) ∈ [0, 1) with t = t(κ) ≥ 0 and the
// fitted scale s > 0, P_j(u) = a_{j,0} + a_{j,1} u + … + a_{j,D} u^D (Horner).
// The fade u(1 − u)³ makes the correction vanish where the [Tokuyoshi2024]
// form is already exact: as κ → 0, u ≈ t/s ∝ κ (the form's residual falls
// like κ², and the correction moves Ê by κ b_j); as κ → ∞, t ≈ √(κ/2) and
// (1 − u)³ ≈ (s/t)³ ∝ κ^{−3/2}, the decay of the form's residual. One
// division, no branch; t + s ≥ s > 0, and for the largest finite κ
// (t ≈ 1.3e19 in float) u = 1 and (1 − u)³ underflows to 0, so does b_j.
template <class T, class S, std::size_t N, std::size_t D>
SGLAB_FORCE_INLINE void sglab_acc_fade(const T& t, const SglabAccParams<S, N, D>& p, T (&b)[N]) {
  const T w = T(1) / (t + T(p.scale));
  const T u = t * w, v = T(p.scale) * w;  // u and 1 − u
  const T fade = u * (v * v) * v;
  for (std::size_t i = 0; i < N; ++i) {
    const S* a = p.num + i * (D + 1);
    T y = T(a[D]);
    for (std::size_t j = 1; j <= D; ++j) y = y * u + T(a[D - j]);
    b[i] = fade * y;
  }
}

// The scale 1/(2√π max(t, ε)) of the [Tokuyoshi2024] tail term
// e^{−z²} expm1(−t²(1 − c²))/(2√π t), ε the epsilon of T. 1/t overflows for
// a subnormal t (t < 1/max: κ ≲ 1e−38 in float, 1e−308 in double), where t²
// is 0 and the tail became 0·inf = NaN. Dividing by ε instead where t ≤ ε
// keeps the term below rounding: |expm1(−x)| ≤ x bounds it by
// t²(1 − c²)/(2√π ε) ≤ t/(2√π) < 0.29ε in f, and Ê = 2π lerp(Ē(−1), Ē(1), f)
// moves by that times 2π(Ē(1) − Ē(−1)) = O(κ), far below an ulp of Ê ≈ π
// (κ ≲ 3t there). `Ops::select` keeps the float batch branch-free (one
// select, not two: the float batch stays within 1.15× of tokuyoshi2024).
template <class T, class Ops = LibmOps> SGLAB_FORCE_INLINE T sglab_acc_tail_scale(const T& t, Ops = {}) {
  const bool keep = t > std::numeric_limits<T>::epsilon();
  return T(0.5) * inv_sqrt_pi_v<T>() / Ops::select(keep, t, std::numeric_limits<T>::epsilon());
}

}  // namespace detail

// Per-light setup of `sglab_acc<N>`: everything that depends on κ alone.
template <class T, class S, std::size_t N, std::size_t D>
SGLAB_FORCE_INLINE SglabAccLight<T, N> sglab_acc_light(const T& kappa, const SglabAccParams<S, N, D>& p) {
  using std::erfc;
  // t and the poles (one exp for both) as the setup of `tokuyoshi2024` (irradiance.hpp).
  const Tokuyoshi2024Light<T> base =
      tokuyoshi2024_light(kappa, Steepness2024Params<S>{p.steep[0], p.steep[1], p.steep[2], p.steep[3], p.steep[4]});
  SglabAccLight<T, N> l;
  l.t = base.t;
  l.half_erfc_t = T(0.5) * erfc(l.t);
  l.tail_scale = detail::sglab_acc_tail_scale(l.t);
  l.t2 = l.t * l.t;
  l.lower = base.lower;
  l.upper = base.upper;
  detail::sglab_acc_fade(l.t, p, l.b);
  return l;
}

// The same setup in float without branches, for the batch kernel: t and the
// poles as the vectorizing setup of `tokuyoshi2024` (irradiance.hpp), erfc(t)
// by branch_free.hpp's erfc_bf (absolute error ≤ 6e−7).
template <class S, std::size_t N, std::size_t D>
SGLAB_FORCE_INLINE SglabAccLight<float, N> sglab_acc_light_branch_free(float kappa, const SglabAccParams<S, N, D>& p) {
  const Tokuyoshi2024Light<float> base = tokuyoshi2024_light_branch_free(
      kappa, Steepness2024Params<S>{p.steep[0], p.steep[1], p.steep[2], p.steep[3], p.steep[4]});
  SglabAccLight<float, N> l;
  l.t = base.t;
  l.half_erfc_t = 0.5f * branch_free::erfc_bf(base.t);
  l.tail_scale = detail::sglab_acc_tail_scale(base.t, detail::BranchFreeOps{});
  l.t2 = base.t * base.t;
  l.lower = base.lower;
  l.upper = base.upper;
  detail::sglab_acc_fade(base.t, p, l.b);
  return l;
}

// Per-shading-point evaluation of `sglab_acc<N>` from the light's state, with
// the elementary functions of `Ops` (the standard library's, or the
// branch-free ones of the batch kernel). The one implementation of the model.
template <class T, std::size_t N, class Ops = detail::LibmOps>
SGLAB_FORCE_INLINE T sglab_acc_eval(const SglabAccLight<T, N>& l, const T& cosine, Ops = {}) {
  const T c = Ops::clamp(cosine, T(-1), T(1));
  const T z = l.t * c;
  const T z2 = z * z;
  const T one_minus_c2 = T(1) - c * c;
  const T g = Ops::exp(-z2);  // e^{−z²}: shared by the [Tokuyoshi2024] tail, erfc(−z) and the correction
  // [Tokuyoshi2024] Listing 7: f = ½(c erfc(−z) + erfc(t)) − e^{−z²} expm1(t²(c² − 1))/(2√π t).
  const T f2024 = T(0.5) * c * Ops::erfc(-z, g) + l.half_erfc_t - g * Ops::expm1(-l.t2 * one_minus_c2) * l.tail_scale;
  // sglab correction: (1 − c²) e^{−z²} Σ_j b_j z^{2j}. Where e^{−z²} has
  // underflowed to 0 the correction is 0 (selected: z^{2j} may overflow there
  // for huge κ, and 0·inf would be NaN).
  T poly = l.b[N - 1];
  for (std::size_t j = N - 1; j-- > 0;) poly = poly * z2 + l.b[j];
  const T corr = Ops::select(g > T(0), one_minus_c2 * g * poly, T(0));
  const T f = Ops::clamp(f2024 + corr, T(0), T(1));
  return two_pi_v<T>() * lerp(l.lower, l.upper, f);
}

// Float batch of `sglab_acc<N>` that vectorizes: the branch-free setup and
// the evaluation above with branch_free.hpp's exp, expm1, erfc and sqrt.
// Distance from the double path: the erfc_bf error (≤ 6e−7 absolute) moves f
// by at most that, i.e. ≤ 6e−7 of the peak E(1, κ), plus float rounding;
// tests/test_branch_free.cpp holds it to 1e−6 of the peak.
template <class S, std::size_t N, std::size_t D>
SGLAB_FLATTEN void irradiance_sglab_acc_batch(const float* __restrict cosine, const float* __restrict kappa, float* __restrict out,
                                std::size_t n, const SglabAccParams<S, N, D>& p) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = sglab_acc_eval(sglab_acc_light_branch_free(kappa[i], p), cosine[i], detail::BranchFreeOps{});
}

// `sglab_acc<N>` in one call: eval(setup(κ), c).
template <class T, class S, std::size_t N, std::size_t D>
SGLAB_FORCE_INLINE T irradiance_sglab_acc(const T& cosine, const T& kappa, const SglabAccParams<S, N, D>& p) {
  return sglab_acc_eval(sglab_acc_light(kappa, p), cosine);
}

}  // namespace sglab
