// validate/erf_check.cpp — references, reduction and output of the erf
// checker (validate/erf_check.hpp has the definitions).
#include "erf_check.hpp"

#include <cfloat>
#include <stdexcept>

#include <boost/math/special_functions/erf.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace sglab::validate {

namespace {

using Big = boost::multiprecision::cpp_bin_float_50;

const Big& two_over_sqrt_pi_50() {
  static const Big v = Big(2) / boost::multiprecision::sqrt(boost::math::constants::pi<Big>());
  return v;
}

// Taylor coefficients erf^(k)(x0)/k!, k = 0 … N−1, in 50 digits:
// erf^(k)(x) = (2/√π)(−1)^(k−1) H_{k−1}(x) e^{−x²} (physicists' Hermite H).
template <std::size_t N> std::array<Big, N> taylor_coefficients_50(const Big& x0) {
  std::array<Big, N> H;  // H_0 … H_{N−2}: H_{n+1} = 2x H_n − 2n H_{n−1}
  H[0] = 1;
  if (N > 2) H[1] = 2 * x0;
  for (std::size_t n = 1; n + 2 < N; ++n) H[n + 1] = 2 * x0 * H[n] - 2 * static_cast<unsigned>(n) * H[n - 1];
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
const std::array<long double, kMaclaurinTerms>& maclaurin_coefficients() {
  static const std::array<long double, kMaclaurinTerms> c = [] {
    std::array<long double, kMaclaurinTerms> r{};
    Big factorial = 1;
    for (std::size_t n = 0; n < kMaclaurinTerms; ++n) {
      if (n) factorial *= static_cast<unsigned>(n);
      const Big v = two_over_sqrt_pi_50() / (factorial * (2 * n + 1));
      r[n] = static_cast<long double>(n % 2 ? Big(-v) : v);
    }
    return r;
  }();
  return c;
}
long double erf_maclaurin(long double x) {
  const auto& c = maclaurin_coefficients();
  const long double x2 = x * x;
  long double s = c[kMaclaurinTerms - 1];
  for (std::size_t n = kMaclaurinTerms - 1; n-- > 0;) s = s * x2 + c[n];
  return x * s;
}

std::string hex(double x) { return fmt::format("{:a}", x); }

// Shortest decimal that reads back as the same float / double.
std::string shortest(double x, const std::string& precision) {
  return precision == "float" ? fmt::format("{}", static_cast<float>(x)) : fmt::format("{}", x);
}

std::string count_str(std::uint64_t n) {
  std::string s = std::to_string(n), out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i && (s.size() - i) % 3 == 0) out += ',';
    out += s[i];
  }
  return out;
}

double max_or_zero(double v) { return v < 0 ? 0.0 : v; }

}  // namespace

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
  if (o.max_ulp > max_ulp || (o.max_ulp == max_ulp && o.worst_x < worst_x)) max_ulp = o.max_ulp, worst_x = o.worst_x;
  if (o.max_abs > max_abs || (o.max_abs == max_abs && o.worst_abs_x < worst_abs_x))
    max_abs = o.max_abs, worst_abs_x = o.worst_abs_x;
  if (o.nonfinite && !(o.first_nonfinite_x >= first_nonfinite_x)) first_nonfinite_x = o.first_nonfinite_x;
  for (std::size_t i = 0; i < histogram.size(); ++i) histogram[i] += o.histogram[i];
}

// --- references ------------------------------------------------------------

long double erf_reference_50(double x) { return static_cast<long double>(boost::math::erf(Big(x))); }
long double erfc_reference_50(double x) { return static_cast<long double>(boost::math::erfc(Big(x))); }

namespace detail {

namespace {
Big erf_50(float x) { return boost::math::erf(Big(x)); }
}  // namespace

ErfFloatReference erf_resolve_float(float x) {
  const Big v = erf_50(x);
  const float r = static_cast<float>(static_cast<double>(v));
  float best = r;
  Big best_d = abs(Big(r) - v);
  for (float nb : {std::nextafter(r, -std::numeric_limits<float>::infinity()),
                   std::nextafter(r, std::numeric_limits<float>::infinity())}) {
    const Big d = abs(Big(nb) - v);
    if (d < best_d) best = nb, best_d = d;
  }
  return {static_cast<double>(v), best, true};
}

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

namespace {

// Float ↔ double through the bits: converting a subnormal float in hardware
// costs a microcode assist (~100 cycles) on x86, and 0.4 % of the inputs are
// subnormal.
inline double to_double(std::uint32_t b) {
  if ((b & 0x7f800000u) == 0) {
    const double m = static_cast<double>(b & 0x7fffffu) * 0x1p-149;
    return b >> 31 ? -m : m;
  }
  return static_cast<double>(std::bit_cast<float>(b));
}
// Bits of RN(r) for r ≥ 0 finite (round to nearest even).
inline std::uint32_t round_to_float_bits(double r) {
  if (r >= 0x1p-126) return std::bit_cast<std::uint32_t>(static_cast<float>(r));
  const double q = r * 0x1p149;  // exact, < 2^23
  return static_cast<std::uint32_t>((q + 0x1p52) - 0x1p52);  // RN to integer; 2^23 → FLT_MIN's bits
}
// 1 / ulp_float(r) for r ≥ 0 finite (a power of two).
inline double inv_ulp_float(double r) {
  if (!(r >= 0x1p-126)) return 0x1p149;
  const auto e = static_cast<int>(std::bit_cast<std::uint64_t>(r) >> 52) - 1023;
  return std::bit_cast<double>(static_cast<std::uint64_t>(23 - e + 1023) << 52);
}
// erf_histogram_bucket without a libm call.
inline std::size_t bucket_fast(double err, bool cr) {
  if (cr) return 0;
  if (err <= 0.5) return 1;
  const auto b = std::bit_cast<std::uint64_t>(err);
  const int e = static_cast<int>(b >> 52) - 1023;  // floor(log2 err) ≥ −1
  const int k = (b & ((std::uint64_t{1} << 52) - 1)) == 0 ? e : e + 1;
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
  if (near_float_midpoint(ref)) {  // decide RN and the error in 50 digits
    const ErfFloatReference r = erf_resolve_float(static_cast<float>(x));
    exact = r.exact;
    cr = std::bit_cast<std::uint32_t>(r.rounded);
    err_abs = static_cast<double>(abs(Big(y) - erf_50(static_cast<float>(x))));
    ++ambiguous;
  }
  const double err_ulp = err_abs * inv_ulp_float(exact);
  stats.add(x, err_ulp, err_abs, yb == cr || ((yb | cr) & 0x7fffffffu) == 0);
  if (!bins.empty()) bins[std::min(bins.size() - 1, static_cast<std::size_t>(x * bin_scale))].add(x, err_ulp, err_abs);
}

void ErfFloatAccum::main_run(const float* x, const float* y, std::size_t n) {
  if (n == 0) return;
  // Straight passes over arrays (the arithmetic ones vectorize); the
  // non-finite and midpoint points take main_slow and are skipped after.
  alignas(64) double xd[kRun];
  alignas(64) double ref[kRun];
  alignas(64) double err_abs[kRun];
  alignas(64) double err_ulp[kRun];
  alignas(64) std::uint8_t bucket[kRun];
  constexpr std::uint8_t kSkip = 255;
  for (std::size_t k = 0; k < n; ++k) xd[k] = to_double(std::bit_cast<std::uint32_t>(x[k]));
  const ErfTaylorFloat t = erf_taylor_float(xd[0], xd[(n - 1) / 2], xd[n - 1]);
  if (t.ok) {
    for (std::size_t k = 0; k < n; ++k) ref[k] = t(xd[k]);
    const double direct = std::erf(xd[n - 1]);
    selfcheck = std::max(selfcheck, std::abs(ref[n - 1] - direct) / static_cast<double>(ulp_double(direct)));
  } else {
    for (std::size_t k = 0; k < n; ++k) ref[k] = std::erf(xd[k]);
  }
  for (std::size_t k = 0; k < n; ++k) err_abs[k] = to_double(std::bit_cast<std::uint32_t>(y[k]));
  for (std::size_t k = 0; k < n; ++k) {
    // 1/ulp_float(ref) = 2^23 · min(2^−floor(log2 ref), 2^126), through the exponent bits.
    const std::uint64_t e = std::bit_cast<std::uint64_t>(ref[k]) & 0x7ff0000000000000u;
    const double inv_p2 = std::bit_cast<double>(0x7fe0000000000000u - e);
    const double inv = (inv_p2 < 0x1p126 ? inv_p2 : 0x1p126) * 0x1p23;
    err_abs[k] = std::abs(err_abs[k] - ref[k]);
    err_ulp[k] = err_abs[k] * inv;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const auto yb = std::bit_cast<std::uint32_t>(y[k]);
    if ((yb & 0x7f800000u) == 0x7f800000u || near_float_midpoint(ref[k])) [[unlikely]] {
      bucket[k] = kSkip;
      main_slow(xd[k], y[k], ref[k]);
      continue;
    }
    const std::uint32_t crb = round_to_float_bits(ref[k]);
    bucket[k] = static_cast<std::uint8_t>(bucket_fast(err_ulp[k], yb == crb || ((yb | crb) & 0x7fffffffu) == 0));
  }

  std::uint32_t hist[4][kErfHistBuckets] = {};  // 4 interleaved copies: no store-to-load chain
  double sq0 = 0, sq1 = 0;
  std::uint64_t count = 0;
  double max_ulp = -1, max_ulp_x = 0, max_abs = -1, max_abs_x = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint8_t b = bucket[k];
    if (b == kSkip) [[unlikely]] continue;
    ++count;
    ++hist[k & 3][b];
    (k & 1 ? sq1 : sq0) += err_ulp[k] * err_ulp[k];
    if (err_ulp[k] > max_ulp) [[unlikely]] max_ulp = err_ulp[k], max_ulp_x = xd[k];
    if (err_abs[k] > max_abs) [[unlikely]] max_abs = err_abs[k], max_abs_x = xd[k];
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
  const auto bin_of = [&](double v) { return std::min(bins.size() - 1, static_cast<std::size_t>(v * bin_scale)); };
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
    if (std::bit_cast<std::uint32_t>(y[k]) == 0x3f800000u) {
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
    s.push_back({FloatSegment::bits, kErfFloatTailBits, 1, 0, kErfFloatFarBits - kErfFloatTailBits, true});
    s.push_back({FloatSegment::bits, kErfFloatFarBits, far_stride, 0, (kErfFloatMaxBits - kErfFloatFarBits) / far_stride + 1, true});
    return s;
  }
  const std::uint32_t stride = std::max<std::uint32_t>(1, o.stride);
  const std::uint32_t tail_stride = std::max<std::uint32_t>(1, o.tail_stride);
  s.push_back({FloatSegment::bits, 0, stride, 0, (kErfFloatTailBits - 1) / stride + 1, false});
  if (o.grid_log2 > 0) {
    const int g = static_cast<int>(std::min<std::uint32_t>(o.grid_log2, 24));  // i·step exact for i < 2^24
    s.push_back({FloatSegment::grid, 0, 0, std::ldexp(4.0f, -g), std::uint64_t{1} << g, false});
  }
  s.push_back({FloatSegment::bits, kErfFloatTailBits, tail_stride, 0, (kErfFloatMaxBits - kErfFloatTailBits) / tail_stride + 1, true});
  return s;
}

void finish_float_report(ErfReport& report, const std::vector<std::shared_ptr<ErfFloatAccum>>& parts,
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
      "correctly rounded float erf: x < 4 from a degree-6 Taylor expansion in double about erfl/expl centres "
      "(runs of {} points) or std::erf in double, points within 8 double ulps of a float midpoint decided with "
      "Boost.Math erf in cpp_bin_float_50 ({} here); Taylor vs std::erf at run ends: max {:.3g} double ulps; "
      "x >= 4: RN(erf) = 1 (erfc(4) < 2^-25), erf = 1 - erfc(x) with erfc in double",
      kRun, report.ambiguous_resolved, report.reference_selfcheck_ulps);
}

std::string float_coverage(const ErfFloatOptions& o, std::uint64_t odd_checked) {
  std::string s;
  if (o.exhaustive) {
    const std::uint32_t far_stride = std::max<std::uint32_t>(1, o.exhaustive_tail_stride);
    if (far_stride == 1)
      s = fmt::format("every float in [0, 4) ({} points) and every float in [4, FLT_MAX] ({} points)",
                      count_str(kErfFloatTailBits), count_str(std::uint64_t{kErfFloatMaxBits} - kErfFloatTailBits + 1));
    else
      s = fmt::format("every float in [0, 4) ({} points), every float in [4, 64) ({} points), every {}th bit pattern "
                      "in [64, FLT_MAX] ({} points; above 64 erfc underflows in double and e^(-x^2) in float)",
                      count_str(kErfFloatTailBits), count_str(kErfFloatFarBits - kErfFloatTailBits), far_stride,
                      count_str((kErfFloatMaxBits - kErfFloatFarBits) / far_stride + 1));
  } else {
    const std::uint32_t stride = std::max<std::uint32_t>(1, o.stride);
    const std::uint32_t tail_stride = std::max<std::uint32_t>(1, o.tail_stride);
    s = fmt::format("sample: every {}th float bit pattern in [0, 4) ({} points)", stride,
                    count_str((kErfFloatTailBits - 1) / stride + 1));
    if (o.grid_log2 > 0) {
      const auto g = std::min<std::uint32_t>(o.grid_log2, 24);
      s += fmt::format(", the uniform grid i*2^{} in [0, 4) ({} points)", 2 - static_cast<int>(g),
                       count_str(std::uint64_t{1} << g));
    }
    s += fmt::format(", every {}th bit pattern in [4, FLT_MAX] ({} points)", tail_stride,
                     count_str((kErfFloatMaxBits - kErfFloatTailBits) / tail_stride + 1));
  }
  s += fmt::format("; negatives by oddness on every {}th bit pattern in (0, FLT_MAX] ({} points); special values",
                   std::max<std::uint32_t>(1, o.odd_stride), count_str(odd_checked));
  return s;
}

std::vector<float> float_specials() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  return {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
          FLT_MIN, -FLT_MIN, 1.0f, -1.0f, FLT_MAX, -FLT_MAX, inf, -inf, std::numeric_limits<float>::quiet_NaN()};
}

std::vector<double> double_specials() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {0.0, -0.0, std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min(),
          DBL_MIN, -DBL_MIN, 1.0, -1.0, DBL_MAX, -DBL_MAX, inf, -inf, std::numeric_limits<double>::quiet_NaN()};
}

bool same_result(double expected, double got) {
  if (std::isnan(expected)) return std::isnan(got);
  return std::bit_cast<std::uint64_t>(expected) == std::bit_cast<std::uint64_t>(got);
}

long double erf_special_expected_double(double x) {
  if (std::isnan(x)) return x;
  if (std::isinf(x)) return x > 0 ? 1.0L : -1.0L;
  if (x == 0) return x;  // keeps the sign of zero
  const Big v = boost::math::erf(Big(std::abs(x)));
  // RN to double, decided in 50 digits.
  const double r = static_cast<double>(v);
  double best = r;
  Big best_d = abs(Big(r) - v);
  for (double nb : {std::nextafter(r, 0.0), std::nextafter(r, 2.0)}) {
    const Big d = abs(Big(nb) - v);
    if (d < best_d) best = nb, best_d = d;
  }
  return x < 0 ? -best : best;
}

std::string double_coverage(const ErfDoubleSample& s, std::uint64_t odd_checked) {
  return fmt::format(
      "sample: uniform grid i*{}/{} in [0, {}) ({} points), {} evenly spaced bit patterns in (0, {}) (every "
      "binade), {} evenly spaced bit patterns in [{}, DBL_MAX]; negatives by oddness on {} bit patterns in "
      "(0, DBL_MAX]; special values",
      s.options.x_max, s.options.grid_points, s.options.x_max, count_str(s.grid_end), count_str(s.main_end - s.grid_end),
      s.options.x_max, count_str(s.x.size() - s.main_end), s.options.x_max, count_str(odd_checked));
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
    r = detail::near_float_midpoint(y) ? detail::erf_resolve_float(a) : ErfFloatReference{y, static_cast<float>(y), false};
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
    const std::uint64_t step = options.tail_points > 1 ? (dmax_bits - xmax_bits) / (options.tail_points - 1) : 0;
    s.x.push_back(std::bit_cast<double>(xmax_bits + step * k));
  }
  s.ref.assign(s.x.size(), 0.0L);

  // Grid: runs of up to detail::kRun points, half-width h ≤ 2^−7. x ≤ 1/2: Maclaurin
  // series in long double; else a degree-12 Taylor expansion about a 50-digit centre
  // (remainder < (2/√π)·1.0865·2^6·√12!/13!·h^13 < 2^−100).
  constexpr std::size_t kDeg = 13;
  const double step = options.x_max / static_cast<double>(std::max<std::size_t>(n_grid, 1));
  const std::size_t run_len = std::clamp<std::size_t>(static_cast<std::size_t>(0x1p-6 / step), 1, detail::kRun);
  const std::size_t runs = (s.grid_end + run_len - 1) / run_len;
  tbb::enumerable_thread_specific<double> selfcheck(0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs, 1), [&](const tbb::blocked_range<std::size_t>& r) {
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
        for (std::size_t i = i0; i < i1; ++i) {
          const long double hh = static_cast<long double>(s.x[i]) - x0;  // exact (Sterbenz)
          long double y = c[kDeg - 1];
          for (std::size_t k = kDeg - 1; k-- > 0;) y = y * hh + c[k];
          s.ref[i] = y;
        }
      } else {
        for (std::size_t i = i0; i < i1; ++i) s.ref[i] = erf_reference_50(s.x[i]);
      }
      if (run % 16 == 0 || run + 1 == runs) {  // spot check the run's far end against 50 digits
        const long double direct = erf_reference_50(xb);
        double& m = selfcheck.local();
        m = std::max(m, static_cast<double>(std::abs(s.ref[i1 - 1] - direct) / ulp_double(direct)));
      }
    }
  });
  for (double m : selfcheck) s.selfcheck_ulps = std::max(s.selfcheck_ulps, m);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(s.grid_end, s.x.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      s.ref[i] = i < s.main_end ? erf_reference_50(s.x[i]) : erfc_reference_50(s.x[i]);
  });
  for (std::size_t i = s.main_end; i < s.x.size(); ++i)
    if (!(s.ref[i] < 0x1p-54L)) throw std::logic_error("erf double sample: erfc(x_max) >= 2^-54, RN(erf) is not 1");
  s.reference = fmt::format(
      "erf in 50 digits (Boost.Math, cpp_bin_float_50), carried in long double: x <= 1/2 by its Maclaurin series, "
      "the grid above by a degree-{} Taylor expansion about a 50-digit centre per run of {} points (max deviation "
      "from direct 50-digit evaluation at spot points: {:.3g} double ulps), the other points directly; x >= {}: "
      "RN(erf) = 1, erf = 1 - erfc(x) with erfc in 50 digits",
      kDeg - 1, run_len, s.selfcheck_ulps, options.x_max);
  return s;
}

// --- output ----------------------------------------------------------------

namespace {

nlohmann::json stats_json(const ErfStats& st) {
  nlohmann::json j;
  j["max_abs"] = max_or_zero(st.max_abs);
  j["max_ulp"] = max_or_zero(st.max_ulp);
  j["worst_x"] = st.worst_x;
  j["worst_x_hex"] = hex(st.worst_x);
  j["worst_x_abs"] = st.worst_abs_x;
  j["rms_ulp"] = st.rms_ulp();
  j["count"] = st.count;
  j["nonfinite"] = st.nonfinite;
  j["correctly_rounded"] = st.correctly_rounded;
  if (st.nonfinite) j["first_nonfinite_x"] = st.first_nonfinite_x;
  return j;
}

std::string percent(std::uint64_t n, std::uint64_t total) {
  if (n == 0) return "-";
  const double p = 100.0 * static_cast<double>(n) / static_cast<double>(total ? total : 1);
  if (p < 0.01) return fmt::format("<0.01% ({})", n);
  return fmt::format("{:.2f}%", p);
}

std::string fmt_ulp(double v) { return v < 0 ? "-" : fmt::format("{:.4g}", v); }
std::string fmt_abs(double v) { return v < 0 ? "-" : fmt::format("{:.3e}", v); }
std::string fmt_value(double v) {
  if (std::isnan(v)) return "nan";
  return fmt::format("{:a}", v);
}

}  // namespace

std::string erf_reports_json(const std::vector<ErfReport>& reports, bool exhaustive) {
  nlohmann::json root;
  root["mode"] = exhaustive ? "exhaustive" : "sample";
  root["ulp_definition"] =
      "|f(x) - erf(x)| / ulp(erf(x)), exact erf(x); ulp(y) = 2^(floor(log2|y|) - p + 1) "
      "(p = 24 float, 53 double), 2^-149 / 2^-1074 below the normal range";
  nlohmann::json results = nlohmann::json::array();
  for (const ErfReport& r : reports) {
    nlohmann::json j = stats_json(r.stats);
    j["variant"] = r.variant;
    j["precision"] = r.precision;
    nlohmann::json hist = nlohmann::json::array();
    for (std::size_t i = 0; i < kErfHistBuckets; ++i) {
      const double up = erf_histogram_upper(i);
      hist.push_back({{"bucket", erf_histogram_label(i)},
                      {"max_ulp", std::isinf(up) ? nlohmann::json(nullptr) : nlohmann::json(up)},
                      {"count", r.stats.histogram[i]}});
    }
    j["histogram"] = hist;
    nlohmann::json tail = stats_json(r.tail);
    tail["from_x"] = r.tail_from;
    tail["not_correctly_rounded"] = r.tail.count - r.tail.correctly_rounded;
    j["constant_region"] = tail;
    j["oddness"] = {{"checked", r.oddness.checked}, {"violations", r.oddness.violations}};
    if (r.oddness.violations) j["oddness"]["first_violation_x"] = r.oddness.first_violation_x;
    nlohmann::json specials = nlohmann::json::array();
    for (const ErfSpecial& sp : r.specials)
      specials.push_back({{"x", fmt_value(sp.x)}, {"expected", fmt_value(sp.expected)}, {"got", fmt_value(sp.got)}, {"ok", sp.ok}});
    j["specials"] = specials;
    j["ambiguous_resolved"] = r.ambiguous_resolved;
    j["reference_selfcheck_ulps"] = r.reference_selfcheck_ulps;
    j["coverage"] = r.coverage;
    j["reference"] = r.reference;
    j["seconds"] = r.seconds;
    results.push_back(std::move(j));
  }
  root["results"] = std::move(results);
  return root.dump(2) + "\n";
}

std::string erf_reports_markdown(const std::vector<ErfReport>& reports, bool exhaustive) {
  std::string md;
  md += fmt::format("# erf accuracy against the correctly rounded erf ({})\n\n", exhaustive ? "exhaustive" : "sample");
  md += "err_ulp = |f(x) - erf(x)| / ulp(erf(x)) with the exact erf(x) (not its rounding); ulp(y) = "
        "2^(floor(log2|y|) - 23) in float, - 52 in double (subnormal spacing below the normal range). "
        "`cr` = correctly rounded results. Non-finite outputs are counted apart and excluded from the rest.\n\n";
  md += "| variant | precision | max ulp | worst x | worst x (hex) | max abs | worst x (abs) | rms ulp | cr | points | "
        "nonfinite | time |\n";
  md += "|---|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const ErfReport& r : reports) {
    const ErfStats& s = r.stats;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.4g} | {} | {} | {} | {:.2f} s |\n", r.variant, r.precision,
                      fmt_ulp(s.max_ulp), shortest(s.worst_x, r.precision), hex(s.worst_x), fmt_abs(s.max_abs),
                      shortest(s.worst_abs_x, r.precision),
                      s.rms_ulp(), percent(s.correctly_rounded, s.count), count_str(s.count), count_str(s.nonfinite),
                      r.seconds);
  }

  // Histogram: rows = buckets (non-empty in some report), columns = reports.
  md += "\n## ulp error distribution (share of points; bucket `<=2^k` holds 2^(k-1) < err <= 2^k)\n\n| bucket |";
  for (const ErfReport& r : reports) md += fmt::format(" {} {} |", r.variant, r.precision);
  md += "\n|---|";
  for (std::size_t i = 0; i < reports.size(); ++i) md += "--:|";
  md += "\n";
  for (std::size_t b = 0; b < kErfHistBuckets; ++b) {
    bool any = false;
    for (const ErfReport& r : reports) any |= r.stats.histogram[b] != 0;
    if (!any) continue;
    md += fmt::format("| {} |", erf_histogram_label(b));
    for (const ErfReport& r : reports) md += fmt::format(" {} |", percent(r.stats.histogram[b], r.stats.count));
    md += "\n";
  }

  md += "\n## Constant region, oddness, references\n\n";
  md += "| variant | precision | constant region from | points | not RN (= not exactly 1) | max ulp there | odd checked | "
        "odd violations | midpoints resolved | reference self-check (double ulps) |\n";
  md += "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const ErfReport& r : reports) {
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {}{} | {} | {:.3g} |\n", r.variant, r.precision, r.tail_from,
                      count_str(r.tail.count), count_str(r.tail.count - r.tail.correctly_rounded + r.tail.nonfinite),
                      fmt_ulp(r.tail.max_ulp), count_str(r.oddness.checked), count_str(r.oddness.violations),
                      r.oddness.violations ? fmt::format(" (first x = {})", hex(r.oddness.first_violation_x)) : "",
                      count_str(r.ambiguous_resolved), r.reference_selfcheck_ulps);
  }

  for (const char* prec : {"float", "double"}) {
    std::vector<const ErfReport*> rs;
    for (const ErfReport& r : reports)
      if (r.precision == prec) rs.push_back(&r);
    if (rs.empty()) continue;
    md += fmt::format("\n## Special values ({}; expected = correctly rounded, sign of zero kept; x marks a mismatch)\n\n| x | expected |", prec);
    for (const ErfReport* r : rs) md += fmt::format(" {} |", r->variant);
    md += "\n|---|---|";
    for (std::size_t i = 0; i < rs.size(); ++i) md += "---|";
    md += "\n";
    for (std::size_t k = 0; k < rs.front()->specials.size(); ++k) {
      const ErfSpecial& sp = rs.front()->specials[k];
      md += fmt::format("| {} | {} |", fmt_value(sp.x), fmt_value(sp.expected));
      for (const ErfReport* r : rs)
        md += fmt::format(" {}{} |", fmt_value(r->specials[k].got), r->specials[k].ok ? "" : " x");
      md += "\n";
    }
  }

  md += "\n## Coverage and reference\n\n";
  std::vector<std::string> seen;
  for (const ErfReport& r : reports) {
    const std::pair<const char*, const std::string*> items[] = {{"coverage", &r.coverage}, {"reference", &r.reference}};
    for (const auto& [what, text] : items) {
      if (std::find(seen.begin(), seen.end(), r.precision + *text) != seen.end()) continue;
      seen.push_back(r.precision + *text);
      md += fmt::format("- {} ({}): {}\n", r.precision, what, *text);
    }
  }
  return md;
}

std::string erf_summary_csv(const std::vector<ErfReport>& reports) {
  std::string csv =
      "variant,precision,max_ulp,worst_x,worst_x_hex,max_abs,worst_x_abs,rms_ulp,count,correctly_rounded,nonfinite,"
      "tail_from,tail_count,tail_not_rn,odd_checked,odd_violations,ambiguous_resolved,seconds\n";
  for (const ErfReport& r : reports) {
    const ErfStats& s = r.stats;
    csv += fmt::format("{},{},{:.17g},{:.17g},{},{:.17g},{:.17g},{:.17g},{},{},{},{},{},{},{},{},{},{:.3f}\n", r.variant,
                       r.precision, max_or_zero(s.max_ulp), s.worst_x, hex(s.worst_x), max_or_zero(s.max_abs), s.worst_abs_x,
                       s.rms_ulp(), s.count, s.correctly_rounded, s.nonfinite, r.tail_from, r.tail.count,
                       r.tail.count - r.tail.correctly_rounded, r.oddness.checked, r.oddness.violations,
                       r.ambiguous_resolved, r.seconds);
  }
  return csv;
}

std::string erf_histogram_csv(const std::vector<ErfReport>& reports) {
  std::string csv = "variant,precision,bucket,max_ulp,count\n";
  for (const ErfReport& r : reports)
    for (std::size_t i = 0; i < kErfHistBuckets; ++i)
      csv += fmt::format("{},{},{},{},{}\n", r.variant, r.precision, erf_histogram_label(i), erf_histogram_upper(i),
                         r.stats.histogram[i]);
  return csv;
}

std::string erf_series_csv(const ErfReport& r) {
  std::string csv = "x_lo,x_hi,count,max_ulp,max_ulp_x,rms_ulp,max_abs\n";
  for (const ErfBin& b : r.series) {
    const double rms = b.count ? std::sqrt(b.sum_sq_ulp / static_cast<double>(b.count)) : 0.0;
    csv += fmt::format("{:.17g},{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g}\n", b.x_lo, b.x_hi, b.count, b.max_ulp,
                       b.max_ulp_x, rms, b.max_abs);
  }
  return csv;
}

}  // namespace sglab::validate
