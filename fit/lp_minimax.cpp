// fit/lp_minimax.cpp — the discrete weighted Chebyshev problem as a linear
// program (COIN-OR CLP) and its exchange on a dense set of rows (lp_minimax.hpp).
#include "fit/lp_minimax.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include <ClpSimplex.hpp>
#include <CoinFinite.hpp>

namespace sglab::fit {

namespace {

// Ill-posed input is refused before any LP is built (lp_minimax.hpp).
void check_problem(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, const Eigen::VectorXd& w) {
  const auto m = a.rows(), n = a.cols();
  if (n == 0) throw std::invalid_argument("lp_minimax: the problem has no unknown (0 columns)");
  if (y.size() != m || w.size() != m)
    throw std::invalid_argument(
        fmt::format("lp_minimax: A has {} rows but y has {} and w {}", m, y.size(), w.size()));
  if (m < n + 1)
    throw std::invalid_argument(fmt::format(
        "lp_minimax: {} rows for {} unknowns: at least {} are needed (the minimax would be 0)", m,
        n, n + 1));
  if (!a.allFinite() || !y.allFinite())
    throw std::invalid_argument("lp_minimax: A or y has a non-finite entry");
  for (Eigen::Index i = 0; i < m; ++i)
    if (!(w[i] > 0) || !std::isfinite(w[i]))
      throw std::invalid_argument(
          fmt::format("lp_minimax: weight {} of row {} is not positive and finite", w[i], i));
  // Columns scaled to unit max norm, then a rank-revealing QR: dependent
  // columns leave x undetermined (the LP would return one of many).
  const Eigen::VectorXd norms = a.cwiseAbs().colwise().maxCoeff().transpose();
  for (Eigen::Index j = 0; j < n; ++j)
    if (norms[j] == 0) throw std::invalid_argument(fmt::format("lp_minimax: column {} is zero", j));
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a * norms.cwiseInverse().asDiagonal());
  qr.setThreshold(1e-13);
  if (qr.rank() < n)
    throw std::invalid_argument(fmt::format(
        "lp_minimax: the {} columns are linearly dependent (rank {}): x is not determined", n,
        qr.rank()));
}

// |(A x − y)_i| / w_i for every row.
Eigen::VectorXd weighted_residuals(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                                   const Eigen::VectorXd& w, const Eigen::VectorXd& x) {
  return (a * x - y).cwiseQuotient(w);
}

// Entries of the scaled LP (|entries| ≤ 1, E = O(1)) below this are taken as 0:
// far under CLP's tolerances (1e−10), and entries of 1e−20 and less (rows where
// e^{−z²} has almost underflowed) made its simplex report a feasible LP infeasible.
constexpr double kNegligible = 1e-15;

// The LP on `rows`: unknowns x (free; columns scaled to unit max norm on
// these rows) and E ≥ 0; per row two constraints, A'x − E ≤ y' and
// A'x + E ≥ y', with A' = A/w, y' = y/w ([Cheney1966] ch. 2). Minimize E.
// With `lower`, the second constraint only on the rows i where lower[i].
LpMinimaxResult solve_lp(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& w, const std::vector<std::size_t>& rows,
                         const std::vector<bool>* lower = nullptr,
                         const Eigen::VectorXd* x_lo = nullptr,
                         const Eigen::VectorXd* x_hi = nullptr) {
  const int n = int(a.cols()), m = int(rows.size());
  Eigen::MatrixXd as(m, n);
  Eigen::VectorXd ys(m);
  for (int r = 0; r < m; ++r) {
    const auto i = Eigen::Index(rows[std::size_t(r)]);
    as.row(r) = a.row(i) / w[i];
    ys[r] = y[i] / w[i];
  }
  // Rows scaled by σ = max |y'| so that E is O(1) against CLP's absolute
  // tolerances (x is unchanged, E is σ times the scaled optimum).
  const double sigma = ys.cwiseAbs().maxCoeff() > 0 ? ys.cwiseAbs().maxCoeff() : 1.0;
  as /= sigma;
  ys /= sigma;
  Eigen::VectorXd scale = as.cwiseAbs().colwise().maxCoeff().transpose();
  for (int j = 0; j < n; ++j)
    if (scale[j] == 0) scale[j] = 1;
  // Column-major sparse form (CLP's loadProblem): n + 1 columns, 2m rows.
  std::vector<CoinBigIndex> start{0};
  std::vector<int> index;
  std::vector<double> value;
  for (int j = 0; j < n; ++j) {
    for (int r = 0; r < m; ++r)
      if (const double v = as(r, j) / scale[j]; std::abs(v) > kNegligible) {
        index.push_back(2 * r), value.push_back(v);
        index.push_back(2 * r + 1), value.push_back(v);
      }
    start.push_back(CoinBigIndex(index.size()));
  }
  for (int r = 0; r < m; ++r)
    index.push_back(2 * r), value.push_back(-1), index.push_back(2 * r + 1), value.push_back(1);
  start.push_back(CoinBigIndex(index.size()));
  std::vector<double> col_lo(std::size_t(n + 1), -COIN_DBL_MAX),
      col_hi(std::size_t(n + 1), COIN_DBL_MAX);
  col_lo[std::size_t(n)] = 0;
  // A box on x, in the scaled unknowns x' = x·scale (infinite entries stay unbounded).
  for (int j = 0; j < n; ++j) {
    if (x_lo && std::isfinite((*x_lo)[j])) col_lo[std::size_t(j)] = (*x_lo)[j] * scale[j];
    if (x_hi && std::isfinite((*x_hi)[j])) col_hi[std::size_t(j)] = (*x_hi)[j] * scale[j];
  }
  std::vector<double> obj(std::size_t(n + 1), 0.0);
  obj[std::size_t(n)] = 1;
  std::vector<double> row_lo(std::size_t(2 * m)), row_hi(std::size_t(2 * m));
  for (int r = 0; r < m; ++r) {
    row_lo[std::size_t(2 * r)] = -COIN_DBL_MAX, row_hi[std::size_t(2 * r)] = ys[r];
    row_lo[std::size_t(2 * r + 1)] = ys[r], row_hi[std::size_t(2 * r + 1)] = COIN_DBL_MAX;
    if (lower && !(*lower)[rows[std::size_t(r)]]) row_lo[std::size_t(2 * r + 1)] = -COIN_DBL_MAX;
  }
  // Dual simplex; where it ends without a clean optimum (the scaled problem
  // optimal but not the unscaled one, or a feasible LP reported infeasible),
  // the same LP afresh by CLP's initialSolve (presolve, its own choice of
  // method), then by primal simplex without scaling.
  ClpSimplex lp;
  for (int attempt = 0; attempt < 3; ++attempt) {
    lp = ClpSimplex();
    lp.setLogLevel(0);
    lp.loadProblem(n + 1, 2 * m, start.data(), index.data(), value.data(), col_lo.data(),
                   col_hi.data(), obj.data(), row_lo.data(), row_hi.data());
    lp.setPrimalTolerance(1e-10);
    lp.setDualTolerance(1e-10);
    if (attempt == 0) lp.dual();
    if (attempt == 1) lp.initialSolve();
    if (attempt == 2) lp.scaling(0), lp.primal();
    if (lp.status() == 0 && lp.secondaryStatus() == 0) break;
  }
  if (lp.status() != 0 || lp.secondaryStatus() != 0)
    throw std::runtime_error(
        fmt::format("lp_minimax: CLP stopped without an optimum (status {}, secondary status {}, "
                    "{} rows, {} unknowns)",
                    lp.status(), lp.secondaryStatus(), m, n));
  LpMinimaxResult out;
  out.x.resize(n);
  const double* sol = lp.getColSolution();
  for (int j = 0; j < n; ++j) out.x[j] = sol[j] / scale[j];
  out.lower_bound = sol[n] * sigma;
  out.working_rows = rows.size();
  return out;
}

// Rows to add: the largest local maxima of |r| above `level` not yet in the
// working set, `per_round` at most, each with `neighbours` rows on either side.
std::vector<std::size_t> rows_to_add(const Eigen::VectorXd& r, double level,
                                     const std::vector<bool>& in_set, const LpMinimaxOptions& o,
                                     std::size_t per_round) {
  std::vector<std::size_t> add;
  std::size_t taken = 0;
  const auto m = std::size_t(r.size());
  for (std::size_t i : extrema(r, level).rows) {
    if (taken == per_round) break;
    bool any = false;
    for (std::size_t k = i >= o.neighbours ? i - o.neighbours : 0;
         k <= std::min(m - 1, i + o.neighbours); ++k)
      if (!in_set[k] && std::find(add.begin(), add.end(), k) == add.end())
        add.push_back(k), any = true;
    taken += any;
  }
  return add;
}

// The one-sided LP on every row (lp_minimax_upper, lp_minimax_upper_boxed) and its achieved
// max: (A x − y)_i/w_i, and its absolute value where lower[i].
LpMinimaxResult solve_upper(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                            const Eigen::VectorXd& w, const std::vector<bool>& lower,
                            const Eigen::VectorXd* x_lo = nullptr,
                            const Eigen::VectorXd* x_hi = nullptr) {
  std::vector<std::size_t> rows(std::size_t(a.rows()));
  std::iota(rows.begin(), rows.end(), std::size_t(0));
  LpMinimaxResult out = solve_lp(a, y, w, rows, &lower, x_lo, x_hi);
  const Eigen::VectorXd r = weighted_residuals(a, y, w, out.x);
  out.achieved = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double v = lower[std::size_t(i)] ? std::abs(r[i]) : std::max(r[i], 0.0);
    if (v > out.achieved) out.achieved = v, out.worst = std::size_t(i);
  }
  out.converged = true;
  return out;
}

}  // namespace

Extrema extrema(const Eigen::VectorXd& r, double level) {
  Extrema out;
  const auto m = r.size();
  std::vector<std::size_t> peaks;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double v = std::abs(r[i]);
    if (v > level && (i == 0 || v >= std::abs(r[i - 1])) && (i + 1 == m || v >= std::abs(r[i + 1])))
      peaks.push_back(std::size_t(i));
  }
  for (std::size_t k = 1; k < peaks.size(); ++k)
    out.alternations += (r[Eigen::Index(peaks[k])] > 0) != (r[Eigen::Index(peaks[k - 1])] > 0);
  std::stable_sort(peaks.begin(), peaks.end(), [&](std::size_t p, std::size_t q) {
    return std::abs(r[Eigen::Index(p)]) > std::abs(r[Eigen::Index(q)]);
  });
  out.rows = std::move(peaks);
  return out;
}

LpMinimaxResult lp_minimax_on(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                              const Eigen::VectorXd& w, const std::vector<std::size_t>& rows) {
  check_problem(a, y, w);
  for (std::size_t i : rows)
    if (i >= std::size_t(a.rows()))
      throw std::invalid_argument(fmt::format("lp_minimax: row {} out of range", i));
  LpMinimaxResult out = solve_lp(a, y, w, rows);
  const Eigen::VectorXd r = weighted_residuals(a, y, w, out.x).cwiseAbs();
  out.achieved = r.maxCoeff(&out.worst);
  return out;
}

LpMinimaxResult lp_minimax_upper(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                                 const Eigen::VectorXd& w, const std::vector<bool>& lower) {
  check_problem(a, y, w);
  if (lower.size() != std::size_t(a.rows()))
    throw std::invalid_argument(
        fmt::format("lp_minimax: {} rows but {} lower flags", a.rows(), lower.size()));
  return solve_upper(a, y, w, lower);
}

LpMinimaxResult lp_minimax_upper_boxed(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                                       const Eigen::VectorXd& w, const std::vector<bool>& lower,
                                       const Eigen::VectorXd& x_lo, const Eigen::VectorXd& x_hi) {
  const auto m = a.rows(), n = a.cols();
  if (n == 0 || y.size() != m || w.size() != m || std::size_t(m) != lower.size() ||
      x_lo.size() != n || x_hi.size() != n)
    throw std::invalid_argument(
        fmt::format("lp_minimax: A is {}x{} but y has {} rows, w {}, lower {}, the box {} and {}",
                    m, n, y.size(), w.size(), lower.size(), x_lo.size(), x_hi.size()));
  if (!a.allFinite() || !y.allFinite())
    throw std::invalid_argument("lp_minimax: A or y has a non-finite entry");
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(x_lo[j] <= x_hi[j]))
      throw std::invalid_argument(fmt::format("lp_minimax: the box of unknown {} is empty", j));
  return solve_upper(a, y, w, lower, &x_lo, &x_hi);
}

LpMinimaxResult lp_minimax(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& w, const LpMinimaxOptions& options) {
  check_problem(a, y, w);
  const auto m = std::size_t(a.rows()), n = std::size_t(a.cols());
  const std::size_t first = std::min(
      m, options.initial_rows ? options.initial_rows : std::max<std::size_t>(32, 4 * (n + 1)));
  const std::size_t per_round = options.peaks_per_round ? options.peaks_per_round : 2 * (n + 1);
  std::vector<bool> in_set(m, false);
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < first; ++k) {
    const std::size_t i = first == 1 ? 0 : k * (m - 1) / (first - 1);  // evenly spread, both ends
    if (!in_set[i]) in_set[i] = true, rows.push_back(i);
  }
  // Rounding of the residuals themselves: below it the two bounds cannot be told apart.
  const double rounding =
      64 * std::numeric_limits<double>::epsilon() * y.cwiseQuotient(w).cwiseAbs().maxCoeff();
  LpMinimaxResult best;
  for (int round = 1;; ++round) {
    std::sort(rows.begin(), rows.end());
    LpMinimaxResult lp = solve_lp(a, y, w, rows);
    const Eigen::VectorXd r = weighted_residuals(a, y, w, lp.x);
    lp.achieved = r.cwiseAbs().maxCoeff(&lp.worst);
    lp.rounds = round;
    // The LP optimum only grows as rows are added; keep the best x seen.
    const double bound = std::max(best.lower_bound, lp.lower_bound);
    if (round == 1 || lp.achieved < best.achieved) best = lp;
    best.lower_bound = bound;
    best.rounds = round;
    best.working_rows = rows.size();
    best.converged = best.achieved <= bound * (1 + options.relative_gap) + rounding;
    if (best.converged || round >= options.max_rounds) return best;
    const auto add = rows_to_add(r, lp.lower_bound, in_set, options, per_round);
    if (add.empty()) return best;  // every peak is in the set: only rounding separates the two
    for (std::size_t i : add) in_set[i] = true, rows.push_back(i);
  }
}

double max_abs_residual(const std::vector<double>& r) {
  double m = 0;
  for (double x : r)
    m = std::isfinite(x) ? std::max(m, std::abs(x)) : std::numeric_limits<double>::infinity();
  return m;
}

LinearSubproblem linear_subproblem(const Residuals& residuals, const std::vector<double>& values,
                                   const std::vector<std::size_t>& linear) {
  const auto m = Eigen::Index(residuals.size()), k = Eigen::Index(linear.size());
  std::vector<const double*> blocks(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) blocks[i] = &values[i];
  std::vector<double> column(linear.size());
  // only the linear blocks are differentiated
  std::vector<double*> jacobians(values.size(), nullptr);
  for (std::size_t c = 0; c < linear.size(); ++c) jacobians[linear[c]] = &column[c];
  Eigen::VectorXd x0(k);
  for (Eigen::Index c = 0; c < k; ++c) x0[c] = values[linear[std::size_t(c)]];
  LinearSubproblem out{Eigen::MatrixXd(m, k), Eigen::VectorXd(m), x0};
  for (Eigen::Index i = 0; i < m; ++i) {
    double r = 0;
    if (!residuals[std::size_t(i)]->Evaluate(blocks.data(), &r, jacobians.data()))
      throw std::runtime_error(fmt::format("lp_minimax: residual {} cannot be evaluated", i));
    for (Eigen::Index c = 0; c < k; ++c) out.a(i, c) = column[std::size_t(c)];
    out.y[i] = -r;
  }
  return out;
}

}  // namespace sglab::fit
