// fit/lp_minimax.hpp — the discrete weighted Chebyshev (minimax) problem
//
//   min_x max_i |(A x − y)_i| / w_i,
//
// the linear sub-problems of the fits (coefficients at fixed nonlinear
// parameters), solved exactly as the linear program
//   min E  subject to  −w_i E ≤ (A x − y)_i ≤ w_i E
// with COIN-OR CLP ([Cheney1966] ch. 2: the discrete Chebyshev problem is an
// LP), and its exchange form on a dense set of rows: solve on a working
// subset, evaluate every row, add the rows where |r_i|/w_i peaks (and their
// neighbours in row order), repeat (the exchange of Remez, [Cheney1966] ch. 3, in discrete form).
//
// A certificate comes with every answer: the LP optimum on any subset of
// the rows is a lower bound of the minimax over all of them (fewer
// constraints), and the max over all rows at the returned x is achieved; the
// exchange stops when the two agree to a tolerance.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "fit/minimax.hpp"

namespace sglab::fit {

struct LpMinimaxOptions {
  // The exchange stops when achieved ≤ lower_bound·(1 + relative_gap) (plus the
  // rounding of the residuals, 64 ε max|y_i/w_i|).
  double relative_gap = 1e-6;
  int max_rounds = 40;
  // rows of the first working set (evenly spread); 0: 4(n + 1), at least 32
  std::size_t initial_rows = 0;
  std::size_t peaks_per_round = 0;  // largest local maxima added per round; 0: 2(n + 1)
  std::size_t neighbours = 1;       // rows on each side of a peak added with it
};

struct LpMinimaxResult {
  Eigen::VectorXd x;
  double lower_bound = 0;  // the LP optimum on the final working set: ≤ the minimax over every row
  double achieved = 0;     // max_i |(A x − y)_i| / w_i over every row
  std::size_t worst = 0;   // the row where `achieved` is reached
  std::size_t working_rows = 0;
  int rounds = 0;
  bool converged = false;  // achieved ≤ lower_bound·(1 + relative_gap) (+ rounding)
};

// min_x max_i |(A x − y)_i| / w_i by the exchange above (one LP when the
// working set starts as every row). Rows are taken in the order given (the
// neighbours of a row are the rows next to it). Throws std::invalid_argument
// for ill-posed input: sizes that disagree, no column, fewer rows than
// columns + 1, a non-finite entry, a weight that is not positive and finite,
// or columns that are linearly dependent (x not determined); and
// std::runtime_error when CLP does not reach an optimum.
LpMinimaxResult lp_minimax(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                           const Eigen::VectorXd& w, const LpMinimaxOptions& options = {});

// The LP optimum (and its x) on exactly the rows `rows` of the problem: the
// building block of the exchange, a lower bound of the minimax on any
// superset of the rows.
LpMinimaxResult lp_minimax_on(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                              const Eigen::VectorXd& w, const std::vector<std::size_t>& rows);

// The one-sided form on every row: min_x E with (A x − y)_i ≤ w_i E on every
// row and (A x − y)_i ≥ −w_i E on the rows where lower[i] (one LP). With y ≥ 0
// and lower[i] = y_i/w_i > E, this is the minimax of |max(0, A x) − y|/w, the
// clamped models' problem (fit/fit_sglab_min.cpp iterates the level).
// `achieved`: the max over rows of (A x − y)_i/w_i, and of its absolute value
// where lower[i].
LpMinimaxResult lp_minimax_upper(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                                 const Eigen::VectorXd& w, const std::vector<bool>& lower);

// lp_minimax_upper with x held in the box x_lo ≤ x ≤ x_hi (±inf entries: unbounded): the
// step of a sequential LP with a trust region (fit/fit_sglab_tab.cpp). The box keeps the
// LP bounded, so dependent or zero columns are allowed here (x is then one of the optima).
LpMinimaxResult lp_minimax_upper_boxed(const Eigen::MatrixXd& a, const Eigen::VectorXd& y,
                                       const Eigen::VectorXd& w, const std::vector<bool>& lower,
                                       const Eigen::VectorXd& x_lo, const Eigen::VectorXd& x_hi);

// The indices of the local maxima of |r_i| (r_i ≥ each neighbour in row
// order) that exceed `level`, largest first, and the count of alternations
// of sign among them: the equioscillation of a best approximation
// ([Cheney1966] ch. 3) shows as n + 1 alternating extrema at the optimum.
struct Extrema {
  std::vector<std::size_t> rows;
  std::size_t alternations = 0;  // sign changes between successive extrema in row order
};
Extrema extrema(const Eigen::VectorXd& r, double level);

// The linear part of a fit's residuals (fit/minimax.hpp) in the parameters
// `linear` at `values` (the others held): r_i(x₀ + δ) = r_i(x₀) + J_i·δ, J the
// Jacobian of the residual code itself (Ceres' automatic derivatives), as
// A δ − y with A = J, y = −r(x₀) (the step δ from x₀ keeps y the size of the
// residuals, not of the coefficients). Exact where the residuals are linear
// in those parameters (a coefficient vector at fixed nonlinear parameters).
struct LinearSubproblem {
  Eigen::MatrixXd a;
  Eigen::VectorXd y;
  Eigen::VectorXd x0;  // `values` at the `linear` indices: the solution is x₀ + δ
};
LinearSubproblem linear_subproblem(const Residuals& residuals, const std::vector<double>& values,
                                   const std::vector<std::size_t>& linear);

// max_i |r_i| of residual values (+inf when one is not finite).
double max_abs_residual(const std::vector<double>& r);

}  // namespace sglab::fit
