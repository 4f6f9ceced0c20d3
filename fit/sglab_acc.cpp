// `sglab fit sglab-acc`: sglab_acc `sglab_acc<N>`
// (include/sglab/sglab_acc.hpp) — the [Tokuyoshi2024] lerp factor plus the
// correction (1 − c²) e^{−z²} Σ_j b_j(κ) z^{2j}, z = t c, with the b_j rational
// in κ over one shared positive denominator and the steepness refitted jointly.
//
// The family's order is (N, D): N correction terms, rational degree D.
//   default         fits the shipped ladder acc1 (1, 2), acc2 (2, 2), acc3 (3, 3),
//                   each warm-started from the committed JSON when present
//                   (else from the next lower member), minimax of the peak_rel
//                   error on a training grid, then measured on the standard grid
//                   and on a held-out dense grid that the fit never sees.
//   --max-error E   the cheapest member of the family whose held-out max peak_rel
//                   (float) on --kappa LO:HI meets E, with its cost from the cost table.
//
// Training grid (never a grid that is used for measuring): κ log-spaced at
// half-step offsets plus the range ends; per κ, cosines at half-step offsets of
// a uniform grid and at c = ±z_k/t(κ) for a uniform z grid, so the structure of
// width ~1/t near c = 0 at large κ is resolved.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_acc.hpp>

#include "fit/minimax.hpp"
#include "validate/reference.hpp"
#include "fit/constants_io.hpp"
#include "fit/targets.hpp"

namespace sglab::fit {

namespace {

struct Member {
  std::size_t n, d;  // correction terms, rational degree
};

// The family, cheapest first (by the operations counted in `operations`).
constexpr Member kFamily[] = {{1, 0}, {1, 1}, {1, 2}, {2, 1}, {2, 2}, {3, 2}, {3, 3}, {4, 3}};
// The shipped ladder: id suffix and member.
struct Rung {
  const char* variant;
  Member member;
};
constexpr Rung kLadder[] = {{"acc1", {1, 2}}, {"acc2", {2, 2}}, {"acc3", {3, 3}}};

// The cost of a member: float scalar ns/eval of the runtime method of the
// same form (N, D), the shipped sglab_acc<k> (its cost does not depend on
// the coefficients), over tokuyoshi2024's, both from the cost table
// (spec.costs, `sglab bench`). Never timed here: a report is the same for the
// same inputs. None for a form no shipped method has, or without a table.
std::optional<double> member_cost(Member m, const MethodCosts& costs) {
  const auto row = [&](const std::string& method) -> std::optional<double> {
    const auto it = costs.float_scalar_ns.find(method);
    return it == costs.float_scalar_ns.end() ? std::nullopt : std::optional<double>(it->second);
  };
  const auto base = row("tokuyoshi2024");
  for (const Rung& r : kLadder)
    if (r.member.n == m.n && r.member.d == m.d) {
      const auto own = row(std::string("sglab_") + r.variant);
      if (own && base) return *own / *base;
    }
  return std::nullopt;
}

// Extra operations over tokuyoshi2024 (float): per light (setup) the rational
// b_j: N(D + 1) + D multiply-adds and one division (none for D = 0); per
// shading point (eval) N − 1 multiply-adds of the polynomial in z² and 4 for
// (1 − c²)·e^{−z²}·poly added to f.
struct Operations {
  int setup, eval;
};
Operations operations(Member m) {
  const int setup = m.d == 0 ? 0 : int(m.n * (m.d + 1) + m.d) + 1;
  return {setup, int(m.n) - 1 + 4};
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

// Parameters: log steep[5], num[N(D+1)], then log den[D]: the steepness
// coefficients and the denominator stay positive by construction (t(κ) real,
// b_j(κ) finite for every κ ≥ 0).
template <class T, std::size_t N, std::size_t D> SglabAccParams<T, N, D> unpack(T const* const* p) {
  using std::exp;
  SglabAccParams<T, N, D> q{};
  for (std::size_t i = 0; i < 5; ++i) q.steep[i] = exp(p[i][0]);
  for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[5 + i][0];
  for (std::size_t i = 0; i < D; ++i) q.den[i] = exp(p[5 + N * (D + 1) + i][0]);
  if constexpr (D == 0) q.den[0] = T(1);
  return q;
}


template <std::size_t N, std::size_t D> struct PeakRelResidual {
  double kappa, cosine, reference, peak;
  template <class T> bool operator()(T const* const* p, T* r) const {
    const SglabAccParams<T, N, D> q = unpack<T, N, D>(p);
    r[0] = (irradiance_sglab_acc(T(cosine), T(kappa), q) - T(reference)) / T(peak);
    return true;
  }
};

// κ log-spaced at half-step offsets over [lo, hi] plus the ends, and twice as
// dense where the 2024 form's residual lives (κ ∈ [0.5, 200], clipped to the range).
std::vector<double> training_kappas(double lo, double hi, int count) {
  std::vector<double> k{lo};
  const double a = std::log(lo), b = std::log(hi);
  for (int i = 0; i < count; ++i) k.push_back(std::exp(a + (b - a) * (i + 0.5) / count));
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

// Held-out grid: `nk` κ log-spaced over [lo, hi] × `nc` cosines uniform over [−1, 1].
std::vector<validate::Query> measuring_grid(double lo, double hi, int nk, int nc) {
  std::vector<validate::Query> q;
  for (double k : kappa_grid(lo, hi, nk))
    for (double c : cosine_grid(nc)) q.push_back({k, c});
  return q;
}

struct Measured {
  double float_max = 0, double_max = 0;
  double float_kappa = 0, float_cosine = 0;
};

template <std::size_t N, std::size_t D>
Measured measure(const SglabAccParams<double, N, D>& p, const std::vector<validate::ReferencePoint>& ref) {
  Measured m;
  for (const auto& r : ref) {
    const double peak = irradiance_upper(r.kappa);
    const double ed = irradiance_sglab_acc(r.cosine, r.kappa, p);
    const float ef = irradiance_sglab_acc(float(r.cosine), float(r.kappa), p);
    const double errd = std::abs(ed - r.irradiance) / peak, errf = std::abs(double(ef) - r.irradiance) / peak;
    m.double_max = std::isfinite(errd) ? std::max(m.double_max, errd) : std::numeric_limits<double>::infinity();
    if (!(errf <= m.float_max)) m.float_max = std::isfinite(errf) ? errf : std::numeric_limits<double>::infinity(),
                                m.float_kappa = r.kappa, m.float_cosine = r.cosine;
  }
  return m;
}

struct MemberFit {
  Member member;
  std::vector<double> values;  // steep[5], num, den (den itself, not its log)
  double train = 0;            // max peak_rel on the training grid (double, fit objective)
  Measured standard, held_out;
  std::optional<double> cost;  // float scalar ns/eval over tokuyoshi2024's, from the cost table (member_cost)
  double floor = 0;            // max over κ of the per-κ optimum at the refitted 2024 t(κ) (0: not computed)
  bool converged = false;
};

template <std::size_t N, std::size_t D> SglabAccParams<double, N, D> params_of(const std::vector<double>& v) {
  SglabAccParams<double, N, D> p{};
  for (std::size_t i = 0; i < 5; ++i) p.steep[i] = v[i];
  for (std::size_t i = 0; i < N * (D + 1); ++i) p.num[i] = v[5 + i];
  for (std::size_t i = 0; i < D; ++i) p.den[i] = v[5 + N * (D + 1) + i];
  if constexpr (D == 0) p.den[0] = 1;
  return p;
}

template <std::size_t N, std::size_t D>
SglabAccFit fit_coefficients(const std::vector<double>& start, const std::vector<SglabAccSample>& samples,
                             bool polish_only) {
  Parameters params;
  for (std::size_t i = 0; i < 5; ++i) params.names.push_back(fmt::format("log_steep{}", i));
  for (std::size_t i = 0; i < N * (D + 1); ++i) params.names.push_back(fmt::format("num{}", i));
  for (std::size_t i = 0; i < D; ++i) params.names.push_back(fmt::format("log_den{}", i));
  for (std::size_t i = 0; i < 5; ++i) params.values.push_back(std::log(start[i]));
  params.values.insert(params.values.end(), start.begin() + 5, start.begin() + 5 + N * (D + 1));
  for (std::size_t i = 0; i < D; ++i) params.values.push_back(std::log(start[5 + N * (D + 1) + i]));
  bound(params);
  Residuals residuals;
  for (const auto& r : samples)
    residuals.push_back(make_residual(PeakRelResidual<N, D>{r.kappa, r.cosine, r.irradiance, irradiance_upper(r.kappa)},
                                      params.size()));
  // Fewer rounds than the defaults: the training grid is large and the
  // staged start is close. From a converged set (the committed JSON) a short
  // polish: the full schedule there takes minutes and moves the error < 2%.
  FitOptions options;
  options.lawson_iterations = polish_only ? 2 : 12;
  options.penalty_decades = polish_only ? 4 : 8;
  options.solver_iterations = polish_only ? 30 : 200;
  const FitResult f = fit(residuals, params, options);
  SglabAccFit out;
  for (std::size_t i = 0; i < 5; ++i) out.values.push_back(std::exp(f.values[i]));
  out.values.insert(out.values.end(), f.values.begin() + 5, f.values.begin() + 5 + N * (D + 1));
  for (std::size_t i = 0; i < D; ++i) out.values.push_back(std::exp(f.values[5 + N * (D + 1) + i]));
  out.max_abs = f.max_abs;
  out.converged = f.converged;
  return out;
}

// Stage 1 — per κ, b_0 … b_{N−1} free at the refitted 2024 steepness t(κ):
// minimax of the peak_rel error over that κ's training cosines. Linear in the
// b_j, so the optimum is unique and smooth in κ (a good start for stage 2);
// its max over κ is the family's floor at that steepness.
template <std::size_t N> struct PerKappaResidual {
  double t, cosine, reference, peak, lower, upper;
  template <class T> bool operator()(T const* const* p, T* r) const {
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

template <std::size_t N> std::vector<KappaOptimum> per_kappa_optima(const std::vector<SglabAccSample>& samples) {
  std::vector<KappaOptimum> out;
  std::vector<double> b;
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    while (end < samples.size() && samples[end].kappa == samples[i].kappa) ++end;
    const double k = samples[i].kappa;
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    Parameters params;
    for (std::size_t j = 0; j < N; ++j) params.names.push_back(fmt::format("b{}", j)), params.values.push_back(0.0);
    bound(params);
    Residuals residuals;
    for (std::size_t s = i; s < end; ++s)
      residuals.push_back(make_residual(PerKappaResidual<N>{t, samples[s].cosine, samples[s].irradiance,
                                                            irradiance_upper(k), irradiance_lower_over_two_pi(k),
                                                            irradiance_upper_over_two_pi(k)},
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
  template <class T> bool operator()(T const* const* p, T* r) const {
    using std::exp;
    using std::log;
    const Steepness2024Params<T> s{exp(p[0][0]), exp(p[1][0]), exp(p[2][0]), exp(p[3][0]), exp(p[4][0])};
    r[0] = T(weight) * (log(steepness2024(T(kappa), s)) - T(log_t));
    return true;
  }
};

// Stage 2b — b_j(κ): rational of degree D over one shared denominator (log
// coefficients), least squares on the per-κ optima weighted by the
// sensitivity of peak_rel to f, (Ē(1) − Ē(−1))/Ē(1).
template <std::size_t N, std::size_t D> struct RationalResidual {
  double kappa, weight;
  std::size_t j;
  double target;
  template <class T> bool operator()(T const* const* p, T* r) const {
    SglabAccParams<T, N, D> q{};
    for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[i][0];
    for (std::size_t i = 0; i < D; ++i) q.den[i] = exp(p[N * (D + 1) + i][0]);
    if constexpr (D == 0) q.den[0] = T(1);
    T b[N];
    detail::sglab_acc_rational(T(kappa), q, b);
    r[0] = T(weight) * (b[j] - T(target));
    return true;
  }
};

// Start values (steep[5], num, den) for member (N, D) from the per-κ optima.
template <std::size_t N, std::size_t D> std::vector<double> staged_start(const std::vector<KappaOptimum>& optima) {
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
    const double w = 1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    rs.push_back(make_residual(LogSteepnessResidual{o.kappa, std::log(o.t), w}, 5));
  }
  const FitResult ft = fit(rs, steep, ls);
  Parameters rat;
  for (std::size_t i = 0; i < N * (D + 1); ++i) rat.names.push_back(fmt::format("num{}", i)), rat.values.push_back(0.0);
  // Denominator roots spread over the κ range: (κ + 1)(κ + 30)(κ + 900)…
  std::vector<double> den{1.0};
  for (std::size_t d = 0; d < D; ++d) {
    const double root = std::pow(30.0, double(d));
    std::vector<double> next(den.size() + 1, 0.0);
    for (std::size_t i = 0; i < den.size(); ++i) next[i] += den[i] * root, next[i + 1] += den[i];
    den = next;
  }
  for (std::size_t i = 0; i < D; ++i) rat.names.push_back(fmt::format("log_den{}", i)), rat.values.push_back(std::log(den[i]));
  bound(rat);
  Residuals rr;
  for (const auto& o : optima) {
    const double w = 1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    for (std::size_t j = 0; j < N; ++j) rr.push_back(make_residual(RationalResidual<N, D>{o.kappa, w, j, o.b[j]}, rat.size()));
  }
  // Numerators first (linear, denominator fixed), then everything.
  Parameters num_only = rat;
  num_only.fixed.assign(rat.size(), false);
  for (std::size_t i = N * (D + 1); i < rat.size(); ++i) num_only.fixed[i] = true;
  rat.values = fit(rr, num_only, ls).values;
  const FitResult fr = fit(rr, rat, ls);
  std::vector<double> out;
  for (double v : ft.values) out.push_back(std::exp(v));
  out.insert(out.end(), fr.values.begin(), fr.values.begin() + N * (D + 1));
  for (std::size_t i = 0; i < D; ++i) out.push_back(std::exp(fr.values[N * (D + 1) + i]));
  return out;
}

SglabAccFit fit_coefficients_any(std::size_t n, std::size_t d, const std::vector<double>& start,
                                 const std::vector<SglabAccSample>& samples, bool polish_only = false) {
#define SGLAB_MEMBER(n_, d_) \
  if (n == n_ && d == d_) return fit_coefficients<n_, d_>(start, samples, polish_only);
  SGLAB_MEMBER(1, 0)
  SGLAB_MEMBER(1, 1)
  SGLAB_MEMBER(1, 2)
  SGLAB_MEMBER(2, 1)
  SGLAB_MEMBER(2, 2)
  SGLAB_MEMBER(3, 2)
  SGLAB_MEMBER(3, 3)
  SGLAB_MEMBER(4, 3)
#undef SGLAB_MEMBER
  throw std::invalid_argument(fmt::format("sglab-acc: no member N={} D={}", n, d));
}

template <std::size_t N, std::size_t D>
MemberFit measure_member(const SglabAccFit& f, const std::vector<validate::ReferencePoint>& standard,
                         const std::vector<validate::ReferencePoint>& held_out) {
  MemberFit out;
  out.member = {N, D};
  out.values = f.values;
  out.train = f.max_abs;
  out.converged = f.converged;
  const auto p = params_of<N, D>(out.values);
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
    std::vector<KappaOptimum> o;
    switch (n) {
      case 1: o = per_kappa_optima<1>(train); break;
      case 2: o = per_kappa_optima<2>(train); break;
      case 3: o = per_kappa_optima<3>(train); break;
      case 4: o = per_kappa_optima<4>(train); break;
      default: throw std::logic_error("sglab-acc: terms not instantiated");
    }
    return by_terms.emplace(n, std::move(o)).first->second;
  }
  double floor(std::size_t n, const std::vector<SglabAccSample>& train) {
    double m = 0;
    for (const auto& o : get(n, train)) m = std::max(m, o.error);
    return m;
  }
};

std::vector<double> staged_start_any(Member m, Floors& floors, const std::vector<SglabAccSample>& train) {
  const auto& optima = floors.get(m.n, train);
#define SGLAB_MEMBER(n_, d_) \
  if (m.n == n_ && m.d == d_) return staged_start<n_, d_>(optima);
  SGLAB_MEMBER(1, 0)
  SGLAB_MEMBER(1, 1)
  SGLAB_MEMBER(1, 2)
  SGLAB_MEMBER(2, 1)
  SGLAB_MEMBER(2, 2)
  SGLAB_MEMBER(3, 2)
  SGLAB_MEMBER(3, 3)
  SGLAB_MEMBER(4, 3)
#undef SGLAB_MEMBER
  throw std::logic_error("sglab-acc: member not instantiated");
}

MemberFit fit_any(Member m, const std::vector<double>& start, const std::vector<SglabAccSample>& train,
                  const std::vector<validate::ReferencePoint>& standard,
                  const std::vector<validate::ReferencePoint>& held_out, bool polish_only = false) {
  const SglabAccFit f = fit_coefficients_any(m.n, m.d, start, train, polish_only);
#define SGLAB_MEMBER(n_, d_) \
  if (m.n == n_ && m.d == d_) return measure_member<n_, d_>(f, standard, held_out);
  SGLAB_MEMBER(1, 0)
  SGLAB_MEMBER(1, 1)
  SGLAB_MEMBER(1, 2)
  SGLAB_MEMBER(2, 1)
  SGLAB_MEMBER(2, 2)
  SGLAB_MEMBER(3, 2)
  SGLAB_MEMBER(3, 3)
  SGLAB_MEMBER(4, 3)
#undef SGLAB_MEMBER
  throw std::logic_error("sglab-acc: member not instantiated");
}

ordered_json coefficients_json(const MemberFit& f) {
  const std::size_t nn = f.member.n * (f.member.d + 1);
  std::vector<double> den(f.values.begin() + 5 + nn, f.values.end());
  if (den.empty()) den.push_back(1.0);  // D = 0: the unused slot
  return {{"steep", std::vector<double>(f.values.begin(), f.values.begin() + 5)},
          {"num", std::vector<double>(f.values.begin() + 5, f.values.begin() + 5 + nn)},
          {"den", den}};
}

// The committed set `variant` as start values, if it exists with the member's shape.
std::optional<std::vector<double>> committed(const std::string& variant, Member m) {
  // Warm start from the project around the working directory, if any.
  const auto root = find_project_root(std::filesystem::current_path());
  if (!root) return std::nullopt;
  const auto path = *root / "data" / "constants" / fmt::format("sglab-acc-{}.json", variant);
  if (!std::filesystem::exists(path)) return std::nullopt;
  try {
    const ordered_json set = load_constant_set(path);  // bounded and strict, as every constants file
    const auto& c = set.at("coefficients");
    std::vector<double> v = c.at("steep").get<std::vector<double>>();
    const auto num = c.at("num").get<std::vector<double>>();
    const auto den = c.at("den").get<std::vector<double>>();
    if (v.size() != 5 || num.size() != m.n * (m.d + 1) || den.size() != std::max<std::size_t>(m.d, 1)) return std::nullopt;
    v.insert(v.end(), num.begin(), num.end());
    if (m.d > 0) v.insert(v.end(), den.begin(), den.end());
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// What the cost column is and where it comes from (the report says which).
std::string cost_source(const MethodCosts& costs) {
  if (costs.source.empty())
    return "none (no cost table; `sglab bench` writes data/results/costs.json): operation counts only";
  return "float scalar ns/eval of the shipped method of the same form over tokuyoshi2024's (CPU), from the cost "
         "table " + costs.source + "; '-' where no shipped method has the form";
}

std::string member_name(Member m) { return fmt::format("N={} D={}", m.n, m.d); }

ordered_json member_report(const MemberFit& f) {
  const Operations ops = operations(f.member);
  const ordered_json cost = f.cost ? ordered_json(*f.cost) : ordered_json(nullptr);
  return {{"terms", f.member.n},
          {"degree", f.member.d},
          {"coefficients", f.values.size()},
          {"extra_setup_operations", ops.setup},
          {"extra_eval_operations", ops.eval},
          {"cost_ratio_float_vs_tokuyoshi2024", cost},
          {"train_max_peak_rel_double", f.train},
          {"floor_at_2024_steepness", f.floor},
          {"standard_max_peak_rel_float", f.standard.float_max},
          {"standard_max_peak_rel_double", f.standard.double_max},
          {"held_out_max_peak_rel_float", f.held_out.float_max},
          {"held_out_max_peak_rel_double", f.held_out.double_max},
          {"held_out_worst_float", {f.held_out.float_kappa, f.held_out.float_cosine}}};
}

std::string member_line(const MemberFit& f, const char* mark) {
  const Operations ops = operations(f.member);
  return fmt::format("  {:<9} {:>6} {:>5}+{:<4} {:>6}  {:>9}  {:.3e}  {:.3e}  {:.3e}  {:.3e}{}\n",
                     member_name(f.member), f.values.size(), ops.setup, ops.eval,
                     f.cost ? fmt::format("{:.3f}", *f.cost) : "-",
                     f.floor > 0 ? fmt::format("{:.2e}", f.floor) : "-", f.train, f.standard.float_max,
                     f.held_out.float_max, f.held_out.double_max, mark);
}

const char* kHeader =
    "  member    coeffs  ops(setup+eval) cost   floor@t24    train      standard(f) held-out(f) held-out(d)\n";

ordered_json constant_set(const FitSpec& spec, const MemberFit& f, const std::string& variant, int held_k, int held_c) {
  const std::string form =
      "E = 2*pi*lerp(E(-1)/2pi, E(1)/2pi, f), f = f2024(c, t) + (1 - c^2)*exp(-z^2)*sum_j b_j*z^(2j), z = t*c; "
      "t(kappa) = kappa*sqrt(0.5*((kappa + s0)*kappa + s1)/(((kappa + s2)*kappa + s3)*kappa + s4)) with s = steep; "
      "b_j = (num[j*(D+1)] + ... + num[j*(D+1)+D]*kappa^D)/(den[0] + ... + den[D-1]*kappa^(D-1) + kappa^D)";
  const std::string objective = fmt::format(
      "minimax of the irradiance peak_rel |E^ - E|/E(1, kappa) (double) on a training grid of {} kappa (40 log-spaced "
      "at half-step offsets, twice as dense in [0.5, 200], plus the ends) x (c = 0, 24 offset cosines, c = +-z_k/t, "
      "z_k = 0.1..3.1), {} points in all, kappa in [{}, {}]",
      training_kappas(spec.kappa_lo, spec.kappa_hi, 40).size(), training_grid(spec.kappa_lo, spec.kappa_hi).size(),
      spec.kappa_lo, spec.kappa_hi);
  ordered_json achieved = {
      {"objective", f.train},
      {"standard_grid", fmt::format("{} kappa x {} cosines", spec.kappa_count, spec.cosine_count)},
      {"standard_max_peak_rel_float", f.standard.float_max},
      {"standard_max_peak_rel_double", f.standard.double_max},
      {"held_out_grid", fmt::format("{} kappa x {} cosines, never used in fitting", held_k, held_c)},
      {"held_out_max_peak_rel_float", f.held_out.float_max},
      {"held_out_max_peak_rel_double", f.held_out.double_max},
      {"extra_operations_vs_tokuyoshi2024", fmt::format("setup {} (one division), eval {} multiply-adds",
                                                        operations(f.member).setup, operations(f.member).eval)}};
  return make_constant_set(spec, "sglab-acc", variant,
                           fmt::format("SglabAccParams<double, {}, {}>", f.member.n, f.member.d), form,
                           coefficients_json(f), objective, achieved);
}

}  // namespace

SglabAccFit fit_sglab_acc_coefficients(std::size_t terms, std::size_t degree, const std::vector<double>& start,
                                            const std::vector<SglabAccSample>& samples) {
  return fit_coefficients_any(terms, degree, start, samples);
}

FitOutcome fit_sglab_acc(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "peak-rel")
    throw std::invalid_argument(fmt::format("sglab-acc objective is 'peak-rel'; got '{}'", spec.objective));
  const int held_k = 200, held_c = 401;
  auto& engine = validate::reference_engine();
  std::vector<SglabAccSample> train;
  for (const auto& r : engine.evaluate(training_grid(spec.kappa_lo, spec.kappa_hi)))
    train.push_back({r.kappa, r.cosine, r.irradiance});
  const auto standard = engine.evaluate(measuring_grid(spec.kappa_lo, spec.kappa_hi, spec.kappa_count, spec.cosine_count));
  const auto held_out = engine.evaluate(measuring_grid(spec.kappa_lo, spec.kappa_hi, held_k, held_c));

  FitOutcome out;
  if (spec.max_error) {
    // Model order: cheapest member first, each warm-started from the previous one.
    const double budget = *spec.max_error;
    std::vector<MemberFit> fits;
    const MemberFit* chosen = nullptr;
    Floors floors;
    for (const Member m : kFamily) {
      // Stage-wise start (per-κ optima, then rational fits), then the joint minimax.
      fits.push_back(fit_any(m, staged_start_any(m, floors, train), train, standard, held_out));
      fits.back().cost = member_cost(m, spec.costs);
      fits.back().floor = floors.floor(m.n, train);
      if (fits.back().converged && fits.back().held_out.float_max <= budget) {
        chosen = &fits.back();
        break;
      }
    }
    out.report = {{"target", spec.target}, {"objective", "model-order"}, {"max_error", budget},
                  {"kappa_range", {spec.kappa_lo, spec.kappa_hi}}, {"cost_source", cost_source(spec.costs)},
                  {"members", ordered_json::array()}};
    out.text = fmt::format("sglab-acc model order, kappa in [{}, {}], budget {:.3e} (held-out float max peak_rel):\n",
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
    const std::string variant = fmt::format("n{}d{}-k{}-{}-e{:g}", chosen->member.n, chosen->member.d, spec.kappa_lo,
                                            spec.kappa_hi, budget);
    out.constant_sets.push_back(constant_set(spec, *chosen, variant, held_k, held_c));
    out.report["chosen"] = member_report(*chosen);
    out.report["chosen"]["variant"] = variant;
    return out;
  }

  // The shipped ladder.
  out.report = {{"target", spec.target}, {"objective", "peak-rel"}, {"kappa_range", {spec.kappa_lo, spec.kappa_hi}},
                {"cost_source", cost_source(spec.costs)}, {"ladder", ordered_json::array()}};
  out.text = fmt::format("sglab-acc ladder, kappa in [{}, {}] (float = float runtime vs double reference):\n",
                         spec.kappa_lo, spec.kappa_hi);
  out.text += fmt::format("  cost: {}\n", cost_source(spec.costs));
  out.text += kHeader;
  Floors floors;
  for (const Rung& rung : kLadder) {
    std::string variant = rung.variant;
    if (spec.kappa_range_given) variant += fmt::format("-k{}-{}", spec.kappa_lo, spec.kappa_hi);
    const auto warm = committed(variant, rung.member);
    MemberFit f = fit_any(rung.member, warm ? *warm : staged_start_any(rung.member, floors, train), train, standard,
                          held_out, warm.has_value());
    f.cost = member_cost(rung.member, spec.costs);
    if (!warm) f.floor = floors.floor(rung.member.n, train);
    out.converged = out.converged && f.converged;
    out.constant_sets.push_back(constant_set(spec, f, variant, held_k, held_c));
    ordered_json r = member_report(f);
    r["variant"] = variant;
    r["warm_start"] = warm ? "committed JSON" : "lower member";
    out.report["ladder"].push_back(r);
    out.text += member_line(f, warm ? "  (warm start: committed JSON)" : "");
  }
  return out;
}

}  // namespace sglab::fit
