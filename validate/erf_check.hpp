// validate/erf_check.hpp — accuracy of an erf implementation against a
// correctly rounded reference: walking the inputs and accumulating the error
// statistics (max, RMS, where, histogram, series over x).
//
// The checker takes any callable `float(float)` / `double(double)`: the
// registry's function pointers, the functors of sglab/erf.hpp, or a lambda
// over refitted coefficients (`erf_listing5(x, params)`). The core loops are
// templates so that a functor inlines into them.
//
// Definitions (every number the checker reports uses these):
//
//   ulp_float(y), ulp_double(y): the spacing of binary32 / binary64 numbers
//                   in the binade of y (reference/error_measures.hpp).
//   err_ulp(x)    = |f(x) − erf(x)| / ulp(erf(x)), with erf(x) the exact
//                   value (a reference far more precise than the format),
//                   not its rounding: a correctly rounded result has
//                   err_ulp ≤ 0.5, a faithful one < 1.
//   err_abs(x)    = |f(x) − erf(x)|.
//
// The correctly rounded reference is reference/erf_reference.hpp; the ulp
// definitions are in reference/error_measures.hpp; the writers of the results (JSON,
// Markdown, CSV) are report/erf_report.hpp. This file walks the inputs and
// accumulates the statistics.
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

#include "common/io.hpp"
#include "reference/erf_reference.hpp"

namespace sglab::validate {

// ---------------------------------------------------------------------------
// The error histogram
// ---------------------------------------------------------------------------

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
  const int k = m == 0.5 ? e - 1 : e;        // smallest k with err ≤ 2^k (≥ 0 here)
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
  double worst_abs_x = 0;  // x of max_abs
  double sum_sq_ulp = 0;
  double first_nonfinite_x = std::numeric_limits<double>::quiet_NaN();
  std::array<std::uint64_t, kErfHistBuckets> histogram{};

  void add(double x, double err_ulp, double err_abs, bool cr) {
    ++count;
    correctly_rounded += cr;
    sum_sq_ulp += err_ulp * err_ulp;
    if (err_ulp > max_ulp || (err_ulp == max_ulp && x < worst_x)) max_ulp = err_ulp, worst_x = x;
    if (err_abs > max_abs || (err_abs == max_abs && x < worst_abs_x))
      max_abs = err_abs, worst_abs_x = x;
    ++histogram[erf_histogram_bucket(err_ulp, cr)];
  }
  void add_nonfinite(double x) {
    ++nonfinite;
    if (!(x >= first_nonfinite_x)) first_nonfinite_x = x;  // keeps the smallest
  }
  void merge(const ErfStats& o);
  double rms_ulp() const {
    return count ? std::sqrt(sum_sq_ulp / static_cast<double>(count)) : 0.0;
  }
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
  ErfStats tail;  // the constant region alone (float x ≥ 4, double x ≥ 6), included in `stats`
  double tail_from = 0;        // where the constant region starts
  std::vector<ErfBin> series;  // max error per bin of x over [0, series_x_max)
  double series_x_max = 0;
  ErfOddness oddness;
  std::vector<ErfSpecial> specials;
  std::uint64_t ambiguous_resolved = 0;  // float: reference points decided in 50 digits
  double reference_selfcheck_ulps = 0;   // max deviation of the fast reference from an independent
                                         // evaluation at spot points, in double ulps (float:
                                         // std::erf, double: direct 50-digit erf)
  std::string coverage;                  // which inputs were covered, in words
  std::string reference;                 // how the reference was computed, in words
  double seconds = 0;                    // wall time of the check
};

// ---------------------------------------------------------------------------
// Float check
// ---------------------------------------------------------------------------

// Bit patterns of the float inputs that delimit the segments (the patterns of
// non-negative floats are ordered like their values, so a range of values is
// a range of patterns).
inline constexpr std::uint32_t kErfFloatTailBits = 0x40800000u;  // 4.0f: from here RN(erf) = 1
inline constexpr std::uint32_t kErfFloatMaxBits = 0x7f7fffffu;   // FLT_MAX = (2 − 2^−23)·2^127
// 64.0f: exhaustive_tail_stride applies above
inline constexpr std::uint32_t kErfFloatFarBits = 0x42800000u;
static_assert(std::bit_cast<std::uint32_t>(4.0f) == kErfFloatTailBits);
static_assert(std::bit_cast<std::uint32_t>(std::numeric_limits<float>::max()) == kErfFloatMaxBits);
static_assert(std::bit_cast<std::uint32_t>(64.0f) == kErfFloatFarBits);

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
void finish_float_report(ErfReport& report,
                         const std::vector<std::shared_ptr<ErfFloatAccum>>& parts,
                         const ErfFloatOptions& options);
std::string float_coverage(const ErfFloatOptions& options, std::uint64_t odd_checked);
std::vector<float> float_specials();
bool same_result(double expected, double got);
// n with thousands separators: 1234567 → "1,234,567".
std::string group_digits(std::uint64_t n);

inline float float_from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

// Points of one segment: count and the x of index i.
struct FloatSegment {
  enum Kind { bits, grid } kind;
  std::uint32_t first;   // bits: first pattern
  std::uint32_t stride;  // bits: pattern stride
  float step;            // grid: x = i·step (a power of two)
  std::uint64_t n;
  bool tail;  // x ≥ 4 (constant region)
};
std::vector<FloatSegment> float_segments(const ErfFloatOptions& options);

template <class F, class X>
void float_segment_loop(F& f, const FloatSegment& seg, X xs,
                        tbb::enumerable_thread_specific<std::shared_ptr<ErfFloatAccum>>& ets,
                        io::Progress* progress) {
  const std::uint64_t runs = (seg.n + reference::detail::kRun - 1) / reference::detail::kRun;
  tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, runs, 4),
                    [&](const tbb::blocked_range<std::uint64_t>& r) {
                      ErfFloatAccum& acc = *ets.local();
                      alignas(64) float xb[reference::detail::kRun];
                      alignas(64) float yb[reference::detail::kRun];
                      for (std::uint64_t run = r.begin(); run != r.end(); ++run) {
                        const std::uint64_t i0 = run * reference::detail::kRun;
                        const auto n = static_cast<std::size_t>(
                            std::min(seg.n, i0 + reference::detail::kRun) - i0);
                        for (std::size_t k = 0; k < n; ++k) xb[k] = xs(i0 + k);
                        for (std::size_t k = 0; k < n; ++k)
                          yb[k] = f(xb[k]);  // the only per-variant code
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
  if (!options.progress_label.empty())
    progress = std::make_unique<io::Progress>(options.progress_label, total);

  tbb::enumerable_thread_specific<std::shared_ptr<ErfFloatAccum>> ets(
      [&] { return make_float_accum(options.bins); });
  for (const FloatSegment& seg : segments) {
    if (seg.kind == FloatSegment::bits)
      float_segment_loop(
          f, seg,
          [&seg](std::uint64_t i) {
            return float_from_bits(seg.first + static_cast<std::uint32_t>(i) * seg.stride);
          },
          ets, progress.get());
    else
      float_segment_loop(
          f, seg, [&seg](std::uint64_t i) { return static_cast<float>(i) * seg.step; }, ets,
          progress.get());
  }
  if (progress) progress->finish();
  std::vector<std::shared_ptr<ErfFloatAccum>> parts(ets.begin(), ets.end());

  // Oddness on sampled negatives: every odd_stride-th pattern in (0, FLT_MAX].
  const std::uint32_t odd_stride = std::max<std::uint32_t>(1, options.odd_stride);
  const std::uint64_t odd_n = (kErfFloatMaxBits - 1) / odd_stride + 1;
  tbb::enumerable_thread_specific<ErfOddness> odd;
  tbb::parallel_for(
      tbb::blocked_range<std::uint64_t>(0, odd_n, 4096),
      [&](const tbb::blocked_range<std::uint64_t>& r) {
        ErfOddness& o = odd.local();
        for (std::uint64_t i = r.begin(); i != r.end(); ++i) {
          const float x = float_from_bits(1 + static_cast<std::uint32_t>(i) * odd_stride);
          const float p = f(x), m = f(-x);
          ++o.checked;
          const bool ok = (std::isnan(p) && std::isnan(m)) ||
                          std::bit_cast<std::uint32_t>(m) == std::bit_cast<std::uint32_t>(-p);
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
    const float expected = reference::erf_reference_float(x).rounded;
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

namespace detail {
std::vector<double> double_specials();
std::string double_coverage(const reference::ErfDoubleSample& s, std::uint64_t odd_checked);
}  // namespace detail

template <class F>
ErfReport check_erf_double(F f, const reference::ErfDoubleSample& s,
                           std::string_view variant = "") {
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
  tbb::enumerable_thread_specific<Acc> ets([&] {
    return Acc{{}, {}, std::vector<ErfBin>(s.options.bins)};
  });
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, s.x.size(), 4096),
      [&](const tbb::blocked_range<std::size_t>& r) {
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
          if (is_tail) {  // exact = 1 − erfc ∈ (1 − 2^−54, 1): RN = 1, ulp_double = 2^−53
            const long double err_abs = std::abs((static_cast<long double>(y) - 1.0L) + s.ref[i]);
            const double err_ulp = static_cast<double>(err_abs * 0x1p53L);  // err_abs / 2^−53
            acc.stats.add(x, err_ulp, static_cast<double>(err_abs), y == 1.0);
            acc.tail.add(x, err_ulp, static_cast<double>(err_abs), y == 1.0);
          } else {
            const long double exact = s.ref[i];
            const long double err_abs = std::abs(static_cast<long double>(y) - exact);
            const double err_ulp = reference::exact_ulp_error_double(y, exact);
            acc.stats.add(x, err_ulp, static_cast<double>(err_abs),
                          y == static_cast<double>(exact));
            if (!acc.bins.empty())
              acc.bins[std::min(acc.bins.size() - 1, static_cast<std::size_t>(x * bin_scale))].add(
                  x, err_ulp, static_cast<double>(err_abs));
          }
        }
      });
  report.series.assign(s.options.bins, ErfBin{});
  for (std::size_t b = 0; b < report.series.size(); ++b) {
    report.series[b].x_lo =
        s.options.x_max * static_cast<double>(b) / static_cast<double>(s.options.bins);
    report.series[b].x_hi =
        s.options.x_max * static_cast<double>(b + 1) / static_cast<double>(s.options.bins);
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
    const bool ok = (std::isnan(p) && std::isnan(m)) ||
                    std::bit_cast<std::uint64_t>(m) == std::bit_cast<std::uint64_t>(-p);
    if (!ok) {
      ++report.oddness.violations;
      if (!(x >= report.oddness.first_violation_x)) report.oddness.first_violation_x = x;
    }
  }
  for (double x : double_specials()) {
    const auto expected = static_cast<double>(reference::detail::erf_special_expected_double(x));
    const double got = f(x);
    report.specials.push_back({x, expected, got, same_result(expected, got)});
  }
  report.coverage = double_coverage(s, report.oddness.checked);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace sglab::validate
