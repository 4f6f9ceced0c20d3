// tests/test_claims.cpp — `sglab claims` checks (validate/claims.hpp).
#include <chrono>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <tuple>

#include <unistd.h>

#include <gtest/gtest.h>

#include "validate/claims.hpp"

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
    const auto g = [](double t, double m, double l) {
      return std::exp(-(t - m) * (t - m) / (l * l));
    };
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
    const auto g = [](double t, double m, double l) {
      return std::exp(2 * (std::cos(t - m) - 1) / (l * l));
    };
    const double lhs = g(x, m1, l1) * g(x, m2, l2), rhs = p.b * g(x, p.mu, p.lambda);
    if (lhs < 1e-250) continue;
    EXPECT_NEAR(rhs / lhs, 1.0, 1e-11) << "trial " << i;
  }
  EXPECT_LT(gaussian_product_max_rel_error(5000, 2u, true), 1e-10);
}
