// validate/erf_check.cpp — the per-run accumulation and reduction of the erf
// checker (validate/erf_check.hpp has the definitions).
#include "validate/erf_check.hpp"

#include <cfloat>
#include <stdexcept>

#include <fmt/format.h>

namespace sglab::validate {

// --- histogram -------------------------------------------------------------

double erf_histogram_upper(std::size_t i) {
  if (i == 0) return 0;
  if (i == 1) return 0.5;
  if (i + 1 >= kErfHistBuckets) return std::numeric_limits<double>::infinity();
  return std::ldexp(1.0, static_cast<int>(i) - 2);
}

std::string erf_histogram_label(std::size_t i) {
  if (i == 0) return "cr";
  if (i == 1) return "<=0.5";
  if (i + 1 >= kErfHistBuckets) return fmt::format(">{}", std::ldexp(1.0, kErfHistMaxLog2));
  return fmt::format("<={}", erf_histogram_upper(i));
}

void ErfStats::merge(const ErfStats& o) {
  count += o.count;
  nonfinite += o.nonfinite;
  correctly_rounded += o.correctly_rounded;
  sum_sq_ulp += o.sum_sq_ulp;
  if (o.max_ulp > max_ulp || (o.max_ulp == max_ulp && o.worst_x < worst_x))
    max_ulp = o.max_ulp, worst_x = o.worst_x;
  if (o.max_abs > max_abs || (o.max_abs == max_abs && o.worst_abs_x < worst_abs_x))
    max_abs = o.max_abs, worst_abs_x = o.worst_abs_x;
  if (o.nonfinite && !(o.first_nonfinite_x >= first_nonfinite_x))
    first_nonfinite_x = o.first_nonfinite_x;
  for (std::size_t i = 0; i < histogram.size(); ++i) histogram[i] += o.histogram[i];
}

std::string detail::group_digits(std::uint64_t n) {
  std::string s = std::to_string(n), out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i && (s.size() - i) % 3 == 0) out += ',';
    out += s[i];
  }
  return out;
}

// --- accumulation ----------------------------------------------------------

namespace detail {

namespace {

// Fields of a binary32 pattern: sign 1 bit, exponent 8 bits, fraction 23 bits.
// exponent field; also the pattern of +inf
constexpr std::uint32_t kFloatExponentMask = 0x7f800000u;
// fraction field; also the largest subnormal's pattern
constexpr std::uint32_t kFloatFractionMask = 0x007fffffu;
constexpr std::uint32_t kFloatMagnitudeMask = 0x7fffffffu;  // all but the sign: the pattern of |x|
constexpr std::uint32_t kFloatOneBits = 0x3f800000u;        // 1.0f
static_assert(std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity()) ==
              kFloatExponentMask);
static_assert(std::bit_cast<std::uint32_t>(1.0f) == kFloatOneBits);
// Fields of a binary64 pattern: sign 1, exponent 11 (bias 1023), fraction 52.
// exponent field; also the pattern of +inf
constexpr std::uint64_t kDoubleExponentMask = 0x7ff0000000000000u;
constexpr std::uint64_t kDoubleFractionMask = (std::uint64_t{1} << 52) - 1;
// 2^1023 (biased exponent 2046, fraction 0). Subtracting the exponent field of
// r = m·2^e (biased e + 1023) from it leaves biased exponent 1023 − e: the
// pattern of 2^−e = 2^−floor(log2 r), for any normal r.
constexpr std::uint64_t kDoubleTwoTo1023Bits = 0x7fe0000000000000u;
static_assert(std::bit_cast<std::uint64_t>(std::numeric_limits<double>::infinity()) ==
              kDoubleExponentMask);
static_assert(std::bit_cast<std::uint64_t>(0x1p1023) == kDoubleTwoTo1023Bits);

// Float ↔ double through the bits: converting a subnormal float in hardware
// costs a microcode assist (~100 cycles) on x86, and 0.4 % of the inputs are
// subnormal.
inline double to_double(std::uint32_t b) {
  if ((b & kFloatExponentMask) == 0) {  // ±0 or subnormal: fraction · 2^−149
    const double m = static_cast<double>(b & kFloatFractionMask) * 0x1p-149;
    return b >> 31 ? -m : m;
  }
  return static_cast<double>(std::bit_cast<float>(b));
}
// Bits of RN(r) for r ≥ 0 finite (round to nearest even): the one rounding of
// a double reference to float in the accumulation.
inline std::uint32_t round_to_float_bits(double r) {
  if (r >= 0x1p-126) return std::bit_cast<std::uint32_t>(static_cast<float>(r));
  const double q = r * 0x1p149;                              // exact, < 2^23
  return static_cast<std::uint32_t>((q + 0x1p52) - 0x1p52);  // RN to integer; 2^23 → FLT_MIN's bits
}
// Both patterns encode the same value (bitwise equal, or +0 and −0).
inline bool same_float(std::uint32_t a, std::uint32_t b) {
  return a == b || ((a | b) & kFloatMagnitudeMask) == 0;
}
// erf_histogram_bucket without a libm call.
inline std::size_t bucket_fast(double err, bool cr) {
  if (cr) return 0;
  if (err <= 0.5) return 1;
  const auto b = std::bit_cast<std::uint64_t>(err);
  const int e = static_cast<int>(b >> 52) - 1023;  // floor(log2 err) ≥ −1
  const int k = (b & kDoubleFractionMask) == 0 ? e : e + 1;
  return k > kErfHistMaxLog2 ? kErfHistBuckets - 1 : static_cast<std::size_t>(2 + k);
}

}  // namespace

void ErfFloatAccum::main_slow(double x, float y, double ref) {
  if (!std::isfinite(y)) {
    stats.add_nonfinite(x);
    return;
  }
  const std::uint32_t yb = std::bit_cast<std::uint32_t>(y);
  double exact = ref;
  std::uint32_t cr = round_to_float_bits(ref);
  double err_abs = std::abs(to_double(yb) - exact);
  if (reference::detail::near_float_midpoint(ref)) {  // decide RN and the error in 50 digits
    const reference::ErfFloatReference r =
        reference::detail::erf_resolve_float(static_cast<float>(x));
    exact = r.exact;
    cr = std::bit_cast<std::uint32_t>(r.rounded);
    err_abs = reference::detail::erf_abs_error_50(static_cast<float>(x), y);
    ++ambiguous;
  }
  const double err_ulp = err_abs / reference::ulp_float(exact);
  stats.add(x, err_ulp, err_abs, same_float(yb, cr));
  if (!bins.empty())
    bins[std::min(bins.size() - 1, static_cast<std::size_t>(x * bin_scale))].add(x, err_ulp,
                                                                                 err_abs);
}

void ErfFloatAccum::main_run(const float* x, const float* y, std::size_t n) {
  if (n == 0) return;
  // Straight passes over arrays (the arithmetic ones vectorize); the
  // non-finite and midpoint points take main_slow and are skipped after.
  alignas(64) double xd[reference::detail::kRun];
  alignas(64) double ref[reference::detail::kRun];
  alignas(64) double err_abs[reference::detail::kRun];
  alignas(64) double err_ulp[reference::detail::kRun];
  alignas(64) std::uint8_t bucket[reference::detail::kRun];
  constexpr std::uint8_t kSkip = 255;
  for (std::size_t k = 0; k < n; ++k) xd[k] = to_double(std::bit_cast<std::uint32_t>(x[k]));
  const reference::detail::ErfTaylorFloat t =
      reference::detail::erf_taylor_float(xd[0], xd[(n - 1) / 2], xd[n - 1]);
  if (t.ok) {
    for (std::size_t k = 0; k < n; ++k) ref[k] = t(xd[k]);
    const double direct = std::erf(xd[n - 1]);
    selfcheck = std::max(selfcheck, std::abs(ref[n - 1] - direct) /
                                        static_cast<double>(reference::ulp_double(direct)));
  } else {
    for (std::size_t k = 0; k < n; ++k) ref[k] = std::erf(xd[k]);
  }
  for (std::size_t k = 0; k < n; ++k) err_abs[k] = to_double(std::bit_cast<std::uint32_t>(y[k]));
  for (std::size_t k = 0; k < n; ++k) {
    // 1/ulp_float(ref) = 2^23 · min(2^−floor(log2 ref), 2^126), through the exponent bits.
    const std::uint64_t e = std::bit_cast<std::uint64_t>(ref[k]) & kDoubleExponentMask;
    // 2^−floor(log2 ref); 2^1023 for 0
    const double inv_p2 = std::bit_cast<double>(kDoubleTwoTo1023Bits - e);
    const double inv = (inv_p2 < 0x1p126 ? inv_p2 : 0x1p126) * 0x1p23;
    err_abs[k] = std::abs(err_abs[k] - ref[k]);
    err_ulp[k] = err_abs[k] * inv;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const auto yb = std::bit_cast<std::uint32_t>(y[k]);
    if ((yb & kFloatExponentMask) == kFloatExponentMask ||
        reference::detail::near_float_midpoint(ref[k])) [[unlikely]] {  // ±inf, NaN
      bucket[k] = kSkip;
      main_slow(xd[k], y[k], ref[k]);
      continue;
    }
    const std::uint32_t crb = round_to_float_bits(ref[k]);
    bucket[k] = static_cast<std::uint8_t>(bucket_fast(err_ulp[k], same_float(yb, crb)));
  }

  std::uint32_t hist[4][kErfHistBuckets] = {};  // 4 interleaved copies: no store-to-load chain
  double sq0 = 0, sq1 = 0;
  std::uint64_t count = 0;
  double max_ulp = -1, max_ulp_x = 0, max_abs = -1, max_abs_x = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t b = bucket[k];
    if (b == kSkip) [[unlikely]]
      continue;
    ++count;
    ++hist[k & 3][b];
    (k & 1 ? sq1 : sq0) += err_ulp[k] * err_ulp[k];
    if (err_ulp[k] > max_ulp) [[unlikely]]
      max_ulp = err_ulp[k], max_ulp_x = xd[k];
    if (err_abs[k] > max_abs) [[unlikely]]
      max_abs = err_abs[k], max_abs_x = xd[k];
  }
  ErfStats run;
  run.count = count;
  run.sum_sq_ulp = sq0 + sq1;
  run.max_ulp = max_ulp;
  run.worst_x = max_ulp_x;
  run.max_abs = max_abs;
  run.worst_abs_x = max_abs_x;
  for (std::size_t b = 0; b < kErfHistBuckets; ++b)
    run.histogram[b] = std::uint64_t{hist[0][b]} + hist[1][b] + hist[2][b] + hist[3][b];
  run.correctly_rounded = run.histogram[0];
  stats.merge(run);

  if (bins.empty() || count == 0) return;
  const auto bin_of = [&](double v) {
    return std::min(bins.size() - 1, static_cast<std::size_t>(v * bin_scale));
  };
  if (bin_of(xd[0]) == bin_of(xd[n - 1])) {
    ErfBin bin;
    bin.count = count;
    bin.max_ulp = max_ulp;
    bin.max_ulp_x = max_ulp_x;
    bin.max_abs = max_abs;
    bin.sum_sq_ulp = run.sum_sq_ulp;
    bins[bin_of(xd[0])].merge(bin);
  } else {
    for (std::size_t k = 0; k < n; ++k)
      if (bucket[k] != kSkip) bins[bin_of(xd[k])].add(xd[k], err_ulp[k], err_abs[k]);
  }
}

void ErfFloatAccum::tail_one(double x, float y) {
  if (!std::isfinite(y)) {
    stats.add_nonfinite(x);
    tail.add_nonfinite(x);
    return;
  }
  const double c = x < 32 ? std::erfc(x) : 0.0;  // erfc(32) < 1e−446: 0 in double anyway
  const double err_abs = std::abs((static_cast<double>(y) - 1.0) + c);
  const double err_ulp = err_abs * 0x1p24;
  stats.add(x, err_ulp, err_abs, y == 1.0f);
  tail.add(x, err_ulp, err_abs, y == 1.0f);
}

void ErfFloatAccum::tail_run(const float* x, const float* y, std::size_t n) {
  if (n == 0) return;
  if (!(x[0] >= 32.0f)) {
    for (std::size_t k = 0; k < n; ++k) tail_one(x[k], y[k]);
    return;
  }
  // x ≥ 32: erfc(x) = 0 in double, so f(x) = 1 has error 0 (< 2^−1000 ulp).
  std::uint64_t ones = 0;
  double first_one = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::bit_cast<std::uint32_t>(y[k]) == kFloatOneBits) {
      if (ones++ == 0) first_one = x[k];
    } else {
      tail_one(x[k], y[k]);
    }
  }
  if (ones) {
    ErfStats run;
    run.add(first_one, 0.0, 0.0, true);
    run.count = ones;
    run.correctly_rounded = ones;
    run.histogram[0] = ones;
    stats.merge(run);
    tail.merge(run);
  }
}

std::shared_ptr<ErfFloatAccum> make_float_accum(std::size_t bins) {
  auto a = std::make_shared<ErfFloatAccum>();
  a->bins.assign(bins, ErfBin{});
  a->bin_scale = static_cast<double>(bins) / 4.0;
  return a;
}

std::vector<FloatSegment> float_segments(const ErfFloatOptions& o) {
  std::vector<FloatSegment> s;
  if (o.exhaustive) {
    const std::uint32_t far_stride = std::max<std::uint32_t>(1, o.exhaustive_tail_stride);
    s.push_back({FloatSegment::bits, 0, 1, 0, kErfFloatTailBits, false});
    s.push_back(
        {FloatSegment::bits, kErfFloatTailBits, 1, 0, kErfFloatFarBits - kErfFloatTailBits, true});
    s.push_back({FloatSegment::bits, kErfFloatFarBits, far_stride, 0,
                 (kErfFloatMaxBits - kErfFloatFarBits) / far_stride + 1, true});
    return s;
  }
  const std::uint32_t stride = std::max<std::uint32_t>(1, o.stride);
  const std::uint32_t tail_stride = std::max<std::uint32_t>(1, o.tail_stride);
  s.push_back({FloatSegment::bits, 0, stride, 0, (kErfFloatTailBits - 1) / stride + 1, false});
  if (o.grid_log2 > 0) {
    // i·step exact for i < 2^24
    const int g = static_cast<int>(std::min<std::uint32_t>(o.grid_log2, 24));
    s.push_back({FloatSegment::grid, 0, 0, std::ldexp(4.0f, -g), std::uint64_t{1} << g, false});
  }
  s.push_back({FloatSegment::bits, kErfFloatTailBits, tail_stride, 0,
               (kErfFloatMaxBits - kErfFloatTailBits) / tail_stride + 1, true});
  return s;
}

void finish_float_report(ErfReport& report,
                         const std::vector<std::shared_ptr<ErfFloatAccum>>& parts,
                         const ErfFloatOptions& options) {
  report.tail_from = 4.0;
  report.series_x_max = 4.0;
  report.series.assign(options.bins, ErfBin{});
  for (std::size_t b = 0; b < options.bins; ++b) {
    report.series[b].x_lo = 4.0 * static_cast<double>(b) / static_cast<double>(options.bins);
    report.series[b].x_hi = 4.0 * static_cast<double>(b + 1) / static_cast<double>(options.bins);
  }
  for (const auto& p : parts) {
    report.stats.merge(p->stats);
    report.tail.merge(p->tail);
    report.ambiguous_resolved += p->ambiguous;
    report.reference_selfcheck_ulps = std::max(report.reference_selfcheck_ulps, p->selfcheck);
    for (std::size_t b = 0; b < p->bins.size(); ++b) report.series[b].merge(p->bins[b]);
  }
  report.reference = fmt::format(
      "correctly rounded float erf: x < 4 from a degree-6 Taylor expansion in double about "
      "erfl/expl centres (runs of {} points) or std::erf in double, points within 8 double ulps of "
      "a float midpoint decided with Boost.Math erf in cpp_bin_float_50 ({} here); Taylor vs "
      "std::erf at run ends: max {:.3g} double ulps; x >= 4: RN(erf) = 1 (erfc(4) < 2^-25), erf = "
      "1 - erfc(x) with erfc in double",
      reference::detail::kRun, report.ambiguous_resolved, report.reference_selfcheck_ulps);
}

std::string float_coverage(const ErfFloatOptions& o, std::uint64_t odd_checked) {
  std::string s;
  if (o.exhaustive) {
    const std::uint32_t far_stride = std::max<std::uint32_t>(1, o.exhaustive_tail_stride);
    if (far_stride == 1)
      s = fmt::format(
          "every float in [0, 4) ({} points) and every float in [4, FLT_MAX] ({} points)",
          group_digits(kErfFloatTailBits),
          group_digits(std::uint64_t{kErfFloatMaxBits} - kErfFloatTailBits + 1));
    else
      s = fmt::format(
          "every float in [0, 4) ({} points), every float in [4, 64) ({} points), every {}th bit "
          "pattern in [64, FLT_MAX] ({} points; above 64 erfc underflows in double and e^(-x^2) in "
          "float)",
          group_digits(kErfFloatTailBits), group_digits(kErfFloatFarBits - kErfFloatTailBits),
          far_stride, group_digits((kErfFloatMaxBits - kErfFloatFarBits) / far_stride + 1));
  } else {
    const std::uint32_t stride = std::max<std::uint32_t>(1, o.stride);
    const std::uint32_t tail_stride = std::max<std::uint32_t>(1, o.tail_stride);
    s = fmt::format("sample: every {}th float bit pattern in [0, 4) ({} points)", stride,
                    group_digits((kErfFloatTailBits - 1) / stride + 1));
    if (o.grid_log2 > 0) {
      const auto g = std::min<std::uint32_t>(o.grid_log2, 24);
      s += fmt::format(", the uniform grid i*2^{} in [0, 4) ({} points)", 2 - static_cast<int>(g),
                       group_digits(std::uint64_t{1} << g));
    }
    s += fmt::format(", every {}th bit pattern in [4, FLT_MAX] ({} points)", tail_stride,
                     group_digits((kErfFloatMaxBits - kErfFloatTailBits) / tail_stride + 1));
  }
  s += fmt::format(
      "; negatives by oddness on every {}th bit pattern in (0, FLT_MAX] ({} points); special "
      "values",
      std::max<std::uint32_t>(1, o.odd_stride), group_digits(odd_checked));
  return s;
}

std::vector<float> float_specials() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  return {0.0f,
          -0.0f,
          std::numeric_limits<float>::denorm_min(),
          -std::numeric_limits<float>::denorm_min(),
          FLT_MIN,
          -FLT_MIN,
          1.0f,
          -1.0f,
          FLT_MAX,
          -FLT_MAX,
          inf,
          -inf,
          std::numeric_limits<float>::quiet_NaN()};
}

std::vector<double> double_specials() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {0.0,
          -0.0,
          std::numeric_limits<double>::denorm_min(),
          -std::numeric_limits<double>::denorm_min(),
          DBL_MIN,
          -DBL_MIN,
          1.0,
          -1.0,
          DBL_MAX,
          -DBL_MAX,
          inf,
          -inf,
          std::numeric_limits<double>::quiet_NaN()};
}

bool same_result(double expected, double got) {
  if (std::isnan(expected)) return std::isnan(got);
  return std::bit_cast<std::uint64_t>(expected) == std::bit_cast<std::uint64_t>(got);
}

std::string double_coverage(const reference::ErfDoubleSample& s, std::uint64_t odd_checked) {
  return fmt::format(
      "sample: uniform grid i*{}/{} in [0, {}) ({} points), {} evenly spaced bit patterns in (0, "
      "{}) (every binade), {} evenly spaced bit patterns in [{}, DBL_MAX]; negatives by oddness on "
      "{} bit patterns in (0, DBL_MAX]; special values",
      s.options.x_max, s.options.grid_points, s.options.x_max, group_digits(s.grid_end),
      group_digits(s.main_end - s.grid_end), s.options.x_max, group_digits(s.x.size() - s.main_end),
      s.options.x_max, group_digits(odd_checked));
}

}  // namespace detail

}  // namespace sglab::validate
