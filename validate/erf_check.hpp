// validate/erf_check.hpp — accuracy of an erf implementation against a
// correctly rounded reference (SPEC §2 erf variants, §3 `abs` and `ulp`).
//
// The checker takes any callable `float(float)` / `double(double)`: the
// registry's function pointers, the functors of sglab/erf.hpp, or a lambda
// over refitted coefficients (`erf_listing5(x, params)`). The core loops are
// templates so that a functor inlines into them.
//
// Definitions (every number the checker reports uses these):
//
//   ulp_float(y)  = 2^(floor(log2|y|) − 23) for |y| ≥ 2^−126 (FLT_MIN),
//                   2^−149 for |y| < 2^−126 (zero and the subnormal range):
//                   the spacing of binary32 numbers in the binade of y.
//   ulp_double(y) = 2^(floor(log2|y|) − 52) for |y| ≥ 2^−1022, else 2^−1074.
//   err_ulp(x)    = |f(x) − erf(x)| / ulp(erf(x)), with erf(x) the exact
//                   value (a reference far more precise than the format),
//                   not its rounding: a correctly rounded result has
//                   err_ulp ≤ 0.5, a faithful one < 1.
//   err_abs(x)    = |f(x) − erf(x)|.
//
// Float reference. erf(x) for x ∈ [0, 4) is a degree-6 Taylor expansion in
// double about the centre of each run of 1024 consecutive inputs (coefficients
// erf^(k)(x0)/k! from erfl/expl and Hermite polynomials; run half-width
// h ≤ 2^−9 and h ≤ x0/64, so the remainder is < 2^−66 relative), or std::erf
// in double where a run is too wide. Either is within a few double ulps of
// erf(x); when that value lies within 8 double ulps of a midpoint between two
// floats, the point is re-evaluated with Boost.Math erf in cpp_bin_float_50 to
// decide the correctly rounded float. Each Taylor run is also compared with
// std::erf at its end point (`reference_selfcheck_ulps`). For x ≥ 4,
// erfc(x) ≤ erfc(4) ≈ 1.5e−8 < 2^−25, so the correctly rounded float is
// exactly 1 and erf(x) = 1 − erfc(x) with erfc in double (0 beyond x = 32,
// where erfc < 1e−446 underflows anyway).
//
// Double reference. cpp_bin_float_50 (Boost.Math erf/erfc), carried in long
// double: on the uniform grid by the Maclaurin series for x ≤ 1/2 and above by
// a degree-12 Taylor expansion about a 50-digit centre per run of points of
// half-width ≤ 2^−7 (relative error ~2^−63, checked against direct 50-digit
// evaluation at spot points), directly elsewhere.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "io.hpp"

namespace sglab::validate {

// ---------------------------------------------------------------------------
// ulp and the error histogram
// ---------------------------------------------------------------------------

// Spacing of binary32 numbers at |y| (see the definition above). NaN → NaN.
inline double ulp_float(double y) {
  const double a = std::abs(y);
  if (!(a >= 0x1p-126)) return std::isnan(y) ? y : 0x1p-149;
  if (std::isinf(a)) return a;
  const auto e = static_cast<int>((std::bit_cast<std::uint64_t>(a) >> 52) & 0x7ff) - 1023;  // floor(log2 a)
  return std::bit_cast<double>(static_cast<std::uint64_t>(e - 23 + 1023) << 52);
}

// Spacing of binary64 numbers at |y| (see the definition above).
inline long double ulp_double(long double y) {
  const long double a = std::abs(y);
  if (std::isnan(a) || std::isinf(a)) return a;
  if (!(a >= 0x1p-1022L)) return 0x1p-1074L;
  int e = 0;
  (void)std::frexp(a, &e);  // a = m·2^e, m ∈ [0.5, 1)
  return std::ldexp(1.0L, e - 1 - 52);
}

// Histogram of ulp errors: bucket 0 counts correctly rounded results
// (f(x) == RN(erf(x))); bucket 1 results within 0.5 ulp (to double precision)
// that are nevertheless not the correctly rounded one (erf(x) within ~2^−53
// relative of a rounding midpoint, or a reference error at a binade boundary); bucket
// 2 + k results with 2^(k−1) < err ≤ 2^k, k = 0 … kErfHistMaxLog2 (bucket 2 is
// (0.5, 1]: faithful); the last bucket err > 2^kErfHistMaxLog2 (a relative
// error above 1 at 2^24 ulps: no correct bit).
inline constexpr int kErfHistMaxLog2 = 24;
inline constexpr std::size_t kErfHistBuckets = 2 + (kErfHistMaxLog2 + 1) + 1;

inline std::size_t erf_histogram_bucket(double err_ulp, bool correctly_rounded) {
  if (correctly_rounded) return 0;
  if (err_ulp <= 0.5) return 1;
  int e = 0;
  const double m = std::frexp(err_ulp, &e);  // err = m·2^e, m ∈ [0.5, 1)
  const int k = m == 0.5 ? e - 1 : e;         // smallest k with err ≤ 2^k (≥ 0 here)
  return k > kErfHistMaxLog2 ? kErfHistBuckets - 1 : static_cast<std::size_t>(2 + k);
}
// Upper edge of bucket i in ulps: 0 ("cr"), 0.5, 1, 2, …, 2^24, +inf.
double erf_histogram_upper(std::size_t i);
// "cr", "<=0.5", "<=1", "<=2", …, "<=16777216", ">16777216".
std::string erf_histogram_label(std::size_t i);

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

// Max / RMS / distribution of the error over a set of points. Non-finite
// outputs for finite inputs are counted in `nonfinite` and excluded from
// every other field.
struct ErfStats {
  std::uint64_t count = 0;              // finite outputs measured
  std::uint64_t nonfinite = 0;          // NaN / ±inf outputs for finite x
  std::uint64_t correctly_rounded = 0;  // f(x) == RN(erf(x))
  double max_ulp = -1;                  // −1 while empty
  double worst_x = 0;                   // x of max_ulp (smallest such x)
  double max_abs = -1;
  double worst_abs_x = 0;               // x of max_abs
  double sum_sq_ulp = 0;
  double first_nonfinite_x = std::numeric_limits<double>::quiet_NaN();
  std::array<std::uint64_t, kErfHistBuckets> histogram{};

  void add(double x, double err_ulp, double err_abs, bool cr) {
    ++count;
    correctly_rounded += cr;
    sum_sq_ulp += err_ulp * err_ulp;
    if (err_ulp > max_ulp || (err_ulp == max_ulp && x < worst_x)) max_ulp = err_ulp, worst_x = x;
    if (err_abs > max_abs || (err_abs == max_abs && x < worst_abs_x)) max_abs = err_abs, worst_abs_x = x;
    ++histogram[erf_histogram_bucket(err_ulp, cr)];
  }
  void add_nonfinite(double x) {
    ++nonfinite;
    if (!(x >= first_nonfinite_x)) first_nonfinite_x = x;  // keeps the smallest
  }
  void merge(const ErfStats& o);
  double rms_ulp() const { return count ? std::sqrt(sum_sq_ulp / static_cast<double>(count)) : 0.0; }
};

// One bin of the downsampled error-over-x series (for plots).
struct ErfBin {
  double x_lo = 0, x_hi = 0;
  std::uint64_t count = 0;
  double max_ulp = 0, max_ulp_x = 0, max_abs = 0, sum_sq_ulp = 0;
  void add(double x, double err_ulp, double err_abs) {
    ++count;
    sum_sq_ulp += err_ulp * err_ulp;
    if (err_ulp > max_ulp || count == 1) max_ulp = err_ulp, max_ulp_x = x;
    if (err_abs > max_abs) max_abs = err_abs;
  }
  void merge(const ErfBin& o) {
    if (o.count == 0) return;
    if (count == 0 || o.max_ulp > max_ulp || (o.max_ulp == max_ulp && o.max_ulp_x < max_ulp_x))
      max_ulp = o.max_ulp, max_ulp_x = o.max_ulp_x;
    max_abs = std::max(max_abs, o.max_abs);
    count += o.count;
    sum_sq_ulp += o.sum_sq_ulp;
  }
};

// f(−x) == −f(x) bit for bit (NaN == NaN) on the sampled negatives.
struct ErfOddness {
  std::uint64_t checked = 0, violations = 0;
  double first_violation_x = std::numeric_limits<double>::quiet_NaN();
};

// A special input with its expected output (correctly rounded, signed zero
// kept) and the variant's output; `ok` compares bit for bit (any NaN == NaN).
struct ErfSpecial {
  double x, expected, got;
  bool ok;
};

struct ErfReport {
  std::string variant;
  std::string precision;  // "float" | "double"
  ErfStats stats;         // every measured point (x ≥ 0)
  ErfStats tail;          // the constant region alone (float x ≥ 4, double x ≥ 6), included in `stats`
  double tail_from = 0;   // where the constant region starts
  std::vector<ErfBin> series;  // max error per bin of x over [0, series_x_max)
  double series_x_max = 0;
  ErfOddness oddness;
  std::vector<ErfSpecial> specials;
  std::uint64_t ambiguous_resolved = 0;  // float: reference points decided in 50 digits
  double reference_selfcheck_ulps = 0;   // max deviation of the fast reference from an independent
                                         // evaluation at spot points, in double ulps (float: std::erf,
                                         // double: direct 50-digit erf)
  std::string coverage;                  // which inputs were covered, in words
  std::string reference;                 // how the reference was computed, in words
  double seconds = 0;                    // wall time of the check
};

// ---------------------------------------------------------------------------
// Single-point references
// ---------------------------------------------------------------------------

struct ErfFloatReference {
  double exact;    // erf(x) to within a few double ulps (50-digit value when resolved)
  float rounded;   // correctly rounded erf(x), signed zero kept
  bool resolved;   // decided with cpp_bin_float_50
};
// Correctly rounded float erf at any float (±0, ±inf, NaN included).
ErfFloatReference erf_reference_float(float x);

// erf(x) from Boost.Math in cpp_bin_float_50, rounded to long double.
long double erf_reference_50(double x);
// erfc(x) likewise.
long double erfc_reference_50(double x);

// ---------------------------------------------------------------------------
// Float check
// ---------------------------------------------------------------------------

inline constexpr std::uint32_t kErfFloatTailBits = 0x40800000u;  // 4.0f: from here RN(erf) = 1
inline constexpr std::uint32_t kErfFloatMaxBits = 0x7f7fffffu;   // FLT_MAX
inline constexpr std::uint32_t kErfFloatFarBits = 0x42800000u;   // 64.0f: exhaustive_tail_stride applies above

struct ErfFloatOptions {
  // Every float in [0, 4) and every float in [4, FLT_MAX] (2.14e9 points).
  bool exhaustive = false;
  // Sample (exhaustive = false): every `stride`-th bit pattern in [0, 4) (all
  // binades down to the subnormals), a uniform grid of 2^grid_log2 points
  // i·4/2^grid_log2 (exact floats; 0 disables), and every `tail_stride`-th
  // bit pattern in [4, FLT_MAX].
  std::uint32_t stride = 257;
  std::uint32_t grid_log2 = 20;
  std::uint32_t tail_stride = 4099;
  // Exhaustive: every float in [4, 64), and every `exhaustive_tail_stride`-th
  // bit pattern in [64, FLT_MAX] (1: every float). Nothing in any variant
  // changes above 64: erfc(x) underflows in double at x ≈ 27.3, e^(−x²) in
  // float at x ≈ 10.1, Listing 5 returns ±1 from 4 on.
  std::uint32_t exhaustive_tail_stride = 1;
  // Negatives: every `odd_stride`-th bit pattern in (0, FLT_MAX], in both modes.
  std::uint32_t odd_stride = 1021;
  std::size_t bins = 2000;     // series bins over [0, 4)
  std::string progress_label;  // non-empty: progress line on stderr (terminals only)
};

namespace detail {

// Taylor expansion of erf about x0 for the inputs of one run [x_first, x_last].
struct ErfTaylorFloat {
  bool ok = false;  // false: the run is too wide, evaluate std::erf directly
  double x0 = 0;
  double c[7] = {};
  double operator()(double x) const {
    const double h = x - x0;  // exact for the float inputs of a run
    return c[0] + h * (c[1] + h * (c[2] + h * (c[3] + h * (c[4] + h * (c[5] + h * c[6])))));
  }
};
ErfTaylorFloat erf_taylor_float(double x_first, double x0, double x_last);

// Is y (≥ 0, within a few double ulps of erf(x)) within `ulps` double ulps of
// a midpoint between two consecutive floats? Then RN(y) may differ from RN(erf(x)).
inline bool near_float_midpoint(double y, int ulps = 8) {
  const double a = std::abs(y);
  if (a >= 0x1p-126) {  // float-normal range: the 29 bits below the float's last bit decide
    const auto low = static_cast<std::int64_t>(std::bit_cast<std::uint64_t>(a) & ((std::uint64_t{1} << 29) - 1));
    const std::int64_t d = low - (std::int64_t{1} << 28);
    return d <= ulps && d >= -ulps;
  }
  const double q = a * 0x1p149;  // in units of the subnormal spacing; exact
  const double frac = q - std::floor(q);
  return std::abs(frac - 0.5) <= ulps * static_cast<double>(ulp_double(a)) * 0x1p149;
}

// Decide a midpoint case in 50 digits.
ErfFloatReference erf_resolve_float(float x);

inline constexpr std::size_t kRun = 1024;  // points per Taylor run / work item

// One thread's partial result. The variant is evaluated by the template loop
// (so that it inlines); the rest of the work per run of points is here.
struct ErfFloatAccum {
  ErfStats stats, tail;
  std::vector<ErfBin> bins;
  double bin_scale = 0;
  std::uint64_t ambiguous = 0;
  double selfcheck = 0;

  // x ∈ [0, 4), increasing; y = f(x).
  void main_run(const float* x, const float* y, std::size_t n);
  // x ≥ 4, increasing: RN(erf(x)) = 1 and erf(x) = 1 − erfc(x) ∈ (1 − 2^−25, 1), ulp 2^−24.
  void tail_run(const float* x, const float* y, std::size_t n);

 private:
  void main_slow(double x, float y, double ref);
  void tail_one(double x, float y);
};

std::shared_ptr<ErfFloatAccum> make_float_accum(std::size_t bins);
void finish_float_report(ErfReport& report, const std::vector<std::shared_ptr<ErfFloatAccum>>& parts,
                         const ErfFloatOptions& options);
std::string float_coverage(const ErfFloatOptions& options, std::uint64_t odd_checked);
std::vector<float> float_specials();
bool same_result(double expected, double got);

inline float float_from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

// Points of one segment: count and the x of index i.
struct FloatSegment {
  enum Kind { bits, grid } kind;
  std::uint32_t first;   // bits: first pattern
  std::uint32_t stride;  // bits: pattern stride
  float step;            // grid: x = i·step (a power of two)
  std::uint64_t n;
  bool tail;             // x ≥ 4 (constant region)
};
std::vector<FloatSegment> float_segments(const ErfFloatOptions& options);

template <class F, class X>
void float_segment_loop(F& f, const FloatSegment& seg, X xs, tbb::enumerable_thread_specific<std::shared_ptr<ErfFloatAccum>>& ets,
                        io::Progress* progress) {
  const std::uint64_t runs = (seg.n + kRun - 1) / kRun;
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, runs, 4), [&](const tbb::blocked_range<std::uint64_t>& r) {
    ErfFloatAccum& acc = *ets.local();
    alignas(64) float xb[kRun];
    alignas(64) float yb[kRun];
    for (std::uint64_t run = r.begin(); run != r.end(); ++run) {
      const std::uint64_t i0 = run * kRun;
      const auto n = static_cast<std::size_t>(std::min(seg.n, i0 + kRun) - i0);
      for (std::size_t k = 0; k < n; ++k) xb[k] = xs(i0 + k);
      for (std::size_t k = 0; k < n; ++k) yb[k] = f(xb[k]);  // the only per-variant code
      if (seg.tail)
        acc.tail_run(xb, yb, n);
      else
        acc.main_run(xb, yb, n);
      if (progress) progress->advance(n);
    }
  });
}

}  // namespace detail

// Error of f against the correctly rounded float erf over x ≥ 0 (the sample
// or every float, see ErfFloatOptions), oddness on sampled negatives, and the
// special values ±0, ±denorm_min, ±FLT_MIN, ±FLT_MAX, ±inf, NaN.
template <class F>
ErfReport check_erf_float(F f, const ErfFloatOptions& options = {}, std::string_view variant = "") {
  using namespace detail;
  const auto start = std::chrono::steady_clock::now();
  ErfReport report;
  report.variant = std::string(variant);
  report.precision = "float";

  const std::vector<FloatSegment> segments = float_segments(options);
  std::uint64_t total = 0;
  for (const FloatSegment& s : segments) total += s.n;
  std::unique_ptr<io::Progress> progress;
  if (!options.progress_label.empty()) progress = std::make_unique<io::Progress>(options.progress_label, total);

  tbb::enumerable_thread_specific<std::shared_ptr<ErfFloatAccum>> ets([&] { return make_float_accum(options.bins); });
  for (const FloatSegment& seg : segments) {
    if (seg.kind == FloatSegment::bits)
      float_segment_loop(f, seg, [&seg](std::uint64_t i) { return float_from_bits(seg.first + static_cast<std::uint32_t>(i) * seg.stride); },
                         ets, progress.get());
    else
      float_segment_loop(f, seg, [&seg](std::uint64_t i) { return static_cast<float>(i) * seg.step; }, ets, progress.get());
  }
  if (progress) progress->finish();
  std::vector<std::shared_ptr<ErfFloatAccum>> parts(ets.begin(), ets.end());

  // Oddness on sampled negatives: every odd_stride-th pattern in (0, FLT_MAX].
  const std::uint32_t odd_stride = std::max<std::uint32_t>(1, options.odd_stride);
  const std::uint64_t odd_n = (kErfFloatMaxBits - 1) / odd_stride + 1;
  tbb::enumerable_thread_specific<ErfOddness> odd;
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, odd_n, 4096), [&](const tbb::blocked_range<std::uint64_t>& r) {
    ErfOddness& o = odd.local();
    for (std::uint64_t i = r.begin(); i != r.end(); ++i) {
      const float x = float_from_bits(1 + static_cast<std::uint32_t>(i) * odd_stride);
      const float p = f(x), m = f(-x);
      ++o.checked;
      const bool ok = (std::isnan(p) && std::isnan(m)) || std::bit_cast<std::uint32_t>(m) == std::bit_cast<std::uint32_t>(-p);
      if (!ok) {
        ++o.violations;
        if (!(x >= o.first_violation_x)) o.first_violation_x = x;
      }
    }
  });
  for (const ErfOddness& o : odd) {
    report.oddness.checked += o.checked;
    report.oddness.violations += o.violations;
    if (o.violations && !(o.first_violation_x >= report.oddness.first_violation_x))
      report.oddness.first_violation_x = o.first_violation_x;
  }

  for (float x : float_specials()) {
    const float expected = erf_reference_float(x).rounded;
    const float got = f(x);
    report.specials.push_back({x, expected, got, same_result(expected, got)});
  }

  finish_float_report(report, parts, options);
  report.coverage = float_coverage(options, report.oddness.checked);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

// ---------------------------------------------------------------------------
// Double check
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
  std::vector<double> x;          // [0, main_end): x < x_max; [main_end, size): tail
  std::vector<long double> ref;   // erf(x) for the main part, erfc(x) for the tail
  std::size_t main_end = 0;
  std::size_t grid_end = 0;       // [0, grid_end) is the uniform grid
  double selfcheck_ulps = 0;      // max |Taylor − direct 50-digit| in double ulps at spot points
  std::string reference;
};
ErfDoubleSample make_erf_double_sample(const ErfDoubleOptions& options = {});

namespace detail {
std::vector<double> double_specials();
long double erf_special_expected_double(double x);
std::string double_coverage(const ErfDoubleSample& s, std::uint64_t odd_checked);
}  // namespace detail

template <class F>
ErfReport check_erf_double(F f, const ErfDoubleSample& s, std::string_view variant = "") {
  using namespace detail;
  const auto start = std::chrono::steady_clock::now();
  ErfReport report;
  report.variant = std::string(variant);
  report.precision = "double";
  report.tail_from = s.options.x_max;
  report.series_x_max = s.options.x_max;
  report.reference = s.reference;
  report.reference_selfcheck_ulps = s.selfcheck_ulps;

  struct Acc {
    ErfStats stats, tail;
    std::vector<ErfBin> bins;
  };
  const double bin_scale = static_cast<double>(s.options.bins) / s.options.x_max;
  tbb::enumerable_thread_specific<Acc> ets([&] { return Acc{{}, {}, std::vector<ErfBin>(s.options.bins)}; });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.x.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    Acc& acc = ets.local();
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const double x = s.x[i];
      const double y = f(x);
      const bool is_tail = i >= s.main_end;
      if (!std::isfinite(y)) {
        acc.stats.add_nonfinite(x);
        if (is_tail) acc.tail.add_nonfinite(x);
        continue;
      }
      if (is_tail) {  // exact = 1 − erfc ∈ (1 − 2^−54, 1): RN = 1, ulp 2^−53
        const long double err_abs = std::abs((static_cast<long double>(y) - 1.0L) + s.ref[i]);
        const double err_ulp = static_cast<double>(err_abs * 0x1p53L);
        acc.stats.add(x, err_ulp, static_cast<double>(err_abs), y == 1.0);
        acc.tail.add(x, err_ulp, static_cast<double>(err_abs), y == 1.0);
      } else {
        const long double exact = s.ref[i];
        const long double err_abs = std::abs(static_cast<long double>(y) - exact);
        const double err_ulp = static_cast<double>(err_abs / ulp_double(exact));
        acc.stats.add(x, err_ulp, static_cast<double>(err_abs), y == static_cast<double>(exact));
        if (!acc.bins.empty())
          acc.bins[std::min(acc.bins.size() - 1, static_cast<std::size_t>(x * bin_scale))].add(x, err_ulp,
                                                                                                  static_cast<double>(err_abs));
      }
    }
  });
  report.series.assign(s.options.bins, ErfBin{});
  for (std::size_t b = 0; b < report.series.size(); ++b) {
    report.series[b].x_lo = s.options.x_max * static_cast<double>(b) / static_cast<double>(s.options.bins);
    report.series[b].x_hi = s.options.x_max * static_cast<double>(b + 1) / static_cast<double>(s.options.bins);
  }
  for (const Acc& a : ets) {
    report.stats.merge(a.stats);
    report.tail.merge(a.tail);
    for (std::size_t b = 0; b < a.bins.size(); ++b) report.series[b].merge(a.bins[b]);
  }

  const std::uint64_t max_bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::max());
  const std::uint64_t n_odd = std::max<std::uint32_t>(1, s.options.odd_points);
  for (std::uint64_t i = 0; i < n_odd; ++i) {
    const double x = std::bit_cast<double>(1 + (max_bits - 1) / n_odd * i);
    const double p = f(x), m = f(-x);
    ++report.oddness.checked;
    const bool ok = (std::isnan(p) && std::isnan(m)) || std::bit_cast<std::uint64_t>(m) == std::bit_cast<std::uint64_t>(-p);
    if (!ok) {
      ++report.oddness.violations;
      if (!(x >= report.oddness.first_violation_x)) report.oddness.first_violation_x = x;
    }
  }
  for (double x : double_specials()) {
    const auto expected = static_cast<double>(erf_special_expected_double(x));
    const double got = f(x);
    report.specials.push_back({x, expected, got, same_result(expected, got)});
  }
  report.coverage = double_coverage(s, report.oddness.checked);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

// ---------------------------------------------------------------------------
// Output (one writer for every format)
// ---------------------------------------------------------------------------

// {"results": [{"variant", "precision", "max_abs", "max_ulp", "worst_x", …}, …]}
std::string erf_reports_json(const std::vector<ErfReport>& reports, bool exhaustive);
// Summary table, histogram table, specials and notes as Markdown.
std::string erf_reports_markdown(const std::vector<ErfReport>& reports, bool exhaustive);
// One row per report.
std::string erf_summary_csv(const std::vector<ErfReport>& reports);
// One row per histogram bucket per report.
std::string erf_histogram_csv(const std::vector<ErfReport>& reports);
// The downsampled series of one report: x_lo,x_hi,count,max_ulp,max_ulp_x,rms_ulp,max_abs.
std::string erf_series_csv(const ErfReport& report);

}  // namespace sglab::validate
