// reference/error_measures.hpp — the error of a value against the truth at one
// point: the metrics of docs/quantities.md, in one place, shared by the fitters
// (fit/) and the validators (validate/).
//
// For a method value x̂ and a reference x at (κ, c), with the lobe's peak
// value x(1, κ):
//   peak_rel = |x̂ − x| / |x(1, κ)|           the headline metric
//   rel      = |x̂/x − 1|, only where |x| ≥ 1e−2·|x(1, κ)| ("significant")
//   abs      = |x̂ − x|
//   ulp      = |x̂ − x| / ulp(x), ulp taken in the evaluated precision
//
// Defined behaviour for special values (SciPy xsref style), for the scalar
// functions:
//   - any NaN argument                         → NaN
//   - x̂ == x (including equal infinities)      → 0
//   - otherwise IEEE arithmetic, so a finite x̂ against an infinite x (or the
//     reverse) is +inf, and a non-zero difference over a zero peak is +inf
//   - x = 0: rel is 0 when x̂ = 0 and +inf otherwise; ulp(0) is the smallest
//     denormal of the evaluated precision.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

namespace sglab::reference {

// "Significant" threshold of `rel` relative to the peak value (docs/quantities.md).
inline constexpr double kSignificantFraction = 1e-2;

// |x̂ − x| with the special-value rules above.
double abs_error(double value, double reference);

// |x̂ − x| / |peak|.
double peak_rel_error(double value, double reference, double peak);

// |x̂/x − 1| (no significance test; see `significant`).
double rel_error(double value, double reference);

// |x| ≥ 1e−2·|peak| (false when either is NaN).
bool significant(double reference, double peak);

// ulp(x) in precision T: the spacing of T-values at |x| rounded to T (the
// smallest denormal for x = 0 and for values below the normal range; NaN for
// non-finite x; for values that round to infinity, the spacing just below
// the largest finite value).
template <class T>
double ulp_of(double reference) {
  if (!std::isfinite(reference)) return std::numeric_limits<double>::quiet_NaN();
  const T a = static_cast<T>(std::abs(reference));
  if (!std::isfinite(a)) {
    const T m = std::numeric_limits<T>::max();
    return static_cast<double>(m) - static_cast<double>(std::nextafter(m, T(0)));
  }
  // Spacing above a (for a power of two this is the larger spacing, the usual
  // "ulp(x) = 2^(e − p + 1)" convention).
  const T next = std::nextafter(a, std::numeric_limits<T>::infinity());
  if (!std::isfinite(next))
    return static_cast<double>(a) - static_cast<double>(std::nextafter(a, T(0)));
  return static_cast<double>(next) - static_cast<double>(a);
}

// |x̂ − x| / ulp(x) in precision T.
template <class T>
double ulp_error(double value, double reference) {
  const double e = abs_error(value, reference);
  if (e == 0 || std::isnan(e)) return e;
  const double u = ulp_of<T>(reference);
  if (std::isnan(u))
    return std::numeric_limits<double>::infinity();  // finite vs infinite reference
  return e / u;
}

// ---------------------------------------------------------------------------
// ulp of an exact value (the erf checker's metric)
// ---------------------------------------------------------------------------
// Unlike ulp_of<T> (the spacing at x rounded to T), these take the binade of
// the exact value itself, so a correctly rounded result is within 0.5 of
// them and a faithful one below 1 even just under a power of two:
//
//   ulp_float(y)  = 2^(floor(log2|y|) − 23) for |y| ≥ 2^−126 (FLT_MIN),
//                   2^−149 (the float denorm_min) below, ±0 included;
//   ulp_double(y) = 2^(floor(log2|y|) − 52) for |y| ≥ 2^−1022 (DBL_MIN),
//                   2^−1074 (the double denorm_min) below.
// Both are defined beyond the format's range by the same formula
// (ulp_float(2^200) = 2^177); ±inf → +inf, NaN → NaN.
//
//   exact_ulp_error_{float,double}(f, y) = |f − y| / ulp(y), y exact (not its
//   rounding): any NaN → NaN; f == y (equal infinities too) → 0; otherwise
//   an infinite f or y → +inf.

// Spacing of binary32 numbers in the binade of |y|.
inline double ulp_float(double y) {
  const double a = std::abs(y);
  if (!(a >= 0x1p-126)) return std::isnan(y) ? y : 0x1p-149;
  if (std::isinf(a)) return a;
  // floor(log2 a) from the biased exponent field of the double (bits 52…62, bias 1023).
  const auto e = static_cast<int>((std::bit_cast<std::uint64_t>(a) >> 52) & 0x7ff) - 1023;
  return std::ldexp(1.0, e - 23);
}

// Spacing of binary64 numbers in the binade of |y|.
inline long double ulp_double(long double y) {
  const long double a = std::abs(y);
  if (std::isnan(a) || std::isinf(a)) return a;
  if (!(a >= 0x1p-1022L)) return 0x1p-1074L;
  int e = 0;
  (void)std::frexp(a, &e);  // a = m·2^e, m ∈ [0.5, 1)
  return std::ldexp(1.0L, e - 1 - 52);
}

// |value − exact| / ulp_float(exact), with the special-value rules above.
inline double exact_ulp_error_float(double value, double exact) {
  if (std::isnan(value) || std::isnan(exact)) return std::numeric_limits<double>::quiet_NaN();
  if (value == exact) return 0;
  if (std::isinf(value) || std::isinf(exact)) return std::numeric_limits<double>::infinity();
  return std::abs(value - exact) / ulp_float(exact);
}

// |value − exact| / ulp_double(exact), the difference taken in long double.
inline double exact_ulp_error_double(double value, long double exact) {
  if (std::isnan(value) || std::isnan(exact)) return std::numeric_limits<double>::quiet_NaN();
  if (static_cast<long double>(value) == exact) return 0;
  if (std::isinf(value) || std::isinf(exact)) return std::numeric_limits<double>::infinity();
  return static_cast<double>(std::abs(static_cast<long double>(value) - exact) / ulp_double(exact));
}

// Worst peak_rel over a set of points, as a fit reports it: 0 for no points,
// +inf as soon as one point's error is not finite (a NaN or infinite output:
// a method that fails anywhere on the grid has no finite worst case), else
// the max of peak_rel_error. The three spans have one entry per point.
double max_peak_rel_error(std::span<const double> values, std::span<const double> references,
                          std::span<const double> peaks);

}  // namespace sglab::reference
