// `sglab fit erf`: minimax refits of the two published erf structures,
//   listing5  x·P(x²) on [0, b], 1 − 2^{−a·Q(a)} on (b, cutoff), ±1 beyond ([Tokuyoshi2022] Listing
//   5) as7125    1 − t(a1 + a2 t + …)e^{−x²}, t = 1/(1 + p x)   ([AS1964] 7.1.25)
// on the absolute error against std::erf in double (accurate to < 1 ulp of
// double, i.e. exact at the 1e−7 level fitted here). Minimax by Lawson's
// reweighting (fit/minimax), then every coefficient is rounded to float one
// at a time while the remaining ones are re-fitted.
//
// With --max-error E the smallest model meeting E is searched: for listing5
// the degrees of P and Q and the split b; for as7125 the number of terms.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <sglab/sglab.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/minimax.hpp"
#include "fit/targets.hpp"

namespace sglab::fit {

namespace {

// The runtime's Listing5Params at the largest degrees searched; unused
// trailing coefficients are held at exactly 0 so Horner evaluates the
// lower-degree polynomial.
constexpr std::size_t kMaxSmall = 8, kMaxLarge = 9, kMaxTerms = 5;

struct Listing5Shape {
  std::size_t small_terms, large_terms;
  double split, cutoff;
};

// Residual erf_listing5(x) − erf(x) with the small (piece 0) or large (piece 1)
// coefficients free: p[i] maps to small[i] for i < kMaxSmall, then large[].
struct Listing5Residual {
  double x, reference, split, cutoff;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    Listing5Params<T, kMaxSmall, kMaxLarge> params{};
    params.split = T(split);
    params.cutoff = T(cutoff);
    for (std::size_t i = 0; i < kMaxSmall; ++i) params.small[i] = p[i][0];
    for (std::size_t i = 0; i < kMaxLarge; ++i) params.large[i] = p[kMaxSmall + i][0];
    r[0] = erf_listing5(T(x), params) - T(reference);
    return true;
  }
};

struct AbramowitzStegunResidual {
  double x, reference;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    AbramowitzStegunParams<T, kMaxTerms> params{};
    params.p = p[0][0];
    for (std::size_t i = 0; i < kMaxTerms; ++i) params.a[i] = p[1 + i][0];
    r[0] = erf_abramowitz_stegun(T(x), params) - T(reference);
    return true;
  }
};

// Chebyshev-distributed points on [a, b] (ends included): dense where
// minimax error peaks cluster.
std::vector<double> chebyshev_points(double a, double b, int n) {
  std::vector<double> x;
  for (int i = 0; i < n; ++i)
    x.push_back(0.5 * (a + b) - 0.5 * (b - a) * std::cos(pi_v<double>() * i / (n - 1)));
  return x;
}

// The worst |erf_variant − erf| of a scan and where it is: the first point of
// the largest error (a NaN error counts as the largest).
struct WorstError {
  double error = 0, where = 0;
  // `later` covers points after this one's
  void join(const WorstError& later) {
    if (!(later.error <= error)) *this = later;
  }
};

// Max |erf_variant − erf| over a dense grid of [0, hi] in double ("exact arithmetic").
template <class F>
std::pair<double, double> max_error_dense(F f, double hi) {
  WorstError worst;
  const int n = 200000;
  for (int i = 0; i <= n; ++i) {
    const double x = hi * i / n;
    worst.join({std::abs(f(x) - std::erf(x)), x});
  }
  return {worst.error, worst.where};
}

// Max |erf_variant − erf| over every float in [0, hi] with a stride, in float:
// tens of millions of points, so split over the cores by TBB's deterministic
// reduction (its partition depends on the range alone, not on the threads),
// each part joined in order, so the result is that of the serial scan.
template <class F>
std::pair<double, double> max_error_float(F f, float hi, std::uint32_t stride) {
  std::uint32_t bits_hi;
  std::memcpy(&bits_hi, &hi, 4);
  const std::uint64_t count = std::uint64_t{bits_hi} / stride + 1;
  const WorstError worst = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::uint64_t>(0, count, 1 << 16), WorstError{},
      [&](const tbb::blocked_range<std::uint64_t>& r, WorstError w) {
        for (std::uint64_t k = r.begin(); k != r.end(); ++k) {
          const auto b = static_cast<std::uint32_t>(k * stride);
          float x;
          std::memcpy(&x, &b, 4);
          w.join({std::abs(static_cast<double>(f(x)) - std::erf(static_cast<double>(x))), x});
        }
        return w;
      },
      [](WorstError lower, const WorstError& upper) {
        lower.join(upper);
        return lower;
      });
  return {worst.error, worst.where};
}

struct Listing5Fit {
  Listing5Shape shape;
  std::vector<double> small, large;
  double small_error, large_error;
  double max_error() const { return std::max(small_error, large_error); }
  int operations() const { return int(shape.small_terms + shape.large_terms); }
};

Parameters listing5_parameters(const Listing5Shape& s, const std::vector<double>& small,
                               const std::vector<double>& large, bool fit_small) {
  Parameters p;
  for (std::size_t i = 0; i < kMaxSmall; ++i) {
    p.names.push_back(fmt::format("small{}", i));
    p.values.push_back(i < small.size() ? small[i] : 0.0);
    p.fixed.push_back(!fit_small || i >= s.small_terms);
  }
  for (std::size_t i = 0; i < kMaxLarge; ++i) {
    p.names.push_back(fmt::format("large{}", i));
    p.values.push_back(i < large.size() ? large[i] : 0.0);
    p.fixed.push_back(fit_small || i >= s.large_terms);
  }
  return p;
}

// Taylor start for x·P(x²): erf(x) = (2/√π) Σ (−1)^n x^{2n+1}/(n!(2n+1)).
std::vector<double> taylor_small(std::size_t n) {
  std::vector<double> c;
  double fact = 1;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) fact *= static_cast<double>(k);
    c.push_back((k % 2 ? -1.0 : 1.0) * 2 / std::sqrt(pi_v<double>()) /
                (fact * static_cast<double>(2 * k + 1)));
  }
  return c;
}

Listing5Fit fit_listing5(const Listing5Shape& shape, std::vector<double> small_start,
                         std::vector<double> large_start, bool round_to_float) {
  Listing5Fit out{shape, {}, {}, 0, 0};
  small_start.resize(kMaxSmall, 0.0);
  large_start.resize(kMaxLarge, 0.0);
  for (std::size_t i = shape.small_terms; i < kMaxSmall; ++i) small_start[i] = 0;
  for (std::size_t i = shape.large_terms; i < kMaxLarge; ++i) large_start[i] = 0;
  for (bool fit_small : {true, false}) {
    const double lo = fit_small ? 0.0 : shape.split, hi = fit_small ? shape.split : shape.cutoff;
    Residuals residuals;
    for (double x : chebyshev_points(lo, hi, 1500)) {
      if (!fit_small && x <= shape.split)
        x = std::nextafter(shape.split, hi);  // the 2^ piece starts above b
      if (!fit_small && x >= shape.cutoff) x = std::nextafter(shape.cutoff, lo);
      residuals.push_back(make_residual(Listing5Residual{x, std::erf(x), shape.split, shape.cutoff},
                                        kMaxSmall + kMaxLarge));
    }
    const Parameters params = listing5_parameters(shape, small_start, large_start, fit_small);
    FitOptions options;
    options.lawson_iterations = 30;
    const FitResult r = round_to_float ? fit_rounded_to_float(residuals, params, options)
                                       : fit(residuals, params, options);
    small_start.assign(r.values.begin(), r.values.begin() + kMaxSmall);
    large_start.assign(r.values.begin() + kMaxSmall, r.values.end());
    (fit_small ? out.small_error : out.large_error) = r.max_abs;
  }
  out.small.assign(small_start.begin(), small_start.begin() + shape.small_terms);
  out.large.assign(large_start.begin(), large_start.begin() + shape.large_terms);
  return out;
}

// A listing5 fit as the runtime's parameters at its exact sizes' padding.
template <class T>
Listing5Params<T, kMaxSmall, kMaxLarge> listing5_params(const Listing5Fit& f) {
  Listing5Params<T, kMaxSmall, kMaxLarge> p{};
  p.split = static_cast<T>(f.shape.split);
  p.cutoff = static_cast<T>(f.shape.cutoff);
  for (std::size_t i = 0; i < f.small.size(); ++i) p.small[i] = static_cast<T>(f.small[i]);
  for (std::size_t i = 0; i < f.large.size(); ++i) p.large[i] = static_cast<T>(f.large[i]);
  return p;
}

struct AsFit {
  std::size_t terms;
  std::vector<double> coefficients;  // p, a1..aN
  double error;
};

AsFit fit_as(std::size_t terms, std::vector<double> start, bool round_to_float) {
  start.resize(1 + kMaxTerms, 0.0);
  Parameters params;
  params.names = {"p"};
  for (std::size_t i = 0; i < kMaxTerms; ++i) params.names.push_back(fmt::format("a{}", i + 1));
  params.values = start;
  params.fixed.assign(1 + kMaxTerms, false);
  for (std::size_t i = terms; i < kMaxTerms; ++i)
    params.values[1 + i] = 0, params.fixed[1 + i] = true;
  Residuals residuals;
  for (double x : chebyshev_points(0, 6, 2000))
    residuals.push_back(make_residual(AbramowitzStegunResidual{x, std::erf(x)}, 1 + kMaxTerms));
  FitOptions options;
  options.lawson_iterations = 40;
  const FitResult r = round_to_float ? fit_rounded_to_float(residuals, params, options)
                                     : fit(residuals, params, options);
  return {terms, std::vector<double>(r.values.begin(), r.values.begin() + 1 + terms), r.max_abs};
}

// An as7125 fit (p, a1..aN) as the runtime's parameters.
template <class T>
AbramowitzStegunParams<T, kMaxTerms> as_params(const std::vector<double>& c) {
  AbramowitzStegunParams<T, kMaxTerms> p{};
  p.p = static_cast<T>(c[0]);
  for (std::size_t i = 1; i < c.size(); ++i) p.a[i - 1] = static_cast<T>(c[i]);
  return p;
}

ordered_json to_json(const std::vector<double>& v) {
  ordered_json a = ordered_json::array();
  for (double x : v) a.push_back(x);
  return a;
}

// The certificate of a fit whose residuals are linear in the parameters
// `linear` at the others' fitted values: the LP optimum on the fit's points
// (fit/lp_minimax.hpp) is the best those parameters can do there (exact
// arithmetic), a lower bound of every member with the others fixed; the fit's
// max on the same points (its coefficients, rounded to float where it rounds)
// is achieved.
ordered_json lp_certificate(const Residuals& residuals, const std::vector<double>& values,
                            std::size_t first, std::size_t count, const std::string& kind,
                            const std::string& grid) {
  std::vector<std::size_t> linear(count);
  std::iota(linear.begin(), linear.end(), first);
  const LinearSubproblem sub = linear_subproblem(residuals, values, linear);
  const LpMinimaxResult lp = lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  const double achieved = max_abs_residual(evaluate_residuals(residuals, values));
  return {{"kind", kind},
          {"grid", grid},
          {"achieved", achieved},
          {"lower_bound", lp.lower_bound},
          {"within_percent_of_best_member", 100 * (achieved / lp.lower_bound - 1)}};
}

// listing5's small piece x·P(x²) is linear in P: its certificate on the fit's
// 1500 Chebyshev points of [0, split], the large piece as fitted.
ordered_json listing5_certificate(const Listing5Fit& f) {
  Residuals residuals;
  for (double x : chebyshev_points(0, f.shape.split, 1500))
    residuals.push_back(make_residual(
        Listing5Residual{x, std::erf(x), f.shape.split, f.shape.cutoff}, kMaxSmall + kMaxLarge));
  std::vector<double> values(kMaxSmall + kMaxLarge, 0.0);
  std::copy(f.small.begin(), f.small.end(), values.begin());
  std::copy(f.large.begin(), f.large.end(), values.begin() + kMaxSmall);
  return lp_certificate(residuals, values, 0, f.small.size(),
                        "lp_small_piece: the best P of this degree",
                        fmt::format("1500 Chebyshev points of [0, {}] (the fit's)", f.shape.split));
}

// as7125 is linear in a1..aN at fixed p: its certificate on the fit's 2000
// Chebyshev points of [0, 6].
ordered_json as_certificate(const AsFit& f) {
  Residuals residuals;
  for (double x : chebyshev_points(0, 6, 2000))
    residuals.push_back(make_residual(AbramowitzStegunResidual{x, std::erf(x)}, 1 + kMaxTerms));
  std::vector<double> values(1 + kMaxTerms, 0.0);
  std::copy(f.coefficients.begin(), f.coefficients.end(), values.begin());
  return lp_certificate(residuals, values, 1, f.coefficients.size() - 1,
                        "lp_at_fitted_p: the best a_i at this p",
                        "2000 Chebyshev points of [0, 6] (the fit's)");
}

// Float-evaluated error: every 16th float in [0, 4] (about 6.8e7 inputs).
// The exhaustive check of every float is `sglab erf --exhaustive`.
constexpr std::uint32_t kFloatStride = 16;

// listing5's model: the published shape refitted, or with --max-error the
// smallest total degree meeting it over splits and degrees (each tried model a
// row of `order_table`); none meeting it: the refit, and the fit not converged.
Listing5Fit choose_listing5(const FitSpec& spec, const Listing5Shape& pub_shape,
                            const std::vector<double>& pub_small,
                            const std::vector<double>& pub_large, bool round,
                            ordered_json& order_table, FitOutcome& out) {
  const auto& pl = constants::erf_listing5_published;
  Listing5Fit chosen;
  if (spec.max_error) {
    // Smallest total degree meeting the budget, over splits b and degrees.
    bool found = false;
    for (double split : {0.5, 0.75, 1.0, 1.25, 1.5, 2.0}) {
      for (std::size_t ns = 2; ns <= kMaxSmall; ++ns) {
        fit_progress_note(fmt::format("listing5 split {}: {} small terms", split, ns));
        const Listing5Fit small_only =
            fit_listing5({ns, 2, split, pl.cutoff}, taylor_small(ns), pub_large, round);
        if (small_only.small_error > *spec.max_error) continue;
        for (std::size_t nl = 2; nl <= kMaxLarge; ++nl) {
          fit_progress_note(fmt::format("listing5 split {}: {}+{} terms", split, ns, nl));
          const Listing5Fit f =
              fit_listing5({ns, nl, split, pl.cutoff}, small_only.small, pub_large, round);
          order_table.push_back({{"split", split},
                                 {"small_terms", ns},
                                 {"large_terms", nl},
                                 {"max_error", f.max_error()},
                                 {"operations", f.operations()}});
          if (f.max_error() <= *spec.max_error) {
            if (!found || f.operations() < chosen.operations()) chosen = f, found = true;
            break;
          }
        }
        break;  // larger ns only costs more for this split
      }
    }
    if (!found) {
      out.converged = false;
      out.text += fmt::format("erf listing5: no model with up to {}+{} terms meets {:.3e}\n",
                              kMaxSmall, kMaxLarge, *spec.max_error);
      chosen = fit_listing5(pub_shape, pub_small, pub_large, round);
    }
  } else {
    chosen = fit_listing5(pub_shape, pub_small, pub_large, round);
  }
  return chosen;
}

// as7125's model: the published 3 terms refitted, or with --max-error the
// fewest terms meeting it (each a row of `order_table`); none: 3 terms, not converged.
AsFit choose_as7125(const FitSpec& spec, const std::vector<double>& pub, bool round,
                    ordered_json& order_table, FitOutcome& out) {
  AsFit chosen;
  if (spec.max_error) {
    bool found = false;
    std::vector<double> start = pub;
    for (std::size_t n = 2; n <= kMaxTerms && !found; ++n) {
      fit_progress_note(fmt::format("as7125: {} terms", n));
      const AsFit f = fit_as(n, start, round);
      order_table.push_back({{"terms", n}, {"max_error", f.error}, {"operations", n + 1}});
      start = f.coefficients;
      if (f.error <= *spec.max_error) chosen = f, found = true;
    }
    if (!found) {
      out.converged = false;
      out.text += fmt::format("erf as7125: no model with up to {} terms meets {:.3e}\n", kMaxTerms,
                              *spec.max_error);
      chosen = fit_as(3, pub, round);
    }
  } else {
    chosen = fit_as(3, pub, round);
  }
  return chosen;
}

// The listing5 structure: its model, its errors against the published one, a
// constant set with its certificate, a report row and a line of text.
void add_listing5(const FitSpec& spec, bool round, FitOutcome& out) {
  const auto& pl = constants::erf_listing5_published;
  const std::vector<double> pub_small(std::begin(pl.small), std::end(pl.small));
  const std::vector<double> pub_large(std::begin(pl.large), std::end(pl.large));
  const Listing5Shape pub_shape{pub_small.size(), pub_large.size(), pl.split, pl.cutoff};
  ordered_json order_table = ordered_json::array();
  const Listing5Fit chosen =
      choose_listing5(spec, pub_shape, pub_small, pub_large, round, order_table, out);
  fit_progress_note("listing5: error of the chosen and published models (dense and float grids)");
  const Listing5Fit published{pub_shape, pub_small, pub_large, 0, 0};
  const auto error_dense = [](const Listing5Fit& f) {
    const auto p = listing5_params<double>(f);
    return max_error_dense([&](double x) { return erf_listing5(x, p); }, 6.0);
  };
  const auto error_float = [](const Listing5Fit& f) {
    const auto p = listing5_params<float>(f);
    return max_error_float([&](float x) { return erf_listing5(x, p); }, 4.0f, kFloatStride);
  };
  const auto exact_fit = error_dense(chosen), exact_pub = error_dense(published);
  const auto float_fit = error_float(chosen), float_pub = error_float(published);
  std::string variant = "listing5-" + std::string(io::to_string(spec.precision));
  if (spec.max_error) variant += fmt::format("-e{:g}", *spec.max_error);
  ordered_json coefficients = {{"split", chosen.shape.split},
                               {"cutoff", chosen.shape.cutoff},
                               {"small", to_json(chosen.small)},
                               {"large", to_json(chosen.large)}};
  ordered_json achieved = {{"objective", exact_fit.first},
                           {"max_abs_exact_arithmetic", exact_fit.first},
                           {"max_abs_float_every_16th_float", float_fit.first}};
  out.constant_sets.push_back(make_constant_set(
      spec, "erf", variant,
      fmt::format("Listing5Params<double, {}, {}>", chosen.small.size(), chosen.large.size()),
      "erf(x) ≈ x*P(x^2) for |x| <= split; 1 - 2^(-a*Q(a)) for split < a=|x| < cutoff; sign(x) "
      "beyond",
      coefficients,
      fmt::format("minimax of |erf_listing5(x) - erf(x)| (Lawson IRLS){}",
                  round ? ", coefficients rounded to float one at a time with re-fits" : ""),
      achieved));
  const ordered_json certificate = listing5_certificate(chosen);
  out.constant_sets.back()["provenance"]["certificate"] = certificate;
  ordered_json row = {
      {"structure", "listing5"}, {"variant", variant}, {"certificate", certificate}};
  for (auto& [k, v] : coefficients.items()) row[k] = v;
  row["max_abs"] = exact_fit.first;
  row["worst_x"] = exact_fit.second;
  row["max_abs_float"] = float_fit.first;
  row["worst_x_float"] = float_fit.second;
  row["operations"] = chosen.operations();
  if (!order_table.empty()) row["model_order"] = order_table;
  row["published"] = {{"max_abs", exact_pub.first},
                      {"worst_x", exact_pub.second},
                      {"max_abs_float", float_pub.first},
                      {"worst_x_float", float_pub.second},
                      {"operations", 13}};
  out.report["results"].push_back(row);
  out.text += fmt::format(
      "erf listing5 ({}): {}+{} terms, split {}: max abs {:.3e} exact, {:.3e} float; published "
      "{:.3e} exact, {:.3e} float; small piece within {:.2f}% of the best P (LP {:.3e})\n",
      variant, chosen.small.size(), chosen.large.size(), chosen.shape.split, exact_fit.first,
      float_fit.first, exact_pub.first, float_pub.first,
      certificate["within_percent_of_best_member"].get<double>(),
      certificate["lower_bound"].get<double>());
}

// The as7125 structure, as add_listing5.
void add_as7125(const FitSpec& spec, bool round, FitOutcome& out) {
  const auto& pa = constants::erf_as7125_published;
  const std::vector<double> pub = {pa.p, pa.a[0], pa.a[1], pa.a[2]};
  ordered_json order_table = ordered_json::array();
  const AsFit chosen = choose_as7125(spec, pub, round, order_table, out);
  fit_progress_note("as7125: error of the chosen and published models (dense and float grids)");
  const auto error_dense = [](const std::vector<double>& c) {
    const auto p = as_params<double>(c);
    return max_error_dense([&](double x) { return erf_abramowitz_stegun(x, p); }, 6.0);
  };
  const auto error_float = [](const std::vector<double>& c) {
    const auto p = as_params<float>(c);
    return max_error_float([&](float x) { return erf_abramowitz_stegun(x, p); }, 4.0f,
                           kFloatStride);
  };
  const auto exact_fit = error_dense(chosen.coefficients), exact_pub = error_dense(pub);
  const auto float_fit = error_float(chosen.coefficients), float_pub = error_float(pub);
  std::string variant = "as7125-" + std::string(io::to_string(spec.precision));
  if (spec.max_error) variant += fmt::format("-e{:g}", *spec.max_error);
  ordered_json coefficients = {
      {"p", chosen.coefficients[0]},
      {"a", to_json({chosen.coefficients.begin() + 1, chosen.coefficients.end()})}};
  ordered_json achieved = {{"objective", exact_fit.first},
                           {"max_abs_exact_arithmetic", exact_fit.first},
                           {"max_abs_float_every_16th_float", float_fit.first}};
  out.constant_sets.push_back(make_constant_set(
      spec, "erf", variant,
      fmt::format("AbramowitzStegunParams<double, {}>", chosen.coefficients.size() - 1),
      "erf(x) ≈ 1 - (a1 t + a2 t^2 + ...) exp(-x^2), t = 1/(1 + p x), x >= 0; odd", coefficients,
      fmt::format("minimax of |erf_as(x) - erf(x)| on [0, 6] (Lawson IRLS){}",
                  round ? ", coefficients rounded to float one at a time with re-fits" : ""),
      achieved));
  const ordered_json certificate = as_certificate(chosen);
  out.constant_sets.back()["provenance"]["certificate"] = certificate;
  ordered_json row = {{"structure", "as7125"},
                      {"variant", variant},
                      {"certificate", certificate},
                      {"p", chosen.coefficients[0]}};
  for (std::size_t i = 1; i < chosen.coefficients.size(); ++i)
    row[fmt::format("a{}", i)] = chosen.coefficients[i];
  row["max_abs"] = exact_fit.first;
  row["worst_x"] = exact_fit.second;
  row["max_abs_float"] = float_fit.first;
  row["worst_x_float"] = float_fit.second;
  if (!order_table.empty()) row["model_order"] = order_table;
  row["published"] = {{"p", pa.p},
                      {"a1", pa.a[0]},
                      {"a2", pa.a[1]},
                      {"a3", pa.a[2]},
                      {"max_abs", exact_pub.first},
                      {"worst_x", exact_pub.second},
                      {"max_abs_float", float_pub.first}};
  out.report["results"].push_back(row);
  out.text += fmt::format(
      "erf as7125 ({}): {} terms: max abs {:.3e} exact, {:.3e} float; published {:.3e} exact, "
      "{:.3e} float; within {:.2f}% of the best a_i at this p (LP {:.3e})\n",
      variant, chosen.coefficients.size() - 1, exact_fit.first, float_fit.first, exact_pub.first,
      float_pub.first, certificate["within_percent_of_best_member"].get<double>(),
      certificate["lower_bound"].get<double>());
}

}  // namespace

FitOutcome fit_erf(const FitSpec& spec) {
  const std::string structure = spec.objective.empty() ? "both" : spec.objective;
  if (structure != "both" && structure != "listing5" && structure != "as7125")
    throw std::invalid_argument(
        fmt::format("erf structures are listing5 and as7125; got '{}'", structure));
  const bool round = spec.precision != io::Precision::float64;
  FitOutcome out;
  out.report = {{"target", "erf"},
                {"precision", std::string(io::to_string(spec.precision))},
                {"results", ordered_json::array()}};
  if (structure != "as7125") add_listing5(spec, round, out);
  if (structure != "listing5") add_as7125(spec, round, out);
  return out;
}

}  // namespace sglab::fit
