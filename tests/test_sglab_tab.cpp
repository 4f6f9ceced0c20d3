// sglab_tab (include/sglab/sglab_tab.hpp): its cells, its table, its behaviour outside the
// fitted range and the certificate of the committed table. Its error against the
// reference engine on random points, its per-light split and float batch are checked with
// every method by tests/test_methods.cpp, its card to κ = FLT_MAX by
// tests/test_kappa_range.cpp.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "reference/reference.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;
constexpr std::size_t kCells = 32, kCoefs = 28;

double card_bound() {
  return sglab::find_method(sglab::irradiance_methods, "sglab_tab")->valid.max_peak_rel;
}

// u = √κ/(1 + √κ) in 32 equal cells: the cell's ends at their κ, κ = 0 and κ = FLT_MAX.
TEST(SglabTab, CellsCoverEveryKappa) {
  for (std::size_t j = 0; j < kCells; ++j) {
    const double u = (double(j) + 0.5) / kCells, k = std::pow(u / (1 - u), 2);
    const auto cell = sglab::detail::sglab_tab_cell<kCells>(k);
    EXPECT_EQ(cell.index, j) << k;
    EXPECT_NEAR(cell.t, 0.0, 1e-12) << k;
  }
  const auto zero = sglab::detail::sglab_tab_cell<kCells>(0.0f);
  EXPECT_EQ(zero.index, 0u);
  EXPECT_EQ(zero.t, -1.0f);
  const auto top = sglab::detail::sglab_tab_cell<kCells>(std::numeric_limits<float>::max());
  EXPECT_EQ(top.index, kCells - 1);
  EXPECT_EQ(top.t, 1.0f);
  // Outside the domain (NaN, κ < 0, +inf) the index stays a cell of the table.
  for (float k :
       {std::numeric_limits<float>::quiet_NaN(), -1.0f, std::numeric_limits<float>::infinity()})
    EXPECT_LT(sglab::detail::sglab_tab_cell<kCells>(k).index, kCells) << k;
  // u = 1/2 is κ = 1: the start of cell 16.
  const auto one = sglab::detail::sglab_tab_cell<kCells>(1.0);
  EXPECT_EQ(one.index, 16u);
  EXPECT_EQ(one.t, -1.0);
}

// Neighbouring cells were fitted apart, but each follows the same smooth E: where they
// meet, their shapes agree to within twice the card's bound at every cosine.
TEST(SglabTab, NeighbouringCellsAgreeWhereTheyMeet) {
  const auto& p = sglab::constants::sglab_tab_float;
  const auto values = [&](std::size_t j, double t) {
    std::vector<double> v(sglab::kSglabTabValues);
    for (std::size_t m = 0; m < v.size(); ++m) {
      const double* c = p.coef + j * kCoefs + m * 4;
      v[m] = c[0] + t * (c[1] + t * (c[2] + t * c[3]));
    }
    return v;
  };
  for (std::size_t j = 0; j + 1 < kCells; ++j) {
    const double u = double(j + 1) / kCells, k = std::pow(u / (1 - u), 2);
    const auto a = values(j, 1.0), b = values(j + 1, -1.0);
    double worst = 0;
    for (int i = 0; i <= 200; ++i) {
      const double c = -1 + i / 100.0;
      const auto shape = [&](const std::vector<double>& v) {
        return std::max(0.0, sglab::detail::sglab_tab_shape(c, v[0], v[1], v[2], v[3], v[4],
                                                            v[5] - std::log1p(k), k * v[6]));
      };
      worst = std::max(worst, std::abs(shape(a) - shape(b)));
    }
    EXPECT_LE(worst, 2 * card_bound()) << "cells " << j << " and " << j + 1 << " at kappa " << k;
  }
}

// Finite and ≥ 0 for every κ ≥ 0 a float holds, and E = π for every normal as κ → 0.
TEST(SglabTab, FiniteAndNonNegativeOutsideTheFittedRange) {
  const float fk[] = {0.0f,  std::numeric_limits<float>::denorm_min(), 1e-30f, 1e-4f, 2e4f, 1e8f,
                      1e30f, std::numeric_limits<float>::max()};
  for (float k : fk)
    for (float c : {-1.0f, -0.3f, 0.0f, 1e-6f, 0.5f, 1.0f}) {
      const float v = sglab::irradiance_sglab_tab(c, k);
      const double d = sglab::irradiance_sglab_tab(double(c), double(k));
      EXPECT_TRUE(std::isfinite(v) && v >= 0) << "float kappa " << hex(k) << " c " << hex(c);
      EXPECT_TRUE(std::isfinite(d) && d >= 0) << "double kappa " << hex(k) << " c " << hex(c);
    }
  for (float c : {-1.0f, 0.0f, 1.0f})
    EXPECT_NEAR(sglab::irradiance_sglab_tab(c, 0.0f), M_PI, card_bound() * M_PI) << c;
}

// The certificate of the committed table (fit/fit_sglab_tab.cpp), recomputed another way:
// per cell, the residual's derivatives in the 20 linear coefficients by Ceres' automatic
// differentiation of the runtime shape (the fit uses its own analytic Jacobian), the LP of
// lp_minimax on the cell's training points with E/E(1) ≥ L; the largest cell bound and the
// achieved max are those the provenance records.
struct CellResidual {
  double kappa, t, cosine, normalized;
  std::vector<double> fixed;  // the cell's 28 coefficients
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    T v[sglab::kSglabTabValues];
    for (std::size_t m = 0; m < sglab::kSglabTabValues; ++m) {
      T acc(0);
      for (std::size_t i = 4; i-- > 0;) {
        const std::size_t j = m * 4 + i;
        acc = acc * T(t) + (j < 20 ? p[j][0] : T(fixed[j]));
      }
      v[m] = acc;
    }
    r[0] = sglab::detail::sglab_tab_shape(T(cosine), v[0], v[1], v[2], v[3], v[4],
                                          v[5] - T(std::log1p(kappa)), T(kappa) * v[6]) -
           T(normalized);
    return true;
  }
};

TEST(SglabTab, CertificateIsThatOfTheCommittedTable) {
  std::ifstream in(sglab::test::checkout_dir() / "data" / "constants" / "sglab-tab-float.json");
  const auto set = nlohmann::json::parse(in);
  const auto& recorded = set["provenance"]["certificate"];
  const auto& p = sglab::constants::sglab_tab_float;
  // The fit's training points: 10 κ a cell equally spaced in u (the top cell's last at
  // u = 1 − 1e−6, then 1e16, 1e24, 1e32) × 201 cosines.
  std::vector<double> kappas;
  std::vector<std::size_t> cell_of;
  for (std::size_t j = 0; j < kCells; ++j)
    for (int i = 0; i < 10; ++i) {
      double u = (double(j) + i / 9.0) / kCells;
      if (j + 1 == kCells && i == 9) u = 1 - 1e-6;
      kappas.push_back(std::pow(u / (1 - u), 2)), cell_of.push_back(j);
    }
  for (double k : {1e16, 1e24, 1e32}) kappas.push_back(k), cell_of.push_back(kCells - 1);
  std::vector<double> cosines;
  for (int i = 0; i <= 200; ++i) cosines.push_back(-1 + i / 100.0);
  const auto ref =
      sglab::reference::reference_engine().evaluate(sglab::fit::product_grid(kappas, cosines));
  double bound = 0, achieved = 0;
  std::size_t rows = 0;
  for (std::size_t j = 0; j < kCells; ++j) {
    const std::vector<double> fixed(p.coef + j * kCoefs, p.coef + (j + 1) * kCoefs);
    sglab::fit::Residuals residuals;
    for (std::size_t i = 0; i < kappas.size(); ++i) {
      if (cell_of[i] != j) continue;
      const double k = kappas[i], e1 = sglab::irradiance_upper(k);
      const double u = std::sqrt(k) / (1 + std::sqrt(k));
      const double t = std::clamp(2 * (u * kCells - double(j)) - 1, -1.0, 1.0);
      for (std::size_t c = 0; c < cosines.size(); ++c) {
        const auto& r = ref[i * cosines.size() + c];
        if (r.irradiance < sglab::fit::kCertificateLevel * e1) continue;
        residuals.push_back(
            sglab::fit::make_residual(CellResidual{k, t, r.cosine, r.irradiance / e1, fixed}, 20));
      }
    }
    const std::vector<double> start(fixed.begin(), fixed.begin() + 20);
    std::vector<std::size_t> linear(20);
    for (std::size_t i = 0; i < 20; ++i) linear[i] = i;
    const auto sub = sglab::fit::linear_subproblem(residuals, start, linear);
    const auto lp = sglab::fit::lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
    bound = std::max(bound, std::min(lp.lower_bound, sglab::fit::kCertificateLevel));
    achieved = std::max(
        achieved, sglab::fit::max_abs_residual(sglab::fit::evaluate_residuals(residuals, start)));
    rows += residuals.size();
  }
  EXPECT_EQ(recorded["grid"].get<std::string>().find(std::to_string(rows) + " training points"),
            std::string("the ").size())
      << recorded["grid"];
  EXPECT_NEAR(achieved, recorded["achieved"].get<double>(), 1e-9 * achieved);
  EXPECT_NEAR(bound, recorded["lower_bound"].get<double>(), 1e-6 * bound);
  EXPECT_LE(bound, achieved);
}

}  // namespace
