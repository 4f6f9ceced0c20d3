// sglab/irradiance.hpp — approximations Ê(c, κ) of the irradiance
// E(c, κ) = ∫ G(ω; v, κ) max(ω·n, 0) dω from a unit-amplitude SG light,
// c = v·n (docs/quantities.md). One function per method id (docs/references.md).
//
// Published methods are faithful transcriptions of their formulas: where they
// fail (division by κ = 0, overflow, cancellation) that is a finding of
// `sglab stability`, not something patched here.
#pragma once

#include <cmath>
#include <cstddef>

#include "branch_free.hpp"
#include "closed_forms.hpp"
#include "constants.hpp"
#include "erf.hpp"
#include "hemispherical.hpp"
#include "math.hpp"
#include "params.hpp"
#include "sg.hpp"

namespace sglab {

// `wang2009`: inner product of the light with the cosine-lobe SG
// a·G(ω; n, λ), λ = 2.133, a = 1.17 ([Wang2009]), clamped at 0, as in
// [Pettineo2016] "SGIrradianceInnerProduct": with d = |κv + λn|,
// Ê = max(2π a e^{d − κ − λ}(1 − e^{−2d})/d, 0).
// The same function is evaluated through sg_inner_product (a·e^{κ3−κ−λ}S(κ3)
// with κ3 = d): the published form subtracts κ + λ from d, which cancels at
// large κ, forms κ² (NaN from inf − inf for κ ≳ 1.8e19 in float), and gives
// 0/0 at d = 0 (c = −1, κ = λ), where (1 − e^{−2d})/d → 2. The stable product
// writes d − κ − λ = −2κλ(1 − c)/(d + κ + λ) (exact algebra: d² − (κ + λ)² =
// −2κλ(1 − c)) and S(d) = 2π(1 − e^{−2d})/d with its d → 0 limit 4π.
template <class T, class S = double>
T irradiance_wang2009(const T& cosine, const T& kappa,
                      const CosineLobeParams<S>& p = constants::cosine_lobe_published) {
  return max0(T(p.amplitude) * sg_inner_product(cosine, kappa, T(p.lambda)));
}

// `punctual`: the cosine pulled out of the integral, Ê = max(c, 0)·2π/κ
// ([Pettineo2016] "SGIrradiancePunctual"). Infinite at κ = 0.
template <class T>
T irradiance_punctual(const T& cosine, const T& kappa) {
  return saturate(cosine) * sphere_integral_approx(kappa);
}

namespace detail {
// Stephen Hill's fitted curve for a normalized SG ([Pettineo2016] "SGIrradianceFitted").
// 1 − scale = 1/κ − 2e^{−2κ} is formed directly (the same value): through
// 1 − scale it rounds to 0 once 1/κ < ulp(1)/2 (κ ≥ 1e8 in float, 1e17 in
// double), and at c = 0 the curve's n²/x became 0/0. With x > 0 kept, n²/x is
// evaluated as n·(n/x): n/x ∈ [c1, 2c1] where the curve applies, so nothing
// underflows at large κ either (at c = 0 it is c1²x, x → 1/√κ).
template <class T, class S>
T hill_normalized(const T& cosine, const T& kappa, const HillParams<S>& p) {
  using std::abs;
  using std::exp;
  using std::sqrt;
  const T c0 = T(p.c0);
  const T c1 = T(1) / (T(4) * c0);
  const T eml = exp(-kappa);
  const T em2l = eml * eml;
  const T rl = T(1) / kappa;
  const T scale = T(1) + T(2) * em2l - rl;
  const T one_minus_scale = rl - T(2) * em2l;  // > 0: 2κe^{−2κ} ≤ 1/e
  const T bias = (eml - em2l) * rl - em2l;
  const T x = sqrt(one_minus_scale);
  const T x0 = c0 * cosine;
  const T x1 = c1 * x;
  const T n = x0 + x1;
  const T y = abs(x0) <= x1 ? n * (n / x) : saturate(cosine);
  return scale * y + bias;
}
}  // namespace detail

// `hill`: Hill's curve times the approximate SG integral 2π/κ ([Pettineo2016]).
// Below κ ≈ 0.6, 1 − 1/κ + 2e^{−2κ} < 0 and sqrt(1 − scale) is taken of a
// number > 1; at κ = 0 the result is NaN.
template <class T, class S = double>
T irradiance_hill(const T& cosine, const T& kappa,
                  const HillParams<S>& p = constants::hill_published) {
  return detail::hill_normalized(cosine, kappa, p) * sphere_integral_approx(kappa);
}

// `hill_exact`: the same curve times the exact integral S(κ) (as Probulator does).
template <class T, class S = double>
T irradiance_hill_exact(const T& cosine, const T& kappa,
                        const HillParams<S>& p = constants::hill_published) {
  return detail::hill_normalized(cosine, kappa, p) * sphere_integral(kappa);
}

// `vsgl2015`: cos⁺/π ≈ G(ω; n, λd)/A(λd) with A(λd) ≈ π and Iwasaki's
// approximate product integral ([Tokuyoshi2015] supplemental §3.2):
// Ê = 2π exp(λ'(c − 1))/(κ + λd), λ' = κλd/(κ + λd).
template <class T, class S = double>
T irradiance_vsgl2015(const T& cosine, const T& kappa,
                      const DiffuseLobeParams<S>& p = constants::diffuse_lobe_published) {
  return sg_inner_product_iwasaki(cosine, kappa, T(p.lambda_d));
}

// `meder2018`: cos θ ≈ a·e^{λm(cos θ − 1)} − b on the upper hemisphere and
// the logistic hemispherical integral (Meder & Brüderlin 2018):
// Ê = a e^{logAmp} H̃(c3, κ3) − b H̃(c, κ) with (κ3, logAmp, c3) the product of
// the light and G(ω; n, λm).
template <class T, class S = double>
T irradiance_meder2018(const T& cosine, const T& kappa,
                       const Meder2018Params<S>& p = constants::meder2018_published) {
  using std::exp;
  const ProductWithNormal<T> prod = sg_product_with_normal(cosine, kappa, T(p.sharpness));
  const T upper = exp(prod.log_amplitude) * hemispherical_meder2018(prod.cosine, prod.sharpness, p);
  return T(p.amplitude) * upper - T(p.offset) * hemispherical_meder2018(cosine, kappa, p);
}

// `tokuyoshi2022`: cos⁺ ≈ α(e^{λ cos θ} − 1) = α(e^{λ} G(ω; n, λ) − 1) on the
// upper hemisphere ([Tokuyoshi2022] Listing 1):
// Ê = max(α(H̃(c3, κ3) e^{λ + logAmp} − H̃(c, κ)), 0) with the erf-based H̃.
// `st` may be any steepness form (Steepness2022Params by default).
template <class T, class Erf = ErfStd, class S = double, class P = Steepness2022Params<double>>
T irradiance_tokuyoshi2022(const T& cosine, const T& kappa,
                           const ClampedCosineParams<S>& cc = constants::clamped_cosine_published,
                           const P& st = constants::steepness2022_published, Erf erf = {}) {
  using std::exp;
  const T lambda = T(cc.lambda), alpha = T(cc.alpha);
  const ProductWithNormal<T> prod = sg_product_with_normal(cosine, kappa, lambda);
  const T p = hemispherical_erf2022(prod.cosine, prod.sharpness, st, erf) *
              exp(lambda + prod.log_amplitude);
  const T q = hemispherical_erf2022(cosine, kappa, st, erf);
  return max0(alpha * p - alpha * q);
}

namespace detail {
// Elementary functions of a method's formula: the standard library's (scalar,
// and Ceres Jets through argument-dependent lookup) ...
struct LibmOps {
  template <class T>
  static T exp(const T& x) {
    using std::exp;
    return exp(x);
  }
  template <class T>
  static T expm1(const T& x) {
    using std::expm1;
    return expm1(x);
  }
  template <class T>
  static T erfc(const T& x) {
    using std::erfc;
    return erfc(x);
  }
  // erfc(x) when e^{−x²} is at hand (unused here).
  template <class T>
  static T erfc(const T& x, const T&) {
    return erfc(x);
  }
  template <class T>
  static T select(bool m, const T& a, const T& b) {
    return m ? a : b;
  }
  template <class T>
  static T clamp(const T& x, const T& lo, const T& hi) {
    return sglab::clamp(x, lo, hi);
  }
};
// ... or sglab's branch-free float approximations (branch_free.hpp), with
// which a loop over the method vectorizes.
struct BranchFreeOps {
  static float exp(float x) { return branch_free::exp_bf(x); }
  static float expm1(float x) { return branch_free::expm1_bf(x); }
  static float erfc(float x) { return branch_free::erfc_bf(x); }
  static float erfc(float x, float exp_minus_x2) { return branch_free::erfc_bf(x, exp_minus_x2); }
  static float select(bool m, float a, float b) { return branch_free::select(m, a, b); }
  static float clamp(float x, float lo, float hi) { return branch_free::clamp(x, lo, hi); }
};
}  // namespace detail

// Interpolation factor of `tokuyoshi2024` as a function of the steepness t
// (Tokuyoshi et al. 2024, supplementary Listing 7):
// f = ½(c erfc(−tc) + erfc(t)) − e^{−t²c²} expm1(t²(c² − 1))/(2√π t),
// saturated to [0, 1]. The last term → 0 as t → 0 (it is ~ t(c² − 1)).
template <class T, class Ops = detail::LibmOps>
SGLAB_FORCE_INLINE T lerp_factor_tokuyoshi2024_at_steepness(const T& cosine, const T& t, Ops = {}) {
  const T c = Ops::clamp(cosine, T(-1), T(1));
  const T tz = t * c;
  const T ez = Ops::exp(-tz * tz);  // e^{−t²c²}
  const T tail = Ops::select(t > T(0), ez * Ops::expm1(t * t * (c * c - T(1))) / t, T(0));
  return Ops::clamp(
      T(0.5) * (c * Ops::erfc(-tz, ez) + Ops::erfc(t)) - T(0.5) * inv_sqrt_pi_v<T>() * tail, T(0),
      T(1));
}

template <class T, class P = Steepness2024Params<double>>
T lerp_factor_tokuyoshi2024(const T& cosine, const T& kappa,
                            const P& p = constants::steepness2024_published) {
  return lerp_factor_tokuyoshi2024_at_steepness(cosine, steepness(kappa, p));
}

// `tokuyoshi2024` split into a per-light setup (everything that depends on κ
// alone: the steepness t(κ) and the exact poles Ē(±1) = E(±1, κ)/2π,
// closed_forms.hpp, Taylor series near κ = 0 as in the paper's Listing 6) and
// a per-shading-point evaluation Ê = 2π lerp(Ē(−1), Ē(1), f(c, t)).
template <class T>
struct Tokuyoshi2024Light {
  T t;      // steepness t(κ)
  T lower;  // Ē(−1, κ)
  T upper;  // Ē(1, κ)
};

template <class T, class P = Steepness2024Params<double>>
SGLAB_FORCE_INLINE Tokuyoshi2024Light<T> tokuyoshi2024_light(
    const T& kappa, const P& p = constants::steepness2024_published) {
  const PoleIrradiances<T> poles = irradiance_poles_over_two_pi(kappa);
  return {steepness(kappa, p), poles.lower, poles.upper};
}

// The same setup in float without branches (both sides of κ < 1 computed and
// selected; branch_free.hpp elementary functions), for the batch kernel, with
// t(κ) of any rational order M (steepness_rational, hemispherical.hpp).
template <class S, std::size_t M>
SGLAB_FORCE_INLINE Tokuyoshi2024Light<float> tokuyoshi2024_light_branch_free(
    float kappa, const SteepnessRationalParams<S, M>& p) {
  namespace bf = branch_free;
  const bool small = kappa < 1.0f;
  const float r = 1.0f / bf::max(kappa, 1.0f);
  // t² = κ² · 0.5 P(κ)/Q(κ) as steepness_rational: monic Horner in κ below 1, in powers of 1/κ
  // (P/κ^M, Q/κ^{M+1}) from 1 on. For M = 2 (the 2024 form, p = {B, A}, q = {E, D, C}):
  // κ²·0.5((κ + A)κ + B) over ((κ + C)κ + D)κ + E, and κ·0.5(1 + (A + B/κ)/κ) over 1 + (C + (D +
  // E/κ)/κ)/κ.
  float ps = 1.0f, qs = 1.0f, pl = 0.0f, ql = 0.0f;
  if constexpr (M > 0)
    for (std::size_t i = M; i-- > 0;) ps = ps * kappa + float(p.p[i]);
  for (std::size_t i = M + 1; i-- > 0;) qs = qs * kappa + float(p.q[i]);
  if constexpr (M > 0)
    for (std::size_t i = 0; i < M; ++i) pl = (pl + float(p.p[i])) * r;
  for (std::size_t i = 0; i <= M; ++i) ql = (ql + float(p.q[i])) * r;
  const float num = bf::select(small, kappa * kappa * (0.5f * ps), kappa * (0.5f * (1.0f + pl)));
  const float den = bf::select(small, qs, 1.0f + ql);
  const float t = bf::sqrt_bf(num / den);
  // Poles as irradiance_poles_over_two_pi, with q = (1 − e^{−κ})/κ for κ ≥ 1.
  const float e = bf::exp_bf(-kappa);
  const float q = (1.0f - e) * r;
  const float upper = bf::select(small, detail::upper_pole_series(kappa), (1.0f - q) * r);
  const float lower = e * bf::select(small, detail::lower_pole_series(kappa), (q - e) * r);
  return {t, lower, upper};
}

template <class S>
SGLAB_FORCE_INLINE Tokuyoshi2024Light<float> tokuyoshi2024_light_branch_free(
    float kappa, const Steepness2024Params<S>& p) {
  return tokuyoshi2024_light_branch_free(kappa, steepness_rational_of(p));
}

template <class T, class Ops = detail::LibmOps>
SGLAB_FORCE_INLINE T tokuyoshi2024_eval(const Tokuyoshi2024Light<T>& light, const T& cosine,
                                        Ops ops = {}) {
  const T f = lerp_factor_tokuyoshi2024_at_steepness(cosine, light.t, ops);
  return two_pi_v<T>() * lerp(light.lower, light.upper, f);
}

// `tokuyoshi2024`: Ê = 2π lerp(Ē(−1), Ē(1), f) (Tokuyoshi et al. 2024,
// supplementary Listings 6-7). `p` may be any steepness form (Steepness2024Params by default).
template <class T, class P = Steepness2024Params<double>>
T irradiance_tokuyoshi2024(const T& cosine, const T& kappa,
                           const P& p = constants::steepness2024_published) {
  return tokuyoshi2024_eval(tokuyoshi2024_light(kappa, p), cosine);
}

// Float batch of `tokuyoshi2024` that vectorizes: the same setup and
// evaluation with branch_free.hpp's exp, expm1, erfc and sqrt. Its distance
// from the double path stays below 1e−6 of the peak E(1, κ) (an erfc error e
// moves f by at most e; measured 3.3e−7 over 2^20 random inputs, as the scalar
// float path), tests/test_branch_free.cpp.
template <class S = double>
SGLAB_FLATTEN void irradiance_tokuyoshi2024_batch(
    const float* __restrict cosine, const float* __restrict kappa, float* __restrict out,
    std::size_t n, const Steepness2024Params<S>& p = constants::steepness2024_published) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = tokuyoshi2024_eval(tokuyoshi2024_light_branch_free(kappa[i], p), cosine[i],
                                detail::BranchFreeOps{});
}

}  // namespace sglab
