// sglab's own accurate models `sglab_acc<N>` (include/sglab/sglab_acc.hpp):
// against the reference engine on random points the fit never saw (float and
// double), the per-light split against the plain function, the exact poles,
// the fitter on synthetic data with known coefficients, and the `eval` /
// `methods --json` commands.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "tests/fit_guard.hpp"
#include "validate/reference.hpp"
#include "fit/targets.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;
using sglab::test::run_sglab;

// Bounds on the max peak_rel |Ê − E|/E(1, κ) over κ ∈ [1e−3, 1e4], c ∈ [−1, 1],
// one row per shipped rung, with the reason for the number.
struct Bound {
  const char* id;
  double float_bound, double_bound;
  const char* reason;
};
constexpr Bound kBounds[] = {
    {"sglab_acc1", 2.2e-4, 2.2e-4, "one term (N=1, D=3): held-out 1.93e-4 (the rational form before issue 17: 2.47e-4)"},
    {"sglab_acc2", 6.5e-5, 6.5e-5, "two terms (N=2, D=3): held-out 5.51e-5 (before: 5.68e-5, 7.5e-5)"},
    {"sglab_acc3", 2.5e-5, 2.5e-5, "three terms (N=3, D=4): held-out 2.12e-5 (before: 2.15e-5, 3.15e-5)"},
};

// Random points, κ log-uniform over [1e−3, 1e4] and c uniform, fixed seed;
// float-exact so the float and double paths see the same inputs.
std::vector<sglab::validate::Query> random_points(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> lk(std::log(1e-3), std::log(1e4)), uc(-1.0, 1.0);
  std::vector<sglab::validate::Query> q;
  for (int i = 0; i < n; ++i)
    q.push_back({double(float(std::exp(lk(rng)))), double(float(uc(rng)))});
  return q;
}

const sglab::Method& method(std::string_view id) {
  const sglab::Method* m = sglab::find_method(sglab::irradiance_methods, id);
  if (!m) throw std::runtime_error("method not registered: " + std::string(id));
  return *m;
}

TEST(SglabAcc, MeetsItsBoundOnRandomPointsNotUsedInFitting) {
  const auto queries = random_points(6000, 20261201);
  const auto ref = sglab::validate::reference_engine().evaluate(queries);
  for (const Bound& b : kBounds) {
    SCOPED_TRACE(b.id);
    const sglab::Method& m = method(b.id);
    EXPECT_EQ(m.origin, sglab::Origin::sglab);
    double worst_f = 0, worst_d = 0;
    std::size_t at_f = 0, at_d = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
      const double peak = sglab::irradiance_upper(ref[i].kappa);
      const double ef = std::abs(double(m.f32(float(ref[i].cosine), float(ref[i].kappa))) - ref[i].irradiance) / peak;
      const double ed = std::abs(m.f64(ref[i].cosine, ref[i].kappa) - ref[i].irradiance) / peak;
      if (!(ef <= worst_f)) worst_f = ef, at_f = i;
      if (!(ed <= worst_d)) worst_d = ed, at_d = i;
    }
    EXPECT_LE(worst_f, b.float_bound) << b.reason << "; float worst at kappa=" << hex(ref[at_f].kappa)
                                      << " c=" << hex(ref[at_f].cosine);
    EXPECT_LE(worst_d, b.double_bound) << b.reason << "; double worst at kappa=" << hex(ref[at_d].kappa)
                                       << " c=" << hex(ref[at_d].cosine);
  }
}

// The ladder is a ladder: more terms never lose accuracy, and the best rung
// beats tokuyoshi2024 (published) by at least 40x on the same points.
TEST(SglabAcc, LadderImprovesOnTokuyoshi2024) {
  const auto queries = random_points(3000, 77);
  const auto ref = sglab::validate::reference_engine().evaluate(queries);
  auto worst = [&](const sglab::Method& m) {
    double w = 0;
    for (const auto& r : ref) w = std::max(w, std::abs(m.f64(r.cosine, r.kappa) - r.irradiance) / sglab::irradiance_upper(r.kappa));
    return w;
  };
  const double t2024 = worst(method("tokuyoshi2024"));
  const double a1 = worst(method("sglab_acc1")), a2 = worst(method("sglab_acc2")), a3 = worst(method("sglab_acc3"));
  EXPECT_LT(a2, a1);
  EXPECT_LT(a3, a2);
  EXPECT_LT(40 * a3, t2024) << "acc3 " << a3 << " vs tokuyoshi2024 " << t2024;
}

// Never worse than tokuyoshi2024 (issue 17 §3): at every κ of a grid no fit
// used (90 κ log-spaced over [1e−3, 1e4] at offsets 0.37 of a step, so none
// is a training, standard or fit-held-out κ) each rung's max float error over
// 301 cosines is at most the larger of tokuyoshi2024's (published, float) at
// that κ and 1e−6. The rational b_j(κ) of before failed this at 20 to 30 of
// these κ (κ < 0.2 and κ > 100, where the 2024 form errs by 1e−7 to 2e−5).
TEST(SglabAcc, NeverWorseThanTokuyoshi2024AtAnyKappa) {
  const int nk = 90, nc = 301;
  std::vector<sglab::validate::Query> queries;
  for (int i = 0; i < nk; ++i) {
    const double k = double(float(std::pow(10.0, -3.0 + 7.0 * (i + 0.37) / nk)));
    for (int j = 0; j < nc; ++j) queries.push_back({k, double(float(-1.0 + 2.0 * j / (nc - 1)))});
  }
  const auto ref = sglab::validate::reference_engine().evaluate(queries);
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
  for (const Bound& b : kBounds) {
    SCOPED_TRACE(b.id);
    const sglab::Method& m = method(b.id);
    int worse = 0;
    for (int i = 0; i < nk; ++i) {
      const double own = max_error_at(m, i), limit = std::max(max_error_at(base, i), 1e-6);
      if (own > limit) ++worse;
      EXPECT_LE(own, limit) << "kappa=" << hex(ref[std::size_t(i * nc)].kappa);
    }
    EXPECT_EQ(worse, 0);
  }
}

TEST(SglabAcc, PerLightSplitEqualsThePlainFunction) {
  const auto queries = random_points(4000, 5);
  for (const Bound& b : kBounds) {
    SCOPED_TRACE(b.id);
    const sglab::Method& m = method(b.id);
    ASSERT_NE(m.light_setup32, nullptr);
    ASSERT_NE(m.light_eval32, nullptr);
    for (const auto& q : queries) {
      float state[sglab::kLightStateFloats];
      m.light_setup32(float(q.kappa), state);
      const float split = m.light_eval32(state, float(q.cosine));
      const float plain = m.f32(float(q.cosine), float(q.kappa));
      // Same operations in the same order: equal up to a few ulp of the peak.
      ASSERT_LE(std::abs(split - plain), 4 * std::numeric_limits<float>::epsilon() * sglab::irradiance_upper(float(q.kappa)))
          << "kappa=" << hex(q.kappa) << " c=" << hex(q.cosine) << " split=" << hex(split) << " plain=" << hex(plain);
    }
  }
}

// The correction vanishes at c = ±1: the poles are the closed forms E(±1, κ).
TEST(SglabAcc, PolesAreExact) {
  for (const Bound& b : kBounds) {
    SCOPED_TRACE(b.id);
    const sglab::Method& m = method(b.id);
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
  for (const Bound& b : kBounds) {
    const sglab::Method& m = method(b.id);
    for (float k : {0.0f, 1e-30f, 1e-3f, 1.0f, 1e4f, 1e30f, std::numeric_limits<float>::max()})
      for (float c : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
        const float v = m.f32(c, k);
        EXPECT_TRUE(std::isfinite(v) && v >= 0) << b.id << " kappa=" << hex(k) << " c=" << hex(c) << " -> " << hex(v);
      }
  }
}

// The fitter recovers the coefficients of data generated by the model itself
// with known coefficients (Ceres nist.cc style: digits recovered).
TEST(SglabAccFit, RecoversKnownSyntheticCoefficients) {
  const sglab::SglabAccParams<double, 2, 2> truth{{1.1, 14.0, 2.2, 11.0, 60.0}, {0.2, 0.5, -0.1, 0.3, -0.2, 0.4}, 3.0};
  std::vector<sglab::fit::SglabAccSample> samples;
  for (double k : sglab::fit::kappa_grid(1e-2, 1e3, 25)) {
    const double t = sglab::steepness2024(k, sglab::Steepness2024Params<double>{1.1, 14.0, 2.2, 11.0, 60.0});
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
    EXPECT_GT(-std::log10(std::abs(f.values[i] - want[i]) / std::abs(want[i])), 5) << "coefficient " << i << " = "
                                                                                      << f.values[i];
  EXPECT_LT(f.max_abs, 1e-12);
}

// Model order: a narrow scene range with a loose budget gets the cheapest
// member (one term of degree 2), while the full range with the 3.5e-5 target
// needs three terms: acc1 and acc2 (the cheaper rungs, fitted on the full
// range) measurably miss it on random points.
//
// An unbounded trust-region step once made a residual NaN in this search
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
  spec.costs.float_scalar_ns = {{"tokuyoshi2024", 10.0}, {"sglab_acc1", 13.0}};
  const std::size_t nonfinite_before = sglab::fit::nonfinite_residual_evaluations();
  const auto out = sglab::fit::run_fit(spec);
  EXPECT_EQ(sglab::fit::nonfinite_residual_evaluations(), nonfinite_before) << out.text;
  ASSERT_TRUE(out.converged) << out.text;
  const auto& chosen = out.report["chosen"];
  EXPECT_EQ(chosen["terms"], 1) << out.text;
  EXPECT_EQ(chosen["degree"], 2) << out.text;
  EXPECT_LE(chosen["held_out_max_peak_rel_float"].get<double>(), 1e-3);
  ASSERT_EQ(out.constant_sets.size(), 1u);
  EXPECT_EQ(out.constant_sets[0]["cpp_type"], "SglabAccParams<double, 1, 2>");
  EXPECT_NE(out.report["cost_source"].get<std::string>().find("a test table"), std::string::npos);
  for (const auto& m : out.report["members"]) EXPECT_TRUE(m["cost_ratio_float_vs_tokuyoshi2024"].is_null()) << m;
  // Every fit is certified (issue 17 §1, fit/lp_minimax.hpp): the LP's bound
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

  const auto ref = sglab::validate::reference_engine().evaluate(random_points(3000, 99));
  for (const char* id : {"sglab_acc1", "sglab_acc2"}) {
    const sglab::Method& m = method(id);
    double worst = 0;
    for (const auto& r : ref) worst = std::max(worst, std::abs(m.f64(r.cosine, r.kappa) - r.irradiance) / sglab::irradiance_upper(r.kappa));
    EXPECT_GT(worst, 3.5e-5) << id;
  }
}

std::filesystem::path temp_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("sglab_models_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

TEST(EvalCommand, PrintsEveryRowInBothPrecisions) {
  const auto points = temp_file("points.csv", "kappa,cosine\n4,0.25\n0.001,-1\n10000, 1\n");
  const auto d = run_sglab({"eval", "--method", "sglab_acc2", "--points", points.string(), "--precision", "double"}, false);
  ASSERT_EQ(d.exit_code, 0) << d.output;
  std::istringstream lines(d.output);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "kappa,cosine,value");
  const sglab::Method& m = method("sglab_acc2");
  const double kappas[] = {4, 0.001, 10000}, cosines[] = {0.25, -1, 1};
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    double k, c, v;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &k, &c, &v), 3) << line;
    EXPECT_EQ(k, kappas[i]);
    EXPECT_EQ(c, cosines[i]);
    EXPECT_EQ(v, m.f64(cosines[i], kappas[i])) << line;  // %.17g round-trips
  }
  const auto f = run_sglab({"eval", "--method", "tokuyoshi2024", "--points", points.string()}, false);
  ASSERT_EQ(f.exit_code, 0) << f.output;
  std::istringstream flines(f.output);
  std::getline(flines, line);
  const sglab::Method& t = method("tokuyoshi2024");
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::getline(flines, line));
    double k, c, v;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &k, &c, &v), 3) << line;
    EXPECT_EQ(float(v), t.f32(float(cosines[i]), float(kappas[i]))) << line;  // %.9g round-trips a float
  }
}

TEST(EvalCommand, RejectsBadInputWithExitCode2) {
  const auto good = temp_file("good.csv", "kappa,cosine\n1,0\n");
  const auto negative = temp_file("negative.csv", "kappa,cosine\n1,0\n-2,0.5\n");
  const auto malformed = temp_file("malformed.csv", "kappa,cosine\n1,zero\n");
  auto r = run_sglab({"eval", "--method", "no_such_method", "--points", good.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown irradiance method 'no_such_method'"), std::string::npos) << r.output;
  r = run_sglab({"eval", "--method", "sglab_acc2", "--points", negative.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(":3: kappa must be finite and >= 0"), std::string::npos) << r.output;
  // Streamed: the row before the bad one was printed (README, `sglab eval`).
  EXPECT_EQ(r.output.find("kappa,cosine,value\n1,0,"), 0u) << r.output;
  r = run_sglab({"eval", "--method", "sglab_acc2", "--points", malformed.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cosine is not a number"), std::string::npos) << r.output;
  r = run_sglab({"eval", "--method", "sglab_acc2", "--points", good.string(), "--precision", "half"});
  EXPECT_EQ(r.exit_code, 2);
}

TEST(MethodsCommand, JsonListsEveryRegisteredMethod) {
  const auto r = run_sglab({"methods", "--json"}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["irradiance"].size(), std::size(sglab::irradiance_methods));
  for (std::size_t i = 0; i < std::size(sglab::irradiance_methods); ++i) {
    const sglab::Method& m = sglab::irradiance_methods[i];
    const auto& e = j["irradiance"][i];
    EXPECT_EQ(e["id"], std::string(m.id));
    EXPECT_EQ(e["origin"], std::string(sglab::to_string(m.origin)));
    EXPECT_EQ(e["source"], std::string(m.source));
    EXPECT_EQ(e["per_light_split"], m.light_setup32 != nullptr);
    for (const auto& set : e["constants"]) {
      // Every constant set named is one that the generated header defines (its JSON exists).
      bool found = false;
      for (const auto& file : std::filesystem::directory_iterator(std::filesystem::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants"))
        found = found || nlohmann::json::parse(std::ifstream(file.path()))["cpp_name"] == set;
      EXPECT_TRUE(found) << m.id << ": constant set " << set << " not in data/constants";
    }
  }
  EXPECT_EQ(j["hemispherical"].size(), std::size(sglab::hemispherical_methods));
  EXPECT_EQ(j["erf"].size(), std::size(sglab::erf_variants));
  std::size_t sglab_origin = 0;
  for (const auto& e : j["irradiance"]) sglab_origin += e["origin"] == "sglab";
  EXPECT_GE(sglab_origin, 3u);
}

}  // namespace
