// reference/erf_reference.cpp — the correctly rounded erf references (see
// reference/erf_reference.hpp).
#include "reference/erf_reference.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <boost/math/special_functions/erf.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

namespace sglab::reference {

namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

const Big& two_over_sqrt_pi_50() {
  static const Big v = Big(2) / boost::multiprecision::sqrt(boost::math::constants::pi<Big>());
  return v;
}

// The T (float or double) nearest to v: the conversion through double, or
// one of its two neighbours when that is closer (ties keep the conversion).
template <class T>
T round_to_nearest(const Big& v) {
  const T r = static_cast<T>(static_cast<double>(v));
  T best = r;
  Big best_d = abs(Big(r) - v);
  for (T nb : {std::nextafter(r, -std::numeric_limits<T>::infinity()),
               std::nextafter(r, std::numeric_limits<T>::infinity())}) {
    const Big d = abs(Big(nb) - v);
    if (d < best_d) best = nb, best_d = d;
  }
  return best;
}

// Taylor coefficients erf^(k)(x0)/k!, k = 0 … N−1, in 50 digits:
// erf^(k)(x) = (2/√π)(−1)^(k−1) H_{k−1}(x) e^{−x²} (physicists' Hermite H).
template <std::size_t N>
std::array<Big, N> taylor_coefficients_50(const Big& x0) {
  std::array<Big, N> H;  // H_0 … H_{N−2}: H_{n+1} = 2x H_n − 2n H_{n−1}
  H[0] = 1;
  if (N > 2) H[1] = 2 * x0;
  for (std::size_t n = 1; n + 2 < N; ++n)
    H[n + 1] = 2 * x0 * H[n] - 2 * static_cast<unsigned>(n) * H[n - 1];
  std::array<Big, N> c;
  c[0] = boost::math::erf(x0);
  const Big g = two_over_sqrt_pi_50() * exp(-x0 * x0);
  Big factorial = 1;
  for (std::size_t k = 1; k < N; ++k) {
    factorial *= static_cast<unsigned>(k);
    const Big v = g * H[k - 1] / factorial;
    c[k] = (k - 1) % 2 ? Big(-v) : v;
  }
  return c;
}

// erf(x) = (2/√π) Σ (−1)^n x^(2n+1) / (n!(2n+1)), coefficients in long double.
constexpr std::size_t kMaclaurinTerms = 24;  // x ≤ 1/2: the 24th term is < 2^−150 relative
struct MaclaurinCoefficients {
  long double c[kMaclaurinTerms];
};
const MaclaurinCoefficients& maclaurin_coefficients() {
  static const MaclaurinCoefficients m = [] {
    MaclaurinCoefficients r{};
    Big factorial = 1;
    for (std::size_t n = 0; n < kMaclaurinTerms; ++n) {
      if (n) factorial *= static_cast<unsigned>(n);
      const Big v = two_over_sqrt_pi_50() / (factorial * (2 * n + 1));
      r.c[n] = static_cast<long double>(n % 2 ? Big(-v) : v);
    }
    return r;
  }();
  return m;
}
long double erf_maclaurin(long double x) { return x * horner(x * x, maclaurin_coefficients().c); }

Big erf_50(float x) { return boost::math::erf(Big(x)); }

}  // namespace

long double erf_reference_50(double x) {
  return static_cast<long double>(boost::math::erf(Big(x)));
}
long double erfc_reference_50(double x) {
  return static_cast<long double>(boost::math::erfc(Big(x)));
}

namespace detail {

ErfFloatReference erf_resolve_float(float x) {
  const Big v = erf_50(x);
  return {static_cast<double>(v), round_to_nearest<float>(v), true};
}

double erf_abs_error_50(float x, float y) { return static_cast<double>(abs(Big(y) - erf_50(x))); }

ErfTaylorFloat erf_taylor_float(double x_first, double x0, double x_last) {
  ErfTaylorFloat t;
  const double h = std::max(x0 - x_first, x_last - x0);
  // Remainder of the degree-6 expansion: |erf^(7)| ≤ (2/√π)·1.0865·2^3·√720 (Cramér's
  // bound on Hermite functions) = 263, so < 263/7!·h^7 ≤ 0.053·2^−63 for h ≤ 2^−9;
  // h ≤ x0/64 keeps every term small against erf(x0).
  if (!(h <= 0x1p-9 && h * 64 <= x0)) return t;
  t.ok = true;
  t.x0 = x0;
  const long double X = x0;
  // 2/√π · e^(−x0²)
  const long double g = 1.1283791670955125738961589031215452L * std::exp(-X * X);
  long double H[6];
  H[0] = 1;
  H[1] = 2 * X;
  for (int n = 1; n < 5; ++n) H[n + 1] = 2 * X * H[n] - 2 * n * H[n - 1];
  t.c[0] = static_cast<double>(std::erf(X));
  long double factorial = 1;
  for (int k = 1; k < 7; ++k) {
    factorial *= k;
    const long double v = g * H[k - 1] / factorial;
    t.c[k] = static_cast<double>((k - 1) % 2 ? -v : v);
  }
  return t;
}

long double erf_special_expected_double(double x) {
  if (std::isnan(x)) return x;
  if (std::isinf(x)) return x > 0 ? 1.0L : -1.0L;
  if (x == 0) return x;  // keeps the sign of zero
  // RN to double, decided in 50 digits
  const double best = round_to_nearest<double>(boost::math::erf(Big(std::abs(x))));
  return x < 0 ? -best : best;
}

}  // namespace detail

ErfFloatReference erf_reference_float(float x) {
  if (std::isnan(x)) return {x, x, false};
  if (std::isinf(x)) return {x > 0 ? 1.0 : -1.0, x > 0 ? 1.0f : -1.0f, false};
  if (x == 0) return {x, x, false};
  const float a = std::abs(x);
  ErfFloatReference r;
  if (a >= 4.0f) {
    r = {1.0 - std::erfc(static_cast<double>(a)), 1.0f, false};
  } else {
    const double y = std::erf(static_cast<double>(a));
    r = detail::near_float_midpoint(y) ? detail::erf_resolve_float(a)
                                       : ErfFloatReference{y, static_cast<float>(y), false};
  }
  if (x < 0) r.exact = -r.exact, r.rounded = -r.rounded;
  return r;
}

// --- double sample ---------------------------------------------------------

ErfDoubleSample make_erf_double_sample(const ErfDoubleOptions& options) {
  static_assert(std::numeric_limits<long double>::digits >= 64,
                "the double reference is carried in long double and needs >= 64 significand bits");
  if (!(options.x_max > 0 && options.x_max <= 6.0))
    throw std::invalid_argument("erf double sample: x_max must be in (0, 6]");
  ErfDoubleSample s;
  s.options = options;
  const std::size_t n_grid = options.grid_points;
  const std::uint64_t xmax_bits = std::bit_cast<std::uint64_t>(options.x_max);
  const std::uint64_t dmax_bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::max());

  for (std::size_t i = 0; i < n_grid; ++i)
    s.x.push_back(options.x_max * static_cast<double>(i) / static_cast<double>(n_grid));
  s.grid_end = s.x.size();
  for (std::uint32_t k = 0; k < options.log_points; ++k)
    s.x.push_back(std::bit_cast<double>(1 + (xmax_bits - 1) / options.log_points * k));
  s.main_end = s.x.size();
  for (std::uint32_t k = 0; k < options.tail_points; ++k) {
    const std::uint64_t step =
        options.tail_points > 1 ? (dmax_bits - xmax_bits) / (options.tail_points - 1) : 0;
    s.x.push_back(std::bit_cast<double>(xmax_bits + step * k));
  }
  s.ref.assign(s.x.size(), 0.0L);

  // Grid: runs of up to detail::kRun points, half-width h ≤ 2^−7. x ≤ 1/2: Maclaurin
  // series in long double; else a degree-12 Taylor expansion about a 50-digit centre
  // (remainder < (2/√π)·1.0865·2^6·√12!/13!·h^13 < 2^−100).
  constexpr std::size_t kDeg = 13;
  const double step = options.x_max / static_cast<double>(std::max<std::size_t>(n_grid, 1));
  const std::size_t run_len =
      std::clamp<std::size_t>(static_cast<std::size_t>(0x1p-6 / step), 1, detail::kRun);
  const std::size_t runs = (s.grid_end + run_len - 1) / run_len;
  tbb::enumerable_thread_specific<double> selfcheck(0.0);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, runs, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t run = r.begin(); run != r.end(); ++run) {
          const std::size_t i0 = run * run_len, i1 = std::min(s.grid_end, i0 + run_len);
          const double xa = s.x[i0], xb = s.x[i1 - 1], x0 = s.x[i0 + (i1 - i0 - 1) / 2];
          const double h = std::max(x0 - xa, xb - x0);
          if (xb <= 0.5) {
            for (std::size_t i = i0; i < i1; ++i) s.ref[i] = erf_maclaurin(s.x[i]);
          } else if (h * 64 <= x0 && h <= 0x1p-7) {
            const auto big = taylor_coefficients_50<kDeg>(Big(x0));
            long double c[kDeg];
            for (std::size_t k = 0; k < kDeg; ++k) c[k] = static_cast<long double>(big[k]);
            for (std::size_t i = i0; i < i1; ++i)
              // x − x0 exact (Sterbenz)
              s.ref[i] = horner(static_cast<long double>(s.x[i]) - x0, c);
          } else {
            for (std::size_t i = i0; i < i1; ++i) s.ref[i] = erf_reference_50(s.x[i]);
          }
          if (run % 16 == 0 || run + 1 == runs) {  // spot check the run's far end against 50 digits
            const long double direct = erf_reference_50(xb);
            double& m = selfcheck.local();
            m = std::max(
                m, static_cast<double>(std::abs(s.ref[i1 - 1] - direct) / ulp_double(direct)));
          }
        }
      });
  for (double m : selfcheck) s.selfcheck_ulps = std::max(s.selfcheck_ulps, m);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(s.grid_end, s.x.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i)
                        s.ref[i] =
                            i < s.main_end ? erf_reference_50(s.x[i]) : erfc_reference_50(s.x[i]);
                    });
  for (std::size_t i = s.main_end; i < s.x.size(); ++i)
    if (!(s.ref[i] < 0x1p-54L))
      throw std::logic_error("erf double sample: erfc(x_max) >= 2^-54, RN(erf) is not 1");
  s.reference = fmt::format(
      "erf in 50 digits (Boost.Math, cpp_bin_float_50), carried in long double: x <= 1/2 by its "
      "Maclaurin series, the grid above by a degree-{} Taylor expansion about a 50-digit centre "
      "per run of {} points (max deviation from direct 50-digit evaluation at spot points: {:.3g} "
      "double ulps), the other points directly; x >= {}: RN(erf) = 1, erf = 1 - erfc(x) with erfc "
      "in 50 digits",
      kDeg - 1, run_len, s.selfcheck_ulps, options.x_max);
  return s;
}

}  // namespace sglab::reference
