// reference/erf_reference.hpp — the correctly rounded erf the checker
// (validate/erf_check.hpp) measures against.
//
// Float reference. erf(x) for x ∈ [0, 4) is a degree-6 Taylor expansion in
// double about the centre of each run of 1024 consecutive inputs (coefficients
// erf^(k)(x0)/k! from erfl/expl and Hermite polynomials; run half-width
// h ≤ 2^−9 and h ≤ x0/64, so the remainder is < 2^−66 relative), or std::erf
// in double where a run is too wide. Either is within a few double ulps of
// erf(x); when that value lies within 8 double ulps of a midpoint between two
// floats, the point is re-evaluated with Boost.Math erf in cpp_bin_float_50 to
// decide the correctly rounded float. Each Taylor run is also compared with
// std::erf at its end point (`reference_selfcheck_ulps` of the report). For
// x ≥ 4, erfc(x) ≤ erfc(4) ≈ 1.5e−8 < 2^−25, so the correctly rounded float is
// exactly 1 and erf(x) = 1 − erfc(x) with erfc in double (0 beyond x = 32,
// where erfc < 1e−446 underflows anyway).
//
// Double reference. cpp_bin_float_50 (Boost.Math erf/erfc), carried in long
// double: on the uniform grid by the Maclaurin series for x ≤ 1/2 and above by
// a degree-12 Taylor expansion about a 50-digit centre per run of points of
// half-width ≤ 2^−7 (relative error ~2^−63, checked against direct 50-digit
// evaluation at spot points), directly elsewhere.
#pragma once

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <sglab/math.hpp>

#include "reference/error_measures.hpp"

namespace sglab::reference {

// ---------------------------------------------------------------------------
// Single-point references
// ---------------------------------------------------------------------------

struct ErfFloatReference {
  double exact;   // erf(x) to within a few double ulps (50-digit value when resolved)
  float rounded;  // correctly rounded erf(x), signed zero kept
  bool resolved;  // decided with cpp_bin_float_50
};
// Correctly rounded float erf at any float (±0, ±inf, NaN included).
ErfFloatReference erf_reference_float(float x);

// erf(x) from Boost.Math in cpp_bin_float_50, rounded to long double.
long double erf_reference_50(double x);
// erfc(x) likewise.
long double erfc_reference_50(double x);

// ---------------------------------------------------------------------------
// Double sample: points with their 50-digit reference
// ---------------------------------------------------------------------------

struct ErfDoubleOptions {
  std::uint32_t grid_points = 1'000'000;  // x = i·x_max/grid_points, i < grid_points
  double x_max = 6.0;                     // erf(x) rounds to 1 in double from x ≈ 5.93
  std::uint32_t log_points = 4096;        // evenly spaced bit patterns in (0, x_max): every binade
  std::uint32_t tail_points = 4096;       // evenly spaced bit patterns in [x_max, DBL_MAX]
  std::uint32_t odd_points = 1u << 16;    // evenly spaced bit patterns in (0, DBL_MAX]
  std::size_t bins = 2000;                // series bins over [0, x_max)
};

// The sample with its 50-digit reference; variant-independent, so build it
// once and check every variant against it.
struct ErfDoubleSample {
  ErfDoubleOptions options;
  std::vector<double> x;         // [0, main_end): x < x_max; [main_end, size): tail
  std::vector<long double> ref;  // erf(x) for the main part, erfc(x) for the tail
  std::size_t main_end = 0;
  std::size_t grid_end = 0;   // [0, grid_end) is the uniform grid
  double selfcheck_ulps = 0;  // max |Taylor − direct 50-digit| in double ulps at spot points
  std::string reference;
};
ErfDoubleSample make_erf_double_sample(const ErfDoubleOptions& options = {});

namespace detail {

inline constexpr std::size_t kRun = 1024;  // points per Taylor run / work item

// Taylor expansion of erf about x0 for the inputs of one run [x_first, x_last].
struct ErfTaylorFloat {
  bool ok = false;  // false: the run is too wide, evaluate std::erf directly
  double x0 = 0;
  double c[7] = {};  // erf^(k)(x0)/k!, k = 0 … 6
  double operator()(double x) const {
    return horner(x - x0, c);  // x − x0 is exact for the float inputs of a run
  }
};
ErfTaylorFloat erf_taylor_float(double x_first, double x0, double x_last);

// Is y (≥ 0, within a few double ulps of erf(x)) within `ulps` double ulps of
// a midpoint between two consecutive floats? Then RN(y) may differ from RN(erf(x)).
inline bool near_float_midpoint(double y, int ulps = 8) {
  const double a = std::abs(y);
  if (a >= 0x1p-126) {  // float-normal range: the 29 bits below the float's last bit decide
    constexpr int kDroppedBits = 52 - 23;  // double significand bits a float does not keep
    const auto low = static_cast<std::int64_t>(std::bit_cast<std::uint64_t>(a) &
                                               ((std::uint64_t{1} << kDroppedBits) - 1));
    // distance from the midpoint pattern 100…0
    const std::int64_t d = low - (std::int64_t{1} << (kDroppedBits - 1));
    return d <= ulps && d >= -ulps;
  }
  const double q = a * 0x1p149;  // in units of the subnormal spacing; exact
  const double frac = q - std::floor(q);
  return std::abs(frac - 0.5) <= ulps * static_cast<double>(ulp_double(a)) * 0x1p149;
}

// Decide a midpoint case in 50 digits.
ErfFloatReference erf_resolve_float(float x);

// |y − erf(x)| with erf(x) in 50 digits, rounded to double.
double erf_abs_error_50(float x, float y);

// Correctly rounded double erf at a special input (±0 keeps its sign, ±inf → ±1, NaN → NaN).
long double erf_special_expected_double(double x);

}  // namespace detail

}  // namespace sglab::reference
