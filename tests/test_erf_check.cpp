// The erf checker (validate/erf_check.hpp) and `sglab erf`: the checker finds
// injected errors, its reference is correctly rounded (checked against
// independent 50-digit evaluation), and the published claims hold.
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <boost/math/special_functions/erf.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <nlohmann/json.hpp>

#include <sglab/erf.hpp>
#include <sglab/registry.hpp>

#include "tests/test_support.hpp"

#include "validate/erf_check.hpp"

namespace {

using sglab::validate::ErfFloatOptions;
using sglab::validate::ErfReport;
using Big = boost::multiprecision::cpp_bin_float_50;

// A small strided sample: fast in Debug too.
ErfFloatOptions small_options() {
  ErfFloatOptions o;
  o.stride = 4093;
  o.grid_log2 = 16;
  o.tail_stride = 65537;
  o.odd_stride = 65537;
  o.bins = 100;
  return o;
}

// Correctly rounded float erf computed independently: 50 digits, nearest of
// the three floats around the double rounding.
float cr_erf_50(float x) {
  const Big v = boost::math::erf(Big(x));
  const float r = static_cast<float>(static_cast<double>(v));
  float best = r;
  Big bd = abs(Big(r) - v);
  for (float nb : {std::nextafter(r, -INFINITY), std::nextafter(r, INFINITY)}) {
    const Big d = abs(Big(nb) - v);
    if (d < bd) best = nb, bd = d;
  }
  return best;
}

std::string hexf(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

}  // namespace

TEST(ErfCheck, UlpDefinitions) {
  using sglab::reference::ulp_double;
  using sglab::reference::ulp_float;
  EXPECT_EQ(ulp_float(1.0), 0x1p-23);
  EXPECT_EQ(ulp_float(0.75), 0x1p-24);
  EXPECT_EQ(ulp_float(std::nextafter(1.0, 0.0)), 0x1p-24);
  EXPECT_EQ(ulp_float(-3.0), 0x1p-22);
  EXPECT_EQ(ulp_float(0.0), 0x1p-149);
  EXPECT_EQ(ulp_float(1e-40), 0x1p-149);
  EXPECT_EQ(ulp_float(FLT_MIN), 0x1p-149);
  EXPECT_EQ(ulp_float(2.0 * FLT_MIN), 0x1p-148);
  EXPECT_EQ(ulp_double(1.0L), 0x1p-52L);
  EXPECT_EQ(ulp_double(0.75L), 0x1p-53L);
  EXPECT_EQ(ulp_double(0.0L), 0x1p-1074L);
  EXPECT_EQ(ulp_double(static_cast<long double>(DBL_MIN)), 0x1p-1074L);
}

TEST(ErfCheck, HistogramBuckets) {
  using sglab::validate::erf_histogram_bucket;
  using sglab::validate::kErfHistBuckets;
  EXPECT_EQ(erf_histogram_bucket(0.3, true), 0u);
  EXPECT_EQ(erf_histogram_bucket(0.3, false), 1u);
  EXPECT_EQ(erf_histogram_bucket(0.5000001, false), 2u);  // (0.5, 1]
  EXPECT_EQ(erf_histogram_bucket(1.0, false), 2u);
  EXPECT_EQ(erf_histogram_bucket(1.5, false), 3u);  // (1, 2]
  EXPECT_EQ(erf_histogram_bucket(4.0, false), 4u);  // (2, 4]
  EXPECT_EQ(erf_histogram_bucket(0x1p24, false), kErfHistBuckets - 2);
  EXPECT_EQ(erf_histogram_bucket(0x1p30, false), kErfHistBuckets - 1);
  EXPECT_EQ(sglab::validate::erf_histogram_label(0), "cr");
  EXPECT_EQ(sglab::validate::erf_histogram_label(3), "<=2");
}

// The fast reference (double erf + midpoint detection + 50-digit resolution)
// is the correctly rounded erf: compare with independent 50-digit rounding.
TEST(ErfCheck, ReferenceIsCorrectlyRounded) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<std::uint32_t> bits(0, 0x40900000u);
  for (int i = 0; i < 3000; ++i) {
    const float x = std::bit_cast<float>(bits(rng));
    const float got = sglab::reference::erf_reference_float(x).rounded;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(got), std::bit_cast<std::uint32_t>(cr_erf_50(x)))
        << "x = " << hexf(x);
  }
  for (float x : {0x1p-149f, 0x1p-126f, 0.5f, 1.0f, 3.9f, 3.92f, 3.95f, 4.0f, 1e30f}) {
    ASSERT_EQ(sglab::reference::erf_reference_float(x).rounded, cr_erf_50(x)) << "x = " << hexf(x);
    ASSERT_EQ(sglab::reference::erf_reference_float(-x).rounded, -cr_erf_50(x))
        << "x = " << hexf(-x);
  }
  EXPECT_TRUE(std::signbit(sglab::reference::erf_reference_float(-0.0f).rounded));
}

// The Taylor runs of the float check agree with a direct 50-digit
// evaluation; the checker of the correctly rounded function itself reports
// only correctly rounded points.
TEST(ErfCheck, CorrectlyRoundedFunctionScoresPerfectly) {
  auto cr = [](float x) { return sglab::reference::erf_reference_float(x).rounded; };
  ErfFloatOptions o = small_options();
  const ErfReport r = sglab::validate::check_erf_float(cr, o, "cr");
  EXPECT_EQ(r.stats.correctly_rounded, r.stats.count);
  EXPECT_LE(r.stats.max_ulp, 0.5 + 1e-6);
  EXPECT_EQ(r.oddness.violations, 0u);
  for (const auto& sp : r.specials) EXPECT_TRUE(sp.ok) << "x = " << hexf(sp.x);
  EXPECT_LT(r.reference_selfcheck_ulps, 4.0);
}

TEST(ErfCheck, TaylorReferenceMatches50Digits) {
  // A run of consecutive floats in [2, 4), as in the exhaustive loop.
  const float x0 = 3.1f;
  const std::uint32_t b0 = std::bit_cast<std::uint32_t>(x0);
  const auto t = sglab::reference::detail::erf_taylor_float(std::bit_cast<float>(b0 - 512), x0,
                                                            std::bit_cast<float>(b0 + 511));
  static_assert(std::is_same_v<decltype(t(1.0)), double>);
  ASSERT_TRUE(t.ok);
  for (std::uint32_t d : {0u, 1u, 100u, 511u}) {
    for (std::uint32_t b : {b0 + d, b0 - d - 1}) {
      const float x = std::bit_cast<float>(b);
      const long double exact = sglab::reference::erf_reference_50(x);
      EXPECT_LE(std::abs(t(x) - exact) / sglab::reference::ulp_double(exact), 2.0L)
          << "x = " << hexf(x);
    }
  }
}

// A function exact everywhere except one x, where it is off by a relative
// 2^−20: the checker reports that x and that ulp error.
TEST(ErfCheck, FindsInjectedError) {
  const float bad = 0.75f;  // on the uniform grid of the sample
  auto f = [bad](float x) {
    const double e = std::erf(static_cast<double>(x));
    return static_cast<float>(x == bad ? e * (1 + 0x1p-20) : e);
  };
  const ErfReport r = sglab::validate::check_erf_float(f, small_options(), "injected");
  const Big exact = boost::math::erf(Big(bad));
  // erf(0.75) ∈ [0.5, 1)
  const double expected_ulp = static_cast<double>(abs(Big(f(bad)) - exact) / Big(0x1p-24));
  EXPECT_EQ(r.stats.worst_x, bad);
  EXPECT_NEAR(r.stats.max_ulp, expected_ulp, 1e-6);
  EXPECT_NEAR(r.stats.max_ulp, 0.711155633653515 * 16, 0.5);  // erf(0.75)·2^−20 / 2^−24
  EXPECT_NEAR(r.stats.max_abs, expected_ulp * 0x1p-24, 1e-12);
  EXPECT_EQ(r.stats.histogram[sglab::validate::erf_histogram_bucket(expected_ulp, false)], 1u);
  EXPECT_EQ(r.stats.nonfinite, 0u);
}

TEST(ErfCheck, CountsNonFiniteOutputs) {
  auto f = [](float x) { return x > 1.0f && x < 1.5f ? NAN : std::erf(x); };
  const ErfReport r = sglab::validate::check_erf_float(f, small_options(), "nan");
  EXPECT_GT(r.stats.nonfinite, 0u);
  EXPECT_GT(r.stats.first_nonfinite_x, 1.0);
  EXPECT_LT(r.stats.first_nonfinite_x, 1.01);
}

TEST(ErfCheck, ReportsOddnessViolations) {
  auto f = [](float x) {
    return x < 0 && x > -2.0f ? -std::erf(-x) * (1 + 0x1p-10f) : std::erf(x);
  };
  const ErfReport r = sglab::validate::check_erf_float(f, small_options(), "not_odd");
  EXPECT_GT(r.oddness.violations, 0u);
  EXPECT_LT(r.oddness.first_violation_x, 1e-30);  // the smallest sampled x
}

TEST(ErfCheck, StdErffIsFaithful) {
  const ErfReport r =
      sglab::validate::check_erf_float([](float x) { return std::erf(x); }, small_options(), "std");
  EXPECT_LT(r.stats.max_ulp, 1.0) << "worst x = " << hexf(r.stats.worst_x);
  EXPECT_EQ(r.stats.nonfinite, 0u);
  EXPECT_EQ(r.oddness.violations, 0u);
  EXPECT_GT(r.stats.count, 300'000u);
}

// A&S 7.1.25 claims |error| ≤ 2.5e−5; the claim holds and is tight.
TEST(ErfCheck, AS7125PublishedBoundHoldsAndIsTight) {
  const ErfReport rf =
      sglab::validate::check_erf_float(sglab::ErfAS7125{}, small_options(), "as7125");
  EXPECT_LE(rf.stats.max_abs, 2.5e-5);
  EXPECT_GE(rf.stats.max_abs, 1e-6);
  EXPECT_LE(rf.stats.worst_abs_x, 4.0);

  sglab::reference::ErfDoubleOptions o;
  o.grid_points = 100'000;
  o.log_points = 256;
  o.tail_points = 64;
  o.odd_points = 256;
  o.bins = 50;
  const auto sample = sglab::reference::make_erf_double_sample(o);
  EXPECT_LT(sample.selfcheck_ulps, 0.01);
  const ErfReport rd = sglab::validate::check_erf_double(sglab::ErfAS7125{}, sample, "as7125");
  EXPECT_LE(rd.stats.max_abs, 2.5e-5);
  EXPECT_GE(rd.stats.max_abs, 1e-6);
  EXPECT_LE(rd.stats.worst_abs_x, 4.0);
  EXPECT_EQ(rd.oddness.violations, 0u);
}

TEST(ErfCheck, Listing5IsOddAndExactlyOneBeyondFour) {
  const ErfReport r =
      sglab::validate::check_erf_float(sglab::ErfListing5{}, small_options(), "listing5");
  EXPECT_EQ(r.oddness.violations, 0u);
  EXPECT_GT(r.oddness.checked, 30'000u);
  EXPECT_GT(r.tail.count, 10'000u);
  EXPECT_EQ(r.tail.correctly_rounded, r.tail.count);  // RN(erf) = 1 there
  for (std::uint32_t b = 0x40800000u; b <= 0x7f7fffffu - 8191; b += 8191) {
    const float x = std::bit_cast<float>(b);
    ASSERT_EQ(sglab::erf_listing5(x), 1.0f) << hexf(x);
    ASSERT_EQ(sglab::erf_listing5(-x), -1.0f) << hexf(-x);
    ASSERT_EQ(sglab::erf_listing5(static_cast<double>(x)), 1.0) << hexf(x);
    ASSERT_EQ(sglab::erf_listing5(-static_cast<double>(x)), -1.0) << hexf(-x);
  }
  EXPECT_EQ(sglab::erf_listing5(INFINITY), 1.0f);
  EXPECT_EQ(sglab::erf_listing5(-INFINITY), -1.0f);
}

// The registry's function pointers and the inlined functor give the same report.
TEST(ErfCheck, FunctionPointerAndFunctorAgree) {
  const sglab::ErfVariant* v = sglab::find_erf_variant("listing5");
  ASSERT_NE(v, nullptr);
  const ErfReport a = sglab::validate::check_erf_float(v->f32, small_options(), "listing5");
  const ErfReport b =
      sglab::validate::check_erf_float(sglab::ErfListing5{}, small_options(), "listing5");
  EXPECT_EQ(a.stats.max_ulp, b.stats.max_ulp);
  EXPECT_EQ(a.stats.worst_x, b.stats.worst_x);
  EXPECT_EQ(a.stats.count, b.stats.count);
  EXPECT_EQ(a.stats.histogram, b.stats.histogram);
}

// The exhaustive segments cover every non-negative finite float once.
TEST(ErfCheck, ExhaustiveCoversEveryFloat) {
  ErfFloatOptions o;
  o.exhaustive = true;
  const auto segs = sglab::validate::detail::float_segments(o);
  std::uint64_t next = 0;
  for (const auto& s : segs) {
    ASSERT_EQ(s.kind, sglab::validate::detail::FloatSegment::bits);
    ASSERT_EQ(s.stride, 1u);
    ASSERT_EQ(s.first, next);
    EXPECT_EQ(s.tail, s.first >= 0x40800000u);
    next += s.n;
  }
  EXPECT_EQ(next, 0x7f800000u);  // +inf's pattern: one past FLT_MAX
}

TEST(ErfCheck, DoubleCheckOfStdIsAccurate) {
  sglab::reference::ErfDoubleOptions o;
  o.grid_points = 50'000;
  o.log_points = 512;
  o.tail_points = 64;
  o.odd_points = 512;
  o.bins = 20;
  const auto sample = sglab::reference::make_erf_double_sample(o);
  const ErfReport r =
      sglab::validate::check_erf_double([](double x) { return std::erf(x); }, sample, "std");
  EXPECT_LT(r.stats.max_ulp, 2.0);  // glibc erf: ≤ ~1.3 ulp
  EXPECT_GT(r.stats.correctly_rounded, r.stats.count * 9 / 10);
  for (const auto& sp : r.specials) EXPECT_TRUE(sp.ok) << "x = " << hexf(sp.x);
  EXPECT_EQ(r.series.size(), 20u);
}

TEST(ErfCommand, UnknownVariantExitsTwoNamingIt) {
  const auto r = sglab::test::run_sglab({"erf", "--variant", "no_such_erf"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no_such_erf"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("listing5"), std::string::npos) << r.output;
}

TEST(ErfCommand, JsonHasTheDocumentedKeys) {
  const auto r = sglab::test::run_sglab(
      {"erf", "--json", "--variant", "listing5", "--variant", "std", "--double-points", "20000"},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.contains("results"));
  ASSERT_EQ(j["results"].size(), 4u);  // 2 variants × float, double
  for (const auto& e : j["results"]) {
    for (const char* key : {"variant", "precision", "max_abs", "max_ulp", "worst_x", "rms_ulp",
                            "count", "nonfinite", "histogram"})
      EXPECT_TRUE(e.contains(key)) << key;
    EXPECT_TRUE(e["precision"] == "float" || e["precision"] == "double");
    EXPECT_TRUE(e["histogram"].is_array());
    std::uint64_t total = 0;
    for (const auto& b : e["histogram"]) total += b["count"].get<std::uint64_t>();
    EXPECT_EQ(total, e["count"].get<std::uint64_t>());
  }
  EXPECT_EQ(j["results"][0]["variant"], "listing5");
  EXPECT_EQ(j["results"][0]["precision"], "float");
  EXPECT_EQ(j["results"][2]["variant"], "std");
  EXPECT_LT(j["results"][2]["max_ulp"].get<double>(), 1.0);  // erff
}

TEST(ErfCommand, OutWritesSeriesAndSummary) {
  const sglab::test::TempDir tmp("erf-out");
  const std::string dir = tmp.path.string();
  const auto r = sglab::test::run_sglab(
      {"erf", "--variant", "as7125", "--bins", "64", "--double-points", "20000", "--out", dir});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"erf_as7125_float.csv", "erf_as7125_double.csv", "erf_summary.csv",
                        "erf_summary.md", "erf_histogram.csv"}) {
    FILE* p = std::fopen((dir + "/" + f).c_str(), "r");
    EXPECT_NE(p, nullptr) << f;
    if (p) std::fclose(p);
  }
}
