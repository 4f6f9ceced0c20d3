// fit/half.hpp — IEEE binary16 arithmetic for evaluating the runtime
// templates "in half precision" (the clamped-cosine fit's `--precision half`).
//
// Storage and every arithmetic result are _Float16 (GCC rounds each
// operation to binary16); transcendental functions are evaluated in float and
// rounded once, as a GPU's half-precision path does. Found by ADL, so the
// runtime's `using std::exp; exp(x)` resolves here for T = Half.
#pragma once

#include <cmath>

namespace sglab::fit {

struct Half {
  _Float16 v;
  constexpr Half() : v(0) {}
  constexpr Half(double x) : v(static_cast<_Float16>(static_cast<float>(x))) {}
  constexpr Half(float x) : v(static_cast<_Float16>(x)) {}
  constexpr Half(int x) : v(static_cast<_Float16>(x)) {}
  constexpr Half(long double x) : v(static_cast<_Float16>(static_cast<float>(x))) {}
  constexpr explicit operator double() const { return static_cast<double>(v); }
  constexpr explicit operator float() const { return static_cast<float>(v); }
  static constexpr Half raw(_Float16 x) {
    Half h;
    h.v = x;
    return h;
  }
};

constexpr Half operator+(Half a, Half b) { return Half::raw(static_cast<_Float16>(a.v + b.v)); }
constexpr Half operator-(Half a, Half b) { return Half::raw(static_cast<_Float16>(a.v - b.v)); }
constexpr Half operator*(Half a, Half b) { return Half::raw(static_cast<_Float16>(a.v * b.v)); }
constexpr Half operator/(Half a, Half b) { return Half::raw(static_cast<_Float16>(a.v / b.v)); }
constexpr Half operator-(Half a) { return Half::raw(-a.v); }
constexpr Half& operator+=(Half& a, Half b) { return a = a + b; }
constexpr Half& operator-=(Half& a, Half b) { return a = a - b; }
constexpr Half& operator*=(Half& a, Half b) { return a = a * b; }
constexpr Half& operator/=(Half& a, Half b) { return a = a / b; }
constexpr bool operator<(Half a, Half b) { return a.v < b.v; }
constexpr bool operator>(Half a, Half b) { return a.v > b.v; }
constexpr bool operator<=(Half a, Half b) { return a.v <= b.v; }
constexpr bool operator>=(Half a, Half b) { return a.v >= b.v; }
constexpr bool operator==(Half a, Half b) { return a.v == b.v; }
constexpr bool operator!=(Half a, Half b) { return a.v != b.v; }

#define SGLAB_HALF_UNARY(name) \
  inline Half name(Half x) { return Half(std::name(static_cast<float>(x))); }
SGLAB_HALF_UNARY(exp)
SGLAB_HALF_UNARY(exp2)
SGLAB_HALF_UNARY(expm1)
SGLAB_HALF_UNARY(log)
SGLAB_HALF_UNARY(sqrt)
SGLAB_HALF_UNARY(erf)
SGLAB_HALF_UNARY(erfc)
SGLAB_HALF_UNARY(abs)
#undef SGLAB_HALF_UNARY

inline bool isfinite(Half x) { return std::isfinite(static_cast<float>(x)); }

}  // namespace sglab::fit
