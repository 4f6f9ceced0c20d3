// `sglab fit sglab-tab`: the table of sglab_tab (include/sglab/sglab_tab.hpp)
//   Ê = E(1, κ)·max(0, A + B (c + √(c² + g)) + D c² + (G + H c²) g),
//   g = e^{S − V c²},  S = s − ln(1 + κ),  V = κ v,
// A, B, D, G, H, s, v cubics in t on each of N equal cells of u = √κ/(1 + √κ).
// The cells share nothing, so each is fitted on its own, by a sequential
// linear program: at the current table the residual is linearized in the
// cell's 28 coefficients (exact in the 20 of A, B, D, G, H, which enter
// linearly), the one-sided LP of the clamped problem (lp_minimax_upper_boxed:
// Ê ≤ E + e everywhere, Ê ≥ E − e where E/E(1) > 1e−6) gives a step with the
// 8 coefficients of s and v held in a trust region, and the step is kept when
// the true max error falls (the region grows) or refused (it shrinks). The
// problem has many local minima in s and v, so no single start is trusted:
//   1. per κ of the training grid, the best seven values at that κ alone (the
//      same SLP with constants, continued from the previous κ and from the
//      best of a grid of S × V): the family's per-κ floor, and a path of S, V;
//   2. per cell (a cold start), from (a) the best constant S, V of a grid at
//      the cell's middle κ, (b) the previous cell's cubics continued (their
//      Taylor shift by one cell), (c) least-squares cubics through the per-κ
//      path; then (d) each cell again from the next cell's cubics, kept where
//      better. Without --cold-start, the committed table's s and v are kept and
//      each cell's A, B, D, G, H cubics refitted by the exact LP.
// Certified per cell: at the fitted s and v the 20 coefficients of A, B, D, G,
// H enter linearly, and the LP on the cell's training points with E/E(1) ≥ L
// bounds how well any of their values could do there; the largest cell bound
// is a bound for the table. docs/models.md#sglab_tab.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Dense>

#include <sglab/sglab.hpp>
#include <sglab/sglab_tab.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/rational_shape_fit.hpp"

namespace sglab::fit {

namespace {

constexpr std::size_t kCells = 32, kDegree = 3;
using TabParams = SglabTabParams<double, kCells, kDegree>;
constexpr std::size_t kValues = kSglabTabValues;         // A, B, D, G, H, s, v
constexpr std::size_t kLinearValues = 5;                 // A, B, D, G, H
constexpr std::size_t kCoefs = kValues * (kDegree + 1);  // per cell
constexpr std::size_t kLinearCoefs = kLinearValues * (kDegree + 1);
constexpr int kKappasPerCell = 10;  // equally spaced in u, both ends of the cell
constexpr int kCosines = 201;       // uniform over [−1, 1]
// Beyond the last training u of the top cell (1 − 1e−6, κ ≈ 1e12): κ towards the largest
// float, where t → 1.
constexpr double kLimitKappas[] = {1e16, 1e24, 1e32};
// Rows where E/E(1) is below this are held only from above (the clamp makes any lower
// value of the shape exact enough).
constexpr double kLowerLevel = 1e-6;
constexpr int kSlpIterations = 100;
// A polish of the committed table: the exact linear coefficients at its s and v only (each
// step of the sequential LP costs about 0.6 s a cell; `fit all` runs in the main job).
constexpr int kPolishIterations = 0;
constexpr const char* kValueNames[] = {"A", "B", "D", "G", "H", "s", "v"};

double u_of(double kappa) { return std::sqrt(kappa) / (1 + std::sqrt(kappa)); }
double kappa_of(double u) {
  return u >= 1 ? std::numeric_limits<double>::infinity() : std::pow(u / (1 - u), 2);
}

// One cell's training points: κ, its local t, cosine and E/E(1, κ), κ-major.
struct Cell {
  std::vector<double> kappa, t, cosine, y;
  std::vector<std::size_t> kappa_start;  // first row of each κ
  std::size_t rows() const { return y.size(); }
};

// The cell's 28 coefficients, value-major: P[m(D + 1) + i] the coefficient of t^i of value m.
using Poly = std::array<double, kCoefs>;

struct Eval {
  Eigen::VectorXd f;  // the shape (unclamped) at every row
  Eigen::MatrixXd j;  // ∂f/∂P
};

// The shape at every row of `cell` (and its Jacobian in the coefficients when `jacobian`).
Eval evaluate(const Cell& cell, const Poly& p, bool jacobian) {
  const auto n = static_cast<Eigen::Index>(cell.rows());
  Eval out{Eigen::VectorXd(n),
           jacobian ? Eigen::MatrixXd(n, Eigen::Index(kCoefs)) : Eigen::MatrixXd()};
  for (Eigen::Index r = 0; r < n; ++r) {
    const auto i = std::size_t(r);
    const double t = cell.t[i], k = cell.kappa[i], c = cell.cosine[i], c2 = c * c;
    std::array<double, kDegree + 1> tp{};
    tp[0] = 1;
    for (std::size_t d = 1; d <= kDegree; ++d) tp[d] = tp[d - 1] * t;
    std::array<double, kValues> v{};
    for (std::size_t m = 0; m < kValues; ++m)
      for (std::size_t d = 0; d <= kDegree; ++d) v[m] += p[m * (kDegree + 1) + d] * tp[d];
    const double S = v[5] - std::log1p(k), V = k * v[6];
    const double x = S - V * c2, bound = detail::kSglabTabExponentBound;
    const double g = std::exp(std::clamp(x, -bound, bound)), w = std::sqrt(c2 + g);
    out.f[r] = v[0] + v[1] * (c + w) + v[2] * c2 + (v[3] + v[4] * c2) * g;
    if (!jacobian) continue;
    const double ds = std::abs(x) < bound ? (v[1] / (2 * w) + v[3] + v[4] * c2) * g : 0.0;
    const std::array<double, kValues> col = {1, c + w, c2, g, g * c2, ds, -ds * c2 * k};
    for (std::size_t m = 0; m < kValues; ++m)
      for (std::size_t d = 0; d <= kDegree; ++d)
        out.j(r, Eigen::Index(m * (kDegree + 1) + d)) = col[m] * tp[d];
  }
  return out;
}

// max |max(0, shape) − y| over the cell.
double cell_error(const Cell& cell, const Poly& p) {
  const Eval e = evaluate(cell, p, false);
  double m = 0;
  for (Eigen::Index r = 0; r < e.f.size(); ++r) {
    const double d = std::abs(std::max(e.f[r], 0.0) - cell.y[std::size_t(r)]);
    m = std::isfinite(d) ? std::max(m, d) : std::numeric_limits<double>::infinity();
  }
  return m;
}

// The violation of row r by the linearized residual d = f + J δ − y at level E: d − E
// above, −d − E below (only where the row is held from below).
double violation(double d, double level, bool lower) {
  return std::max(d - level, lower ? -d - level : -std::numeric_limits<double>::infinity());
}

// The rows to add to a working set: per κ of the cell, the local maxima over c of `score`
// above 0 (rows in κ-major, cosine order), each with its two neighbours.
void add_peaks(const Cell& cell, const Eigen::VectorXd& score, std::vector<bool>& in,
               std::vector<std::size_t>& rows) {
  for (std::size_t i = 0; i < cell.kappa_start.size(); ++i) {
    const std::size_t b = cell.kappa_start[i],
                      e = i + 1 < cell.kappa_start.size() ? cell.kappa_start[i + 1] : cell.rows();
    for (std::size_t r = b; r < e; ++r) {
      const double s = score[Eigen::Index(r)];
      if (!(s > 0) || (r > b && score[Eigen::Index(r - 1)] > s) ||
          (r + 1 < e && score[Eigen::Index(r + 1)] > s))
        continue;
      for (std::size_t q = r > b + 2 ? r - 2 : b; q <= std::min(e - 1, r + 2); ++q)
        if (!in[q]) in[q] = true, rows.push_back(q);
    }
  }
}

// One step of the sequential LP: the linear coefficients free, those of s and v within
// `region`·(1 + |p|) of p (region 0: s and v held). The LP over every row of the cell is
// solved by exchange (fit/lp_minimax.hpp): on a working set of rows, first the local peaks
// of the current error per κ, then every row its step violates added, until none does;
// the LP optimum of the set is then that of all rows.
std::optional<Poly> lp_step(const Cell& cell, const Poly& p, double region) {
  const Eval e = evaluate(cell, p, true);
  const auto n = e.f.size();
  if (!e.f.allFinite() || !e.j.allFinite()) return std::nullopt;
  Eigen::VectorXd y(n), score(n);
  std::vector<bool> lower(static_cast<std::size_t>(n));
  for (Eigen::Index r = 0; r < n; ++r) {
    y[r] = cell.y[std::size_t(r)] - e.f[r];
    lower[std::size_t(r)] = cell.y[std::size_t(r)] > kLowerLevel;
    score[r] = std::abs(std::max(e.f[r], 0.0) - cell.y[std::size_t(r)]) + 1e-300;
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(Eigen::Index(kCoefs), -inf);
  Eigen::VectorXd hi = Eigen::VectorXd::Constant(Eigen::Index(kCoefs), inf);
  for (std::size_t j = kLinearCoefs; j < kCoefs; ++j)
    lo[Eigen::Index(j)] = -region * (1 + std::abs(p[j])),
    hi[Eigen::Index(j)] = -lo[Eigen::Index(j)];
  // The columns that are not 0 on this cell (a cell of one κ at t = 0 moves only the
  // constant terms).
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < Eigen::Index(kCoefs); ++j)
    if (e.j.col(j).cwiseAbs().maxCoeff() > 0) cols.push_back(j);
  const auto nc = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd jc(n, nc);
  Eigen::VectorXd loc(nc), hic(nc);
  for (Eigen::Index k = 0; k < nc; ++k)
    jc.col(k) = e.j.col(cols[std::size_t(k)]), loc[k] = lo[cols[std::size_t(k)]],
    hic[k] = hi[cols[std::size_t(k)]];
  std::vector<bool> in(static_cast<std::size_t>(n), false);
  std::vector<std::size_t> rows;
  add_peaks(cell, score, in, rows);
  try {
    for (int round = 0; round < 20; ++round) {
      std::sort(rows.begin(), rows.end());
      const auto m = static_cast<Eigen::Index>(rows.size());
      Eigen::MatrixXd a(m, nc);
      Eigen::VectorXd ys(m);
      std::vector<bool> low(rows.size());
      for (Eigen::Index k = 0; k < m; ++k) {
        const auto r = static_cast<Eigen::Index>(rows[std::size_t(k)]);
        a.row(k) = jc.row(r), ys[k] = y[r], low[std::size_t(k)] = lower[std::size_t(r)];
      }
      const LpMinimaxResult lp =
          lp_minimax_upper_boxed(a, ys, Eigen::VectorXd::Ones(m), low, loc, hic);
      const Eigen::VectorXd d = jc * lp.x - y;
      const double level = lp.lower_bound * (1 + 1e-9) + 1e-15;
      bool violated = false;
      for (Eigen::Index r = 0; r < n; ++r) {
        score[r] = violation(d[r], level, lower[std::size_t(r)]);
        violated = violated || (score[r] > 0 && !in[std::size_t(r)]);
      }
      if (!violated) {
        Poly q = p;
        for (Eigen::Index k = 0; k < nc; ++k) q[std::size_t(cols[std::size_t(k)])] += lp.x[k];
        return q;
      }
      add_peaks(cell, score, in, rows);
    }
  } catch (const std::runtime_error&) {
    // CLP without an optimum: the caller shrinks the region
  }
  return std::nullopt;
}

struct CellFit {
  Poly p{};
  double error = std::numeric_limits<double>::infinity();
};

// The linear coefficients' exact best at p's s and v, then the sequential LP.
CellFit slp(const Cell& cell, Poly p, int iterations = kSlpIterations) {
  if (const auto q = lp_step(cell, p, 0.0)) p = *q;
  CellFit best{p, cell_error(cell, p)};
  // Stops when the region is below 1e−6 or ten steps have gained less than 0.1 %.
  double region = 0.3, ten_ago = best.error;
  for (int it = 1; it <= iterations && region > 1e-6; ++it) {
    const auto q = lp_step(cell, best.p, region);
    const double e = q ? cell_error(cell, *q) : std::numeric_limits<double>::infinity();
    if (e < best.error) {
      best = {*q, e};
      region = std::min(1.5 * region, 1.0);
    } else {
      region *= 0.4;
    }
    if (it % 10 == 0) {
      if (best.error > 0.999 * ten_ago) break;
      ten_ago = best.error;
    }
  }
  return best;
}

// The coefficients of p(t + d) (a Taylor shift): a neighbouring cell's cubics continued.
Poly shifted(const Poly& p, double d) {
  Poly q{};
  for (std::size_t m = 0; m < kValues; ++m)
    for (std::size_t j = 0; j <= kDegree; ++j) {
      double binom = 1, sum = 0;
      for (std::size_t i = j; i <= kDegree; ++i) {
        sum += p[m * (kDegree + 1) + i] * binom * std::pow(d, double(i - j));
        binom = binom * double(i + 1) / double(i + 1 - j);
      }
      q[m * (kDegree + 1) + j] = sum;
    }
  return q;
}

// Constant cubics of S, V at κ (at κ = 0, where V = κ v is 0 whatever v, v = 0).
Poly constant_start(double S, double V, double kappa) {
  Poly p{};
  p[5 * (kDegree + 1)] = S + std::log1p(kappa);
  p[6 * (kDegree + 1)] = kappa > 0 ? V / kappa : 0.0;
  return p;
}

// The rows of `cell` at its κ number i alone (t set to 0: constants).
Cell one_kappa(const Cell& cell, std::size_t i) {
  const std::size_t b = cell.kappa_start[i],
                    e = i + 1 < cell.kappa_start.size() ? cell.kappa_start[i + 1] : cell.rows();
  Cell one;
  for (std::size_t r = b; r < e; ++r) {
    one.kappa.push_back(cell.kappa[r]), one.t.push_back(0.0);
    one.cosine.push_back(cell.cosine[r]), one.y.push_back(cell.y[r]);
  }
  one.kappa_start = {0};
  return one;
}

// The best constant S, V of a grid (S ∈ [−12, 4], V/max(κ, 1) ∈ [−1, 2]) at one κ, by
// the least-squares A, B, D, G, H at each.
Poly grid_start(const Cell& one) {
  const double k = one.kappa[0], scale = std::max(k, 1.0);
  const auto n = static_cast<Eigen::Index>(one.rows());
  Eigen::Map<const Eigen::VectorXd> y(one.y.data(), n);
  double best = std::numeric_limits<double>::infinity(), bs = 0, bv = 0;
  Eigen::MatrixXd a(n, 5);
  for (double S = 4; S >= -12; S -= 1)
    for (double vn = -1; vn <= 2.0001; vn += 0.25) {
      const double V = vn * scale;
      for (Eigen::Index r = 0; r < n; ++r) {
        const double c = one.cosine[std::size_t(r)], c2 = c * c;
        const double g = std::exp(std::clamp(S - V * c2, -80.0, 80.0));
        a.row(r) << 1, c + std::sqrt(c2 + g), c2, g, g * c2;
      }
      const Eigen::VectorXd x = a.colPivHouseholderQr().solve(y);
      const double e = (a * x - y).cwiseAbs().maxCoeff();
      if (e < best) best = e, bs = S, bv = V;
    }
  return constant_start(bs, bv, k);
}

// Step 1 at every κ of a cell, continued from `previous` (the last κ's values).
struct PathPoint {
  double kappa, S, V, error;
};
std::vector<PathPoint> per_kappa(const Cell& cell, std::optional<Poly>& previous) {
  std::vector<PathPoint> out;
  for (std::size_t i = 0; i < cell.kappa_start.size(); ++i) {
    const Cell one = one_kappa(cell, i);
    const double k = one.kappa[0];
    CellFit best = slp(one, grid_start(one), 40);
    if (previous) {
      // The previous κ's values with S and V held (s, v re-anchored at this κ).
      Poly p = *previous;
      const CellFit c = slp(one, p, 40);
      if (c.error < best.error) best = c;
    }
    previous = best.p;
    const double s = best.p[5 * (kDegree + 1)], v = best.p[6 * (kDegree + 1)];
    out.push_back({k, s - std::log1p(k), k * v, best.error});
  }
  return out;
}

// Least-squares cubics in t through a path of S + ln(1 + κ) and V/κ.
Poly path_start(const Cell& cell, const std::vector<PathPoint>& path) {
  const auto n = static_cast<Eigen::Index>(path.size());
  Eigen::MatrixXd a(n, Eigen::Index(kDegree + 1));
  Eigen::VectorXd s(n), v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = cell.t[cell.kappa_start[std::size_t(i)]], k = path[std::size_t(i)].kappa;
    for (std::size_t d = 0; d <= kDegree; ++d) a(i, Eigen::Index(d)) = std::pow(t, double(d));
    s[i] = path[std::size_t(i)].S + std::log1p(k);
    v[i] = k > 0 ? path[std::size_t(i)].V / k : 0.0;
  }
  const auto qr = a.colPivHouseholderQr();
  const Eigen::VectorXd cs = qr.solve(s), cv = qr.solve(v);
  Poly p{};
  for (std::size_t d = 0; d <= kDegree; ++d) {
    p[5 * (kDegree + 1) + d] = cs[Eigen::Index(d)];
    p[6 * (kDegree + 1) + d] = cv[Eigen::Index(d)];
  }
  return p;
}

// The training cells: kKappasPerCell κ equally spaced in u over each cell (the top cell
// to u = 1 − 1e−6, then kLimitKappas) × kCosines cosines, with the reference values.
struct Training {
  std::vector<Cell> cells;
  std::vector<reference::ReferencePoint> points;
};
Training training_cells() {
  std::vector<double> kappas;
  std::vector<std::size_t> cell_of;
  for (std::size_t j = 0; j < kCells; ++j)
    for (int i = 0; i < kKappasPerCell; ++i) {
      double u = (double(j) + double(i) / (kKappasPerCell - 1)) / double(kCells);
      if (j + 1 == kCells && i + 1 == kKappasPerCell) u = 1 - 1e-6;
      kappas.push_back(kappa_of(u)), cell_of.push_back(j);
    }
  for (double k : kLimitKappas) kappas.push_back(k), cell_of.push_back(kCells - 1);
  const auto cosines = cosine_grid(kCosines);
  const auto ref = rational_reference_grid(kappas, cosines);
  Training out{std::vector<Cell>(kCells), ref};
  auto& cells = out.cells;
  for (std::size_t i = 0; i < kappas.size(); ++i) {
    Cell& cell = cells[cell_of[i]];
    const double k = kappas[i], u = u_of(k), e1 = irradiance_upper(k);
    const double t = std::clamp(2 * (u * double(kCells) - double(cell_of[i])) - 1, -1.0, 1.0);
    cell.kappa_start.push_back(cell.rows());
    for (std::size_t c = 0; c < cosines.size(); ++c) {
      const auto& r = ref[i * cosines.size() + c];
      cell.kappa.push_back(k), cell.t.push_back(t), cell.cosine.push_back(r.cosine);
      cell.y.push_back(r.irradiance / e1);
    }
  }
  return out;
}

TabParams table_of(const std::vector<CellFit>& fits) {
  TabParams p{};
  for (std::size_t j = 0; j < kCells; ++j)
    std::copy(fits[j].p.begin(), fits[j].p.end(), p.coef + j * kCoefs);
  return p;
}

std::optional<std::vector<Poly>> tab_committed_start(const std::string& variant, double lo,
                                                     double hi) {
  const auto c = committed_coefficients("sglab-tab", variant, lo, hi);
  if (!c || !c->contains("coef") || c->at("coef").size() != kCells * kCoefs) return std::nullopt;
  std::vector<Poly> out(kCells);
  for (std::size_t i = 0; i < kCells * kCoefs; ++i)
    out[i / kCoefs][i % kCoefs] = c->at("coef")[i].get<double>();
  return out;
}

constexpr const char* kTabForm =
    "E = E(1,kappa)*max(0, A + B*(c + sqrt(c^2 + g)) + D*c^2 + (G + H*c^2)*g), g = "
    "exp(clamp(S - V*c^2, -80, 80)), S = s - ln(1 + kappa), V = kappa*v; on cell j of u = "
    "sqrt(kappa)/(1 + sqrt(kappa)) (32 equal cells of [0, 1], t = 2(32u - j) - 1), A, B, D, G, "
    "H, s, v are cubics in t: coef[(7j + m)*4 + i] the coefficient of t^i of value m "
    "(A, B, D, G, H, s, v)";

}  // namespace

FitOutcome fit_sglab_tab(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "irradiance")
    throw std::invalid_argument(
        fmt::format("sglab-tab has the one objective 'irradiance'; got '{}'", spec.objective));
  if (spec.kappa_range_given)
    throw std::invalid_argument(
        "sglab-tab: --kappa does not apply: the table's cells cover every kappa >= 0");
  const std::string variant(io::to_string(spec.precision));
  std::optional<std::vector<Poly>> committed;
  if (!spec.cold_start) committed = tab_committed_start(variant, spec.kappa_lo, spec.kappa_hi);

  const Training training = training_cells();
  const std::vector<Cell>& cells = training.cells;
  const std::vector<reference::ReferencePoint>& train = training.points;
  std::vector<CellFit> fits(kCells);
  std::vector<PerKappaShape> per;
  double floor = 0;
  {
    std::optional<Poly> previous;
    for (std::size_t j = 0; j < kCells; ++j) {
      fit_progress_note(fmt::format("sglab-tab: cell {} of {}", j + 1, kCells));
      const Cell& cell = cells[j];
      const auto keep = [&](const CellFit& f) {
        if (f.error < fits[j].error) fits[j] = f;
      };
      if (committed) {  // a polish: the floor is the one the committed set records
        keep(slp(cell, (*committed)[j], kPolishIterations));
        continue;
      }
      // 1. The per-κ path (and floor, below).
      const std::vector<PathPoint> path = per_kappa(cell, previous);
      for (const PathPoint& q : path) per.push_back({q.kappa, {q.S, q.V}, q.error});
      // 2. The cell from its starts.
      const std::size_t middle = cell.kappa_start.size() / 2;
      keep(slp(cell, grid_start(one_kappa(cell, middle))));
      if (j > 0) keep(slp(cell, shifted(fits[j - 1].p, 2.0)));
      keep(slp(cell, path_start(cell, path)));
    }
  }
  if (committed)
    floor = committed_floor("sglab-tab", variant, spec.kappa_lo, spec.kappa_hi)
                .value_or(std::numeric_limits<double>::quiet_NaN());
  else
    for (std::size_t j = kCells - 1; j-- > 0;) {
      const CellFit f = slp(cells[j], shifted(fits[j + 1].p, -2.0));
      if (f.error < fits[j].error) fits[j] = f;
    }
  double objective = 0;
  for (const CellFit& f : fits) objective = std::max(objective, f.error);
  // The per-κ floor: at each training κ the best seven values found, by the per-κ search
  // or as the fitted cubics' values there (which are one choice of them).
  if (!committed) {
    std::size_t i = 0;
    for (std::size_t j = 0; j < kCells; ++j)
      for (std::size_t k = 0; k < cells[j].kappa_start.size(); ++k, ++i) {
        const Cell one = one_kappa(cells[j], k);
        Cell at = one;
        std::fill(at.t.begin(), at.t.end(), cells[j].t[cells[j].kappa_start[k]]);
        per[i].error = std::min(per[i].error, cell_error(at, fits[j].p));
        floor = std::max(floor, per[i].error);
      }
  }

  const TabParams table = table_of(fits);
  const auto model = [&table](auto c, auto k) { return irradiance_sglab_tab(c, k, table); };
  const MeasuringGrids grids = measuring_grids(spec);
  const Measurements m = measure_all(model, train, grids);

  // Certificate: per cell, the LP over the 20 linear coefficients at the fitted s and v,
  // on the rows with E/E(1) ≥ L.
  double bound = 0, achieved = 0;
  std::size_t cert_rows = 0, working_rows = 0;
  bool lp_converged = true;
  for (std::size_t j = 0; j < kCells; ++j) {
    Cell top;
    for (std::size_t r = 0; r < cells[j].rows(); ++r)
      if (cells[j].y[r] >= kCertificateLevel) {
        top.kappa.push_back(cells[j].kappa[r]), top.t.push_back(cells[j].t[r]);
        top.cosine.push_back(cells[j].cosine[r]), top.y.push_back(cells[j].y[r]);
      }
    top.kappa_start = {0};
    const Eval e = evaluate(top, fits[j].p, true);
    const Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(top.y.data(), e.f.size()) - e.f;
    const Eigen::MatrixXd a = e.j.leftCols(Eigen::Index(kLinearCoefs));
    const LpMinimaxResult lp = lp_minimax(a, y, Eigen::VectorXd::Ones(y.size()));
    bound = std::max(bound, std::min(lp.lower_bound, kCertificateLevel));
    achieved = std::max(achieved, y.cwiseAbs().maxCoeff());
    cert_rows += top.rows(), working_rows += lp.working_rows;
    lp_converged = lp_converged && lp.converged;
  }
  const ordered_json certificate = {
      {"kind",
       "lp_per_cell_at_fitted_s_v: per cell the cubics of A, B, D, G and H free, s and v as "
       "fitted; bound max over cells of min(LP optimum, L)"},
      {"grid", fmt::format("the {} training points with E/E(1) >= L = {} (of {})", cert_rows,
                           kCertificateLevel, train.size())},
      {"achieved", achieved},
      {"lower_bound", bound},
      {"within_percent_of_best_member", 100 * (achieved / bound - 1)},
      {"lp", {{"working_rows", working_rows}, {"cells", kCells}, {"converged", lp_converged}}}};

  ordered_json coefficients;
  coefficients["coef"] = ordered_json::array();
  for (double x : table.coef) coefficients["coef"].push_back(x);
  const ordered_json achieved_record = achieved_json(objective, floor, m, grids);
  FitSpec recorded = spec;
  recorded.kappa_count = int(kCells) * kKappasPerCell + int(std::size(kLimitKappas));
  recorded.cosine_count = kCosines;
  FitOutcome out;
  out.converged = std::isfinite(objective);
  out.constant_sets.push_back(make_constant_set(
      recorded, "sglab-tab", variant, "SglabTabParams<double, 32, 3>", kTabForm, coefficients,
      fmt::format("minimax of the sglab_tab irradiance peak_rel error (double), cell by cell, "
                  "over {} kappa per cell equally spaced in u (both ends; the top cell to u = 1 - "
                  "1e-6, then kappa 1e16, 1e24, 1e32) x {} uniform cosines; start: {}",
                  kKappasPerCell, kCosines,
                  committed ? "the committed table (polish)"
                            : "per cell the best of a grid start, the previous cell continued "
                              "and the per-kappa path, then the next cell continued"),
      achieved_record));
  out.constant_sets.back()["provenance"]["certificate"] = certificate;
  out.report = {{"target", "sglab-tab"},
                {"variant", variant},
                {"converged", out.converged},
                {"start", committed ? "committed constant set" : "cold start"},
                {"per_kappa_floor", floor},
                {"objective_error", objective},
                {"achieved", achieved_record},
                {"certificate", certificate},
                {"coefficients", coefficients},
                {"per_kappa", per_kappa_json(per)}};
  std::string text = fmt::format("sglab-tab/{}: per-kappa floor {:.3g}; training max {:.3g}\n",
                                 variant, floor, objective);
  for (std::size_t j = 0; j < kCells; ++j)
    text += fmt::format("  cell {:2} kappa [{:.4g}, {:.4g}]: {:.3g}\n", j, cells[j].kappa.front(),
                        cells[j].kappa.back(), fits[j].error);
  text += fmt::format(
      "  {}: max peak_rel float {:.3g}, double {:.3g}\n  {}: max peak_rel float {:.3g} at "
      "kappa {:.4g}, c {:.4g}, double {:.3g}\n  certificate: achieved {:.3g} on the points with "
      "E/E(1) >= {}, no A, B, D, G, H cubics at the fitted s, v do better than {:.3g}\n",
      grids.standard_name, m.standard.float_max, m.standard.double_max, grids.held_out_name,
      m.held_out.float_max, m.held_out.float_kappa, m.held_out.float_cosine, m.held_out.double_max,
      achieved, kCertificateLevel, bound);
  out.text = std::move(text);
  return out;
}

}  // namespace sglab::fit
