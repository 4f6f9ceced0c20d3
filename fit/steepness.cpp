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
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <boost/math/tools/minima.hpp>

#include <sglab/sglab.hpp>

#include "fit/minimax.hpp"
#include "fit/targets.hpp"
#include "validate/reference.hpp"

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
double exact_normalized(bool y2022, const validate::ReferencePoint& r) {
  if (y2022) return r.normalized;
  const double lo = irradiance_lower(r.kappa), hi = irradiance_upper(r.kappa);
  return (r.irradiance - lo) / (hi - lo);
}

// t*(κ): minimax over the cosines of model(c, t) − exact, by a scan in log t
// followed by Brent's method around the best scan point.
double optimal_steepness(bool y2022, const std::vector<validate::ReferencePoint>& column,
                         double t_guess) {
  std::vector<double> exact;
  for (const auto& r : column) exact.push_back(exact_normalized(y2022, r));
  auto max_err = [&](double log_t) {
    const double t = std::exp(log_t);
    double m = 0;
    for (std::size_t i = 0; i < column.size(); ++i)
      m = std::max(m, std::abs(model_at_steepness(y2022, column[i].cosine, t) - exact[i]));
    return m;
  };
  const double center = std::log(t_guess);
  double best = center, best_err = max_err(center);
  const int n = 80;
  for (int i = 0; i <= n; ++i) {
    const double x = center - 3 + 6.0 * i / n;
    const double e = max_err(x);
    if (e < best_err) best_err = e, best = x;
  }
  const double step = 6.0 / n;
  const auto r = boost::math::tools::brent_find_minima(max_err, best - step, best + step, 52);
  return std::exp(r.second <= best_err ? r.first : best);
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
                        const std::vector<validate::ReferencePoint>& ref) {
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
OrderFit fit_order(bool y2022, const std::vector<validate::ReferencePoint>& ref,
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

FitOutcome fit_steepness_order(const FitSpec& spec, bool y2022,
                               const std::vector<validate::ReferencePoint>& ref) {
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
  return out;
}

// The residuals of one objective: t(κ)/t*(κ) − 1 with t* the per-κ optimum on
// 201 cosines (each t* appended to `t_opt`), or the irradiance peak_rel error
// on the reference points.
Residuals steepness_residuals(const std::string& objective, bool y2022,
                              const std::vector<double>& kappas,
                              const std::vector<validate::ReferencePoint>& ref,
                              std::size_t parameters, std::vector<double>& t_opt) {
  Residuals residuals;
  if (objective == "optimal-t") {
    // A denser cosine column for t*: 201 cosines.
    const auto dense = cosine_grid(201);
    for (double k : kappas) {
      std::vector<validate::Query> column_q;
      for (double c : dense) column_q.push_back({k, c});
      const auto column = validate::reference_engine().evaluate(column_q);
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
    std::vector<validate::Query> q;
    for (double c : dense) q.push_back({k, c});
    const auto column = validate::reference_engine().evaluate(q);
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
  std::vector<validate::Query> queries;
  for (double k : kappas)
    for (double c : cosines) queries.push_back({k, c});
  const auto ref = validate::reference_engine().evaluate(queries);

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
  return out;
}

}  // namespace sglab::fit
