// The minimax engine of fit/lp_minimax.hpp against closed forms: the best
// polynomial approximation of x^{n+1} on [−1, 1] ([Cheney1966] ch. 3), its
// equioscillation, a weighted problem solved by hand, the certificate
// (lower bound ≤ achieved) and the refusal of ill-posed input.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fit/lp_minimax.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::fit::extrema;
using sglab::fit::lp_minimax;
using sglab::fit::lp_minimax_on;

// Coefficients of the Chebyshev polynomial T_k in the monomial basis, by the
// three-term recurrence T_{k+1} = 2x T_k − T_{k−1}.
std::vector<double> chebyshev_coefficients(int k) {
  std::vector<double> prev{1}, cur{0, 1};
  if (k == 0) return prev;
  for (int i = 1; i < k; ++i) {
    std::vector<double> next(cur.size() + 1, 0.0);
    for (std::size_t j = 0; j < cur.size(); ++j) next[j + 1] += 2 * cur[j];
    for (std::size_t j = 0; j < prev.size(); ++j) next[j] -= prev[j];
    prev = cur;
    cur = next;
  }
  return cur;
}

// Rows x_i of a uniform grid of [−1, 1] and the points cos(kπ/(n + 1)), where
// x^{n+1} − 2^{−n} T_{n+1} − x^{n+1} peaks: sorted, so that row neighbours are
// neighbours in x.
std::vector<double> grid_with_extrema(int n, int uniform) {
  std::vector<double> x;
  for (int i = 0; i < uniform; ++i) x.push_back(-1 + 2.0 * i / (uniform - 1));
  for (int k = 1; k <= n; ++k) x.push_back(std::cos(k * M_PI / (n + 1)));
  std::sort(x.begin(), x.end());
  return x;
}

struct Problem {
  Eigen::MatrixXd a;
  Eigen::VectorXd y, w;
};

// Degree-n polynomial (monomials) against f on the points x, weights 1.
template <class F>
Problem polynomial_problem(const std::vector<double>& x, int n, F f) {
  Problem p{Eigen::MatrixXd(Eigen::Index(x.size()), n + 1), Eigen::VectorXd(Eigen::Index(x.size())),
            Eigen::VectorXd::Ones(Eigen::Index(x.size()))};
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int j = 0; j <= n; ++j) p.a(Eigen::Index(i), j) = std::pow(x[i], j);
    p.y[Eigen::Index(i)] = f(x[i]);
  }
  return p;
}

TEST(LpMinimax, BestPolynomialApproximationOfAMonomialIsTheChebyshevClosedForm) {
  for (int n = 1; n <= 8; ++n) {
    const auto x = grid_with_extrema(n, 2001);
    const Problem p = polynomial_problem(x, n, [n](double v) { return std::pow(v, n + 1); });
    const auto r = lp_minimax(p.a, p.y, p.w);
    const double want = std::ldexp(1.0, -n);  // 2^{−n}
    ASSERT_TRUE(r.converged) << "n = " << n;
    // CLP's feasibility tolerance (1e-10 on rows of size ~1) bounds the
    // bound's agreement; the exchange stops at a relative gap of 1e-6.
    EXPECT_NEAR(r.achieved, want, 1e-6 * want) << "n = " << n;
    EXPECT_NEAR(r.lower_bound, want, 1e-7 * want) << "n = " << n;
    EXPECT_LE(r.lower_bound, want * (1 + 1e-12)) << "n = " << n;
    EXPECT_LT(r.working_rows, x.size()) << "the exchange solved on a subset";
    // p*(x) = x^{n+1} − 2^{−n} T_{n+1}(x): its coefficients.
    const auto t = chebyshev_coefficients(n + 1);
    // The monomial basis is ill-conditioned (|coefficients| up to 2.25 at n = 8).
    for (int j = 0; j <= n; ++j)
      EXPECT_NEAR(r.x[j], -want * t[std::size_t(j)], 1e-7) << "n = " << n << ", x^" << j;
  }
}

TEST(LpMinimax, ErrorOfTheBestApproximationEquioscillates) {
  // exp on [−1, 1], degree n: no closed form, but the alternation theorem
  // ([Cheney1966] ch. 3): n + 2 extrema of equal size and alternating sign.
  for (int n = 2; n <= 5; ++n) {
    std::vector<double> x;
    for (int i = 0; i < 4001; ++i) x.push_back(-1 + 2.0 * i / 4000);
    const Problem p = polynomial_problem(x, n, [](double v) { return std::exp(v); });
    const auto r = lp_minimax(p.a, p.y, p.w);
    ASSERT_TRUE(r.converged);
    const Eigen::VectorXd res = p.a * r.x - p.y;
    const auto e = extrema(res, r.achieved * (1 - 1e-3));
    EXPECT_EQ(e.rows.size(), std::size_t(n + 2)) << "n = " << n;
    EXPECT_EQ(e.alternations, std::size_t(n + 1)) << "n = " << n;
  }
}

TEST(LpMinimax, LowerBoundOnAnySubsetIsBelowTheAchievedMaximum) {
  std::vector<double> x;
  for (int i = 0; i < 3001; ++i) x.push_back(-1 + 2.0 * i / 3000);
  const Problem p = polynomial_problem(x, 4, [](double v) { return 1 / (1.5 + v); });
  const auto full = lp_minimax(p.a, p.y, p.w);
  ASSERT_TRUE(full.converged);
  EXPECT_LE(full.lower_bound, full.achieved);
  std::vector<std::size_t> every, some;
  for (std::size_t i = 0; i < x.size(); ++i) every.push_back(i);
  for (std::size_t i = 0; i < x.size(); i += 97) some.push_back(i);
  // one LP on every row: the exact minimax
  const auto all_rows = lp_minimax_on(p.a, p.y, p.w, every);
  const auto subset = lp_minimax_on(p.a, p.y, p.w, some);
  EXPECT_LE(subset.lower_bound, all_rows.lower_bound * (1 + 1e-12));
  EXPECT_LE(all_rows.lower_bound, full.achieved * (1 + 1e-12));
  EXPECT_NEAR(full.achieved, all_rows.lower_bound, 1e-6 * all_rows.lower_bound);
  EXPECT_GT(subset.achieved, subset.lower_bound)
      << "a sparse subset misses the peaks: its x is worse on every row";
}

TEST(LpMinimax, WeightsAreHonoured) {
  // One unknown c against y = 0 (weight 1) and y = 1 (weight 3), alternating:
  // min max(|c|, |c − 1|/3) is reached where c = (1 − c)/3: c = E = 1/4.
  const int m = 40;
  Eigen::MatrixXd a = Eigen::MatrixXd::Ones(m, 1);
  Eigen::VectorXd y(m), w(m);
  for (int i = 0; i < m; ++i) y[i] = i % 2, w[i] = i % 2 ? 3 : 1;
  const auto r = lp_minimax(a, y, w);
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.x[0], 0.25, 1e-12);
  EXPECT_NEAR(r.achieved, 0.25, 1e-12);
  EXPECT_NEAR(r.lower_bound, 0.25, 1e-12);
  // Every weight × 4: the same x, the weighted error / 4.
  const auto scaled = lp_minimax(a, y, Eigen::VectorXd(4 * w));
  EXPECT_NEAR(scaled.x[0], 0.25, 1e-12);
  EXPECT_NEAR(scaled.achieved, 0.0625, 1e-12);
}

void expect_refused(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, const Eigen::VectorXd& w,
                    const std::string& fragment) {
  try {
    lp_minimax(a, y, w);
    ADD_FAILURE() << "accepted; expected a message with '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(LpMinimax, IllPosedInputIsRefusedWithAClearMessage) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(10, 2);
  const Eigen::VectorXd y = Eigen::VectorXd::Random(10), w = Eigen::VectorXd::Ones(10);
  expect_refused(Eigen::MatrixXd(10, 0), y, w, "no unknown");
  expect_refused(a, Eigen::VectorXd::Ones(9), w, "rows but y has 9");
  expect_refused(a.topRows(2), y.head(2), w.head(2), "at least 3");
  Eigen::MatrixXd dependent = a;
  dependent.col(1) = 2 * a.col(0);
  expect_refused(dependent, y, w, "linearly dependent");
  Eigen::MatrixXd zero = a;
  zero.col(1).setZero();
  expect_refused(zero, y, w, "column 1 is zero");
  Eigen::VectorXd bad_w = w;
  bad_w[3] = 0;
  expect_refused(a, y, bad_w, "weight 0 of row 3");
  bad_w[3] = -1;
  expect_refused(a, y, bad_w, "weight -1 of row 3");
  Eigen::VectorXd bad_y = y;
  bad_y[5] = std::nan("");
  expect_refused(a, bad_y, w, "non-finite");
  EXPECT_THROW(lp_minimax_on(a, y, w, {0, 1, 10}), std::invalid_argument);
}

// y = p0 + p1·x + p2·x² − data, the residual code of a fit: its linear part
// in (p0, p2) at p1 held is exact, and the LP on it is the minimax.
struct QuadraticResidual {
  double x, data;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = p[0][0] + p[1][0] * T(x) + p[2][0] * T(x * x) - T(data);
    return true;
  }
};

TEST(LpMinimax, LinearSubproblemOfAFitsResidualsIsExact) {
  using namespace sglab::fit;
  Residuals residuals;
  std::vector<double> xs;
  for (int i = 0; i < 101; ++i) xs.push_back(-1 + 0.02 * i);
  for (double x : xs) residuals.push_back(make_residual(QuadraticResidual{x, std::abs(x)}, 3));
  const std::vector<double> values = {0.3, 0.0, -0.7};  // p1 = 0 held: |x| is even
  const LinearSubproblem sub = linear_subproblem(residuals, values, {0, 2});
  ASSERT_EQ(sub.a.cols(), 2);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    EXPECT_DOUBLE_EQ(sub.a(Eigen::Index(i), 0), 1.0);
    EXPECT_NEAR(sub.a(Eigen::Index(i), 1), xs[i] * xs[i], 1e-15);
    // −r(x₀)
    EXPECT_NEAR(sub.y[Eigen::Index(i)], std::abs(xs[i]) - 0.3 + 0.7 * xs[i] * xs[i], 1e-15);
  }
  // Best even quadratic to |x| on [−1, 1] = best linear a + b·s to √s on
  // s = x² ∈ [0, 1]: b = 1, a = 1/8, error 1/8 (chord slope, tangent at s = 1/4).
  const auto r = lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  EXPECT_NEAR(sub.x0[0] + r.x[0], 0.125, 1e-9);
  EXPECT_NEAR(sub.x0[1] + r.x[1], 1.0, 1e-9);
  EXPECT_NEAR(r.achieved, 0.125, 1e-9);
  EXPECT_LE(r.lower_bound, r.achieved * (1 + 1e-9));
}

// The schema (fit/constants_schema.cpp) checks a certificate: a set whose
// certificate lacks its lower bound, or whose bound is above what the fit
// achieved or not positive, is refused, naming the file and the key.
TEST(LpMinimax, ConstantSetWithAnIncompleteCertificateIsRefused) {
  namespace fs = std::filesystem;
  sglab::test::TempDir tmp("lp_certificate");
  const fs::path dir = tmp.path / "constants";
  fs::create_directories(dir);
  for (const auto& e :
       fs::directory_iterator(fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants"))
    fs::copy_file(e.path(), dir / e.path().filename());
  const fs::path file = dir / "sglab-acc-acc3.json";
  std::ifstream in(file);
  auto set = nlohmann::ordered_json::parse(in);
  set["provenance"]["certificate"] = {
      {"kind", "lp_at_fitted_steepness"}, {"grid", "g"}, {"achieved", 0.5}};
  std::ofstream(file, std::ios::trunc) << set.dump(2);
  const auto r = sglab::test::run_sglab({"constants", "--dir", dir.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("sglab-acc-acc3.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("provenance.certificate.lower_bound"), std::string::npos) << r.output;
  // A bound above what the fit achieved, or not positive, is no certificate.
  for (double bad : {0.6, 0.0}) {
    set["provenance"]["certificate"]["lower_bound"] = bad;
    std::ofstream(file, std::ios::trunc) << set.dump(2);
    const auto refused = sglab::test::run_sglab({"constants", "--dir", dir.string()});
    EXPECT_EQ(refused.exit_code, 2) << bad << ": " << refused.output;
    EXPECT_NE(refused.output.find("provenance.certificate.lower_bound"), std::string::npos)
        << refused.output;
  }
  set["provenance"]["certificate"]["lower_bound"] = 0.4;
  std::ofstream(file, std::ios::trunc) << set.dump(2);
  EXPECT_EQ(sglab::test::run_sglab({"constants", "--dir", dir.string()}).exit_code, 0);
}

}  // namespace
