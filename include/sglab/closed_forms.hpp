// sglab/closed_forms.hpp — exact closed forms of docs/quantities.md.
//
// H(c, κ) = ∫_{ω·n>0} G dω and E(c, κ) = ∫ G max(ω·n, 0) dω for a unit
// amplitude SG at the poles c = ±1 (and H at c = 0), and the sphere integral.
// Accurate to a few ulp for κ from 0 through the largest finite value:
// cancellation is removed with (e^x − 1)/x and Taylor series near κ = 0, and
// nothing is formed that could overflow (no κ²).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>

#include "math.hpp"
#include "sg.hpp"

namespace sglab {

namespace detail {

// Coefficients of the Taylor series at κ = 0 used below, as exact rationals
// rounded to double at compile time:
//   (κ − 1 + e^{−κ})/κ²        = Σ_{m≥0} (−κ)^m / (m + 2)!
//   (1 − e^{−κ}(1 + κ))/κ²     = Σ_{m≥0} (−κ)^m (m + 1) / (m + 2)!
// For κ < 1 the first omitted term is below 3e−17 of either sum with 18 terms
// (double and wider) and below 3e−9 with 11 terms (float).
inline constexpr std::size_t kSeriesTerms = 18;
template <class T>
inline constexpr std::size_t kPoleSeriesTerms = sizeof(T) <= sizeof(float) ? 11 : kSeriesTerms;

template <bool kLower>
constexpr double pole_series_coefficient(std::size_t m) {
  long double f = 1;  // (m + 2)!
  for (std::size_t i = 2; i <= m + 2; ++i) f *= static_cast<long double>(i);
  const long double sign = (m % 2 == 0) ? 1.0L : -1.0L;
  const long double num = kLower ? static_cast<long double>(m + 1) : 1.0L;
  return static_cast<double>(sign * num / f);
}

// Horner's rule unrolled at compile time, each coefficient a constant T(c):
// no loop, no long double, and nothing that stops vectorization.
template <bool kLower, class T, std::size_t... I>
T pole_series(const T& kappa, std::index_sequence<I...>) {
  constexpr std::size_t N = sizeof...(I) + 1;
  T y = T(pole_series_coefficient<kLower>(N - 1));
  ((y = y * kappa + T(pole_series_coefficient<kLower>(N - 2 - I))), ...);
  return y;
}

// Σ (−κ)^m/(m + 2)! and Σ (−κ)^m (m + 1)/(m + 2)! (see above), for κ < 1.
template <class T>
T upper_pole_series(const T& kappa) {
  return pole_series<false>(kappa, std::make_index_sequence<kPoleSeriesTerms<T> - 1>{});
}
template <class T>
T lower_pole_series(const T& kappa) {
  return pole_series<true>(kappa, std::make_index_sequence<kPoleSeriesTerms<T> - 1>{});
}

}  // namespace detail

// Both poles at once, Ē(±1, κ) = E(±1, κ)/2π: one exp and one expm1 per κ.
template <class T>
struct PoleIrradiances {
  T lower;  // Ē(−1, κ)
  T upper;  // Ē(1, κ)
};

// Ē(1, κ) = (κ − 1 + e^{−κ})/κ², Ē(−1, κ) = e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ².
// κ < 1: the Taylor series above (exact limits 1/2 and 1/2 at κ = 0).
// κ ≥ 1: with q = (1 − e^{−κ})/κ, Ē(1) = (1 − q)/κ and Ē(−1) = e^{−κ}(q − e^{−κ})/κ:
// no κ², so no overflow at κ = FLT_MAX; the difference q − e^{−κ} loses at
// most a factor ~2 at κ = 1.
template <class T>
SGLAB_FORCE_INLINE PoleIrradiances<T> irradiance_poles_over_two_pi(const T& kappa) {
  using std::exp;
  const T e = exp(-kappa);
  if (kappa < T(1)) return {e * detail::lower_pole_series(kappa), detail::upper_pole_series(kappa)};
  const T q = expm1_over_x(-kappa);
  return {e * ((q - e) / kappa), (T(1) - q) / kappa};
}

// Ē(1, κ) = E(1, κ)/2π = (κ − 1 + e^{−κ})/κ² (upper pole; → 1/2 as κ → 0).
template <class T>
T irradiance_upper_over_two_pi(const T& kappa) {
  if (kappa < T(1)) return detail::upper_pole_series(kappa);
  // (1 − (1 − e^{−κ})/κ)/κ: no κ², so no overflow at κ = FLT_MAX.
  return (T(1) - expm1_over_x(-kappa)) / kappa;
}

// Ē(−1, κ) = E(−1, κ)/2π = e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ² (lower pole; → 1/2 as κ → 0,
// like Ē(1, κ): at κ = 0 the SG is constant and E = π at every cosine).
template <class T>
T irradiance_lower_over_two_pi(const T& kappa) {
  return irradiance_poles_over_two_pi(kappa).lower;
}

// E(1, κ) = 2π(κ − 1 + e^{−κ})/κ². From κ = 1 on, 2π(1 − (1 − e^{−κ})/κ) is
// divided by κ once, so E stays accurate where Ē(1, κ) ≈ 1/κ would be a
// denormal (κ > 1/min_normal) but 2π/κ is not.
template <class T>
T irradiance_upper(const T& kappa) {
  if (kappa < T(1)) return two_pi_v<T>() * irradiance_upper_over_two_pi(kappa);
  return two_pi_v<T>() * (T(1) - expm1_over_x(-kappa)) / kappa;
}

// E(−1, κ) = 2π e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ² (docs/quantities.md).
template <class T>
T irradiance_lower(const T& kappa) {
  return two_pi_v<T>() * irradiance_lower_over_two_pi(kappa);
}

// H(1, κ) = 2π(1 − e^{−κ})/κ ([Tokuyoshi2022] "A(κ)"). From κ = 1 on,
// 2π(1 − e^{−κ}) is divided by κ once: 1/κ is a denormal for κ > 1/min_normal,
// 2π/κ is not.
template <class T>
T hemispherical_upper(const T& kappa) {
  using std::expm1;
  if (kappa < T(1)) return two_pi_v<T>() * expm1_over_x(-kappa);
  return two_pi_v<T>() * -expm1(-kappa) / kappa;
}

// H(−1, κ) = e^{−κ} H(1, κ) (docs/quantities.md; [Tokuyoshi2022] supplementary §2.2 "B(κ)").
template <class T>
T hemispherical_lower(const T& kappa) {
  using std::exp;
  return exp(-kappa) * hemispherical_upper(kappa);
}

// H(0, κ) = S(κ)/2, accurate through the largest finite κ (see sphere_integral).
template <class T>
T hemispherical_equator(const T& kappa) {
  return T(0.5) * sphere_integral(kappa);
}

}  // namespace sglab
