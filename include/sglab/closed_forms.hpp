// sglab/closed_forms.hpp — exact closed forms of SPEC §1.
//
// H(c, κ) = ∫_{ω·n>0} G dω and E(c, κ) = ∫ G max(ω·n, 0) dω for a unit
// amplitude SG at the poles c = ±1 (and H at c = 0), and the sphere integral.
// Accurate to a few ulp for κ from 0 through the largest finite value:
// cancellation is removed with (e^x − 1)/x and Taylor series near κ = 0, and
// nothing is formed that could overflow (no κ²).
#pragma once

#include <cmath>
#include <cstddef>

#include "math.hpp"
#include "sg.hpp"

namespace sglab {

namespace detail {

// Coefficients of the Taylor series at κ = 0 used below, as exact rationals
// evaluated at compile time.
//   (κ − 1 + e^{−κ})/κ²        = Σ_{m≥0} (−κ)^m / (m + 2)!
//   (1 − e^{−κ}(1 + κ))/κ²     = Σ_{m≥0} (−κ)^m (m + 1) / (m + 2)!
// With 18 terms the first omitted term is below 3e−17 of either sum for κ ≤ 1.
inline constexpr std::size_t kSeriesTerms = 18;

constexpr long double factorial(std::size_t n) {
  long double f = 1;
  for (std::size_t i = 2; i <= n; ++i) f *= static_cast<long double>(i);
  return f;
}

template <bool kLower> struct PoleSeries {
  long double c[kSeriesTerms];
  constexpr PoleSeries() : c{} {
    for (std::size_t m = 0; m < kSeriesTerms; ++m) {
      const long double sign = (m % 2 == 0) ? 1.0L : -1.0L;
      const long double num = kLower ? static_cast<long double>(m + 1) : 1.0L;
      c[m] = sign * num / factorial(m + 2);
    }
  }
};
inline constexpr PoleSeries<false> kUpperSeries{};
inline constexpr PoleSeries<true> kLowerSeries{};

}  // namespace detail

// Ē(1, κ) = E(1, κ)/2π = (κ − 1 + e^{−κ})/κ² (upper pole; → 1/2 as κ → 0).
template <class T> T irradiance_upper_over_two_pi(const T& kappa) {
  if (kappa < T(1)) {
    // Series in κ; only the first terms matter for float.
    T y = T(detail::kUpperSeries.c[detail::kSeriesTerms - 1]);
    for (std::size_t i = detail::kSeriesTerms - 1; i-- > 0;)
      y = y * kappa + T(detail::kUpperSeries.c[i]);
    return y;
  }
  // (1 − (1 − e^{−κ})/κ)/κ: no κ², so no overflow at κ = FLT_MAX.
  return (T(1) - expm1_over_x(-kappa)) / kappa;
}

// Ē(−1, κ) = E(−1, κ)/2π = e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ² (lower pole; → 1/2 as κ → 0,
// like Ē(1, κ): at κ = 0 the SG is constant and E = π at every cosine).
template <class T> T irradiance_lower_over_two_pi(const T& kappa) {
  using std::exp;
  const T e = exp(-kappa);
  if (kappa < T(1)) {
    T y = T(detail::kLowerSeries.c[detail::kSeriesTerms - 1]);
    for (std::size_t i = detail::kSeriesTerms - 1; i-- > 0;)
      y = y * kappa + T(detail::kLowerSeries.c[i]);
    return e * y;
  }
  // ((1 − e^{−κ})/κ − e^{−κ})/κ: the difference loses at most a factor ~2 at κ = 1.
  return e * ((expm1_over_x(-kappa) - e) / kappa);
}

// E(1, κ) = 2π(κ − 1 + e^{−κ})/κ². From κ = 1 on, 2π(1 − (1 − e^{−κ})/κ) is
// divided by κ once, so E stays accurate where Ē(1, κ) ≈ 1/κ would be a
// denormal (κ > 1/min_normal) but 2π/κ is not.
template <class T> T irradiance_upper(const T& kappa) {
  if (kappa < T(1)) return two_pi_v<T>() * irradiance_upper_over_two_pi(kappa);
  return two_pi_v<T>() * (T(1) - expm1_over_x(-kappa)) / kappa;
}

// E(−1, κ) = 2π e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ² (SPEC §1).
template <class T> T irradiance_lower(const T& kappa) {
  return two_pi_v<T>() * irradiance_lower_over_two_pi(kappa);
}

// H(1, κ) = 2π(1 − e^{−κ})/κ ([Tokuyoshi2022] "A(κ)"). From κ = 1 on,
// 2π(1 − e^{−κ}) is divided by κ once: 1/κ is a denormal for κ > 1/min_normal,
// 2π/κ is not.
template <class T> T hemispherical_upper(const T& kappa) {
  using std::expm1;
  if (kappa < T(1)) return two_pi_v<T>() * expm1_over_x(-kappa);
  return two_pi_v<T>() * -expm1(-kappa) / kappa;
}

// H(−1, κ) = e^{−κ} H(1, κ) (SPEC §1; seed 000 §2.2 "B(κ)").
template <class T> T hemispherical_lower(const T& kappa) {
  using std::exp;
  return exp(-kappa) * hemispherical_upper(kappa);
}

// H(0, κ) = S(κ)/2, accurate through the largest finite κ (see sphere_integral).
template <class T> T hemispherical_equator(const T& kappa) {
  return T(0.5) * sphere_integral(kappa);
}

}  // namespace sglab
