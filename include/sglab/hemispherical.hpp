// sglab/hemispherical.hpp — approximate hemispherical integrals of an SG.
//
// H̃(c, κ) = lerp(H(−1, κ), H(1, κ), s̃(c, κ)) with the exact poles
// H(1, κ) = 2π(1 − e^{−κ})/κ, H(−1, κ) = e^{−κ} H(1, κ) ([Tokuyoshi2022] supplementary §2.2) and an
// approximate normalized hemispherical integral s̃.
#pragma once

#include <cmath>

#include "closed_forms.hpp"
#include "constants.hpp"
#include "erf.hpp"
#include "math.hpp"
#include "params.hpp"

namespace sglab {

// t(κ) = κ √((0.5κ + A)/((κ + B)κ + C))  (Tokuyoshi 2022, Eq. 6). For κ ≥ 1 the
// same ratio is evaluated as √κ √((0.5 + A/κ)/(1 + B/κ + C/κ²)) so that
// nothing overflows up to the largest finite κ; t → √(κ/2) as κ → ∞.
template <class T, class S = double>
SGLAB_FORCE_INLINE T steepness2022(
    const T& kappa, const Steepness2022Params<S>& p = constants::steepness2022_published) {
  using std::sqrt;
  const T A = T(p.A), B = T(p.B), C = T(p.C);
  if (kappa < T(1)) return kappa * sqrt((T(0.5) * kappa + A) / ((kappa + B) * kappa + C));
  const T r = T(1) / kappa;
  return sqrt(kappa) * sqrt((T(0.5) + A * r) / (T(1) + (B + C * r) * r));
}

// t(κ) = κ √(0.5((κ + A)κ + B)/(((κ + C)κ + D)κ + E))  (Tokuyoshi et al. 2024,
// supplementary Listing 7), rearranged for κ ≥ 1 as above.
template <class T, class S = double>
SGLAB_FORCE_INLINE T steepness2024(
    const T& kappa, const Steepness2024Params<S>& p = constants::steepness2024_published) {
  using std::sqrt;
  const T A = T(p.A), B = T(p.B), C = T(p.C), D = T(p.D), E = T(p.E);
  if (kappa < T(1))
    return kappa *
           sqrt(T(0.5) * ((kappa + A) * kappa + B) / (((kappa + C) * kappa + D) * kappa + E));
  const T r = T(1) / kappa;
  return sqrt(kappa) * sqrt(T(0.5) * (T(1) + (A + B * r) * r) / (T(1) + (C + (D + E * r) * r) * r));
}

// t(κ) of order M (params.hpp), evaluated as κ√(0.5 P/Q) for κ < 1 and as
// √κ √(0.5 (P/κ^M)/(Q/κ^{M+1})) in powers of 1/κ above, so nothing overflows.
template <class T, class S, std::size_t M>
SGLAB_FORCE_INLINE T steepness_rational(const T& kappa, const SteepnessRationalParams<S, M>& p) {
  using std::sqrt;
  if (kappa < T(1)) {
    T P = T(1), Q = T(1);
    if constexpr (M > 0)
      for (std::size_t i = M; i-- > 0;) P = P * kappa + T(p.p[i]);
    for (std::size_t i = M + 1; i-- > 0;) Q = Q * kappa + T(p.q[i]);
    return kappa * sqrt(T(0.5) * P / Q);
  }
  const T r = T(1) / kappa;
  // P/κ^M = 1 + p[M−1] r + … + p[0] r^M, Horner in r from p[0].
  T P = T(0), Q = T(0);
  if constexpr (M > 0)
    for (std::size_t i = 0; i < M; ++i) P = (P + T(p.p[i])) * r;
  for (std::size_t i = 0; i <= M; ++i) Q = (Q + T(p.q[i])) * r;
  return sqrt(kappa) * sqrt(T(0.5) * (T(1) + P) / (T(1) + Q));
}

// The 2024 form as the order-2 rational form: p = {B, A}, q = {E, D, C}
// (SteepnessRationalParams); steepness_rational evaluates it with the same
// operations as steepness2024.
template <class S>
constexpr SteepnessRationalParams<S, 2> steepness_rational_of(const Steepness2024Params<S>& s) {
  return {{s.B, s.A}, {s.E, s.D, s.C}};
}

// One name for every steepness form, so methods can take any of them.
template <class T, class S>
SGLAB_FORCE_INLINE T steepness(const T& kappa, const Steepness2022Params<S>& p) {
  return steepness2022(kappa, p);
}
template <class T, class S>
SGLAB_FORCE_INLINE T steepness(const T& kappa, const Steepness2024Params<S>& p) {
  return steepness2024(kappa, p);
}
template <class T, class S, std::size_t M>
SGLAB_FORCE_INLINE T steepness(const T& kappa, const SteepnessRationalParams<S, M>& p) {
  return steepness_rational(kappa, p);
}

// erf(t c)/erf(t), with its t → 0 limit c: erf(tc)/erf(t) = c(1 + t²(1 − c²)/3 + O(t⁴)),
// so below t = 2^−13 (float) or 2^−27 (double) the ratio is c to working
// precision, and erf(t) can no longer underflow into the denormals.
template <class T, class Erf = ErfStd>
T erf_ratio(const T& t, const T& cosine, Erf erf = {}) {
  const T tiny = sizeof(T) <= sizeof(float) ? T(0x1p-13) : T(0x1p-27);
  if (t < tiny) return cosine;
  // An approximate erf need not be monotone to the last ulp (Listing 5 is
  // not): keep the ratio in [−1, 1] so that s̃ stays in [0, 1].
  return clamp(erf(t * cosine) / erf(t), T(-1), T(1));
}

// s̃(c, κ) = ½ + ½ erf(t(κ) c)/erf(t(κ))  (Tokuyoshi 2022, Eq. 5).
template <class T, class Erf = ErfStd, class P = Steepness2022Params<double>>
T normalized_erf2022(const T& cosine, const T& kappa,
                     const P& p = constants::steepness2022_published, Erf erf = {}) {
  const T t = steepness(kappa, p);
  return T(0.5) + T(0.5) * erf_ratio(t, clamp(cosine, T(-1), T(1)), erf);
}

// H̃(c, κ) = 2π lerp(e^{−κ}, 1, s̃) (1 − e^{−κ})/κ  ([Tokuyoshi2022] Listing 3, `erf2022`).
template <class T, class Erf = ErfStd, class P = Steepness2022Params<double>>
T hemispherical_erf2022(const T& cosine, const T& kappa,
                        const P& p = constants::steepness2022_published, Erf erf = {}) {
  using std::exp;
  const T s = normalized_erf2022(cosine, kappa, p, erf);
  return two_pi_v<T>() * lerp(exp(-kappa), T(1), s) * expm1_over_x(-kappa);
}

// Meder & Brüderlin 2018 logistic steepness t(κ) = √κ (a2κ² + a1κ)/(κ² + b1κ + b0),
// transcribed as published: κ² overflows for κ ≳ 1.8e19 in float.
template <class T, class S = double>
T steepness_meder2018(const T& kappa,
                      const Meder2018Params<S>& p = constants::meder2018_published) {
  using std::sqrt;
  return sqrt(kappa) * (T(p.a2) * kappa * kappa + T(p.a1) * kappa) /
         (kappa * kappa + T(p.b1) * kappa + T(p.b0));
}

// Meder & Brüderlin 2018 normalized hemispherical integral: the logistic in
// t(κ)c normalized so that s(−1) = 0 and s(1) = 1 ([Meder2018]),
//   s = (e^{t}e^{tc} − 1)/((e^{t} − 1)(e^{tc} + 1)),  → (1 + c)/2 as t → 0.
// Multiplying through by e^{−t}e^{−tc} gives the same function as
//   s = σ(tc)·(1 − e^{−t(1+c)})/(1 − e^{−t}),  σ(z) = 1/(1 + e^{−z}),
// evaluated here stably in float and double: σ from e^{−t|c|} ≤ 1 (no
// overflow at large t), the ratio as expm1(−t(1+c))/expm1(−t) for t ≥ 1 and as
// (1 + c)·E(−t(1+c))/E(−t) with E(x) = (e^x − 1)/x below (no 0/0 at t = 0,
// where E = 1). (The plain logistic 1/(1 + e^{−tc}) is not normalized: its
// s(1) → 1/2 as κ → 0.)
template <class T, class S = double>
T normalized_meder2018(const T& cosine, const T& kappa,
                       const Meder2018Params<S>& p = constants::meder2018_published) {
  using std::abs;
  using std::exp;
  using std::expm1;
  const T t = steepness_meder2018(kappa, p);
  const T c = clamp(cosine, T(-1), T(1));
  const T e = exp(-(t * abs(c)));
  const T sigma = c < T(0) ? e / (T(1) + e) : T(1) / (T(1) + e);  // σ(tc)
  const T u = T(1) + c;
  const T ratio =
      t < T(1) ? u * (expm1_over_x(-(t * u)) / expm1_over_x(-t)) : expm1(-(t * u)) / expm1(-t);
  return saturate(sigma * ratio);
}

template <class T, class S = double>
T hemispherical_meder2018(const T& cosine, const T& kappa,
                          const Meder2018Params<S>& p = constants::meder2018_published) {
  using std::exp;
  const T s = normalized_meder2018(cosine, kappa, p);
  return two_pi_v<T>() * lerp(exp(-kappa), T(1), s) * expm1_over_x(-kappa);
}

}  // namespace sglab
