// sglab/math.hpp — small numerical helpers shared by every runtime header.
//
// Everything here is a template over the scalar type so that the float path
// really runs in float, the double path in double, and Ceres can
// differentiate the same code with Jets (unqualified math calls resolve to
// ceres::exp & co. through argument-dependent lookup).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

// Batch kernels must inline their whole body into the loop to vectorize.
// SGLAB_FLATTEN on a batch kernel inlines everything it calls, however large
// the translation unit that instantiates it: without it GCC's unit-growth
// limits can leave a call in the loop in a big TU, the loop stays scalar, and
// the linker may keep that copy of the (weak) template instance.
// SGLAB_FORCE_INLINE on the per-light setups and evaluations, and on the
// steepness forms and poles they call, makes a method's scalar call one
// function with its coefficients folded into it; left to g++'s inlining
// budget, which differs per binary, the callgrind counts of
// data/results/callgrind.csv moved with unrelated code (sglab_acc2's scalar
// call by 57 instructions when sglab_acc4 was added to the registry).
#if defined(__GNUC__) || defined(__clang__)
#define SGLAB_FORCE_INLINE inline __attribute__((always_inline))
#define SGLAB_FLATTEN __attribute__((flatten))
#else
#define SGLAB_FORCE_INLINE inline
#define SGLAB_FLATTEN
#endif

namespace sglab {

namespace detail {
// A long double constant in T: rounded once for float and double, exact for
// long double and wider types. A Ceres Jet (value member `a`, derivative `v`)
// is built from its value type, so the rounding is said, not implied.
template <class T>
constexpr T constant(long double x) {
  if constexpr (requires(T t) {
                  t.a;
                  t.v;
                })
    return T(static_cast<decltype(T{}.a)>(x));
  else
    return static_cast<T>(x);
}
}  // namespace detail

// Constants as functions so that they also instantiate for Ceres Jets (not literal types).
template <class T>
constexpr T pi_v() {
  return detail::constant<T>(3.141592653589793238462643383279502884L);
}
// 2π and 4π as exact multiples of π in T (scaling by a power of two commutes
// with rounding).
template <class T>
constexpr T two_pi_v() {
  return T(2) * pi_v<T>();
}
template <class T>
constexpr T four_pi_v() {
  return T(4) * pi_v<T>();
}
template <class T>
constexpr T inv_sqrt_pi_v() {
  return detail::constant<T>(0.5641895835477562869480794515607725858L);
}

// Horner evaluation c[0] + x(c[1] + x(c[2] + ...)), coefficients lowest
// order first.
template <class T, class C, std::size_t N>
constexpr T horner(const T& x, const C (&c)[N]) {
  T y = T(c[N - 1]);
  for (std::size_t i = N - 1; i-- > 0;) y = y * x + T(c[i]);
  return y;
}

// Variadic Horner: horner(x, c0, c1, c2) = c0 + x(c1 + x c2)  (pbrt-v4 style).
template <class T, class C>
constexpr T horner(const T&, C c0) {
  return T(c0);
}
template <class T, class C, class... Cs>
constexpr T horner(const T& x, C c0, Cs... cs) {
  return horner(x, cs...) * x + T(c0);
}

template <class T>
constexpr T lerp(const T& a, const T& b, const T& t) {
  return a + t * (b - a);
}

template <class T>
constexpr T clamp(const T& x, const T& lo, const T& hi) {
  return x < lo ? lo : (hi < x ? hi : x);
}

template <class T>
constexpr T saturate(const T& x) {
  return clamp(x, T(0), T(1));
}

template <class T>
constexpr T max0(const T& x) {
  return x < T(0) ? T(0) : x;
}

// (e^x − 1)/x without cancellation ([Tokuyoshi2022] Listing 4 cites [Higham2002] for
// the same purpose). With a correctly rounded-ish expm1 from the standard
// library the quotient is accurate to a few ulp for every x; the x = 0 limit
// is 1. x = −inf gives 0, x = +inf gives +inf.
template <class T>
T expm1_over_x(const T& x) {
  using std::expm1;
  if (x == T(0)) return T(1);
  return expm1(x) / x;
}

}  // namespace sglab
