// sglab/sg.hpp — spherical Gaussian primitives.
//
// G(ω; v, κ) = exp(κ(ω·v − 1)), κ ≥ 0, |v| = 1 (unit amplitude; docs/quantities.md).
// Every function here is sglab's own and is finite and non-negative for all
// finite κ ≥ 0 and cosines in [−1, 1].
#pragma once

#include <cmath>

#include "math.hpp"

namespace sglab {

template <class T>
struct Vec3 {
  T x, y, z;
};
template <class T>
constexpr Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
constexpr Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
constexpr Vec3<T> operator*(const T& s, const Vec3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
T length(const Vec3<T>& a) {
  using std::sqrt;
  return sqrt(dot(a, a));
}

// G at cosine c between ω and the axis.
template <class T>
T sg_evaluate(const T& cosine, const T& kappa) {
  using std::exp;
  return exp(kappa * (cosine - T(1)));
}

// G at direction ω for axis v: ω·v − 1 = −|ω − v|²/2 for unit vectors, which
// keeps the exponent exact near the peak (Tokuyoshi 2025, vMF on S²).
template <class T>
T sg_evaluate(const Vec3<T>& omega, const Vec3<T>& axis, const T& kappa) {
  using std::exp;
  const Vec3<T> d = omega - axis;
  return exp(T(-0.5) * kappa * dot(d, d));
}

namespace detail {
// S(m·x) = 2π(1 − e^{−2mx})/(mx) for a sharpness given as a scale m > 0 times
// a scaled value x ≥ 0, so that a product sharpness m·x that overflows still
// gives its (normal) S. Below mx = 1, 4π·(e^{−2κ} − 1)/(−2κ) keeps full
// accuracy down to the denormals. From mx = 1 on, 2π/m times 1 − e^{−2mx} is
// divided by x once: −2mx may overflow to −inf there, which only makes
// e^{−2mx} = 0, and 2π/m ≥ 2π/max is a normal number in float and double.
template <class T>
T sphere_integral_scaled(const T& m, const T& x) {
  using std::expm1;
  const T kappa = m * x;
  if (kappa < T(1)) return four_pi_v<T>() * expm1_over_x(T(-2) * kappa);
  return (two_pi_v<T>() / m) * -expm1(T(-2) * kappa) / x;
}
}  // namespace detail

// Exact sphere integral S(κ) = 2π(1 − e^{−2κ})/κ = 4π·(e^{−2κ} − 1)/(−2κ)
// ([Tokuyoshi2015]; → 4π as κ → 0, → 2π/κ as κ → ∞), accurate from κ = 0
// through the largest finite κ (where 2π/κ is still a normal number).
template <class T>
T sphere_integral(const T& kappa) {
  return detail::sphere_integral_scaled(T(1), kappa);
}

// The large-κ approximation 2π/κ of S(κ) ([Pettineo2016] "ApproximateSGIntegral").
// Infinite at κ = 0: callers that need κ → 0 use sphere_integral.
template <class T>
T sphere_integral_approx(const T& kappa) {
  return two_pi_v<T>() / kappa;
}

// Product of two SGs: G(ω; v1, κ1) G(ω; v2, κ2) = e^{logAmp} G(ω; v3, κ3)
// with κ3 = |κ1 v1 + κ2 v2| ([Tokuyoshi2022] Eq. 1).
template <class T>
struct SGLobe {
  Vec3<T> axis;
  T sharpness;
  T log_amplitude;
};

// The log-amplitude κ3 − κ1 − κ2 cancels catastrophically when κ1 or κ2 is
// large. Since κ3² = (κ1 + κ2)² − κ1κ2|v1 − v2|²,
//   κ3 − κ1 − κ2 = −κ1κ2|v1 − v2|² / (κ3 + κ1 + κ2),
// a sum of non-negative terms (equivalent to [Tokuyoshi2022] Eq. 2). The axis of a
// zero-sharpness product (opposite axes, equal κ) is taken as v1.
template <class T>
SGLobe<T> sg_product(const Vec3<T>& v1, const T& kappa1, const Vec3<T>& v2, const T& kappa2) {
  using std::sqrt;
  // Scale by the larger sharpness so that |κ1 v1 + κ2 v2| cannot overflow.
  const T m = kappa1 < kappa2 ? kappa2 : kappa1;
  if (!(m > T(0))) return {v1, T(0), T(0)};
  const T ks1 = kappa1 / m, ks2 = kappa2 / m;
  const Vec3<T> a = ks1 * v1 + ks2 * v2;
  const T a_len = length(a);
  // κ3/m from |κ1v1 + κ2v2|² = (κ1 − κ2)² + κ1κ2|v1 + v2|² (unit axes): a sum
  // of non-negative terms, with κ1 − κ2 exact where it cancels (opposite axes,
  // nearly equal κ, where |a| would keep only the rounding of κ1/m − κ2/m).
  const Vec3<T> e = v1 + v2;
  const T dk = (kappa1 - kappa2) / m;
  const T k3 = m * sqrt(dk * dk + ks1 * ks2 * dot(e, e));
  const Vec3<T> d = v1 - v2;
  // −κ1κ2|d|²/(κ3 + κ1 + κ2) = −min(κ1, κ2)|d|²/(κ3/m + κ1/m + κ2/m) with
  // m = max(κ1, κ2): the denominator lies in [1, 3], so nothing overflows and
  // the smaller sharpness is never scaled into the denormals.
  const T kmin = kappa1 < kappa2 ? kappa1 : kappa2;
  const T log_amp = -kmin * (dot(d, d) / (a_len + kappa1 / m + kappa2 / m));
  const Vec3<T> axis = a_len > T(0) ? (T(1) / a_len) * a : v1;
  return {axis, k3, log_amp};
}

// Scalar form of the product of a light SG (v, κ) with an SG (n, λ) about
// the normal, where c = v·n: the product sharpness, its log-amplitude and the
// cosine between the product axis and n. |v − n|² = 2(1 − c).
template <class T>
struct ProductWithNormal {
  T sharpness;
  T log_amplitude;
  T cosine;
};

namespace detail {
// The product with the normal as a scale m = max(κ, λ) and κ3/m, so that
// callers can use κ3 where m·(κ3/m) overflows (sg_inner_product).
template <class T>
struct ScaledProductWithNormal {
  T scale;             // m = max(κ, λ)
  T sharpness_scaled;  // κ3/m ∈ [0, 2]
  T log_amplitude;
  T cosine;
};
template <class T>
ScaledProductWithNormal<T> product_with_normal_scaled(const T& cosine_in, const T& kappa,
                                                      const T& lambda) {
  using std::sqrt;
  // A cosine a rounding error outside [−1, 1] (c = −1 − ulp from a dot
  // product) would make κ3² negative at κ = λ: clamp it (NaN stays NaN).
  const T cosine = clamp(cosine_in, T(-1), T(1));
  // κ3² = κ² + λ² + 2κλc = (κ − λ)² + 2κλ(1 + c): a sum of non-negative terms,
  // exact near c = −1, scaled by m = max(κ, λ) against overflow.
  const T m = kappa < lambda ? lambda : kappa;
  if (!(m > T(0))) return {T(0), T(0), T(0), T(1)};
  // (κ − λ)/m, not κ/m − λ/m: κ − λ is exact where it cancels (Sterbenz),
  // while κ/m − λ/m would keep only the rounding of the larger quotient.
  const T ks = kappa / m, ls = lambda / m, diff = (kappa - lambda) / m;
  const T k3s = sqrt(diff * diff + T(2) * ks * ls * (T(1) + cosine));  // κ3/m
  // κ3 − κ − λ = −2κλ(1 − c)/(κ3 + κ + λ) = −2 min(κ, λ)(1 − c)/(κ3/m + κ/m + λ/m)
  // (see sg_product): the denominator lies in [1, 3], nothing overflows or underflows.
  const T kmin = kappa < lambda ? kappa : lambda;
  const T log_amp = T(-2) * (kmin * ((T(1) - cosine) / (k3s + ks + ls)));
  // Product axis (κv + λn)/κ3, its cosine with n = (κc + λ)/κ3, clamped:
  // rounding may push it a hair outside [−1, 1].
  const T c3 = k3s > T(0) ? clamp((ks * cosine + ls) / k3s, T(-1), T(1)) : T(1);
  return {m, k3s, log_amp, c3};
}
}  // namespace detail

template <class T>
ProductWithNormal<T> sg_product_with_normal(const T& cosine, const T& kappa, const T& lambda) {
  const detail::ScaledProductWithNormal<T> p =
      detail::product_with_normal_scaled(cosine, kappa, lambda);
  return {p.scale * p.sharpness_scaled, p.log_amplitude, p.cosine};
}

// Exact inner product ∫ G(ω; v1, κ1) G(ω; v2, κ2) dω = e^{logAmp} S(κ3)
// ([Wang2009]), with c = v1·v2, evaluated through the stable product. κ3 may
// exceed the largest finite value (κ1, κ2 > max/2, c near 1) while the
// result, about 2π/κ3, is still a normal number: S is taken from the scaled
// sharpness.
template <class T>
T sg_inner_product(const T& cosine, const T& kappa1, const T& kappa2) {
  using std::exp;
  const detail::ScaledProductWithNormal<T> p =
      detail::product_with_normal_scaled(cosine, kappa1, kappa2);
  return exp(p.log_amplitude) * detail::sphere_integral_scaled(p.scale, p.sharpness_scaled);
}

// Iwasaki et al. 2012 approximate product integral ([Tokuyoshi2015] supplemental §3.2):
// ∫ G1 G2 dω ≈ 2π G(c; κ1κ2/(κ1 + κ2)) / (κ1 + κ2). Both κ = 0 gives 0/0;
// the approximation is meant for κ1 + κ2 ≫ 1 and returns +inf there.
// κ1κ2/(κ1 + κ2) is formed as b/(1 + b/a), a = max(κ1, κ2), b = min(κ1, κ2)
// (the same value): κ1κ2 overflows at the largest κ, and inf·(c − 1) was NaN at c = 1.
template <class T>
T sg_inner_product_iwasaki(const T& cosine, const T& kappa1, const T& kappa2) {
  const T sum = kappa1 + kappa2;
  const T a = kappa1 < kappa2 ? kappa2 : kappa1, b = kappa1 < kappa2 ? kappa1 : kappa2;
  const T lambda = sum > T(0) ? b / (T(1) + b / a) : T(0);
  return two_pi_v<T>() * sg_evaluate(cosine, lambda) / sum;
}

}  // namespace sglab
