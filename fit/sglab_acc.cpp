// `sglab fit sglab-acc`: the sglab_acc ladder (include/sglab/sglab_acc.hpp), the
// [Tokuyoshi2024] lerp factor plus a faded even correction, members (N, D, M). Warm starts,
// the Ceres/LP alternation, the never-worse-than-tokuyoshi2024 weight, the training grid and
// the certificate: docs/models.md#sglab_acc1--sglab_acc4.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_acc.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "validate/reference.hpp"

namespace sglab::fit {

namespace {

struct Member {
  std::size_t n, d;   // correction terms, degree of the P_j
  std::size_t m = 2;  // order of the rational steepness t(κ) (2: the 2024 form)
  bool operator==(const Member&) const = default;
};

// The number of steepness coefficients of order m: P has m, Q m + 1 (params.hpp).
constexpr std::size_t steep_count(std::size_t m) { return 2 * m + 1; }

// The family, cheapest first (by the operations counted in `operations`):
// the one list of the members that are instantiated (with_member below).
constexpr Member kFamily[] = {{1, 2},    {1, 3}, {2, 2}, {2, 3},    {2, 5}, {3, 3},   {3, 4},
                              {3, 4, 3}, {4, 4}, {3, 6}, {3, 6, 3}, {4, 6}, {4, 6, 3}};

template <std::size_t V>
using Size = std::integral_constant<std::size_t, V>;

// f(Size<N>{}, Size<D>{}, Size<M>{}) for the member m = {N, D, M} of kFamily: the one bridge
// from a runtime member to the templated code (a fold over kFamily's indices).
template <class F>
auto with_member(Member m, F&& f) {
  using R = decltype(f(Size<kFamily[0].n>{}, Size<kFamily[0].d>{}, Size<kFamily[0].m>{}));
  return [&]<std::size_t... I>(std::index_sequence<I...>)->R {
    std::optional<R> r;
    ((m == kFamily[I] &&
      (r.emplace(f(Size<kFamily[I].n>{}, Size<kFamily[I].d>{}, Size<kFamily[I].m>{})), true)) ||
     ...);
    if (!r)
      throw std::invalid_argument(
          fmt::format("sglab-acc: no member N={} D={} M={}", m.n, m.d, m.m));
    return std::move(*r);
  }
  (std::make_index_sequence<std::size(kFamily)>{});
}

// f(Size<N>{}) for the number of terms N of a member of kFamily.
template <class F>
auto with_terms(std::size_t n, F&& f) {
  const Member* m =
      std::find_if(std::begin(kFamily), std::end(kFamily), [n](Member e) { return e.n == n; });
  if (m == std::end(kFamily))
    throw std::invalid_argument(fmt::format("sglab-acc: no member with N={}", n));
  return with_member(*m, [&](auto terms, auto, auto) { return f(terms); });
}
// The shipped ladder: id suffix and member.
struct Rung {
  const char* variant;
  Member member;
  double target;  // T of the weight w(κ): the max peak_rel error aimed at
};
constexpr Rung kLadder[] = {{"acc1", {1, 3}, 2.4e-4},
                            {"acc2", {2, 5}, 3.2e-5},
                            {"acc3", {3, 6, 3}, 1e-5},
                            {"acc4", {4, 6, 3}, 5e-6}};

// The cost of a member: the cost of the runtime method of the same form
// (N, D), the shipped sglab_acc<k> (its cost does not depend on the
// coefficients), over tokuyoshi2024's, both from the cost table (spec.costs:
// GPU cycles on navi21 when the table has them, else CPU batch ns). Never
// measured here: a report is the same for the same inputs. None for a form no
// shipped method has, or without a table.
std::optional<double> member_cost(Member m, const MethodCosts& costs) {
  const auto row = [&](const std::string& method) -> std::optional<double> {
    const auto it = costs.per_method.find(method);
    return it == costs.per_method.end() ? std::nullopt : std::optional<double>(it->second);
  };
  const auto base = row("tokuyoshi2024");
  for (const Rung& r : kLadder)
    if (r.member == m) {
      const auto own = row(std::string("sglab_") + r.variant);
      if (own && base) return *own / *base;
    }
  return std::nullopt;
}

// Extra operations over tokuyoshi2024 (float): per light (setup) the faded
// b_j: one division 1/(t + s), 5 multiplications for u, 1 − u and u(1 − u)³,
// N·D multiply-adds of the P_j and N products, and 2(M − 2) multiply-adds of
// a steepness of order M above the 2024 form's 2; per shading point (eval) N − 1
// multiply-adds of the polynomial in z² and 4 for (1 − c²)·e^{−z²}·poly added to f.
struct Operations {
  int setup, eval;
};
Operations operations(Member m) {
  return {1 + 5 + int(m.n * m.d + m.n) + 2 * (int(m.m) - 2), int(m.n) - 1 + 4};
}

// The search space of every solve below, a box (Ceres keeps each trial point
// inside it): log coefficients (names starting with "log") in [−200, 50],
// linear ones in [−1e6, 1e6]; the fits land far inside (|log| ≤ 46, |num| < 1).
// On the box the model and its derivatives are finite for every κ > 0 and
// c ∈ [−1, 1]: every coefficient is ≤ e^50 ≈ 5e21, and every denominator of
// t(κ) and b_j(κ) is ≥ min(κ³, 1) (κ < 1: the monic κ^k term plus positive
// ones; κ ≥ 1: 1 plus positive terms in 1/κ), so no intermediate overflows.
// Unbounded, a trust-region step once reached log B = 1024: e^1024 = inf, and
// the residual was NaN (Ceres rejected the step and logged it).
constexpr double kLogLower = -200, kLogUpper = 50, kLinearBound = 1e6;

void bound(Parameters& p) {
  p.lower.clear();
  p.upper.clear();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool log = p.names[i].rfind("log", 0) == 0;
    p.lower.push_back(log ? kLogLower : -kLinearBound);
    p.upper.push_back(log ? kLogUpper : kLinearBound);
    p.values[i] = std::clamp(p.values[i], p.lower[i], p.upper[i]);
  }
}

// Parameters: log steep[2M + 1], num[N(D+1)], then log scale: the steepness
// coefficients and the scale stay positive by construction (t(κ) real,
// b_j(κ) finite for every κ ≥ 0).
template <class T, std::size_t N, std::size_t D, std::size_t M>
SglabAccParams<T, N, D, M> unpack(T const* const* p) {
  using std::exp;
  constexpr std::size_t K = steep_count(M);
  SglabAccParams<T, N, D, M> q{};
  for (std::size_t i = 0; i < K; ++i) q.steep[i] = exp(p[i][0]);
  for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[K + i][0];
  q.scale = exp(p[K + N * (D + 1)][0]);
  return q;
}

// The peak_rel error divided by the sample's weight (SglabAccSample::weight).
template <std::size_t N, std::size_t D, std::size_t M>
struct PeakRelResidual {
  double kappa, cosine, reference, peak, weight;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const SglabAccParams<T, N, D, M> q = unpack<T, N, D, M>(p);
    r[0] = (irradiance_sglab_acc(T(cosine), T(kappa), q) - T(reference)) / T(peak * weight);
    return true;
  }
};

// κ log-spaced at half-step offsets over [lo, hi] plus the ends, and twice as
// dense where the 2024 form's residual lives (κ ∈ [0.5, 200], clipped to the range).
std::vector<double> training_kappas(double lo, double hi, int count) {
  std::vector<double> k = log_midpoints(lo, hi, count);
  k.push_back(lo);
  const double a = std::log(lo), b = std::log(hi);
  const double da = std::log(std::max(lo, 0.5)), db = std::log(std::min(hi, 200.0));
  if (db > da) {
    const int dense = 2 * int(std::ceil(count * (db - da) / (b - a)));
    for (int i = 0; i < dense; ++i) k.push_back(std::exp(da + (db - da) * (i + 0.25) / dense));
  }
  k.push_back(hi);
  std::sort(k.begin(), k.end());
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

std::vector<validate::Query> training_grid(double lo, double hi) {
  std::vector<validate::Query> q;
  const int uniform = 24, zcount = 16;
  for (double k : training_kappas(lo, hi, 40)) {
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    q.push_back({k, 0.0});
    for (int j = 0; j < uniform; ++j) q.push_back({k, -1 + 2 * (j + 0.5) / uniform});
    for (int j = 0; j < zcount; ++j) {
      const double c = 0.2 * (j + 0.5) / t;  // z = 0.1 … 3.1
      if (c < 1) q.push_back({k, c}), q.push_back({k, -c});
    }
  }
  return q;
}

// Dense training grid of the certificate (and of the LP's exchange): κ as
// training_kappas with twice the count, per κ c = 0, 64 cosines at half-step
// offsets of a uniform grid and c = ±z_k/t(κ), z_k = 0.05 … 3.15 (32), sorted
// by c (the exchange adds a peak's neighbours in c). Never a measuring grid.
constexpr int kDenseKappas = 80, kDenseUniform = 64;

}  // namespace

std::vector<validate::Query> sglab_acc_dense_grid(double lo, double hi) {
  std::vector<validate::Query> q;
  const int uniform = kDenseUniform, zcount = 32;
  for (double k : training_kappas(lo, hi, kDenseKappas)) {
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    std::vector<double> c{0.0};
    for (int j = 0; j < uniform; ++j) c.push_back(-1 + 2 * (j + 0.5) / uniform);
    for (int j = 0; j < zcount; ++j)
      if (const double x = 0.1 * (j + 0.5) / t; x < 1) c.push_back(x), c.push_back(-x);
    std::sort(c.begin(), c.end());
    for (double x : c) q.push_back({k, x});
  }
  return q;
}

namespace {

// The errors of member (N, D) with coefficients p on `ref` (model_family.hpp).
template <std::size_t N, std::size_t D, std::size_t M>
Measured measure(const SglabAccParams<double, N, D, M>& p,
                 const std::vector<validate::ReferencePoint>& ref) {
  return fit::measure([&](auto c, auto k) { return irradiance_sglab_acc(c, k, p); }, ref);
}

// The certificate of a member's fit, on the dense training
// grid (sglab_acc_dense_grid), in the units of the fit's objective, peak_rel/w(κ):
// achieved ≥ lower_bound ≥ per_kappa_floor.
struct Certificate {
  double achieved = 0;  // max at the final coefficients (double), every row
  // LP optimum at the fitted steepness t(κ) and scale s: the best member with those
  double lower_bound = 0;
  // max over κ of the optimum with b_j(κ) free at each κ, t(κ) as fitted
  double per_kappa_floor = 0;
  double per_kappa_floor_peak_rel = 0;  // the same without the weight w(κ) (plain max peak_rel)
  std::size_t rows = 0, kappas = 0, working_rows = 0;
  int rounds = 0;
  bool converged = false;  // the LP's exchange closed the gap (lp_minimax.hpp)
};

struct MemberFit {
  Member member;
  Certificate certificate;
  std::vector<double> values;  // steep[2M + 1], num, scale (itself, not its log)
  double train = 0;  // the fit objective: max of peak_rel/w(κ) on the training grid (double)
  Measured standard, held_out;
  // float scalar ns/eval over tokuyoshi2024's, from the cost table (member_cost)
  std::optional<double> cost;
  double floor = 0;  // max over κ of the per-κ optimum at the refitted 2024 t(κ) (0: not computed)
  bool converged = false;
};

template <std::size_t N, std::size_t D, std::size_t M>
SglabAccParams<double, N, D, M> params_of(const std::vector<double>& v) {
  constexpr std::size_t K = steep_count(M);
  SglabAccParams<double, N, D, M> p{};
  for (std::size_t i = 0; i < K; ++i) p.steep[i] = v[i];
  for (std::size_t i = 0; i < N * (D + 1); ++i) p.num[i] = v[K + i];
  p.scale = v[K + N * (D + 1)];
  return p;
}

// The residuals of member (N, D, M) on `samples`, of the parameters log steep[2M + 1], num, log
// scale.
template <std::size_t N, std::size_t D, std::size_t M>
Residuals member_residuals(const std::vector<SglabAccSample>& samples) {
  Residuals residuals;
  for (const auto& r : samples)
    residuals.push_back(make_residual(PeakRelResidual<N, D, M>{r.kappa, r.cosine, r.irradiance,
                                                               irradiance_upper(r.kappa), r.weight},
                                      steep_count(M) + N * (D + 1) + 1));
  return residuals;
}

template <std::size_t N, std::size_t D, std::size_t M>
SglabAccFit fit_coefficients(const std::vector<double>& start,
                             const std::vector<SglabAccSample>& samples, bool polish_only) {
  constexpr std::size_t K = steep_count(M);
  Parameters params;
  for (std::size_t i = 0; i < K; ++i) params.names.push_back(fmt::format("log_steep{}", i));
  for (std::size_t i = 0; i < N * (D + 1); ++i) params.names.push_back(fmt::format("num{}", i));
  params.names.push_back("log_scale");
  for (std::size_t i = 0; i < K; ++i) params.values.push_back(std::log(start[i]));
  params.values.insert(params.values.end(), start.begin() + K, start.begin() + K + N * (D + 1));
  params.values.push_back(std::log(start[K + N * (D + 1)]));
  bound(params);
  const Residuals residuals = member_residuals<N, D, M>(samples);
  // Fewer rounds than the defaults: the training grid is large and the
  // staged start is close. From a converged set (the committed JSON) a short
  // polish: the full schedule there takes minutes and moves the error < 2%.
  FitOptions options;
  options.lawson_iterations = polish_only ? 2 : 12;
  options.penalty_decades = polish_only ? 4 : 8;
  options.solver_iterations = polish_only ? 30 : 200;
  const FitResult f = fit(residuals, params, options);
  SglabAccFit out;
  for (std::size_t i = 0; i < K; ++i) out.values.push_back(std::exp(f.values[i]));
  out.values.insert(out.values.end(), f.values.begin() + K, f.values.begin() + K + N * (D + 1));
  out.values.push_back(std::exp(f.values[K + N * (D + 1)]));
  out.max_abs = f.max_abs;
  out.converged = f.converged;
  return out;
}

// Stage 1 — per κ, b_0 … b_{N−1} free at the refitted 2024 steepness t(κ):
// minimax of the peak_rel error over that κ's training cosines. Linear in the
// b_j, so the optimum is unique and smooth in κ (a good start for stage 2);
// its max over κ is the family's floor at that steepness.
template <std::size_t N>
struct PerKappaResidual {
  double t, cosine, reference, peak, lower, upper;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    using std::erfc;
    SglabAccLight<T, N> l;
    l.t = T(t);
    l.half_erfc_t = T(0.5) * erfc(l.t);
    l.tail_scale = T(0.5) * inv_sqrt_pi_v<T>() / l.t;
    l.t2 = l.t * l.t;
    l.lower = T(lower);
    l.upper = T(upper);
    for (std::size_t j = 0; j < N; ++j) l.b[j] = p[j][0];
    r[0] = (sglab_acc_eval(l, T(cosine)) - T(reference)) / T(peak);
    return true;
  }
};

struct KappaOptimum {
  double kappa, t, error;
  std::vector<double> b;
};

template <std::size_t N>
std::vector<KappaOptimum> per_kappa_optima(const std::vector<SglabAccSample>& samples) {
  std::vector<KappaOptimum> out;
  std::vector<double> b;
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    while (end < samples.size() && samples[end].kappa == samples[i].kappa) ++end;
    const double k = samples[i].kappa;
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    Parameters params;
    for (std::size_t j = 0; j < N; ++j)
      params.names.push_back(fmt::format("b{}", j)), params.values.push_back(0.0);
    bound(params);
    Residuals residuals;
    for (std::size_t s = i; s < end; ++s)
      residuals.push_back(make_residual(
          PerKappaResidual<N>{t, samples[s].cosine, samples[s].irradiance, irradiance_upper(k),
                              irradiance_lower_over_two_pi(k), irradiance_upper_over_two_pi(k)},
          params.size()));
    FitOptions options;
    options.lawson_iterations = 10;
    options.penalty_decades = 6;
    options.solver_iterations = 50;
    const FitResult f = fit(residuals, params, options);
    b = f.values;
    out.push_back({k, t, f.max_abs, b});
    i = end;
  }
  return out;
}

// Stage 2a — t(κ): the 2024 rational form (log coefficients) by least squares on log t − log t*.
struct LogSteepnessResidual {
  double kappa, log_t, weight;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    using std::exp;
    using std::log;
    const Steepness2024Params<T> s{exp(p[0][0]), exp(p[1][0]), exp(p[2][0]), exp(p[3][0]),
                                   exp(p[4][0])};
    r[0] = T(weight) * (log(steepness2024(T(kappa), s)) - T(log_t));
    return true;
  }
};

// Stage 2b — b_j(κ) = u(1 − u)³ P_j(u), u = t/(t + s) (log scale), least
// squares on the per-κ optima (at their steepness t) weighted by the
// sensitivity of peak_rel to f, (Ē(1) − Ē(−1))/Ē(1).
template <std::size_t N, std::size_t D>
struct FadeResidual {
  double t, weight;
  std::size_t j;
  double target;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    SglabAccParams<T, N, D, 2> q{};  // the fade alone: the steepness is unused
    for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[i][0];
    q.scale = exp(p[N * (D + 1)][0]);
    T b[N];
    detail::sglab_acc_fade(T(t), q, b);
    r[0] = T(weight) * (b[j] - T(target));
    return true;
  }
};

// The steepness coefficients steep (params.hpp order, highest first) of order
// m(steep) raised to order `to`: P and Q both multiplied by (κ + 1) per step,
// so t(κ) is the same function (a start for a higher order that begins at the
// lower one's error). Every coefficient stays positive.
std::vector<double> raise_steepness_order(const std::vector<double>& steep, std::size_t to) {
  std::size_t m = (steep.size() - 1) / 2;
  std::vector<double> p{1.0}, q{1.0};  // monic, highest first
  p.insert(p.end(), steep.begin(), steep.begin() + long(m));
  q.insert(q.end(), steep.begin() + long(m), steep.end());
  const auto times_kappa_plus_one = [](std::vector<double>& c) {
    c.push_back(0.0);
    for (std::size_t i = c.size() - 1; i > 0; --i) c[i] += c[i - 1];
  };
  for (; m < to; ++m) times_kappa_plus_one(p), times_kappa_plus_one(q);
  std::vector<double> out(p.begin() + 1, p.end());
  out.insert(out.end(), q.begin() + 1, q.end());
  return out;
}

// Start values (steep[2M + 1], num, scale) for member (N, D, M) from the per-κ optima.
template <std::size_t N, std::size_t D, std::size_t M>
std::vector<double> staged_start(const std::vector<KappaOptimum>& optima) {
  FitOptions ls;
  ls.norm = Norm::least_squares;
  ls.solver_iterations = 200;
  Parameters steep;
  const auto& s0 = constants::steepness2024_irradiance;
  steep.names = {"logA", "logB", "logC", "logD", "logE"};
  steep.values = {std::log(s0.A), std::log(s0.B), std::log(s0.C), std::log(s0.D), std::log(s0.E)};
  bound(steep);
  Residuals rs;
  for (const auto& o : optima) {
    const double w =
        1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    rs.push_back(make_residual(LogSteepnessResidual{o.kappa, std::log(o.t), w}, 5));
  }
  const FitResult ft = fit(rs, steep, ls);
  Parameters fade;
  for (std::size_t i = 0; i < N * (D + 1); ++i)
    fade.names.push_back(fmt::format("num{}", i)), fade.values.push_back(0.0);
  fade.names.push_back("log_scale");
  // u = 1/2 at t = 2 (κ ≈ 8), the middle of the 2024 form's residual
  fade.values.push_back(std::log(2.0));
  bound(fade);
  Residuals rr;
  for (const auto& o : optima) {
    const double w =
        1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    for (std::size_t j = 0; j < N; ++j)
      rr.push_back(make_residual(FadeResidual<N, D>{o.t, w, j, o.b[j]}, fade.size()));
  }
  // Polynomials first (linear, scale fixed), then everything.
  Parameters num_only = fade;
  num_only.fixed.assign(fade.size(), false);
  num_only.fixed.back() = true;
  fade.values = fit(rr, num_only, ls).values;
  const FitResult fr = fit(rr, fade, ls);
  std::vector<double> out;
  for (double v : ft.values) out.push_back(std::exp(v));
  out = raise_steepness_order(out, M);
  out.insert(out.end(), fr.values.begin(), fr.values.begin() + N * (D + 1));
  out.push_back(std::exp(fr.values.back()));
  return out;
}

// The parameters of member_residuals (log steep, num, log scale) of values (steep, num, scale),
// `k` steepness coefficients.
std::vector<double> log_parameters(std::vector<double> v, std::size_t k) {
  for (std::size_t i = 0; i < k; ++i) v[i] = std::log(v[i]);
  v.back() = std::log(v.back());
  return v;
}

// The best numerators at the steepness and scale of `values` on `samples`:
// at fixed t(κ) and s, f̂ and so Ê is linear in the coefficients of every P_j,
// so the minimax is the LP of fit/lp_minimax.hpp (exchange from a subset of
// the rows). Returns `values` with those numerators, and the LP's answer
// with `achieved` taken on the model itself (the clamp of f̂ to [0, 1] lies
// outside the linear part).
template <std::size_t N, std::size_t D, std::size_t M>
std::pair<std::vector<double>, LpMinimaxResult> best_numerators(
    const std::vector<double>& values, const std::vector<SglabAccSample>& samples) {
  constexpr std::size_t K = steep_count(M);
  const Residuals residuals = member_residuals<N, D, M>(samples);
  std::vector<std::size_t> linear(N * (D + 1));
  std::iota(linear.begin(), linear.end(), K);
  const LinearSubproblem sub = linear_subproblem(residuals, log_parameters(values, K), linear);
  LpMinimaxResult lp = lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  std::vector<double> out = values;
  for (std::size_t k = 0; k < linear.size(); ++k) out[K + k] += lp.x[Eigen::Index(k)];  // x₀ + δ
  lp.achieved = max_abs_residual(evaluate_residuals(residuals, log_parameters(out, K)));
  return {out, lp};
}

// The per-κ floor at the steepness steep[2M + 1]: at each κ of `samples` (grouped
// by κ) the LP optimum over its cosines with b_0 … b_{N−1} free (PerKappaResidual),
// t(κ) fixed; no member with that t(κ) does better at that κ, whatever its
// fade, scale or degree. Returns the max over κ weighted (÷ w(κ)) and plain.
template <std::size_t N, std::size_t M>
std::pair<double, double> per_kappa_floor(const std::vector<double>& steep,
                                          const std::vector<SglabAccSample>& samples) {
  SglabAccParams<double, 1, 0, M> own{};
  std::copy(steep.begin(), steep.begin() + long(steep_count(M)), own.steep);
  const auto sp = detail::sglab_acc_steepness(own);
  double weighted = 0, plain = 0;
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    while (end < samples.size() && samples[end].kappa == samples[i].kappa) ++end;
    const double k = samples[i].kappa, t = steepness(k, sp);
    Residuals residuals;
    std::vector<std::size_t> rows;
    for (std::size_t s = i; s < end; ++s, rows.push_back(rows.size()))
      residuals.push_back(make_residual(
          PerKappaResidual<N>{t, samples[s].cosine, samples[s].irradiance, irradiance_upper(k),
                              irradiance_lower_over_two_pi(k), irradiance_upper_over_two_pi(k)},
          N));
    std::vector<std::size_t> linear(N);
    std::iota(linear.begin(), linear.end(), std::size_t(0));
    const LinearSubproblem sub = linear_subproblem(residuals, std::vector<double>(N, 0.0), linear);
    const double f =
        lp_minimax_on(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()), rows).lower_bound;
    plain = std::max(plain, f);
    weighted = std::max(weighted, f / samples[i].weight);
    i = end;
  }
  return {weighted, plain};
}

// Alternations of the LP (exact numerators at fixed t, s) with a Ceres polish
// of every parameter (t, s move), each round kept only if it lowers the LP's achieved max.
constexpr int kAlternations = 3;

SglabAccFit fit_coefficients_any(Member m, const std::vector<double>& start,
                                 const std::vector<SglabAccSample>& samples,
                                 bool polish_only = false) {
  return with_member(m, [&](auto N, auto D, auto M) {
    return fit_coefficients<N(), D(), M()>(start, samples, polish_only);
  });
}

template <std::size_t N, std::size_t D, std::size_t M>
MemberFit measure_member(const SglabAccFit& f,
                         const std::vector<validate::ReferencePoint>& standard,
                         const std::vector<validate::ReferencePoint>& held_out) {
  MemberFit out;
  out.member = {N, D, M};
  out.values = f.values;
  out.train = f.max_abs;
  out.converged = f.converged;
  const auto p = params_of<N, D, M>(out.values);
  out.standard = measure(p, standard);
  out.held_out = measure(p, held_out);
  return out;
}

// Per-κ optima for N terms (computed once per N).
struct Floors {
  std::map<std::size_t, std::vector<KappaOptimum>> by_terms;
  const std::vector<KappaOptimum>& get(std::size_t n, const std::vector<SglabAccSample>& train) {
    auto it = by_terms.find(n);
    if (it != by_terms.end()) return it->second;
    std::vector<KappaOptimum> o =
        with_terms(n, [&](auto N) { return per_kappa_optima<decltype(N)::value>(train); });
    return by_terms.emplace(n, std::move(o)).first->second;
  }
  double floor(std::size_t n, const std::vector<SglabAccSample>& train) {
    double m = 0;
    for (const auto& o : get(n, train)) m = std::max(m, o.error);
    return m;
  }
};

std::vector<double> staged_start_any(Member m, Floors& floors,
                                     const std::vector<SglabAccSample>& train) {
  const auto& optima = floors.get(m.n, train);
  return with_member(m,
                     [&](auto N, auto D, auto M) { return staged_start<N(), D(), M()>(optima); });
}

// Member (N, D) from `start`: Ceres (fit_coefficients) on the training grid,
// then the LP on the dense grid at its t(κ) and s, alternating with Ceres
// polishes; measured on the standard and held-out grids, and certified.
template <std::size_t N, std::size_t D, std::size_t M>
MemberFit certified_fit(const std::vector<double>& start, const std::vector<SglabAccSample>& train,
                        const std::vector<SglabAccSample>& dense,
                        const std::vector<validate::ReferencePoint>& standard,
                        const std::vector<validate::ReferencePoint>& held_out, bool polish_only) {
  // Round 0: the LP at the start's t(κ) and s (a refit from a committed set
  // is never worse than it); then Ceres and the LP in turn while they gain.
  constexpr std::size_t K = steep_count(M);
  auto [values, lp] = best_numerators<N, D, M>(start, dense);
  SglabAccFit f = fit_coefficients<N, D, M>(values, train, polish_only);
  for (int round = 1; round <= kAlternations; ++round) {
    const SglabAccFit g = round == 1 ? f : fit_coefficients<N, D, M>(values, train, true);
    auto [next, next_lp] = best_numerators<N, D, M>(g.values, dense);
    if (!(next_lp.achieved < lp.achieved)) break;
    values = std::move(next), lp = next_lp;
  }
  f.values = values;
  f.max_abs = max_abs_residual(
      evaluate_residuals(member_residuals<N, D, M>(train), log_parameters(values, K)));
  MemberFit out = measure_member<N, D, M>(f, standard, held_out);
  const auto [floor_weighted, floor_plain] = per_kappa_floor<N, M>(values, dense);
  std::size_t kappas = 0;
  for (std::size_t i = 0; i < dense.size(); ++i)
    kappas += i == 0 || dense[i].kappa != dense[i - 1].kappa;
  out.certificate = {lp.achieved, lp.lower_bound,  floor_weighted, floor_plain, dense.size(),
                     kappas,      lp.working_rows, lp.rounds,      lp.converged};
  return out;
}

MemberFit fit_any(Member m, const std::vector<double>& start,
                  const std::vector<SglabAccSample>& train,
                  const std::vector<SglabAccSample>& dense,
                  const std::vector<validate::ReferencePoint>& standard,
                  const std::vector<validate::ReferencePoint>& held_out, bool polish_only = false) {
  return with_member(m, [&](auto N, auto D, auto M) {
    return certified_fit<N(), D(), M()>(start, train, dense, standard, held_out, polish_only);
  });
}

// The values (steep, num, scale) of member `from` embedded in member `to`
// (no fewer terms, no lower degree or steepness order): the added terms and
// degrees 0, the steepness raised (raise_steepness_order). The same function.
std::vector<double> embed(Member from, const std::vector<double>& values, Member to) {
  const std::size_t kf = steep_count(from.m), kt = steep_count(to.m);
  std::vector<double> v =
      raise_steepness_order(std::vector<double>(values.begin(), values.begin() + long(kf)), to.m);
  v.resize(kt + to.n * (to.d + 1), 0.0);
  for (std::size_t j = 0; j < from.n; ++j)
    for (std::size_t k = 0; k <= from.d; ++k)
      v[kt + j * (to.d + 1) + k] = values[kf + j * (from.d + 1) + k];
  v.push_back(values.back());  // scale
  return v;
}

// Start values for member m: the latest earlier fit nested in it (no more
// terms, no higher degree or steepness order) embedded (embed: the same function, so the fit
// starts at that member's error), else the staged start from the per-κ optima.
std::vector<double> start_for(Member m, const std::vector<MemberFit>& earlier, Floors& floors,
                              const std::vector<SglabAccSample>& train) {
  for (auto it = earlier.rbegin(); it != earlier.rend(); ++it) {
    const Member e = it->member;
    if (e.n > m.n || e.d > m.d || e.m > m.m) continue;
    return embed(e, it->values, m);
  }
  return staged_start_any(m, floors, train);
}

ordered_json coefficients_json(const MemberFit& f) {
  const std::size_t k = steep_count(f.member.m), nn = f.member.n * (f.member.d + 1);
  return {{"steep", std::vector<double>(f.values.begin(), f.values.begin() + long(k))},
          {"num", std::vector<double>(f.values.begin() + long(k), f.values.begin() + long(k + nn))},
          {"scale", f.values.back()}};
}

// The committed set `variant` over [lo, hi] as start values, if it exists
// with the member's number of terms and no higher degree or steepness order
// (embedded: the same function). The flag says whether it has the member's
// shape exactly (a polish) or was embedded.
std::optional<std::pair<std::vector<double>, bool>> committed(const std::string& variant, Member m,
                                                              double lo, double hi) {
  const auto c = committed_coefficients("sglab-acc", variant, lo, hi);
  if (!c) return std::nullopt;
  try {
    std::vector<double> v = c->at("steep").get<std::vector<double>>();
    const auto num = c->at("num").get<std::vector<double>>();
    if (!c->contains("scale") || v.size() % 2 != 1 || num.size() % m.n != 0) return std::nullopt;
    const Member own{m.n, num.size() / m.n - 1, (v.size() - 1) / 2};
    if (own.d > m.d || own.m > m.m || own.m < 1) return std::nullopt;
    v.insert(v.end(), num.begin(), num.end());
    v.push_back(c->at("scale").get<double>());
    return std::pair{embed(own, v, m), own == m};
  } catch (const std::exception&) {
    return std::nullopt;  // another shape: fit from the lower member
  }
}

// What the cost column is and where it comes from (the report says which).
std::string cost_source(const MethodCosts& costs) {
  if (costs.source.empty())
    return "none (no cost table; `sglab bench` writes data/results/costs.json): operation counts "
           "only";
  return costs.what +
         " of the shipped method of the same form over tokuyoshi2024's, from the "
         "cost table " +
         costs.source + "; '-' where no shipped method has the form";
}

// The training samples weighted for target T: w(κ) = min(T, max(e₂₀₂₄(κ), 8e−7)),
// e₂₀₂₄(κ) the float error of tokuyoshi2024 at κ, max over the κ's samples
// (the samples come grouped by κ, as training_grid makes them).
std::vector<SglabAccSample> weighted(std::vector<SglabAccSample> samples, double target) {
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    double base = 0;
    for (; end < samples.size() && samples[end].kappa == samples[i].kappa; ++end)
      base = std::max(base, error_tokuyoshi2024_float(samples[end].kappa, samples[end].cosine,
                                                      samples[end].irradiance));
    for (; i < end; ++i) samples[i].weight = std::min(target, std::max(base, 8e-7));
  }
  return samples;
}

// The certificate (Certificate) as the report and the constant set carry it.
ordered_json certificate_json(const Certificate& c) {
  return {
      {"kind", "lp_at_fitted_steepness"},
      {"what",
       "lower_bound: the LP optimum (COIN-OR CLP) of the coefficients of every P_j at the fitted "
       "t(kappa) and scale s, the best member with those; achieved: the max at the shipped "
       "coefficients; both of "
       "max peak_rel/w(kappa) (double) on the grid below"},
      {"grid",
       fmt::format("dense training grid: {} kappa x (c = 0, {} offset cosines, c = +-z_k/t, z_k = "
                   "0.05..3.15), {} points, never a measuring grid",
                   c.kappas, kDenseUniform, c.rows)},
      {"achieved", c.achieved},
      {"lower_bound", c.lower_bound},
      {"within_percent_of_best_member", 100 * (c.achieved / c.lower_bound - 1)},
      {"per_kappa_floor",
       {{"kind",
         "b_j(kappa) free at each kappa, t(kappa) as fitted: no member with this steepness does "
         "better"},
        {"weighted", c.per_kappa_floor},
        {"max_peak_rel", c.per_kappa_floor_peak_rel}}},
      {"lp", {{"working_rows", c.working_rows}, {"rounds", c.rounds}, {"converged", c.converged}}}};
}

std::string member_name(Member m) { return fmt::format("N={} D={} M={}", m.n, m.d, m.m); }

// "within x% of the best member" (the certificate's achieved over its lower bound).
std::string within_text(const Certificate& c) {
  return fmt::format(
      "achieved {:.4e} (weighted, dense training grid), within {:.2f}% of the best member at the "
      "fitted steepness and scale ({:.4e}, LP); per-kappa floor at that steepness {:.4e} (max "
      "peak_rel {:.3e})",
      c.achieved, 100 * (c.achieved / c.lower_bound - 1), c.lower_bound, c.per_kappa_floor,
      c.per_kappa_floor_peak_rel);
}

ordered_json member_report(const MemberFit& f) {
  const Operations ops = operations(f.member);
  const ordered_json cost = f.cost ? ordered_json(*f.cost) : ordered_json(nullptr);
  return {{"terms", f.member.n},
          {"degree", f.member.d},
          {"steepness_order", f.member.m},
          {"coefficients", f.values.size()},
          {"extra_setup_operations", ops.setup},
          {"extra_eval_operations", ops.eval},
          {"cost_ratio_vs_tokuyoshi2024", cost},
          {"floor_at_2024_steepness", f.floor},
          {"standard_max_peak_rel_float", f.standard.float_max},
          {"standard_max_peak_rel_double", f.standard.double_max},
          {"held_out_max_peak_rel_float", f.held_out.float_max},
          {"held_out_max_peak_rel_double", f.held_out.double_max},
          {"held_out_worst_float", {f.held_out.float_kappa, f.held_out.float_cosine}},
          {"weighted_objective", f.train},
          {"held_out_never_worse_ratio", f.held_out.never_worse},
          {"held_out_never_worse_worst_kappa", f.held_out.never_worse_kappa},
          {"certificate", certificate_json(f.certificate)},
          {"summary", within_text(f.certificate)}};
}

std::string member_line(const MemberFit& f, const char* mark) {
  const Operations ops = operations(f.member);
  const Certificate& c = f.certificate;
  return fmt::format(
      "  {:<13} {:>6} {:>5}+{:<4} {:>6}  {:>9}  {:.3e}  {:.3e}  {:.3e}  {:.3e}  {:.3f}   {:.3e}  "
      "{:.3e} {:>6.2f}%  {:.3e}  {:.3e}{}\n",
      member_name(f.member), f.values.size(), ops.setup, ops.eval,
      f.cost ? fmt::format("{:.3f}", *f.cost) : "-",
      f.floor > 0 ? fmt::format("{:.2e}", f.floor) : "-", f.train, f.standard.float_max,
      f.held_out.float_max, f.held_out.double_max, f.held_out.never_worse, c.achieved,
      c.lower_bound, 100 * (c.achieved / c.lower_bound - 1), c.per_kappa_floor,
      c.per_kappa_floor_peak_rel, mark);
}

// The last five columns are the certificate (certificate_json), weighted,
// on the dense training grid: achieved, the LP bound (best member at the
// fitted steepness and scale), how far above it, the per-κ floor weighted and plain.
const char* kHeader =
    "  member        coeffs  ops(setup+eval) cost   floor@t24    weighted   standard(f) "
    "held-out(f) "
    "held-out(d) never-worse  dense      LP bound    within  floor/k(w)  floor/k(peak_rel)\n";

ordered_json constant_set(const FitSpec& spec, const MemberFit& f, const std::string& variant,
                          const MeasuringGrids& grids, double target) {
  const std::string form =
      "E = 2*pi*lerp(E(-1)/2pi, E(1)/2pi, f), f = f2024(c, t) + (1 - c^2)*exp(-z^2)*sum_j "
      "b_j*z^(2j), z = t*c; t(kappa) = kappa*sqrt(0.5*P/Q) with s = steep, P = (..(kappa + "
      "s0)*kappa + ..)*kappa + s[M-1], Q = (..(kappa + s[M])*kappa + ..)*kappa + s[2M] (M = 2: "
      "((kappa + s0)*kappa + s1)/(((kappa + s2)*kappa + s3)*kappa + s4)); b_j = u*(1 - "
      "u)^3*(num[j*(D+1)] + num[j*(D+1)+1]*u + ... + num[j*(D+1)+D]*u^D), u = t/(t + scale)";
  const std::string objective = fmt::format(
      "minimax of the irradiance peak_rel |E^ - E|/E(1, kappa) (double) divided by w(kappa) = "
      "min(T, max(e2024(kappa), 8e-7)), T = {:g}, e2024(kappa) the float error of tokuyoshi2024 at "
      "kappa (never worse than it), on a training grid of {} kappa (40 log-spaced at half-step "
      "offsets, twice as dense in [0.5, 200], plus the ends) x (c = 0, 24 offset cosines, c = "
      "+-z_k/t, z_k = 0.1..3.1), {} points in all, kappa in [{}, {}] (Ceres, every parameter); "
      "alternating with the exact minimax of the coefficients of every P_j at the fitted t(kappa) "
      "and s (a linear program, COIN-OR CLP) on the dense training grid of the certificate, whose "
      "max is the objective",
      target, training_kappas(spec.kappa_lo, spec.kappa_hi, 40).size(),
      training_grid(spec.kappa_lo, spec.kappa_hi).size(), spec.kappa_lo, spec.kappa_hi);
  ordered_json achieved = {{"objective", f.certificate.achieved},
                           {"training_grid_objective", f.train}};
  achieved.update(measured_json(grids, f.standard, f.held_out));
  achieved["extra_operations_vs_tokuyoshi2024"] =
      fmt::format("setup {} (one division), eval {} multiply-adds", operations(f.member).setup,
                  operations(f.member).eval);
  ordered_json set = make_constant_set(
      spec, "sglab-acc", variant,
      fmt::format("SglabAccParams<double, {}, {}, {}>", f.member.n, f.member.d, f.member.m), form,
      coefficients_json(f), objective, achieved);
  set["provenance"]["certificate"] = certificate_json(f.certificate);
  return set;
}

// The grids of one sglab-acc run: training (Ceres), dense training (the LP
// and the certificate), and two measuring grids no fit uses.
struct Grids {
  std::vector<SglabAccSample> train, dense;
  MeasuringGrids measuring;
};

Grids grids_for(const FitSpec& spec) {
  Grids g;
  auto& engine = validate::reference_engine();
  for (const auto& r : engine.evaluate(training_grid(spec.kappa_lo, spec.kappa_hi)))
    g.train.push_back({r.kappa, r.cosine, r.irradiance});
  for (const auto& r : engine.evaluate(sglab_acc_dense_grid(spec.kappa_lo, spec.kappa_hi)))
    g.dense.push_back({r.kappa, r.cosine, r.irradiance});
  g.measuring = measuring_grids(spec);
  return g;
}

// --max-error: the cheapest member meeting the budget, each warm-started from the previous one.
FitOutcome fit_model_order(const FitSpec& spec, const Grids& g) {
  const auto& [train, dense, measuring] = g;
  const auto& standard = measuring.standard;
  const auto& held_out = measuring.held_out;
  FitOutcome out;
  // Model order: cheapest member first, each warm-started from the previous one.
  const double budget = *spec.max_error;
  std::vector<MemberFit> fits;
  const MemberFit* chosen = nullptr;
  Floors floors;
  fits.reserve(std::size(kFamily));  // `chosen` points into it
  for (const Member m : kFamily) {
    // A nested earlier member (or the stage-wise start: per-κ optima, then fade fits), then the
    // joint minimax.
    fits.push_back(fit_any(m, start_for(m, fits, floors, train), weighted(train, budget),
                           weighted(dense, budget), standard, held_out));
    fits.back().cost = member_cost(m, spec.costs);
    fits.back().floor = floors.floor(m.n, train);
    if (fits.back().converged && fits.back().held_out.float_max <= budget &&
        fits.back().held_out.never_worse <= 1) {
      chosen = &fits.back();
      break;
    }
  }
  out.report = {{"target", spec.target},
                {"objective", "model-order"},
                {"max_error", budget},
                {"kappa_range", {spec.kappa_lo, spec.kappa_hi}},
                {"cost_source", cost_source(spec.costs)},
                {"members", ordered_json::array()}};
  out.text = fmt::format(
      "sglab-acc model order, kappa in [{}, {}], budget {:.3e} (held-out float max peak_rel):\n",
      spec.kappa_lo, spec.kappa_hi, budget);
  out.text += fmt::format("  cost: {}\n", cost_source(spec.costs));
  out.text += kHeader;
  for (const auto& f : fits) {
    out.report["members"].push_back(member_report(f));
    out.text += member_line(f, &f == chosen ? "  <- cheapest meeting the budget" : "");
  }
  if (!chosen) {
    out.converged = false;
    out.report["chosen"] = nullptr;
    out.text += "  no member of the family meets the budget\n";
    return out;
  }
  const std::string variant =
      fmt::format("n{}d{}m{}-k{}-{}-e{:g}", chosen->member.n, chosen->member.d, chosen->member.m,
                  spec.kappa_lo, spec.kappa_hi, budget);
  out.constant_sets.push_back(constant_set(spec, *chosen, variant, measuring, budget));
  out.report["chosen"] = member_report(*chosen);
  out.report["chosen"]["variant"] = variant;
  return out;
}

// The shipped ladder, each rung warm-started from its committed set.
FitOutcome fit_ladder(const FitSpec& spec, const Grids& g) {
  const auto& [train, dense, measuring] = g;
  const auto& standard = measuring.standard;
  const auto& held_out = measuring.held_out;
  FitOutcome out;
  out.report = {{"target", spec.target},
                {"objective", "peak-rel"},
                {"kappa_range", {spec.kappa_lo, spec.kappa_hi}},
                {"cost_source", cost_source(spec.costs)},
                {"ladder", ordered_json::array()}};
  out.text = fmt::format(
      "sglab-acc ladder, kappa in [{}, {}] (float = float runtime vs double reference):\n",
      spec.kappa_lo, spec.kappa_hi);
  out.text += fmt::format("  cost: {}\n", cost_source(spec.costs));
  out.text += kHeader;
  Floors floors;
  std::vector<MemberFit> done;
  for (const Rung& rung : kLadder) {
    std::string variant = rung.variant;
    if (spec.kappa_range_given) variant += fmt::format("-k{}-{}", spec.kappa_lo, spec.kappa_hi);
    const auto warm = committed(variant, rung.member, spec.kappa_lo, spec.kappa_hi);
    MemberFit f =
        fit_any(rung.member, warm ? warm->first : start_for(rung.member, done, floors, train),
                weighted(train, rung.target), weighted(dense, rung.target), standard, held_out,
                warm && warm->second);
    done.push_back(f);
    f.cost = member_cost(rung.member, spec.costs);
    if (!warm) f.floor = floors.floor(rung.member.n, train);
    out.converged = out.converged && f.converged;
    out.constant_sets.push_back(constant_set(spec, f, variant, measuring, rung.target));
    ordered_json r = member_report(f);
    r["variant"] = variant;
    const bool nested = std::any_of(done.begin(), done.end() - 1, [&](const MemberFit& e) {
      return e.member.n <= rung.member.n && e.member.d <= rung.member.d &&
             e.member.m <= rung.member.m;
    });
    r["warm_start"] = warm ? "committed JSON" : nested ? "lower member" : "per-kappa optima";
    out.report["ladder"].push_back(r);
    out.text += member_line(f, warm ? "  (warm start: committed JSON)" : "");
  }
  return out;
}

}  // namespace

SglabAccFit fit_sglab_acc_coefficients(std::size_t terms, std::size_t degree,
                                       const std::vector<double>& start,
                                       const std::vector<SglabAccSample>& samples) {
  return fit_coefficients_any({terms, degree}, start, samples);
}

FitOutcome fit_sglab_acc(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "peak-rel")
    throw std::invalid_argument(
        fmt::format("sglab-acc objective is 'peak-rel'; got '{}'", spec.objective));
  const Grids g = grids_for(spec);
  return spec.max_error ? fit_model_order(spec, g) : fit_ladder(spec, g);
}

}  // namespace sglab::fit
