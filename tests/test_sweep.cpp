// The accuracy sweep (the standard grid of docs/quantities.md): the grid, float-exact inputs, exact
// closed forms used as methods, a deliberately perturbed method; and the `sglab sweep` command-line
// contract.
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/closed_forms.hpp>
#include <sglab/registry.hpp>

#include "reference/reference.hpp"
#include "tests/test_support.hpp"
#include "validate/sweep.hpp"

namespace sr = sglab::reference;
namespace sv = sglab::validate;
using sglab::test::hex;

namespace {

sv::SweepOptions quiet(std::vector<sglab::io::Precision> precisions = {
                           sglab::io::Precision::float32, sglab::io::Precision::float64}) {
  sv::SweepOptions o;
  o.precisions = std::move(precisions);
  o.progress = false;
  return o;
}

sglab::Method method(std::string_view id, float (*f32)(float, float),
                     double (*f64)(double, double)) {
  return sglab::Method{{.id = id, .source = "test"}, f32, f64, nullptr, nullptr};
}

// The exact closed forms at c = ±1 (and H at c = 0) "as methods" (docs/quantities.md).
template <class T>
T exact_irradiance(T c, T k) {
  return c > T(0) ? sglab::irradiance_upper(k) : sglab::irradiance_lower(k);
}
template <class T>
T exact_hemispherical(T c, T k) {
  if (c == T(0)) return sglab::hemispherical_equator(k);
  return c > T(0) ? sglab::hemispherical_upper(k) : sglab::hemispherical_lower(k);
}
template <class T>
T exact_normalized(T c, T /*kappa*/) {
  // s(0, κ) = (S/2 − e^{−κ}H(1))/((1 − e^{−κ})H(1)) = ((1 + e^{−κ})/2 − e^{−κ})/(1 − e^{−κ}) = 1/2.
  if (c == T(0)) return T(0.5);
  return c > T(0) ? T(1) : T(0);
}

// The perturbed method: the reference itself, times (1 + 1e−3) at one point.
constexpr float kPerturbedKappa = 1.0f;
constexpr float kPerturbedCosine = 0.5f;
constexpr double kPerturbation = 1e-3;
double perturbed64(double c, double k) {
  const double e = sr::reference_engine().evaluate(k, c).irradiance;
  return (k == kPerturbedKappa && c == kPerturbedCosine) ? e * (1 + kPerturbation) : e;
}
float perturbed32(float c, float k) { return static_cast<float>(perturbed64(c, k)); }

// NaN at one point, the reference elsewhere; and NaN unless the inputs are float-exact.
double nan_at_point64(double c, double k) {
  if (k == kPerturbedKappa && c == kPerturbedCosine)
    return std::numeric_limits<double>::quiet_NaN();
  return sr::reference_engine().evaluate(k, c).irradiance;
}
float nan_at_point32(float c, float k) { return static_cast<float>(nan_at_point64(c, k)); }
double float_exact_or_nan64(double c, double k) {
  if (static_cast<double>(static_cast<float>(c)) != c ||
      static_cast<double>(static_cast<float>(k)) != k)
    return std::numeric_limits<double>::quiet_NaN();
  return sr::reference_engine().evaluate(k, c).irradiance;
}
float float_exact_or_nan32(float c, float k) {
  return static_cast<float>(float_exact_or_nan64(c, k));
}

}  // namespace

TEST(SweepGrid, DefaultIsTheSpecStandardGrid) {
  const sv::SweepGrid g;
  const auto k = g.kappas();
  const auto c = g.cosines();
  ASSERT_EQ(k.size(), 29u);
  ASSERT_EQ(c.size(), 41u);
  const auto k_spec = sglab::test::standard_kappas();   // 10^(i/4), i = −12…16
  const auto c_spec = sglab::test::standard_cosines();  // −1 + 2i/40
  for (std::size_t i = 0; i < k.size(); ++i)
    EXPECT_EQ(k[i], k_spec[i]) << i << ": " << hex(k[i]) << " vs " << hex(k_spec[i]);
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_EQ(c[i], c_spec[i]) << i << ": " << hex(c[i]) << " vs " << hex(c_spec[i]);
  // Decades are the decimal literals.
  const double decades[] = {1e-3, 1e-2, 1e-1, 1, 10, 100, 1e3, 1e4};
  for (int d = 0; d < 8; ++d) EXPECT_EQ(k[4 * d], decades[d]) << hex(k[4 * d]);
  EXPECT_EQ(c.front(), -1.0);
  EXPECT_EQ(c[20], 0.0);
  EXPECT_EQ(c.back(), 1.0);
}

TEST(SweepGrid, CustomGridsAndValidation) {
  sv::SweepGrid g{0.5, 8, 5, 3};
  const auto k = g.kappas();
  ASSERT_EQ(k.size(), 5u);
  EXPECT_EQ(k.front(), 0.5);
  EXPECT_EQ(k.back(), 8.0);
  EXPECT_NEAR(k[2], 2.0, 1e-15);
  EXPECT_EQ(g.cosines(), (std::vector<double>{-1, 0, 1}));
  EXPECT_EQ((sv::SweepGrid{3, 3, 1, 2}.kappas()), std::vector<double>{3});

  EXPECT_NO_THROW(sv::SweepGrid{}.validate());
  EXPECT_THROW((sv::SweepGrid{0, 1, 3, 5}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{-1, 1, 3, 5}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{2, 1, 3, 5}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{1, 2, 1, 5}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{1, 2, 0, 5}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{1, 2, 3, 1}.validate()), std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{1, std::numeric_limits<double>::infinity(), 3, 5}.validate()),
               std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{std::numeric_limits<double>::quiet_NaN(), 1, 3, 5}.validate()),
               std::invalid_argument);
  EXPECT_THROW((sv::SweepGrid{1, 1e39, 3, 5}.validate()), std::invalid_argument);   // not a float
  EXPECT_THROW((sv::SweepGrid{1e-50, 1, 3, 5}.validate()), std::invalid_argument);  // 0 in float
}

TEST(SweepGrid, FloatExactRounding) {
  const auto nominal = sv::SweepGrid{}.kappas();
  const auto exact = sv::float_exact(nominal);
  ASSERT_EQ(exact.size(), nominal.size());
  for (std::size_t i = 0; i < exact.size(); ++i) {
    EXPECT_EQ(exact[i], static_cast<double>(static_cast<float>(nominal[i])));
    EXPECT_EQ(static_cast<double>(static_cast<float>(exact[i])), exact[i]);
  }
  EXPECT_NE(exact[0], 1e-3);  // 1e−3 is not a float: the sweep uses the float
}

TEST(Sweep, InputsAreFloatExactAndSharedByBothPrecisions) {
  const sv::SweepGrid g{1e-3, 1e4, 8, 9};
  const sglab::Method m = method("float_exact_check", float_exact_or_nan32, float_exact_or_nan64);
  const sv::SweepMethod methods[] = {{sv::Quantity::irradiance, m}};
  const auto r = sv::sweep(g, methods, quiet());
  ASSERT_EQ(r.kappas.size(), 8u);
  ASSERT_EQ(r.cosines.size(), 9u);
  for (double k : r.kappas) EXPECT_EQ(static_cast<double>(static_cast<float>(k)), k) << hex(k);
  for (double c : r.cosines) EXPECT_EQ(static_cast<double>(static_cast<float>(c)), c) << hex(c);
  for (std::size_t k = 0; k < r.kappas.size(); ++k) {
    EXPECT_EQ(r.peak[k].kappa, r.kappas[k]);
    EXPECT_EQ(r.peak[k].cosine, 1.0);
    for (std::size_t j = 0; j < r.cosines.size(); ++j) {
      EXPECT_EQ(r.reference[r.index(k, j)].kappa, r.kappas[k]);
      EXPECT_EQ(r.reference[r.index(k, j)].cosine, r.cosines[j]);
    }
  }
  const auto* d = r.find("float_exact_check", sv::Quantity::irradiance, sglab::io::kCpuDouble);
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->summary.nonfinite, 0u);  // the double path saw float-exact inputs
  EXPECT_LT(d->summary.peak_rel.max, 1e-15);
}

TEST(Sweep, ExactClosedFormsGiveNearZeroError) {
  const sv::SweepGrid g{1e-3, 1e4, 29, 3};  // c ∈ {−1, 0, 1}
  const sglab::Method e = method("exact_E", exact_irradiance<float>, exact_irradiance<double>);
  const sglab::Method h =
      method("exact_H", exact_hemispherical<float>, exact_hemispherical<double>);
  const sglab::Method s = method("exact_s", exact_normalized<float>, exact_normalized<double>);
  // E has no closed form at c = 0: hold exact_E to c = ±1 with a 2-cosine grid.
  const sv::SweepMethod poles[] = {{sv::Quantity::irradiance, e}};
  const sv::SweepMethod all[] = {{sv::Quantity::hemispherical, h}, {sv::Quantity::normalized, s}};
  const auto rp = sv::sweep(sv::SweepGrid{1e-3, 1e4, 29, 2}, poles, quiet());
  const auto ra = sv::sweep(g, all, quiet());
  for (const auto* r : {&rp, &ra}) {
    ASSERT_FALSE(r->entries.empty());
    for (const sv::SweepEntry& en : r->entries) {
      SCOPED_TRACE(fmt::format("{} {} {}", en.method, sv::to_string(en.quantity),
                               sv::to_string(en.precision)));
      EXPECT_EQ(en.summary.nonfinite, 0u);
      EXPECT_EQ(en.summary.invalid_reference, 0u);
      EXPECT_EQ(en.summary.peak_rel.count, r->kappas.size() * r->cosines.size());
      const double tol = en.precision == sglab::io::kCpuDouble ? 1e-13 : 1e-6;
      EXPECT_LT(en.summary.peak_rel.max, tol) << "at κ = " << en.summary.peak_rel.worst_kappa
                                              << ", c = " << en.summary.peak_rel.worst_cosine;
      ASSERT_EQ(en.per_kappa.size(), r->kappas.size());
      for (const auto& row : en.per_kappa) EXPECT_LE(row.peak_rel.max, en.summary.peak_rel.max);
    }
  }
}

TEST(Sweep, PerturbedMethodGivesExpectedMaxAndLocation) {
  const sv::SweepGrid g{0.1, 10, 5, 5};  // κ ∈ {0.1, 0.316, 1, 3.16, 10}, c ∈ {−1, −0.5, 0, 0.5, 1}
  const sv::SweepMethod methods[] = {
      {sv::Quantity::irradiance, method("perturbed", perturbed32, perturbed64)},
      {sv::Quantity::irradiance, method("nan_at_point", nan_at_point32, nan_at_point64)},
  };
  const auto r = sv::sweep(g, methods, quiet());
  ASSERT_EQ(r.entries.size(), 4u);
  const auto& ref = sr::reference_engine();
  const double expected = kPerturbation *
                          ref.evaluate(kPerturbedKappa, kPerturbedCosine).irradiance /
                          ref.evaluate(kPerturbedKappa, 1.0).irradiance;
  for (sglab::io::Precision f : {sglab::io::Precision::float32, sglab::io::Precision::float64}) {
    SCOPED_TRACE(std::string(sv::to_string(f)));
    const auto* p = r.find("perturbed", sv::Quantity::irradiance, sglab::io::on_cpu(f));
    ASSERT_NE(p, nullptr);
    EXPECT_NEAR(p->summary.peak_rel.max, expected,
                f == sglab::io::Precision::float64 ? 1e-12 : 1e-6);
    EXPECT_EQ(p->summary.peak_rel.worst_kappa, kPerturbedKappa);
    EXPECT_EQ(p->summary.peak_rel.worst_cosine, kPerturbedCosine);
    EXPECT_NEAR(p->summary.rel.max, kPerturbation,
                f == sglab::io::Precision::float64 ? 1e-12 : 1e-6);
    EXPECT_EQ(p->summary.nonfinite, 0u);
    // Per κ: only κ = 1 (index 2) carries the perturbation.
    ASSERT_EQ(p->per_kappa.size(), 5u);
    EXPECT_NEAR(p->per_kappa[2].peak_rel.max, expected, 1e-6);
    EXPECT_EQ(p->per_kappa[2].peak_rel.worst_cosine, kPerturbedCosine);
    if (f == sglab::io::Precision::float64) {
      for (std::size_t k : {0u, 1u, 3u, 4u}) EXPECT_EQ(p->per_kappa[k].peak_rel.max, 0.0);
    }
    // Point data.
    const std::size_t i = r.index(2, 3);
    EXPECT_EQ(r.cosines[3], kPerturbedCosine);
    EXPECT_NEAR(p->peak_rel[i], expected, 1e-6);

    const auto* n = r.find("nan_at_point", sv::Quantity::irradiance, sglab::io::on_cpu(f));
    ASSERT_NE(n, nullptr);
    EXPECT_EQ(n->summary.nonfinite, 1u);
    EXPECT_EQ(n->summary.first_nonfinite_kappa, kPerturbedKappa);
    EXPECT_EQ(n->summary.first_nonfinite_cosine, kPerturbedCosine);
    EXPECT_EQ(n->summary.peak_rel.count, 24u);  // excluded from max and RMS
    EXPECT_TRUE(std::isfinite(n->summary.peak_rel.max));
    EXPECT_TRUE(std::isnan(n->peak_rel[i]));
    EXPECT_EQ(n->per_kappa[2].nonfinite, 1u);
  }
}

TEST(Sweep, RegisteredMethodsAndTables) {
  const sv::SweepGrid g{0.01, 100, 5, 9};
  const auto methods = sv::registered_sweep_methods();
  EXPECT_EQ(methods.size(), std::size(sglab::irradiance_methods) +
                                std::size(sglab::hemispherical_methods) +
                                std::size(sglab::normalized_methods));
  const auto r = sv::sweep(g, methods, quiet());
  EXPECT_EQ(r.entries.size(), 2 * methods.size());
  const auto* t24 = r.find("tokuyoshi2024", sv::Quantity::irradiance, sglab::io::kCpuDouble);
  ASSERT_NE(t24, nullptr);
  EXPECT_EQ(t24->summary.nonfinite, 0u);
  EXPECT_LT(t24->summary.peak_rel.max, 0.05);

  const auto summary = sv::summary_table(r);
  std::vector<std::string> names;
  for (const auto& c : summary.columns()) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"method", "quantity", "precision", "max_peak_rel",
                                             "worst_kappa", "worst_cosine", "rms_peak_rel",
                                             "max_rel", "nonfinite"}));
  EXPECT_EQ(summary.rows().size(), r.entries.size());
  EXPECT_EQ(sv::per_kappa_table(r).rows().size(), r.entries.size() * 5);
  const auto points = sv::points_table(r);
  EXPECT_EQ(points.rows().size(), r.entries.size() * 5 * 9);
  names.clear();
  for (const auto& c : points.columns()) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"kappa", "cosine", "method", "quantity", "precision",
                                             "value", "reference", "peak_rel"}));
}

// ---------------------------------------------------------------------------
// `sglab sweep` command line

namespace {

// `sglab sweep --out DIR ARGS`.
sglab::test::CommandResult sweep_cli(const std::string& args, const sglab::test::TempDir& dir) {
  std::vector<std::string> argv = {"sweep", "--out", dir.path.string()};
  for (std::string& w : sglab::test::words(args)) argv.push_back(std::move(w));
  return sglab::test::run_sglab(argv);
}

}  // namespace

TEST(SweepCli, JsonHasTheDocumentedKeys) {
  const sglab::test::TempDir dir("sweep-json");
  const auto r = sweep_cli("--kappa 0.1:10:3 --cosines 5 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);  // stdout carries only JSON
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 2u);
  const auto& g = j.at("grid");
  EXPECT_EQ(g.at("kappa_lo").get<double>(), 0.1);
  EXPECT_EQ(g.at("kappa_hi").get<double>(), 10.0);
  EXPECT_EQ(g.at("kappa_count").get<int>(), 3);
  EXPECT_EQ(g.at("cosine_count").get<int>(), 5);
  const auto& results = j.at("results");
  ASSERT_EQ(results.size(),
            2 * (std::size(sglab::irradiance_methods) + std::size(sglab::hemispherical_methods) +
                 std::size(sglab::normalized_methods)));
  const std::vector<std::string> keys = {"method",       "quantity",    "precision",
                                         "max_peak_rel", "worst_kappa", "worst_cosine",
                                         "rms_peak_rel", "max_rel",     "nonfinite"};
  for (const auto& e : results) {
    EXPECT_EQ(e.size(), keys.size());
    for (const auto& k : keys) EXPECT_TRUE(e.contains(k)) << k;
    const std::string q = e.at("quantity");
    EXPECT_TRUE(q == "irradiance" || q == "hemispherical" || q == "normalized") << q;
    const std::string p = e.at("precision");
    EXPECT_TRUE(p == "float" || p == "double") << p;
    EXPECT_TRUE(e.at("nonfinite").is_number_integer());
  }
  namespace fs = std::filesystem;
  for (const char* f :
       {"summary.csv", "summary.md", "summary.json", "per_kappa.csv", "per_kappa.md", "points.csv"})
    EXPECT_TRUE(fs::exists(dir.path / f)) << f;
}

TEST(SweepCli, MethodFilter) {
  const sglab::test::TempDir dir("sweep-filter");
  const auto r =
      sweep_cli("--kappa 1:1:1 --cosines 3 --method meder2018 --method tokuyoshi2024 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  // meder2018 exists for all three quantities, tokuyoshi2024 for irradiance only; × 2 precisions.
  EXPECT_EQ(j.at("results").size(), 8u);
}

TEST(SweepCli, BadKappaExitsTwoNamingTheOption) {
  const sglab::test::TempDir dir("sweep-bad-kappa");
  for (const char* bad :
       {"--kappa=-1:10:5", "--kappa -1:10:5", "--kappa a:b:c", "--kappa 1:10", "--kappa 1:10:5:7",
        "--kappa 10:1:5", "--kappa 1:10:0", "--kappa 1:10:1", "--kappa inf:1e4:3",
        "--kappa 1:nan:3", "--kappa 0:10:5", "--kappa 1:1e40:5", "--kappa 1:10:2.5"}) {
    const auto r = sweep_cli(bad, dir);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("--kappa"), std::string::npos) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("sglab: error:"), std::string::npos) << bad << "\n" << r.output;
  }
}

TEST(SweepCli, BadCosinesAndUnknownMethodExitTwo) {
  const sglab::test::TempDir dir("sweep-bad");
  for (const char* bad : {"--cosines 1", "--cosines x", "--cosines -3"}) {
    const auto r = sweep_cli(bad, dir);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("--cosines"), std::string::npos) << bad << "\n" << r.output;
  }
  const auto r = sweep_cli("--method no_such_method", dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no_such_method"), std::string::npos) << r.output;
  for (const auto& m : sglab::irradiance_methods)
    EXPECT_NE(r.output.find(std::string(m.id)), std::string::npos) << m.id;
}
