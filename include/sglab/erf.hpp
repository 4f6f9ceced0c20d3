// sglab/erf.hpp — error function variants (docs/references.md).
//
// Each variant is a function template over the scalar type and its
// coefficients, plus a small functor type so that methods can be
// instantiated with any variant: `Erf` in hemispherical.hpp and
// irradiance.hpp defaults to ErfStd.
#pragma once

#include <cmath>
#include <cstddef>

#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"

namespace sglab {

// [Tokuyoshi2022] Listing 5 (after an NVIDIA forum erff, [NVForumErff]): odd polynomial x·P(x²)
// on |x| ≤ split, 1 − 2^{−a·Q(a)} on split < a < cutoff, ±1 beyond.
// Published error: not stated; measured by `sglab erf`.
template <class T, class S, std::size_t NS, std::size_t NL>
T erf_listing5(const T& x, const Listing5Params<S, NS, NL>& p) {
  using std::abs;
  using std::exp2;
  const T a = abs(x);
  if (a >= T(p.cutoff)) return x < T(0) ? T(-1) : T(1);
  if (a > T(p.split)) {
    const T y = T(1) - exp2(-a * horner(a, p.large));
    return x < T(0) ? -y : y;
  }
  return x * horner(x * x, p.small);  // NaN propagates here, as in Listing 5
}

// [AS1964] 7.1.25 (3 terms, claimed |error| ≤ 2.5e−5; quoted in [Xu2011] supplemental §3)
// and 7.1.26 (5 terms): 1 − t(a1 + a2 t + …)e^{−x²}, t = 1/(1 + p|x|), odd.
template <class T, class S, std::size_t N>
T erf_abramowitz_stegun(const T& x, const AbramowitzStegunParams<S, N>& p) {
  using std::abs;
  using std::exp;
  const T a = abs(x);
  const T t = T(1) / (T(1) + T(p.p) * a);
  const T y = T(1) - t * horner(t, p.a) * exp(-a * a);
  return x < T(0) ? -y : y;
}

// The published coefficient sets.
template <class T>
T erf_listing5(const T& x) {
  return erf_listing5(x, constants::erf_listing5_published);
}
template <class T>
T erf_abramowitz_stegun(const T& x) {
  return erf_abramowitz_stegun(x, constants::erf_as7125_published);
}

// Functors used as the `Erf` policy of the methods.
struct ErfStd {
  static constexpr const char* id = "std";
  template <class T>
  T operator()(const T& x) const {
    using std::erf;
    return erf(x);
  }
};
struct ErfListing5 {
  static constexpr const char* id = "listing5";
  template <class T>
  T operator()(const T& x) const {
    return erf_listing5(x);
  }
};
struct ErfAS7125 {
  static constexpr const char* id = "as7125";
  template <class T>
  T operator()(const T& x) const {
    return erf_abramowitz_stegun(x);
  }
};

}  // namespace sglab
