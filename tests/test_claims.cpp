// tests/test_claims.cpp — `sglab claims` checks and `sglab figures` output.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "claims.hpp"
#include "figures.hpp"
#include "io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace sglab::validate;

TEST(Claims, AbramowitzStegunBoundHolds) {
  const double err = as7125_max_abs_error(200'001);
  EXPECT_LE(err, 2.5e-5);
  EXPECT_GT(err, 1e-6);  // a real approximation, not std::erf
}

TEST(Claims, AbramowitzStegunVerdictInTable) {
  // The full claim list without the (slow) t* fits.
  const auto claims = check_claims({});
  bool found = false;
  for (const Claim& c : claims)
    if (c.id == "as7125_bound") {
      found = true;
      EXPECT_EQ(c.verdict, "holds") << c.measured;
    }
  EXPECT_TRUE(found);
  const Table t = claims_table(claims);
  EXPECT_EQ(t.rows().size(), claims.size());
  EXPECT_NO_THROW(t.column_index("verdict"));
}

TEST(Claims, FresnelMonotoneForEta1_5) {
  const FresnelShape s = fresnel_shape(1.5);
  EXPECT_TRUE(s.monotone_increasing);
  EXPECT_TRUE(s.quasiconvex);
  EXPECT_LT(s.eq6_max_error, 1e-12);
}

TEST(Claims, FresnelNotMonotoneButQuasiconvexForEta5) {
  const FresnelShape s = fresnel_shape(5.0);
  EXPECT_FALSE(s.monotone_increasing);
  EXPECT_TRUE(s.quasiconvex);
  EXPECT_LT(s.eq6_max_error, 1e-12);  // Eq. 6 still gives the maximum
  // Normal incidence: ((η−1)/(η+1))².
  EXPECT_NEAR(fresnel_dielectric(1.0, 5.0), 4.0 / 9.0, 1e-15);
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, 1e-15);
}

TEST(Claims, GaussianProductIdentityAtRandomPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> mu(-2, 2), lam(0.2, 2), xs(-3, 3);
  for (int i = 0; i < 1000; ++i) {
    const double m1 = mu(rng), l1 = lam(rng), m2 = mu(rng), l2 = lam(rng), x = xs(rng);
    const auto p = gaussian_product(m1, l1, m2, l2);
    const auto g = [](double x, double m, double l) { return std::exp(-(x - m) * (x - m) / (l * l)); };
    const double lhs = g(x, m1, l1) * g(x, m2, l2), rhs = p.b * g(x, p.mu, p.lambda);
    if (lhs < 1e-250) continue;
    EXPECT_NEAR(rhs / lhs, 1.0, 1e-11) << "trial " << i;
  }
  EXPECT_LT(gaussian_product_max_rel_error(5000, 1u, false), 1e-10);
}

TEST(Claims, CircularGaussianProductIdentityAtRandomPoints) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> mu(-std::numbers::pi, std::numbers::pi), lam(0.2, 2);
  for (int i = 0; i < 1000; ++i) {
    const double m1 = mu(rng), l1 = lam(rng), m2 = mu(rng), l2 = lam(rng), x = mu(rng);
    const auto p = circular_gaussian_product(m1, l1, m2, l2);
    const auto g = [](double x, double m, double l) { return std::exp(2 * (std::cos(x - m) - 1) / (l * l)); };
    const double lhs = g(x, m1, l1) * g(x, m2, l2), rhs = p.b * g(x, p.mu, p.lambda);
    if (lhs < 1e-250) continue;
    EXPECT_NEAR(rhs / lhs, 1.0, 1e-11) << "trial " << i;
  }
  EXPECT_LT(gaussian_product_max_rel_error(5000, 2u, true), 1e-10);
}

TEST(Figures, ReadParetoCsvRejectsBadHeader) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sglab_test_claims_{}", ::getpid());
  fs::create_directories(dir);
  sglab::io::write_file_atomic(dir / "bad.csv", "method,cost\nx,1\n");
  EXPECT_THROW(read_pareto_csv(dir / "bad.csv"), std::invalid_argument);
  fs::remove_all(dir);
}

TEST(Figures, CommandWritesPngAndSvg) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  const fs::path dir = fs::temp_directory_path() / fmt::format("sglab_test_figures_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path pareto = dir / "pareto.csv";
  sglab::io::write_file_atomic(pareto,
                               "method,refit,precision,kappa_lo,kappa_hi,ns_per_eval,max_peak_rel,frontier\n"
                               "punctual,false,float,0.001,10000,0.8,0.9,true\n"
                               "wang2009,false,float,0.001,10000,2.5,0.35,false\n"
                               "hill,false,float,0.001,10000,3.0,0.05,true\n"
                               "tokuyoshi2022,false,float,0.001,10000,12.0,0.0045,true\n"
                               "tokuyoshi2024_refit,true,float,0.001,10000,15.0,0.0014,true\n"
                               "tokuyoshi2024,false,double,0.001,10000,20.0,0.0013,true\n"
                               "\"meder2018\",false,double,0.001,10000,9.0,0.02,true\n");
  const fs::path out = dir / "figs";
  const auto r = sglab::test::run_sglab({"figures", "--out", out.string(), "--pareto", pareto.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* stem : {"a_clamped_cosine", "b_steepness", "c_irradiance_kappa4", "d_peak_rel_heatmaps", "e_pareto",
                           "f_erf_ulp"})
    for (const char* ext : {".png", ".svg"}) {
      const fs::path p = out / (std::string(stem) + ext);
      ASSERT_TRUE(fs::exists(p)) << p << "\n" << r.output;
      EXPECT_GT(fs::file_size(p), 1000u) << p;
    }
  EXPECT_TRUE(fs::exists(out / "index.md"));
  EXPECT_TRUE(fs::exists(out / "a_clamped_cosine.csv"));
  EXPECT_TRUE(fs::exists(out / "e_pareto_points.csv"));
  fs::remove_all(dir);
}

TEST(Figures, MissingParetoFileIsSkipped) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  // Only checks the command line path: figure (e) skipped with a message, exit 0.
  const fs::path dir = fs::temp_directory_path() / fmt::format("sglab_test_figures_np_{}", ::getpid());
  fs::remove_all(dir);
  const auto r =
      sglab::test::run_sglab({"figures", "--out", (dir / "figs").string(), "--pareto", (dir / "absent.csv").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("not found"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "figs" / "e_pareto.png"));
  fs::remove_all(dir);
}
