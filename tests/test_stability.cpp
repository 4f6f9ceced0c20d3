// The stability table: it flags known failures of published methods
// (punctual is infinite at κ = 0, Hill fails at small κ), splits valid from
// invalid inputs, and finds no failure of sglab's own primitives on valid
// inputs (docs/quantities.md). Plus the `sglab stability --json` contract.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/constants.hpp>
#include <sglab/registry.hpp>

#include "tests/test_support.hpp"
#include "validate/stability.hpp"

namespace sv = sglab::validate;

namespace {

const sv::StabilityReport& stability_report() {
  static const sv::StabilityReport r = sv::stability();
  return r;
}

const sv::StabilityRow& row(const std::string& function, sglab::io::Precision f, bool valid) {
  const sv::StabilityRow* r = stability_report().find(function, f, valid);
  if (!r) throw std::runtime_error("no stability row for " + function);
  return *r;
}

constexpr sglab::io::Precision kFormats[] = {sglab::io::Precision::float32,
                                             sglab::io::Precision::float64};

}  // namespace

TEST(Stability, EveryFunctionHasFourRows) {
  const auto& rows = stability_report().rows;
  ASSERT_FALSE(rows.empty());
  ASSERT_EQ(rows.size() % 4, 0u);
  for (std::size_t i = 0; i < rows.size(); i += 4) {
    EXPECT_EQ(rows[i].function, rows[i + 3].function);
    EXPECT_EQ(rows[i].precision, sglab::io::Precision::float32);
    EXPECT_EQ(rows[i + 2].precision, sglab::io::Precision::float64);
    EXPECT_TRUE(rows[i].valid_inputs);
    EXPECT_FALSE(rows[i + 1].valid_inputs);
    EXPECT_GT(rows[i].evaluations, 0u) << rows[i].function;
    EXPECT_GT(rows[i + 1].evaluations, 0u) << rows[i].function;
  }
  for (const auto& m : sglab::irradiance_methods)
    EXPECT_NE(stability_report().find(fmt::format("irradiance/{}", m.id),
                                      sglab::io::Precision::float64, true),
              nullptr)
        << m.id;
  // Probed inputs include κ = 0, the smallest denormal, FLT_MAX, DBL_MAX (double), +inf, NaN.
  const auto& kd = stability_report().kappas_double;
  EXPECT_NE(std::find(kd.begin(), kd.end(), 0.0), kd.end());
  EXPECT_NE(std::find(kd.begin(), kd.end(), std::numeric_limits<double>::denorm_min()), kd.end());
  EXPECT_NE(std::find(kd.begin(), kd.end(), std::numeric_limits<double>::max()), kd.end());
  EXPECT_NE(std::find(kd.begin(), kd.end(), static_cast<double>(std::numeric_limits<float>::max())),
            kd.end());
  EXPECT_NE(std::find(kd.begin(), kd.end(), std::numeric_limits<double>::infinity()), kd.end());
  EXPECT_TRUE(std::any_of(kd.begin(), kd.end(), [](double k) { return std::isnan(k); }));
  const auto& kf = stability_report().kappas_float;
  EXPECT_NE(std::find(kf.begin(), kf.end(),
                      static_cast<double>(std::numeric_limits<float>::denorm_min())),
            kf.end());
}

TEST(Stability, PunctualIsInfiniteAtKappaZero) {
  for (sglab::io::Precision f : kFormats) {
    const auto& r = row("irradiance/punctual", f, true);
    const auto& inf = r[sv::FailureKind::inf];
    EXPECT_GT(inf.count, 0u);
    EXPECT_EQ(inf.kappa_min, 0.0);
    EXPECT_LT(inf.kappa_max, 1e-30);  // 2π/κ overflows only for κ = 0 and the smallest denormals
    EXPECT_NE(inf.example.find("inf"), std::string::npos) << inf.example;
  }
}

TEST(Stability, HillFailsAtSmallKappa) {
  for (sglab::io::Precision f : kFormats) {
    const auto& r = row("irradiance/hill", f, true);
    EXPECT_GT(r.failure_count(), 0u);
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& fs : r.failures)
      if (fs.count && !std::isnan(fs.kappa_min)) smallest = std::min(smallest, fs.kappa_min);
    EXPECT_EQ(smallest, 0.0);
  }
}

TEST(Stability, InvalidInputsAreCountedSeparately) {
  for (sglab::io::Precision f : kFormats) {
    // NaN in, NaN out: a finding on invalid inputs only.
    const auto& invalid = row("sg_evaluate(c, κ)", f, false);
    EXPECT_GT(invalid[sv::FailureKind::nan].count, 0u);
    EXPECT_TRUE(invalid[sv::FailureKind::nan].at_nan_kappa);
    const auto& valid = row("sg_evaluate(c, κ)", f, true);
    EXPECT_EQ(valid.failure_count(), 0u) << valid[sv::FailureKind::nan].example;
  }
}

TEST(Stability, SglabPrimitivesHaveNoFailureOnValidInputs) {
  const auto failures = sv::own_failures_on_valid_inputs(stability_report());
  for (const sv::StabilityRow* r : failures) {
    std::string what;
    for (std::size_t k = 0; k < sv::kFailureKinds; ++k)
      if (r->failures[k].count && r->is_failure(static_cast<sv::FailureKind>(k)))
        what += fmt::format("\n  {} x{}: {}", sv::to_string(static_cast<sv::FailureKind>(k)),
                            r->failures[k].count, r->failures[k].example);
    ADD_FAILURE() << r->function << " (" << sv::to_string(r->precision)
                  << ") on valid inputs:" << what;
  }
  // The list is drawn from the sglab and refit rows only.
  for (const sv::StabilityRow& r : stability_report().rows) {
    if (r.function == "sg_product_with_normal.sharpness") {
      EXPECT_EQ(r.origin, sglab::Origin::sglab);
    }
    if (r.function == "irradiance/punctual" || r.function == "irradiance/hill") {
      EXPECT_EQ(r.origin, sglab::Origin::published);
    }
  }
}

// A registered method's rows carry the registry's origin (Method::origin), so
// that sglab's models and the refits are held to "no failure on valid inputs".
TEST(Stability, MethodRowsCarryTheRegistryOrigin) {
  const auto check = [](std::string_view kind, std::span<const sglab::Method> methods) {
    for (const sglab::Method& m : methods)
      for (sglab::io::Precision f : kFormats)
        for (bool valid : {true, false}) {
          const std::string name = fmt::format("{}/{}", kind, m.id);
          EXPECT_EQ(row(name, f, valid).origin, m.origin) << name << " " << sv::to_string(f);
        }
  };
  check("irradiance", sglab::irradiance_methods);
  check("hemispherical", sglab::hemispherical_methods);
  check("normalized", sglab::normalized_methods);
  EXPECT_EQ(row("irradiance/sglab_acc3", sglab::io::Precision::float32, true).origin,
            sglab::Origin::sglab);
  EXPECT_EQ(row("irradiance/tokuyoshi2024_refit", sglab::io::Precision::float64, true).origin,
            sglab::Origin::refit);
}

// Every binade of the subnormals is probed, in both precisions: 2^e from the
// smallest subnormal to the smallest normal, and the largest subnormal.
template <class T>
void expect_subnormal_binades(const std::vector<double>& probed) {
  const auto has = [&](T v) {
    return std::find(probed.begin(), probed.end(), static_cast<double>(v)) != probed.end();
  };
  int binades = 0;
  for (T k = std::numeric_limits<T>::denorm_min(); k < std::numeric_limits<T>::min();
       k *= T(2), ++binades)
    EXPECT_TRUE(has(k)) << sglab::test::hex(k);
  EXPECT_EQ(binades, std::numeric_limits<T>::digits - 1);
  EXPECT_TRUE(has(std::numeric_limits<T>::min()));
  EXPECT_TRUE(has(std::numeric_limits<T>::min() - std::numeric_limits<T>::denorm_min()));
}

TEST(Stability, ProbesCoverEverySubnormalBinade) {
  expect_subnormal_binades<float>(stability_report().kappas_float);
  expect_subnormal_binades<double>(stability_report().kappas_double);
}

// The κ probes include every method's own lobe sharpness (κ = λ gives κ3 = 0 at
// c = −1, the 0/0 of the published wang2009 form), in both precisions.
TEST(Stability, ProbesIncludeTheMethodsSharpnessConstants) {
  const auto& kf = stability_report().kappas_float;
  const auto& kd = stability_report().kappas_double;
  ASSERT_FALSE(sv::method_sharpness_constants().empty());
  for (double lambda : sv::method_sharpness_constants()) {
    EXPECT_NE(std::find(kd.begin(), kd.end(), lambda), kd.end()) << sglab::test::hex(lambda);
    const double lf = static_cast<float>(lambda);
    EXPECT_NE(std::find(kf.begin(), kf.end(), lf), kf.end()) << sglab::test::hex(lf);
  }
  const auto has = [&](double v) { return std::find(kd.begin(), kd.end(), v) != kd.end(); };
  EXPECT_TRUE(has(sglab::constants::cosine_lobe_published.lambda));
  EXPECT_TRUE(has(sglab::constants::meder2018_published.sharpness));
  EXPECT_TRUE(has(sglab::constants::diffuse_lobe_published.lambda_d));
  EXPECT_TRUE(has(sglab::constants::clamped_cosine_published.lambda));
}

// Accuracy is judged relative to the exact value wherever that is a normal
// number of the evaluated precision: a 0 for an exact 1e−300 is a lost
// result, not rounding. Below the normals, 1e−4 of the smallest normal.
TEST(Stability, AccuracyIsRelativeDownToTheSmallestNormal) {
  EXPECT_TRUE(sv::is_inaccurate<double>(0.0, 1e-300L));
  EXPECT_TRUE(sv::is_inaccurate<double>(2e-300, 1e-300L));
  EXPECT_TRUE(sv::is_inaccurate<double>(1.001e-300, 1e-300L));
  EXPECT_FALSE(sv::is_inaccurate<double>(1.00000001e-300, 1e-300L));
  EXPECT_TRUE(sv::is_inaccurate<double>(0.0, 3.5e-308L));  // 2π/DBL_MAX, a normal double
  // a denormal: within 1e−4 of the smallest normal
  EXPECT_FALSE(sv::is_inaccurate<double>(0.0, 1e-320L));
  EXPECT_TRUE(sv::is_inaccurate<float>(0.0f, 1.85e-38L));  // 2π/FLT_MAX, a normal float
  EXPECT_FALSE(sv::is_inaccurate<float>(0.0f, 1e-44L));
  EXPECT_FALSE(sv::is_inaccurate<float>(1.0f, 1.00001L));
}

// The reference engine is one of sglab's own primitives: probed like them
// (exact at the poles and, for H and s, at the horizon), refusing invalid input.
TEST(Stability, ReferenceEngineIsProbed) {
  for (const char* name :
       {"reference/hemispherical", "reference/irradiance", "reference/normalized"})
    for (sglab::io::Precision f : kFormats) {
      const auto& valid = row(name, f, true);
      EXPECT_EQ(valid.origin, sv::Origin::sglab) << name;
      EXPECT_GT(valid.evaluations, 100u) << name;
      const auto& invalid = row(name, f, false);
      EXPECT_GT(invalid.evaluations, 0u) << name;
      EXPECT_EQ(invalid.failure_count(), 0u)
          << name << ": invalid input must be refused, not answered";
    }
}

// Published methods whose transcription-level defects were fixed: wang2009 at
// κ = λ, c = −1 (0/0) and at large κ (cancelling exponent); Hill at c = 0 for
// large κ (0/0). What remains of Hill is its κ = 0 (1/κ) and small-κ finding.
TEST(Stability, FixedTranscriptionDefectsStayFixed) {
  for (sglab::io::Precision f : kFormats) {
    for (const char* id : {"irradiance/wang2009", "irradiance/wang2009_refit"}) {
      const auto& r = row(id, f, true);
      EXPECT_EQ(r[sv::FailureKind::nan].count, 0u) << id << ": " << r[sv::FailureKind::nan].example;
      EXPECT_EQ(r[sv::FailureKind::inf].count, 0u) << id << ": " << r[sv::FailureKind::inf].example;
    }
    for (const char* id : {"irradiance/hill", "irradiance/hill_exact"}) {
      const auto& nan = row(id, f, true)[sv::FailureKind::nan];
      if (nan.count) {
        EXPECT_LT(nan.kappa_max, 1e-30) << id << ": " << nan.example;
      }
    }
    // Meder's s: NaN only where the published t(κ) overflows (κ² beyond max).
    const auto& meder = row("normalized/meder2018", f, true);
    if (meder[sv::FailureKind::nan].count) {
      EXPECT_GE(meder[sv::FailureKind::nan].kappa_min, 1e19) << meder[sv::FailureKind::nan].example;
    }
    EXPECT_EQ(meder[sv::FailureKind::out_of_range].count, 0u);
  }
}

TEST(Stability, FindingsSayWhyPublishedFailuresRemain) {
  const sv::Table t = sv::stability_findings_table(stability_report());
  const std::size_t why = t.column_index("why"), function = t.column_index("function"),
                    origin = t.column_index("origin"), inputs = t.column_index("inputs");
  std::size_t published_valid = 0;
  for (const auto& r : t.rows()) {
    const auto& text = std::get<std::string>(r[why]);
    EXPECT_FALSE(text.empty()) << std::get<std::string>(r[function]);
    if (std::get<std::string>(r[origin]) == "published" &&
        std::get<std::string>(r[inputs]) == "valid") {
      ++published_valid;
      EXPECT_EQ(text.find("a bug"), std::string::npos) << std::get<std::string>(r[function]);
    }
  }
  EXPECT_GT(published_valid, 0u);
  for (const auto& r : t.rows())
    if (std::get<std::string>(r[function]) == "irradiance/punctual" &&
        std::get<std::string>(r[inputs]) == "valid") {
      EXPECT_NE(std::get<std::string>(r[why]).find("2π/κ"), std::string::npos);
    }
}

TEST(Stability, TableHasCountsAndKappaSpans) {
  const sv::Table t = sv::stability_table(stability_report());
  EXPECT_EQ(t.rows().size(), stability_report().rows.size());
  for (const char* c : {"function", "origin", "precision", "inputs", "nan", "nan_kappa_min",
                        "nan_kappa_max", "inf", "inf_kappa_min", "overflow", "negative",
                        "out_of_range", "out_of_range_kappa_max", "approximation", "first_failure"})
    EXPECT_NO_THROW(t.column_index(c)) << c;
}

TEST(StabilityCli, JsonParses) {
  const sglab::test::TempDir tmp("stability");
  const std::string dir = tmp.path.string();
  const auto r = sglab::test::run_sglab({"stability", "--out", dir, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output.substr(0, 2000);
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.contains("results"));
  ASSERT_TRUE(j.contains("inputs"));
  EXPECT_EQ(j.at("results").size(), stability_report().rows.size());
  for (const auto& e : j.at("results"))
    for (const char* k : {"function", "origin", "precision", "inputs", "nan", "inf", "overflow",
                          "negative", "out_of_range"})
      EXPECT_TRUE(e.contains(k)) << k;
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir) / "stability.csv"));
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir) / "stability.md"));
}
