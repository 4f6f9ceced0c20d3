// `sglab fit steepness2022|steepness2024`: the rational steepness t(κ) of
//   2022: s̃(c, κ) = ½ + ½ erf(t c)/erf(t), t = κ√((0.5κ + A)/((κ + B)κ + C))  ([Tokuyoshi2022] Eq.
//   5/6) 2024: Ê = lerp(E(−1), E(1), f(c, t)), t = κ√(0.5((κ + A)κ + B)/(((κ + C)κ + D)κ + E))
// Two objectives:
//   optimal-t  — per κ the optimal steepness t*(κ) (minimax over c of the
//                2022 s̃ − s, or of the 2024 f − (E − E(−1))/(E(1) − E(−1))),
//                then the coefficients minimax the relative error t/t* − 1
//                (the paper's route, [Tokuyoshi2022] supplementary Fig. 2);
//   irradiance — the coefficients minimax the peak_rel error of the
//                tokuyoshi2022 / tokuyoshi2024 irradiance over the grid.
// Every fit (either objective, and --max-error's orders) is certified by the
// per-κ floor (per_kappa_floor and certificate_json below).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <fmt/format.h>
#include <boost/math/tools/minima.hpp>

#include <sglab/sglab.hpp>

#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit {

namespace {

bool is2022(const FitSpec& spec) { return spec.target == "steepness2022"; }

// Steepness with coefficients p[0..] (3 for 2022, 5 for 2024), through the runtime.
template <class T>
T steepness(bool y2022, const T& kappa, T const* const* p) {
  if (y2022) return steepness2022(kappa, Steepness2022Params<T>{p[0][0], p[1][0], p[2][0]});
  return steepness2024(kappa, Steepness2024Params<T>{p[0][0], p[1][0], p[2][0], p[3][0], p[4][0]});
}

// The normalized quantity as a function of t: 2022 s̃, 2024 f.
double model_at_steepness(bool y2022, double cosine, double t) {
  if (y2022) return 0.5 + 0.5 * erf_ratio(t, cosine);
  return lerp_factor_tokuyoshi2024_at_steepness(cosine, t);
}

// The exact counterpart: s(c, κ), or (E(c) − E(−1))/(E(1) − E(−1)).
double exact_normalized(bool y2022, const reference::ReferencePoint& r) {
  if (y2022) return r.normalized;
  const double lo = irradiance_lower(r.kappa), hi = irradiance_upper(r.kappa);
  return (r.irradiance - lo) / (hi - lo);
}

// min over t > 0 of `column_error(t)` (a max over one κ's cosines): a scan of
// log t over log(t_guess) ± 3 (81 points), then Brent's method around the best
// scan point. Returns (t, column_error(t)).
template <class F>
std::pair<double, double> minimize_over_steepness(const F& column_error, double t_guess) {
  const auto at_log = [&](double log_t) { return column_error(std::exp(log_t)); };
  const double center = std::log(t_guess);
  double best = center, best_err = at_log(center);
  const int n = 80;
  for (int i = 0; i <= n; ++i) {
    const double x = center - 3 + 6.0 * i / n;
    const double e = at_log(x);
    if (e < best_err) best_err = e, best = x;
  }
  const double step = 6.0 / n;
  const auto r = boost::math::tools::brent_find_minima(at_log, best - step, best + step, 52);
  return r.second <= best_err ? std::pair{std::exp(r.first), r.second}
                              : std::pair{std::exp(best), best_err};
}

// The minimum of `column_error` refined to the resolution of double: a golden
// section search of [t/(1 + r), t(1 + r)] (r = 0.08, the scan's step, the
// minimum unimodal there) until its ends are adjacent doubles, from the scan +
// Brent minimum (t, e). Brent stops at a relative step of 2⁻²⁶ in log t, and
// at a kink of the max over the cosines (where two cosines' errors cross) that
// leaves the value up to a few percent above the minimum where the error rises
// steeply in t (κ → 0); here the value is left above the minimum by at most the
// slope times an ulp of t. Returns the best (t, column_error(t)) seen.
template <class F>
std::pair<double, double> refine_minimum(const F& column_error, std::pair<double, double> best) {
  constexpr double kInvPhi = 0.6180339887498949;
  double a = best.first / 1.08, b = best.first * 1.08;
  double x1 = b - kInvPhi * (b - a), x2 = a + kInvPhi * (b - a);
  double f1 = column_error(x1), f2 = column_error(x2);
  for (int i = 0; i < 200 && std::nextafter(a, b) < b; ++i) {
    if (f1 <= f2) {
      if (f1 < best.second) best = {x1, f1};
      b = x2, x2 = x1, f2 = f1, x1 = b - kInvPhi * (b - a), f1 = column_error(x1);
    } else {
      if (f2 < best.second) best = {x2, f2};
      a = x1, x1 = x2, f1 = f2, x2 = a + kInvPhi * (b - a), f2 = column_error(x2);
    }
  }
  for (const auto& [x, f] : {std::pair{x1, f1}, std::pair{x2, f2}})
    if (f < best.second) best = {x, f};
  return best;
}

// t*(κ): minimax over the cosines of model(c, t) − exact.
double optimal_steepness(bool y2022, const std::vector<reference::ReferencePoint>& column,
                         double t_guess) {
  std::vector<double> exact;
  for (const auto& r : column) exact.push_back(exact_normalized(y2022, r));
  auto max_err = [&](double t) {
    double m = 0;
    for (std::size_t i = 0; i < column.size(); ++i)
      m = std::max(m, std::abs(model_at_steepness(y2022, column[i].cosine, t) - exact[i]));
    return m;
  };
  return minimize_over_steepness(max_err, t_guess).first;
}

struct RelativeSteepnessResidual {
  bool y2022;
  double kappa, t_opt;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    r[0] = steepness(y2022, T(kappa), p) / T(t_opt) - T(1);
    return true;
  }
};

struct IrradianceResidual {
  bool y2022;
  double kappa, cosine, reference, peak;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const T k(kappa), c(cosine);
    T e;
    if (y2022) {
      e = irradiance_tokuyoshi2022(
          c, k,
          ClampedCosineParams<T>{T(constants::clamped_cosine_published.lambda),
                                 T(constants::clamped_cosine_published.alpha)},
          Steepness2022Params<T>{p[0][0], p[1][0], p[2][0]});
    } else {
      e = irradiance_tokuyoshi2024(
          c, k, Steepness2024Params<T>{p[0][0], p[1][0], p[2][0], p[3][0], p[4][0]});
    }
    r[0] = (e - T(reference)) / T(peak);
    return true;
  }
};

std::vector<double> published(bool y2022) {
  if (y2022) {
    const auto& p = constants::steepness2022_published;
    return {p.A, p.B, p.C};
  }
  const auto& p = constants::steepness2024_published;
  return {p.A, p.B, p.C, p.D, p.E};
}

// Irradiance max peak_rel (double) of the method with coefficients `v` over the references.
double irradiance_error(bool y2022, const std::vector<double>& v,
                        const std::vector<reference::ReferencePoint>& ref) {
  double m = 0;
  for (const auto& r : ref) {
    const double e =
        y2022 ? irradiance_tokuyoshi2022(r.cosine, r.kappa, constants::clamped_cosine_published,
                                         Steepness2022Params<double>{v[0], v[1], v[2]})
              : irradiance_tokuyoshi2024(r.cosine, r.kappa,
                                         Steepness2024Params<double>{v[0], v[1], v[2], v[3], v[4]});
    const double err = std::abs(e - r.irradiance) / irradiance_upper(r.kappa);
    m = std::isfinite(err) ? std::max(m, err) : std::numeric_limits<double>::infinity();
  }
  return m;
}

// The certificate. The steepness forms have only nonlinear
// parameters, so the bound is the per-κ floor: at each κ of a dense training
// grid (kCertificateKappas log-midpoints of [lo, hi], never a point of a
// measuring grid, fit/model_family.hpp, × kCertificateCosines uniform cosines)
// the min over t of the max over that κ's cosines of the error. Any t(κ) form
// errs at that κ by at least the floor, so the max over κ of the floors bounds
// every form on the grid; achieved is the fitted form's max on the same grid.
//   2024: Ê = 2π lerp(Ē(−1), Ē(1), f(c, t)) depends on t(κ) alone, and the
//         measure is the irradiance peak_rel |Ê − E|/E(1, κ) (for both
//         objectives: optimal-t's own measure t/t* − 1 has floor 0).
//   2022: Ê = α(H̃(c₃, κ₃; t(κ₃))e^{λ + logAmp} − H̃(c, κ; t(κ))) evaluates t
//         at the light's κ and at the product's κ₃ = |κω + λn|, which varies
//         with c, so no per-κ floor over one t bounds the irradiance error; the
//         measure is the one t(κ) alone controls, the normalized hemispherical
//         integral |s̃(c, t(κ)) − s(c, κ)| (what optimal-t's t* minimaxes).
// The floor at a κ is a numerical minimum (minimize_over_steepness, then
// refine_minimum to the resolution of double), capped by the error at the
// fitted and the published t(κ), so it never exceeds either.
constexpr int kCertificateKappas = 112, kCertificateCosines = 201;

struct KappaFloor {
  double kappa, t_best, floor, achieved;  // achieved: at the fitted t(κ)
};

std::vector<KappaFloor> per_kappa_floor(bool y2022, const std::function<double(double)>& t_fit,
                                        double lo, double hi) {
  const auto kappas = log_midpoints(lo, hi, kCertificateKappas);
  const auto cosines = cosine_grid(kCertificateCosines);
  const auto ref = reference::reference_engine().evaluate(product_grid(kappas, cosines));
  std::vector<KappaFloor> out;
  for (std::size_t i = 0; i < kappas.size(); ++i) {
    const double k = kappas[i];
    const auto* column = &ref[i * cosines.size()];
    const PoleIrradiances<double> poles = irradiance_poles_over_two_pi(k);
    const double peak = irradiance_upper(k);
    const auto column_error = [&](double t) {
      double m = 0;
      for (std::size_t j = 0; j < cosines.size(); ++j) {
        const auto& r = column[j];
        const double e =
            y2022
                ? std::abs(model_at_steepness(true, r.cosine, t) - r.normalized)
                : std::abs(tokuyoshi2024_eval(
                               Tokuyoshi2024Light<double>{t, poles.lower, poles.upper}, r.cosine) -
                           r.irradiance) /
                      peak;
        m = std::isfinite(e) ? std::max(m, e) : std::numeric_limits<double>::infinity();
      }
      return m;
    };
    const double t_pub = y2022 ? steepness2022(k) : steepness2024(k);
    const double achieved = column_error(t_fit(k));
    auto [t_best, floor] =
        refine_minimum(column_error, minimize_over_steepness(column_error, t_fit(k)));
    for (double t : {t_fit(k), t_pub})
      if (const double e = column_error(t); e < floor) floor = e, t_best = t;
    out.push_back({k, t_best, floor, achieved});
  }
  return out;
}

ordered_json certificate_json(bool y2022, const std::vector<KappaFloor>& floors, double lo,
                              double hi) {
  const auto bound = std::max_element(floors.begin(), floors.end(),
                                      [](auto& a, auto& b) { return a.floor < b.floor; });
  const auto worst = std::max_element(floors.begin(), floors.end(),
                                      [](auto& a, auto& b) { return a.achieved < b.achieved; });
  ordered_json per = ordered_json::array();
  for (const auto& f : floors) per.push_back({f.kappa, f.t_best, f.floor, f.achieved});
  return {
      {"kind",
       "per_kappa_floor: t free at each kappa (scan of log t, Brent, golden section to "
       "the resolution of double), no t(kappa) form "
       "does better"},
      {"what",
       y2022 ? "|s~(c, t(kappa)) - s(c, kappa)|, the normalized hemispherical integral (max over "
               "the grid): the 2022 irradiance evaluates t at kappa and at the product's "
               "kappa3 = |kappa w + lambda n|, which varies with c, so a floor over one t per "
               "kappa bounds no irradiance error; s~ is what t(kappa) alone controls"
             : "tokuyoshi2024 irradiance max peak_rel (double) over the grid, for either objective "
               "(optimal-t's own measure t/t* - 1 has floor 0)"},
      {"grid", fmt::format("dense training grid: {} kappa (log-midpoints of {} cells of [{}, {}]) "
                           "x {} uniform cosines, never a measuring grid",
                           floors.size(), floors.size(), lo, hi, kCertificateCosines)},
      {"achieved", worst->achieved},
      {"achieved_kappa", worst->kappa},
      {"lower_bound", bound->floor},
      {"lower_bound_kappa", bound->kappa},
      {"within_percent_of_best_member", 100 * (worst->achieved / bound->floor - 1)},
      {"per_kappa", {{"columns", {"kappa", "t_best", "floor", "achieved"}}, {"rows", per}}}};
}

// The certificate in the report (with its per-κ table) and in the constant set (without).
void attach_certificate(FitOutcome& out, const ordered_json& certificate) {
  out.report["certificate"] = certificate;
  ordered_json recorded = certificate;
  recorded.erase("per_kappa");
  for (auto& set : out.constant_sets) set["provenance"]["certificate"] = recorded;
}

std::string certificate_text(bool y2022, const ordered_json& c) {
  return fmt::format(
      "  certificate: {} {:.4e} (at kappa {:.4g}), per-kappa floor {:.4e} (at kappa {:.4g}): "
      "within {:.2f}% of the best t(kappa) form\n",
      y2022 ? "max |s~ - s|" : "irradiance peak_rel", c["achieved"].get<double>(),
      c["achieved_kappa"].get<double>(), c["lower_bound"].get<double>(),
      c["lower_bound_kappa"].get<double>(), c["within_percent_of_best_member"].get<double>());
}

// Model order: t(κ) of order M (SteepnessRationalParams) in the 2022 or
// 2024 method, fitted on the irradiance peak_rel error.
template <std::size_t M>
struct RationalIrradianceResidual {
  bool y2022;
  double kappa, cosine, reference, peak;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    SteepnessRationalParams<T, M> params{};
    for (std::size_t i = 0; i < M; ++i) params.p[i] = p[i][0];
    for (std::size_t i = 0; i <= M; ++i) params.q[i] = p[M + i][0];
    const T k(kappa), c(cosine);
    const T e = y2022 ? irradiance_tokuyoshi2022(
                            c, k,
                            ClampedCosineParams<T>{T(constants::clamped_cosine_published.lambda),
                                                   T(constants::clamped_cosine_published.alpha)},
                            params)
                      : irradiance_tokuyoshi2024(c, k, params);
    r[0] = (e - T(reference)) / T(peak);
    return true;
  }
};

struct OrderFit {
  std::size_t order;
  std::vector<double> p, q;
  double error;
  // Multiply-adds of t(κ) (Horner of P and Q) plus the fixed 0.5·, ÷, √ and κ·.
  int operations() const { return int(p.size() + q.size()) + 4; }
};

// Start values of order M from the published forms (M = 1: 2022, M = 2: 2024)
// or from order M − 1 multiplied through by (κ + 1)/(κ + 1).
std::pair<std::vector<double>, std::vector<double>> order_start(std::size_t m,
                                                                const OrderFit* lower) {
  const auto& a = constants::steepness2022_published;
  const auto& b = constants::steepness2024_published;
  if (m == 0) return {{}, {a.C / (2 * a.A)}};  // t ≈ κ√(0.5/(κ + q0)) matches 2022 as κ → 0
  if (m == 1) return {{2 * a.A}, {a.C, a.B}};
  if (m == 2) return {{b.B, b.A}, {b.E, b.D, b.C}};
  // (κ + 1)·P: coefficients shift up.
  auto times = [](const std::vector<double>& c) {  // c lowest first, implicit leading 1
    std::vector<double> out(c.size() + 1, 0.0);
    for (std::size_t i = 0; i < c.size(); ++i) out[i] += c[i], out[i + 1] += c[i];
    out[c.size()] += 1;
    return out;
  };
  return {times(lower->p), times(lower->q)};
}

template <std::size_t M>
OrderFit fit_order(bool y2022, const std::vector<reference::ReferencePoint>& ref,
                   const OrderFit* lower) {
  auto [p0, q0] = order_start(M, lower);
  Parameters params;
  for (std::size_t i = 0; i < M; ++i)
    params.names.push_back(fmt::format("p{}", i)), params.values.push_back(p0[i]);
  for (std::size_t i = 0; i <= M; ++i)
    params.names.push_back(fmt::format("q{}", i)), params.values.push_back(q0[i]);
  Residuals residuals;
  for (const auto& r : ref)
    residuals.push_back(
        make_residual(RationalIrradianceResidual<M>{y2022, r.kappa, r.cosine, r.irradiance,
                                                    irradiance_upper(r.kappa)},
                      params.size()));
  const FitResult f = fit(residuals, params);
  return {M, std::vector<double>(f.values.begin(), f.values.begin() + M),
          std::vector<double>(f.values.begin() + M, f.values.end()), f.max_abs};
}

// t(κ) of a fitted order, through the runtime's SteepnessRationalParams.
template <std::size_t M>
double rational_steepness(const OrderFit& f, double kappa) {
  SteepnessRationalParams<double, M> params{};
  for (std::size_t i = 0; i < M; ++i) params.p[i] = f.p[i];
  for (std::size_t i = 0; i <= M; ++i) params.q[i] = f.q[i];
  return steepness(kappa, params);
}
double rational_steepness(const OrderFit& f, double kappa) {
  switch (f.order) {
    case 0:
      return rational_steepness<0>(f, kappa);
    case 1:
      return rational_steepness<1>(f, kappa);
    case 2:
      return rational_steepness<2>(f, kappa);
    default:
      return rational_steepness<3>(f, kappa);
  }
}

FitOutcome fit_steepness_order(const FitSpec& spec, bool y2022,
                               const std::vector<reference::ReferencePoint>& ref) {
  const double budget = *spec.max_error;
  std::vector<OrderFit> fits;
  const OrderFit* chosen = nullptr;
  for (std::size_t m = 0; m <= 3 && !chosen; ++m) {
    const OrderFit* lower = fits.empty() ? nullptr : &fits.back();
    fit_progress_note(fmt::format("rational order {}", m));
    switch (m) {
      case 0:
        fits.push_back(fit_order<0>(y2022, ref, lower));
        break;
      case 1:
        fits.push_back(fit_order<1>(y2022, ref, lower));
        break;
      case 2:
        fits.push_back(fit_order<2>(y2022, ref, lower));
        break;
      default:
        fits.push_back(fit_order<3>(y2022, ref, lower));
        break;
    }
    if (fits.back().error <= budget) chosen = &fits.back();
  }
  const std::string method = y2022 ? "tokuyoshi2022" : "tokuyoshi2024";
  FitOutcome out;
  out.report = {{"target", spec.target},
                {"objective", "model-order"},
                {"method", method},
                {"max_error", budget},
                {"kappa_range", {spec.kappa_lo, spec.kappa_hi}},
                {"orders", ordered_json::array()}};
  out.text = fmt::format("{} model order for {} irradiance, kappa in [{}, {}], budget {:.3e}:\n",
                         spec.target, method, spec.kappa_lo, spec.kappa_hi, budget);
  out.text += "  order  coefficients  operations  max peak_rel\n";
  for (const auto& f : fits) {
    out.report["orders"].push_back({{"order", f.order},
                                    {"coefficients", f.p.size() + f.q.size()},
                                    {"operations", f.operations()},
                                    {"max_peak_rel", f.error}});
    out.text += fmt::format("  {:>5}  {:>12}  {:>10}  {:.4e}{}\n", f.order, f.p.size() + f.q.size(),
                            f.operations(), f.error,
                            &f == chosen ? "  <- smallest meeting the budget" : "");
  }
  if (!chosen) {
    out.converged = false;
    out.text += "  no order up to 3 meets the budget\n";
    out.report["chosen"] = nullptr;
    return out;
  }
  const std::string variant =
      fmt::format("order{}-k{}-{}-e{:g}", chosen->order, spec.kappa_lo, spec.kappa_hi, budget);
  ordered_json coefficients = {{"p", chosen->p.empty() ? std::vector<double>{0.0} : chosen->p},
                               {"q", chosen->q}};
  out.constant_sets.push_back(make_constant_set(
      spec, spec.target, variant, fmt::format("SteepnessRationalParams<double, {}>", chosen->order),
      "t(kappa) = kappa*sqrt(0.5*P(kappa)/Q(kappa)), P, Q monic of degrees M, M+1 (coefficients "
      "lowest order first)",
      coefficients,
      fmt::format("smallest order M meeting max {} irradiance peak_rel <= {} over {} kappa x {} "
                  "cosines, kappa in [{}, {}]",
                  method, budget, spec.kappa_count, spec.cosine_count, spec.kappa_lo,
                  spec.kappa_hi),
      {{"objective", chosen->error},
       {"max_peak_rel", chosen->error},
       {"operations", chosen->operations()}}));
  out.report["chosen"] = {{"order", chosen->order},
                          {"p", chosen->p},
                          {"q", chosen->q},
                          {"max_peak_rel", chosen->error},
                          {"operations", chosen->operations()},
                          {"variant", variant}};
  const ordered_json certificate =
      certificate_json(y2022,
                       per_kappa_floor(
                           y2022, [&](double k) { return rational_steepness(*chosen, k); },
                           spec.kappa_lo, spec.kappa_hi),
                       spec.kappa_lo, spec.kappa_hi);
  attach_certificate(out, certificate);
  out.text += certificate_text(y2022, certificate);
  return out;
}

// The residuals of one objective: t(κ)/t*(κ) − 1 with t* the per-κ optimum on
// 201 cosines (each t* appended to `t_opt`), or the irradiance peak_rel error
// on the reference points.
Residuals steepness_residuals(const std::string& objective, bool y2022,
                              const std::vector<double>& kappas,
                              const std::vector<reference::ReferencePoint>& ref,
                              std::size_t parameters, std::vector<double>& t_opt) {
  Residuals residuals;
  if (objective == "optimal-t") {
    // A denser cosine column for t*: 201 cosines.
    const auto dense = cosine_grid(201);
    for (double k : kappas) {
      std::vector<reference::Query> column_q;
      for (double c : dense) column_q.push_back({k, c});
      const auto column = reference::reference_engine().evaluate(column_q);
      const double guess = y2022 ? steepness2022(k) : steepness2024(k);
      t_opt.push_back(optimal_steepness(y2022, column, guess));
      residuals.push_back(
          make_residual(RelativeSteepnessResidual{y2022, k, t_opt.back()}, parameters));
    }
  } else {
    for (const auto& r : ref)
      residuals.push_back(make_residual(
          IrradianceResidual{y2022, r.kappa, r.cosine, r.irradiance, irradiance_upper(r.kappa)},
          parameters));
  }
  return residuals;
}

std::string describe_objective(const FitSpec& spec, const std::string& objective, bool y2022,
                               std::size_t kappas, std::size_t cosines) {
  return objective == "optimal-t"
             ? fmt::format(
                   "minimax of t(kappa)/t*(kappa) - 1 over {} log-spaced kappa in [{}, {}]; t* "
                   "minimaxes the {} over 201 cosines",
                   kappas, spec.kappa_lo, spec.kappa_hi,
                   y2022 ? "normalized hemispherical integral s" : "2024 interpolation factor")
             : fmt::format(
                   "minimax of the {} irradiance peak_rel error over {} kappa x {} cosines, kappa "
                   "in [{}, {}]",
                   y2022 ? "tokuyoshi2022" : "tokuyoshi2024", kappas, cosines, spec.kappa_lo,
                   spec.kappa_hi);
}

}  // namespace

std::vector<double> optimal_steepness(const std::string& target,
                                      const std::vector<double>& kappas) {
  const bool y2022 = target == "steepness2022";
  std::vector<double> out;
  const auto dense = cosine_grid(201);
  for (double k : kappas) {
    std::vector<reference::Query> q;
    for (double c : dense) q.push_back({k, c});
    const auto column = reference::reference_engine().evaluate(q);
    out.push_back(optimal_steepness(y2022, column, y2022 ? steepness2022(k) : steepness2024(k)));
  }
  return out;
}

FitOutcome fit_steepness(const FitSpec& spec) {
  const bool y2022 = is2022(spec);
  const std::string objective = spec.objective.empty() ? "irradiance" : spec.objective;
  if (objective != "optimal-t" && objective != "irradiance")
    throw std::invalid_argument(fmt::format(
        "{} objectives are 'optimal-t' and 'irradiance'; got '{}'", spec.target, objective));
  const std::vector<std::string> names = y2022 ? std::vector<std::string>{"A", "B", "C"}
                                               : std::vector<std::string>{"A", "B", "C", "D", "E"};
  const auto kappas = kappa_grid(spec.kappa_lo, spec.kappa_hi, spec.kappa_count);
  const auto cosines = cosine_grid(spec.cosine_count);
  std::vector<reference::Query> queries;
  for (double k : kappas)
    for (double c : cosines) queries.push_back({k, c});
  const auto ref = reference::reference_engine().evaluate(queries);

  if (spec.max_error) return fit_steepness_order(spec, y2022, ref);

  Parameters params;
  params.names = names;
  params.values = published(y2022);
  std::vector<double> t_opt;
  const Residuals residuals =
      steepness_residuals(objective, y2022, kappas, ref, params.size(), t_opt);
  const FitResult result = fit(residuals, params);
  const FitResult at_published = [&] {
    FitResult f;
    const auto r = evaluate_residuals(residuals, params.values);
    for (std::size_t i = 0; i < r.size(); ++i)
      if (!(std::abs(r[i]) <= f.max_abs)) f.max_abs = std::abs(r[i]), f.worst = i;
    return f;
  }();

  std::string variant = objective;
  if (spec.kappa_range_given) variant += fmt::format("-k{}-{}", spec.kappa_lo, spec.kappa_hi);
  ordered_json coefficients, pub_coefficients;
  for (std::size_t i = 0; i < names.size(); ++i) {
    coefficients[names[i]] = result.values[i];
    pub_coefficients[names[i]] = params.values[i];
  }
  const double fit_irr = irradiance_error(y2022, result.values, ref);
  const double pub_irr = irradiance_error(y2022, params.values, ref);
  const std::string objective_text =
      describe_objective(spec, objective, y2022, kappas.size(), cosines.size());
  ordered_json achieved = {{"objective", result.max_abs}, {"irradiance_max_peak_rel", fit_irr}};
  FitOutcome out;
  out.converged = result.converged;
  out.constant_sets.push_back(
      make_constant_set(spec, spec.target, variant,
                        y2022 ? "Steepness2022Params<double>" : "Steepness2024Params<double>",
                        y2022 ? "t(kappa) = kappa*sqrt((0.5*kappa + A)/((kappa + B)*kappa + C))"
                              : "t(kappa) = kappa*sqrt(0.5*((kappa + A)*kappa + B)/(((kappa + "
                                "C)*kappa + D)*kappa + E))",
                        coefficients, objective_text, achieved));
  out.report = {{"target", spec.target},
                {"variant", variant},
                {"objective", objective},
                {"converged", result.converged}};
  for (auto& [k, v] : coefficients.items()) out.report[k] = v;
  out.report["objective_error"] = result.max_abs;
  out.report["irradiance_max_peak_rel"] = fit_irr;
  out.report["published"] = pub_coefficients;
  out.report["published"]["objective_error"] = at_published.max_abs;
  out.report["published"]["irradiance_max_peak_rel"] = pub_irr;
  if (!t_opt.empty()) {
    ordered_json table = ordered_json::array();
    for (std::size_t i = 0; i < kappas.size(); ++i) table.push_back({kappas[i], t_opt[i]});
    out.report["optimal_t"] = table;
  }
  out.text = fmt::format(
      "{} ({}): {}\n  objective {:.4e} (published {:.4e}); irradiance max peak_rel {:.4e} "
      "(published {:.4e})\n",
      spec.target, variant, coefficients.dump(), result.max_abs, at_published.max_abs, fit_irr,
      pub_irr);
  const std::vector<double>& v = result.values;
  const ordered_json certificate = certificate_json(
      y2022,
      per_kappa_floor(
          y2022,
          [&](double k) {
            return y2022 ? steepness(k, Steepness2022Params<double>{v[0], v[1], v[2]})
                         : steepness(k, Steepness2024Params<double>{v[0], v[1], v[2], v[3], v[4]});
          },
          spec.kappa_lo, spec.kappa_hi),
      spec.kappa_lo, spec.kappa_hi);
  attach_certificate(out, certificate);
  out.text += certificate_text(y2022, certificate);
  return out;
}

}  // namespace sglab::fit
