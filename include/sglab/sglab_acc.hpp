// sglab/sglab_acc.hpp — sglab's own models `sglab_acc<N>`: the [Tokuyoshi2024] interpolation
//   Ê(c, κ) = 2π lerp(Ē(−1, κ), Ē(1, κ), f̂),
//   f̂ = f₂₀₂₄(c, t) + (1 − c²) e^{−z²} Σ_{j<N} b_j(κ) z^{2j},  z = t c,
// with a faded even correction; form, fit, error and cost: docs/models.md#sglab_acc1--sglab_acc4.
// `sglab_acc_light` is the κ-only part, `sglab_acc_eval` the per-point part; the plain
// function is exactly eval(setup(κ), c).
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
template <class T, std::size_t N>
struct SglabAccLight {
  T t;             // steepness t(κ)
  T half_erfc_t;   // ½ erfc(t)
  T tail_scale;    // 1/(2√π (t + m)) (detail::sglab_acc_tail_scale)
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
template <class T, class S, std::size_t N, std::size_t D, std::size_t M>
SGLAB_FORCE_INLINE void sglab_acc_fade(const T& t, const SglabAccParams<S, N, D, M>& p, T (&b)[N]) {
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

// The scale 1/(2√π (t + m)) of the [Tokuyoshi2024] tail term
// e^{−z²} expm1(−t²(1 − c²))/(2√π t), m the smallest normal number of T. 1/t
// overflows for a subnormal t (t < 1/max: κ ≲ 1e−38 in float, 1e−308 in
// double), where t² is 0 and the tail became 0·inf = NaN; 1/(t + m) ≤ 1/m is
// finite. t + m rounds to t itself wherever m is below half an ulp of t
// (t ≥ 2^−101 in float, 2^−969 in double); below that the tail term is at most
// t(1 − c²)/(2√π) < 1e−30, far below an ulp of f. One addition, where a select
// of max(t, ε) took four instructions of the float batch (its cost stays within
// 1.15× of tokuyoshi2024's, data/results/callgrind.csv).
template <class T, class Ops = LibmOps>
SGLAB_FORCE_INLINE T sglab_acc_tail_scale(const T& t, Ops = {}) {
  return T(0.5) * inv_sqrt_pi_v<T>() / (t + std::numeric_limits<T>::min());
}

// The steepness of `p` as SteepnessRationalParams (params.hpp,
// steepness_rational in hemispherical.hpp): steep lists P's and Q's
// coefficients highest order first, p and q lowest first. For M = 2 the
// same operations as steepness2024 (tests/test_sglab_acc.cpp).
template <class S, std::size_t N, std::size_t D, std::size_t M>
constexpr SteepnessRationalParams<S, M> sglab_acc_steepness(const SglabAccParams<S, N, D, M>& p) {
  SteepnessRationalParams<S, M> r{};
  for (std::size_t i = 0; i < M; ++i) r.p[M - 1 - i] = p.steep[i];
  for (std::size_t i = 0; i <= M; ++i) r.q[M - i] = p.steep[M + i];
  return r;
}

}  // namespace detail

// Per-light setup of `sglab_acc<N>`: everything that depends on κ alone.
template <class T, class S, std::size_t N, std::size_t D, std::size_t M>
SGLAB_FORCE_INLINE SglabAccLight<T, N> sglab_acc_light(const T& kappa,
                                                       const SglabAccParams<S, N, D, M>& p) {
  using std::erfc;
  // t and the poles (one exp for both) as the setup of `tokuyoshi2024` (irradiance.hpp).
  const Tokuyoshi2024Light<T> base = tokuyoshi2024_light(kappa, detail::sglab_acc_steepness(p));
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
template <class S, std::size_t N, std::size_t D, std::size_t M>
SGLAB_FORCE_INLINE SglabAccLight<float, N> sglab_acc_light_branch_free(
    float kappa, const SglabAccParams<S, N, D, M>& p) {
  const Tokuyoshi2024Light<float> base =
      tokuyoshi2024_light_branch_free(kappa, detail::sglab_acc_steepness(p));
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
  // e^{−z²}: shared by the [Tokuyoshi2024] tail, erfc(−z) and the correction
  const T g = Ops::exp(-z2);
  // [Tokuyoshi2024] Listing 7: f = ½(c erfc(−z) + erfc(t)) − e^{−z²} expm1(t²(c² − 1))/(2√π t).
  const T f2024 = T(0.5) * c * Ops::erfc(-z, g) + l.half_erfc_t -
                  g * Ops::expm1(-l.t2 * one_minus_c2) * l.tail_scale;
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
template <class S, std::size_t N, std::size_t D, std::size_t M>
SGLAB_FLATTEN void irradiance_sglab_acc_batch(const float* __restrict cosine,
                                              const float* __restrict kappa, float* __restrict out,
                                              std::size_t n, const SglabAccParams<S, N, D, M>& p) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = sglab_acc_eval(sglab_acc_light_branch_free(kappa[i], p), cosine[i],
                            detail::BranchFreeOps{});
}

// `sglab_acc<N>` in one call: eval(setup(κ), c).
template <class T, class S, std::size_t N, std::size_t D, std::size_t M>
SGLAB_FORCE_INLINE T irradiance_sglab_acc(const T& cosine, const T& kappa,
                                          const SglabAccParams<S, N, D, M>& p) {
  return sglab_acc_eval(sglab_acc_light(kappa, p), cosine);
}

}  // namespace sglab
