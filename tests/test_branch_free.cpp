// Branch-free float elementary functions, the vectorizing float batch of
// tokuyoshi2024, its per-light split and the compile-time pole series, each
// against an independent truth: the standard library in double, the scalar
// double path of the method, and the reference engine.
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "validate/reference.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;
namespace bf = sglab::branch_free;

// x = ±10^u, u uniform on [lo, hi].
std::vector<float> log_uniform(std::size_t n, double lo, double hi, double sign, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<float> x(n);
  for (float& v : x) v = static_cast<float>(sign * std::pow(10.0, u(rng)));
  return x;
}

TEST(BranchFree, ExpRelativeErrorWithinTwoUlp) {
  std::vector<float> xs = log_uniform(200000, -8, std::log10(87.0), -1, 1);
  const auto pos = log_uniform(100000, -8, std::log10(88.0), 1, 2);
  xs.insert(xs.end(), pos.begin(), pos.end());
  xs.insert(xs.end(), {0.0f, -0.0f, -87.0f, 88.0f, 0.34657359f, -0.34657359f, 1.0f, -1.0f});
  for (float x : xs) {
    const double want = std::exp(static_cast<double>(x));
    const double got = bf::exp_bf(x);
    ASSERT_LE(std::abs(got - want), 2 * std::numeric_limits<float>::epsilon() * want) << hex(x);
  }
  // Far below the float range: exactly 0, never NaN.
  for (float x : {-87.5f, -100.0f, -1e30f, -std::numeric_limits<float>::infinity()}) EXPECT_EQ(bf::exp_bf(x), 0.0f);
}

TEST(BranchFree, Expm1RelativeErrorWithinThreeUlpForNonPositive) {
  std::vector<float> xs = log_uniform(300000, -30, std::log10(87.0), -1, 3);
  xs.insert(xs.end(), {-0.0f, -0.34657359f, -0.3465736f, -0.34657356f, -1e-45f, -87.0f});
  for (float x : xs) {
    const double want = std::expm1(static_cast<double>(x));
    const double got = bf::expm1_bf(x);
    ASSERT_LE(std::abs(got - want), 3 * std::numeric_limits<float>::epsilon() * std::abs(want)) << hex(x);
  }
  EXPECT_EQ(bf::expm1_bf(0.0f), 0.0f);
  EXPECT_EQ(bf::expm1_bf(-1e30f), -1.0f);
  EXPECT_EQ(bf::expm1_bf(-std::numeric_limits<float>::infinity()), -1.0f);
}

TEST(BranchFree, ErfcAbsoluteErrorWithinSixTimesTenToMinusSeven) {
  // [AS1964] 7.1.26: |ε| ≤ 1.5e−7; float rounding adds up to ~4e−7 near x = 0
  // (the polynomial cancels there), about 1e−7 beyond |x| = 0.75 (measured
  // 5.9e−7 and 2.8e−7).
  for (int i = -600000; i <= 600000; ++i) {
    const float x = static_cast<float>(i * 1e-5);
    const double want = std::erfc(static_cast<double>(x));
    ASSERT_LE(std::abs(bf::erfc_bf(x) - want), std::abs(x) < 0.75f ? 6.5e-7 : 3e-7) << hex(x);
  }
  for (float x : {1e4f, 1e19f, std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity()}) {
    EXPECT_EQ(bf::erfc_bf(x), 0.0f) << hex(x);
    EXPECT_EQ(bf::erfc_bf(-x), 2.0f) << hex(x);
  }
}

TEST(BranchFree, SqrtWithinOneUlp) {
  std::vector<float> ys = log_uniform(300000, -37, 38, 1, 4);
  ys.insert(ys.end(), {1.0f, 4.0f, 2.0f, std::numeric_limits<float>::min(), std::numeric_limits<float>::max() / 2});
  for (float y : ys) {
    const double want = std::sqrt(static_cast<double>(y));
    ASSERT_LE(std::abs(bf::sqrt_bf(y) - want), std::numeric_limits<float>::epsilon() * want) << hex(y);
  }
  EXPECT_EQ(bf::sqrt_bf(0.0f), 0.0f);
}

TEST(BranchFree, SelectMinMaxClamp) {
  EXPECT_EQ(bf::select(true, 1.0f, 2.0f), 1.0f);
  EXPECT_EQ(bf::select(false, 1.0f, 2.0f), 2.0f);
  EXPECT_EQ(bf::min(-3.0f, 2.0f), -3.0f);
  EXPECT_EQ(bf::max(-3.0f, 2.0f), 2.0f);
  EXPECT_EQ(bf::clamp(1.5f, -1.0f, 1.0f), 1.0f);
  EXPECT_EQ(bf::clamp(-1.5f, -1.0f, 1.0f), -1.0f);
  EXPECT_EQ(bf::clamp(0.25f, -1.0f, 1.0f), 0.25f);
}

// The float pole series (11 terms) and closed forms against the naive formula
// in long double where it is accurate, and against double, on both sides of κ = 1.
TEST(PoleSeries, FloatAndDoubleMatchAcrossKappaOne) {
  for (double kappa : {0.0, 1e-30, 1e-6, 0.01, 0.25, 0.5, 0.9, 0.99999994, 1.0, 1.0000001, 1.5, 3.0, 50.0, 1e6}) {
    SCOPED_TRACE(hex(kappa));
    const auto d = sglab::irradiance_poles_over_two_pi(kappa);
    const auto f = sglab::irradiance_poles_over_two_pi(static_cast<float>(kappa));
    EXPECT_EQ(d.upper, sglab::irradiance_upper_over_two_pi(kappa));
    EXPECT_EQ(d.lower, sglab::irradiance_lower_over_two_pi(kappa));
    EXPECT_LE(std::abs(f.upper - d.upper), 2e-7 * d.upper);
    EXPECT_LE(std::abs(f.lower - d.lower), 2e-7 * d.upper);  // relative to the peak
    if (kappa >= 0.25) {
      // Naive formulas in long double (cancellation ≤ ~2^6 here).
      const long double k = kappa, e = std::exp(-k);
      const long double up = (k - 1 + e) / (k * k), lo = e * (1 - e - k * e) / (k * k);
      EXPECT_LE(std::abs(d.upper - static_cast<double>(up)), 1e-15 * static_cast<double>(up));
      EXPECT_LE(std::abs(d.lower - static_cast<double>(lo)), 1e-15 * static_cast<double>(up));
    } else {
      EXPECT_NEAR(d.upper, 0.5 - kappa / 6, kappa * kappa / 24 + 1e-16);
      EXPECT_NEAR(d.lower, 0.5 - 5 * kappa / 6, kappa * kappa + 1e-16);  // e^{−κ}(1/2 − κ/3 + …)
    }
  }
}

// Float batch (vectorizing kernel) against the scalar double path: ≤ 1e−6 of
// the peak E(1, κ) over 2^20 random inputs (κ log-uniform in [1e−3, 1e4], c
// uniform), the standard grid, and edge κ; scalar float for scale.
void check_batch_against_double(const sglab::Method& m) {
  SCOPED_TRACE(std::string(m.id));
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<float> c, k;
  for (int i = 0; i < (1 << 20); ++i) {
    k.push_back(static_cast<float>(std::pow(10.0, -3 + 7 * u(rng))));
    c.push_back(static_cast<float>(-1 + 2 * u(rng)));
  }
  for (double kappa : sglab::test::standard_kappas())
    for (double cosine : sglab::test::standard_cosines()) {
      k.push_back(static_cast<float>(kappa));
      c.push_back(static_cast<float>(cosine));
    }
  for (float kappa : {0.0f, 1e-30f, 0.99999994f, 1.0f, 1e20f, std::numeric_limits<float>::max()})
    for (float cosine : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
      k.push_back(kappa);
      c.push_back(cosine);
    }
  std::vector<float> out(k.size());
  m.batch32(c.data(), k.data(), out.data(), k.size());
  double worst_batch = 0, worst_scalar = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    const double want = m.f64(c[i], k[i]);
    const double peak = sglab::irradiance_upper(static_cast<double>(k[i]));
    ASSERT_TRUE(std::isfinite(out[i])) << hex(k[i]) << " " << hex(c[i]);
    const double e = std::abs(out[i] - want) / peak;
    ASSERT_LE(e, 1e-6) << "kappa " << hex(k[i]) << " c " << hex(c[i]) << " batch " << out[i] << " double " << want;
    worst_batch = std::max(worst_batch, e);
    worst_scalar = std::max(worst_scalar, std::abs(m.f32(c[i], k[i]) - want) / peak);
  }
  // Both float paths are at float noise; the batch at most a few times the scalar.
  EXPECT_LE(worst_scalar, 1e-6);
  std::printf("%s: max |float batch - double| / peak = %.3g, scalar float %.3g\n", std::string(m.id).c_str(),
              worst_batch, worst_scalar);
}

TEST(Tokuyoshi2024Batch, PublishedMatchesDoubleWithinOneMillionthOfPeak) {
  check_batch_against_double(*sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024"));
}

TEST(Tokuyoshi2024Batch, RefitMatchesDoubleWithinOneMillionthOfPeak) {
  check_batch_against_double(*sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024_refit"));
}

// The method's own error against the reference engine over the standard grid
// is unchanged by the batch kernel: max peak_rel ≈ 1.55e−3 (scalar float).
TEST(Tokuyoshi2024Batch, PeakRelAgainstReferenceUnchanged) {
  const auto& engine = sglab::validate::reference_engine();
  std::vector<sglab::validate::Query> q;
  for (double kappa : sglab::test::standard_kappas())
    for (double cosine : sglab::test::standard_cosines())
      q.push_back({static_cast<double>(static_cast<float>(kappa)), static_cast<double>(static_cast<float>(cosine))});
  const auto ref = engine.evaluate(q);
  std::vector<float> c, k, out(q.size());
  for (const auto& p : q) {
    c.push_back(static_cast<float>(p.cosine));
    k.push_back(static_cast<float>(p.kappa));
  }
  const auto* m = sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024");
  m->batch32(c.data(), k.data(), out.data(), q.size());
  double worst_batch = 0, worst_scalar = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double peak = sglab::irradiance_upper(q[i].kappa);
    worst_batch = std::max(worst_batch, std::abs(out[i] - ref[i].irradiance) / peak);
    worst_scalar = std::max(worst_scalar, std::abs(m->f32(c[i], k[i]) - ref[i].irradiance) / peak);
  }
  EXPECT_NEAR(worst_scalar, 1.55e-3, 0.01e-3);
  EXPECT_LE(std::abs(worst_batch - worst_scalar), 1e-6);
}

// sglab's accurate models: the same vectorizing kernel (one implementation of
// the model, sglab_acc_eval, with branch_free.hpp's exp/expm1/erfc). erfc_bf
// is within 6e−7 absolute and an erfc error e moves the lerp factor by at most
// e, so the batch stays within 1e−6 of the peak of the scalar double path.
TEST(SglabAccBatch, MatchesDoubleWithinOneMillionthOfPeak) {
  for (const char* id : {"sglab_acc1", "sglab_acc2", "sglab_acc3"}) {
    const sglab::Method* m = sglab::find_method(sglab::irradiance_methods, id);
    ASSERT_TRUE(m && m->batch32);
    check_batch_against_double(*m);
  }
}

// Against the reference engine: sglab_acc3's float batch keeps its accuracy
// target 3.5e−5 of the peak over the standard grid and 8192 random points
// (κ log-uniform in [1e−3, 1e4]), and its max error is the scalar float
// path's to within 1e−6.
TEST(SglabAccBatch, Acc3KeepsItsAccuracyAgainstTheReference) {
  const auto& engine = sglab::validate::reference_engine();
  std::vector<sglab::validate::Query> q;
  for (double kappa : sglab::test::standard_kappas())
    for (double cosine : sglab::test::standard_cosines())
      q.push_back({static_cast<double>(static_cast<float>(kappa)), static_cast<double>(static_cast<float>(cosine))});
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 8192; ++i)
    q.push_back({static_cast<double>(static_cast<float>(std::pow(10.0, -3 + 7 * u(rng)))),
                 static_cast<double>(static_cast<float>(-1 + 2 * u(rng)))});
  const auto ref = engine.evaluate(q);
  std::vector<float> c, k, out(q.size());
  for (const auto& p : q) {
    c.push_back(static_cast<float>(p.cosine));
    k.push_back(static_cast<float>(p.kappa));
  }
  const auto* m = sglab::find_method(sglab::irradiance_methods, "sglab_acc3");
  ASSERT_TRUE(m);
  m->batch32(c.data(), k.data(), out.data(), q.size());
  double worst_batch = 0, worst_scalar = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double peak = sglab::irradiance_upper(q[i].kappa);
    worst_batch = std::max(worst_batch, std::abs(out[i] - ref[i].irradiance) / peak);
    worst_scalar = std::max(worst_scalar, std::abs(m->f32(c[i], k[i]) - ref[i].irradiance) / peak);
  }
  std::printf("sglab_acc3 vs reference: batch %.4g, scalar float %.4g\n", worst_batch, worst_scalar);
  EXPECT_LE(worst_batch, 3.5e-5);
  EXPECT_LE(std::abs(worst_batch - worst_scalar), 1e-6);
}

// The per-light split equals the plain float evaluation (the same operations
// in the same order) for every method that has it.
TEST(LightSplit, EvalOfSetupEqualsPlainFloat) {
  int with_split = 0;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    if (!m.light_setup32 && !m.light_eval32) continue;
    ASSERT_TRUE(m.light_setup32 && m.light_eval32) << m.id << ": setup and eval come together";
    ++with_split;
    for (double kappa : sglab::test::standard_kappas()) {
      float state[sglab::kLightStateFloats];
      m.light_setup32(static_cast<float>(kappa), state);
      for (double cosine : sglab::test::standard_cosines()) {
        const float want = m.f32(static_cast<float>(cosine), static_cast<float>(kappa));
        const float got = m.light_eval32(state, static_cast<float>(cosine));
        const double peak = sglab::irradiance_upper(kappa);
        ASSERT_LE(std::abs(got - want), 4 * std::numeric_limits<float>::epsilon() * peak)
            << m.id << " kappa " << kappa << " c " << cosine;
      }
    }
  }
  EXPECT_GE(with_split, 2);  // tokuyoshi2024 and tokuyoshi2024_refit at least
}

TEST(LightSplit, Tokuyoshi2024SetupHoldsSteepnessAndPoles) {
  for (double kappa : {0.0, 1e-3, 0.5, 1.0, 4.0, 1e4}) {
    const auto light = sglab::tokuyoshi2024_light(kappa);
    EXPECT_EQ(light.t, sglab::steepness2024(kappa));
    EXPECT_EQ(light.upper, sglab::irradiance_upper_over_two_pi(kappa));
    EXPECT_EQ(light.lower, sglab::irradiance_lower_over_two_pi(kappa));
    for (double c : {-1.0, 0.0, 0.3, 1.0})
      EXPECT_EQ(sglab::tokuyoshi2024_eval(light, c), sglab::irradiance_tokuyoshi2024(c, kappa));
  }
}

}  // namespace
