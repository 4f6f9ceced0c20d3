// sglab's own accurate models `sglab_acc<N>` (include/sglab/sglab_acc.hpp):
// the ladder against tokuyoshi2024, never worse than it at any κ, the exact
// poles, the fitter on synthetic data with known coefficients, and the `eval`
// / `methods --json` commands. Their error against the reference engine on
// random points, per-light split and float batch are checked with every
// method by tests/test_methods.cpp, bounds on their registry cards
// (tests/test_kappa_range.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "fit/targets.hpp"
#include "reference/reference.hpp"
#include "tests/fit_guard.hpp"
#include "tests/random_points.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;
using sglab::test::random_points;
using sglab::test::run_sglab;

// The shipped rungs; their bounds are on their registry cards, checked by
// tests/test_methods.cpp and tests/test_kappa_range.cpp with every method.
constexpr const char* kRungs[] = {"sglab_acc1", "sglab_acc2", "sglab_acc3", "sglab_acc4"};

using sglab::test::method;

// The ladder is a ladder: more terms never lose accuracy, and the best rung
// beats tokuyoshi2024 (published) by at least 40x on the same points.
TEST(SglabAcc, LadderImprovesOnTokuyoshi2024) {
  const auto queries = random_points(3000, 77);
  const auto ref = sglab::reference::reference_engine().evaluate(queries);
  auto worst = [&](const sglab::Method& m) {
    double w = 0;
    for (const auto& r : ref)
      w = std::max(
          w, std::abs(m.f64(r.cosine, r.kappa) - r.irradiance) / sglab::irradiance_upper(r.kappa));
    return w;
  };
  const double t2024 = worst(method("tokuyoshi2024"));
  const double a1 = worst(method("sglab_acc1")), a2 = worst(method("sglab_acc2")),
               a3 = worst(method("sglab_acc3")), a4 = worst(method("sglab_acc4"));
  EXPECT_LT(a2, a1);
  EXPECT_LT(a3, a2);
  EXPECT_LT(a4, a3);
  EXPECT_LT(40 * a3, t2024) << "acc3 " << a3 << " vs tokuyoshi2024 " << t2024;
}

// Never worse than tokuyoshi2024 (docs/models.md#sglab_acc1--sglab_acc4): at every κ of a grid no
// fit used (90 κ log-spaced over [1e−3, 1e4] at offsets 0.37 of a step, so none is a training,
// standard or fit-held-out κ) each rung's max float error over 301 cosines is at most the larger of
// tokuyoshi2024's (published, float) at that κ and 1e−6; the fade of b_j(κ) is what holds it where
// the 2024 form errs by only 1e−7 to 2e−5 (κ < 0.2 and κ > 100).
TEST(SglabAcc, NeverWorseThanTokuyoshi2024AtAnyKappa) {
  const int nk = 90, nc = 301;
  std::vector<sglab::reference::Query> queries;
  for (int i = 0; i < nk; ++i) {
    const double k = double(float(std::pow(10.0, -3.0 + 7.0 * (i + 0.37) / nk)));
    for (int j = 0; j < nc; ++j) queries.push_back({k, double(float(-1.0 + 2.0 * j / (nc - 1)))});
  }
  const auto ref = sglab::reference::reference_engine().evaluate(queries);
  const sglab::Method& base = method("tokuyoshi2024");
  const auto max_error_at = [&](const sglab::Method& m, int i) {
    double w = 0;
    for (int j = 0; j < nc; ++j) {
      const auto& r = ref[std::size_t(i * nc + j)];
      w = std::max(w, std::abs(double(m.f32(float(r.cosine), float(r.kappa))) - r.irradiance) /
                          sglab::irradiance_upper(r.kappa));
    }
    return w;
  };
  for (const char* id : kRungs) {
    SCOPED_TRACE(id);
    const sglab::Method& m = method(id);
    int worse = 0;
    for (int i = 0; i < nk; ++i) {
      const double own = max_error_at(m, i), limit = std::max(max_error_at(base, i), 1e-6);
      if (own > limit) ++worse;
      EXPECT_LE(own, limit) << "kappa=" << hex(ref[std::size_t(i * nc)].kappa);
    }
    EXPECT_EQ(worse, 0);
  }
}

// The correction vanishes at c = ±1: the poles are the closed forms E(±1, κ).
TEST(SglabAcc, PolesAreExact) {
  for (const char* id : kRungs) {
    SCOPED_TRACE(id);
    const sglab::Method& m = method(id);
    for (int i = -12; i <= 16; ++i) {
      const double k = double(float(std::pow(10.0, i / 4.0)));
      const double up = sglab::irradiance_upper(k), lo = sglab::irradiance_lower(k);
      EXPECT_LE(std::abs(m.f64(1.0, k) - up), 1e-14 * up) << hex(k);
      EXPECT_LE(std::abs(m.f64(-1.0, k) - lo), 1e-14 * up) << hex(k);
      const float upf = sglab::irradiance_upper(float(k)), lof = sglab::irradiance_lower(float(k));
      EXPECT_LE(std::abs(m.f32(1.0f, float(k)) - upf), 4e-7f * upf) << hex(k);
      EXPECT_LE(std::abs(m.f32(-1.0f, float(k)) - lof), 4e-7f * upf) << hex(k);
    }
  }
}

TEST(SglabAcc, NeverNaNAtTheEdges) {
  for (const char* id : kRungs) {
    const sglab::Method& m = method(id);
    for (float k : {0.0f, 1e-30f, 1e-3f, 1.0f, 1e4f, 1e30f, std::numeric_limits<float>::max()})
      for (float c : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
        const float v = m.f32(c, k);
        EXPECT_TRUE(std::isfinite(v) && v >= 0)
            << id << " kappa=" << hex(k) << " c=" << hex(c) << " -> " << hex(v);
      }
  }
}

// The steepness of order M (params.hpp): for M = 2 it is the 2024 form, the
// same operations as steepness2024 (bit for bit in double and float); and an
// order-3 steepness whose P and Q share a factor (κ + r) is the order-2 one,
// so the whole model is the same function (to rounding) in the scalar and
// the float batch paths, on both sides of κ = 1.
TEST(SglabAcc, SteepnessOfOrderMIsTheRationalForm) {
  const auto& a = sglab::constants::sglab_acc1;
  const sglab::Steepness2024Params<double> s24{a.steep[0], a.steep[1], a.steep[2], a.steep[3],
                                               a.steep[4]};
  const auto rational = sglab::steepness_rational_of(s24);
  for (double k : {1e-3, 0.37, 0.999, 1.0, 2.5, 40.0, 9e3}) {
    EXPECT_EQ(sglab::steepness_rational(k, rational), sglab::steepness2024(k, s24)) << k;
    EXPECT_EQ(sglab::steepness_rational(float(k), rational), sglab::steepness2024(float(k), s24))
        << k;
  }
  // P = κ² + A κ + B and Q = κ³ + C κ² + D κ + E times (κ + r), highest first.
  const double r = 0.7;
  sglab::SglabAccParams<double, 1, 3, 3> b{};
  const double p3[] = {a.steep[0] + r, a.steep[1] + r * a.steep[0], r * a.steep[1]};
  const double q4[] = {a.steep[2] + r, a.steep[3] + r * a.steep[2], a.steep[4] + r * a.steep[3],
                       r * a.steep[4]};
  std::copy(std::begin(p3), std::end(p3), b.steep);
  std::copy(std::begin(q4), std::end(q4), b.steep + 3);
  std::copy(std::begin(a.num), std::end(a.num), b.num);
  b.scale = a.scale;
  std::vector<float> cs, ks;
  for (double k : sglab::fit::kappa_grid(1e-3, 1e4, 41))
    for (int j = 0; j <= 20; ++j) {
      const double c = -1 + 0.1 * j;
      const double want = sglab::irradiance_sglab_acc(c, k, a);
      EXPECT_NEAR(sglab::irradiance_sglab_acc(c, k, b), want, 1e-13 * sglab::irradiance_upper(k))
          << "kappa " << k << " c " << c;
      ks.push_back(float(k)), cs.push_back(float(c));
    }
  std::vector<float> out2(cs.size()), out3(cs.size());
  sglab::irradiance_sglab_acc_batch(cs.data(), ks.data(), out2.data(), cs.size(), a);
  sglab::irradiance_sglab_acc_batch(cs.data(), ks.data(), out3.data(), cs.size(), b);
  for (std::size_t i = 0; i < cs.size(); ++i)
    EXPECT_NEAR(out3[i], out2[i], 1e-6 * sglab::irradiance_upper(double(ks[i])))
        << "kappa " << ks[i] << " c " << cs[i];
}

// The fitter recovers the coefficients of data generated by the model itself
// with known coefficients (Ceres nist.cc style: digits recovered).
TEST(SglabAccFit, RecoversKnownSyntheticCoefficients) {
  const sglab::SglabAccParams<double, 2, 2, 2> truth{
      {1.1, 14.0, 2.2, 11.0, 60.0}, {0.2, 0.5, -0.1, 0.3, -0.2, 0.4}, 3.0};
  std::vector<sglab::fit::SglabAccSample> samples;
  for (double k : sglab::fit::kappa_grid(1e-2, 1e3, 25)) {
    const double t =
        sglab::steepness2024(k, sglab::Steepness2024Params<double>{1.1, 14.0, 2.2, 11.0, 60.0});
    for (int j = 0; j < 20; ++j) {
      const double c = std::min(0.99, 0.15 * (j + 0.5) / t);
      samples.push_back({k, c, sglab::irradiance_sglab_acc(c, k, truth)});
      samples.push_back({k, -c, sglab::irradiance_sglab_acc(-c, k, truth)});
    }
  }
  const std::vector<double> start{1.0, 13.0, 2.0, 10.0, 55.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0};
  const auto f = sglab::fit::fit_sglab_acc_coefficients(2, 2, start, samples);
  ASSERT_TRUE(f.converged);
  const std::vector<double> want{1.1, 14.0, 2.2, 11.0, 60.0, 0.2, 0.5, -0.1, 0.3, -0.2, 0.4, 3.0};
  ASSERT_EQ(f.values.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_GT(-std::log10(std::abs(f.values[i] - want[i]) / std::abs(want[i])), 5)
        << "coefficient " << i << " = " << f.values[i];
  EXPECT_LT(f.max_abs, 1e-12);
}

// The grid the certificate's bound is computed on: at every κ the cosines are distinct, sorted,
// within (−1, 1), symmetric about 0 (c and −c both, c = 0 once), and hold the ±z_k/t(κ) pairs.
TEST(SglabAccFit, CertificateGridIsSymmetricAndDistinctAtEveryKappa) {
  const auto q = sglab::fit::sglab_acc_dense_grid(1e-3, 1e4);
  ASSERT_FALSE(q.empty());
  std::size_t kappas = 0;
  for (std::size_t first = 0; first < q.size();) {
    std::size_t last = first;
    while (last + 1 < q.size() && q[last + 1].kappa == q[first].kappa) ++last;
    ++kappas;
    const double k = q[first].kappa;
    std::vector<double> c;
    for (std::size_t i = first; i <= last; ++i) c.push_back(q[i].cosine);
    ASSERT_GE(c.size(), 65u) << "kappa " << k;  // c = 0 and 64 uniform at least
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_GT(c[i], -1.0) << "kappa " << k;
      EXPECT_LT(c[i], 1.0) << "kappa " << k;
      if (i > 0) {
        EXPECT_LT(c[i - 1], c[i]) << "kappa " << k << ": not sorted and distinct";
      }
      EXPECT_EQ(c[i], -c[c.size() - 1 - i]) << "kappa " << k << ": not symmetric";
    }
    EXPECT_EQ(std::count(c.begin(), c.end(), 0.0), 1) << "kappa " << k;
    // the first z pair: c = ±0.05/t(κ), whenever it lies inside (−1, 1)
    const double t = sglab::steepness2024(k, sglab::constants::steepness2024_irradiance);
    if (0.05 / t < 1) {
      EXPECT_NE(std::find(c.begin(), c.end(), 0.05 / t), c.end()) << "kappa " << k;
      EXPECT_NE(std::find(c.begin(), c.end(), -0.05 / t), c.end()) << "kappa " << k;
    }
    first = last + 1;
  }
  EXPECT_GE(kappas, 80u);
}

// The grid's κ are log-spaced with a band three times as dense over [0.5, 200], where the
// irradiance changes shape fastest: κ per decade in each part of the band against outside it.
TEST(SglabAccFit, CertificateGridIsDenserOverHalfToTwoHundred) {
  std::vector<double> k;
  for (const auto& p : sglab::fit::sglab_acc_dense_grid(1e-3, 1e4))
    if (k.empty() || k.back() != p.kappa) k.push_back(p.kappa);
  const auto per_decade = [&k](double lo, double hi) {
    const auto n = std::count_if(k.begin(), k.end(), [&](double x) { return lo <= x && x < hi; });
    return double(n) / std::log10(hi / lo);
  };
  const double outside = per_decade(1e-3, 0.5), above = per_decade(200, 1e4);
  EXPECT_NEAR(outside / above, 1.0, 0.15);  // 80 cells over the 7 decades: 11.4 per decade
  EXPECT_NEAR(above, 80 / 7.0, 1.0);
  for (const auto& [lo, hi] : {std::pair{0.5, 5.0}, std::pair{5.0, 50.0}, std::pair{50.0, 200.0}})
    EXPECT_GE(per_decade(lo, hi), 2.5 * outside) << "[" << lo << ", " << hi << ")";
}

// Model order: a narrow scene range with a loose budget gets the cheapest
// member (one term of degree 2), while the full range needs more terms for
// the targets of the two- and three-term rungs: acc1 (one term) measurably misses 3.5e-5
// and acc2 (two terms) 1e-5 on random points.
//
// An unbounded trust-region step can make a residual NaN in this search
// (fit_guard.hpp fails the process then); the
// cost column comes from the cost table given (null for forms no shipped
// method has), never from a timing taken in the fit.
TEST(SglabAccFit, NarrowRangeWithLooseBudgetNeedsASmallerOrder) {
  sglab::fit::FitSpec spec;
  spec.target = "sglab-acc";
  spec.kappa_lo = 2;
  spec.kappa_hi = 50;
  spec.kappa_range_given = true;
  spec.max_error = 1e-3;
  spec.costs.source = "a test table";
  spec.costs.what = "a test cost";
  spec.costs.per_method = {{"tokuyoshi2024", 10.0}, {"sglab_acc1", 13.0}};
  const std::size_t nonfinite_before = sglab::fit::nonfinite_residual_evaluations();
  const auto out = sglab::fit::run_fit(spec);
  EXPECT_EQ(sglab::fit::nonfinite_residual_evaluations(), nonfinite_before) << out.text;
  ASSERT_TRUE(out.converged) << out.text;
  const auto& chosen = out.report["chosen"];
  EXPECT_EQ(chosen["terms"], 1) << out.text;
  EXPECT_EQ(chosen["degree"], 2) << out.text;
  EXPECT_LE(chosen["held_out_max_peak_rel_float"].get<double>(), 1e-3);
  ASSERT_EQ(out.constant_sets.size(), 1u);
  EXPECT_EQ(out.constant_sets[0]["cpp_type"], "SglabAccParams<double, 1, 2, 2>");
  EXPECT_NE(out.report["cost_source"].get<std::string>().find("a test table"), std::string::npos);
  for (const auto& m : out.report["members"])
    EXPECT_TRUE(m["cost_ratio_vs_tokuyoshi2024"].is_null()) << m;
  // Every fit is certified (fit/lp_minimax.hpp): the LP's bound
  // (the best member at the fitted steepness) ≤ the achieved max, the per-κ
  // floor ≤ that bound; in the report and in the set's provenance.
  for (const auto& m : out.report["members"]) {
    const auto& c = m["certificate"];
    const double achieved = c["achieved"].get<double>(), bound = c["lower_bound"].get<double>();
    EXPECT_GT(bound, 0) << c;
    EXPECT_LE(bound, achieved * (1 + 1e-6)) << c;
    EXPECT_LE(c["per_kappa_floor"]["weighted"].get<double>(), bound * (1 + 1e-6)) << c;
    EXPECT_TRUE(c["lp"]["converged"].get<bool>()) << c;
    EXPECT_NE(m["summary"].get<std::string>().find("of the best member"), std::string::npos) << m;
  }
  EXPECT_EQ(out.constant_sets[0]["provenance"]["certificate"]["kind"], "lp_at_fitted_steepness");

  const auto ref = sglab::reference::reference_engine().evaluate(random_points(3000, 99));
  for (const auto& [id, target] :
       {std::pair{"sglab_acc1", 3.5e-5}, std::pair{"sglab_acc2", 1e-5}}) {
    const sglab::Method& m = method(id);
    double worst = 0;
    for (const auto& r : ref)
      worst = std::max(worst, std::abs(m.f64(r.cosine, r.kappa) - r.irradiance) /
                                  sglab::irradiance_upper(r.kappa));
    EXPECT_GT(worst, target) << id;
  }
}

}  // namespace
