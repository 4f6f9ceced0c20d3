// `sglab fit sglab-min`: the coefficients of sglab_min
// (include/sglab/sglab_min.hpp)
//   Ê = y·max(0, A(y) + B(y) c + G(y) c²),  y = 1/(κ + s),
// A quadratic, B and G linear in y, in the named steps of the rational-shape fitter
// (fit/rational_shape_fit.hpp):
//   1. per κ of the training grid, the A, B, G of max(0, A + B c + G c²) that
//      minimax peak_rel over the training cosines: the family's per-κ floor;
//   2. at fixed s the model is linear in its seven coefficients but for the
//      clamp: their exact best by the one-sided LP (lp_minimax_upper: Ê ≤ E +
//      e everywhere, Ê ≥ E − e where E/E(1) > e, the level e iterated to its
//      fixed point, where that is the clamped problem itself);
//   3. s by golden-section search of log s on that exact optimum (over a
//      bracket found on a log grid), then a polish of all eight parameters
//      by the joint minimax on the runtime function (Jets through
//      irradiance_sglab_min), kept where it does better;
// then certified: at the fitted s every coefficient enters linearly, and the
// LP of clamped_lp_certificate (fit/model_family.hpp) bounds how well any of
// their values could do. The training grid is that of the rational-shape
// fitter plus four κ beyond the range (1e5, 1e6, 1e8, 1e20: y → 0, the limit
// the form reaches as κ → ∞), so that the bound holds to κ = FLT_MAX.
// docs/models.md#sglab_min.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Dense>

#include <sglab/sglab.hpp>
#include <sglab/sglab_min.hpp>

#include "fit/lp_minimax.hpp"
#include "fit/rational_shape_fit.hpp"

namespace sglab::fit {

namespace {

// The coefficients of A, B, G (SglabMinParams), then s.
constexpr const char* kMinPolys[] = {"a", "b", "g"};
constexpr std::size_t kMinSizes[] = {3, 2, 2};
constexpr std::size_t kMinLinear = 7;
constexpr std::size_t kMinParameters = kMinLinear + 1;
constexpr double kMinLimitKappas[] = {1e5, 1e6, 1e8, 1e20};

template <class T, class Value>
SglabMinParams<T> min_params(Value value) {
  SglabMinParams<T> p{};
  std::size_t i = 0;
  T* polys[] = {p.a, p.b, p.g};
  for (std::size_t n = 0; n < 3; ++n)
    for (std::size_t j = 0; j < kMinSizes[n]; ++j) polys[n][j] = value(i++);
  p.s = value(i);
  return p;
}

// Step 1 residual: peak_rel of E(1)·max(0, A + B c + G c²) at one (κ, c).
struct MinShapeResidual {
  double cosine, normalized;  // E(c, κ)/E(1, κ)
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const T c(cosine);
    r[0] = max0(p[0][0] + c * (p[1][0] + c * p[2][0])) - T(normalized);
    return true;
  }
};

// Step 3 residual: peak_rel of the runtime function at one (κ, c).
struct MinModelResidual {
  double kappa, cosine, reference, peak, kappa_max;  // kappa_max unused (certificate's form)
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const auto params = min_params<T>([p](std::size_t i) { return p[i][0]; });
    r[0] = (irradiance_sglab_min(T(cosine), T(kappa), params) - T(reference)) / T(peak);
    return true;
  }
};

std::unique_ptr<ceres::CostFunction> model_residual(const reference::ReferencePoint& r) {
  return make_residual(
      MinModelResidual{r.kappa, r.cosine, r.irradiance, irradiance_upper(r.kappa), 0.0},
      kMinParameters);
}

PerKappaShape per_kappa_at(double k, const std::vector<double>& cosines,
                           const std::vector<reference::ReferencePoint>& ref,
                           const std::optional<PerKappaShape>& previous) {
  const double e1 = irradiance_upper(k);
  // The first (largest κ) starts from max(c, 0), the κ → ∞ shape.
  Parameters params{{"A", "B", "G"}, previous ? previous->shape : std::vector{0.0, 1.0, 0.0}, {}};
  Residuals residuals;
  for (std::size_t j = 0; j < cosines.size(); ++j)
    residuals.push_back(make_residual(MinShapeResidual{ref[j].cosine, ref[j].irradiance / e1}, 3));
  const FitResult f = fit(residuals, params);
  return {k, {f.values.begin(), f.values.begin() + 3}, f.max_abs};
}

// Step 2 at one s: the seven coefficients' exact best on `train` (the
// one-sided LP, its level iterated), then s.
std::vector<double> best_at(const std::vector<reference::ReferencePoint>& train, double s) {
  const auto rows = static_cast<Eigen::Index>(train.size());
  Eigen::MatrixXd m(rows, Eigen::Index(kMinLinear));
  Eigen::VectorXd t(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const auto& r = train[std::size_t(i)];
    const double y = 1 / (r.kappa + s), e1 = irradiance_upper(r.kappa);
    Eigen::Index col = 0;
    double cp = 1;  // c^n
    for (std::size_t n = 0; n < 3; ++n, cp *= r.cosine)
      for (std::size_t j = 0; j < kMinSizes[n]; ++j)
        m(i, col++) = y * std::pow(y, double(j)) * cp / e1;
    t(i) = r.irradiance / e1;
  }
  double level = 0;
  LpMinimaxResult lp;
  for (int round = 0; round < 12; ++round) {
    std::vector<bool> lower(static_cast<std::size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) lower[std::size_t(i)] = t(i) > level;
    lp = lp_minimax_upper(m, t, Eigen::VectorXd::Ones(rows), lower);
    if (std::abs(lp.lower_bound - level) <= 1e-12) break;
    level = lp.lower_bound;
  }
  std::vector<double> values(lp.x.data(), lp.x.data() + lp.x.size());
  values.push_back(s);
  return values;
}

double max_error(const Residuals& residuals, const std::vector<double>& values) {
  double e = 0;
  for (double r : evaluate_residuals(residuals, values))
    e = std::isfinite(r) ? std::max(e, std::abs(r)) : std::numeric_limits<double>::infinity();
  return e;
}

std::optional<std::vector<double>> committed_start(const std::string& variant, double lo,
                                                   double hi) {
  const auto c = committed_coefficients("sglab-min", variant, lo, hi);
  if (!c) return std::nullopt;
  std::vector<double> values;
  for (std::size_t n = 0; n < 3; ++n) {
    if (!c->contains(kMinPolys[n]) || c->at(kMinPolys[n]).size() != kMinSizes[n])
      return std::nullopt;
    for (const auto& x : c->at(kMinPolys[n])) values.push_back(x.get<double>());
  }
  if (!c->contains("s")) return std::nullopt;
  values.push_back(c->at("s").get<double>());
  return values;
}

ordered_json coefficients_json(const std::vector<double>& v) {
  ordered_json c;
  std::size_t i = 0;
  for (std::size_t n = 0; n < 3; ++n) {
    c[kMinPolys[n]] = ordered_json::array();
    for (std::size_t j = 0; j < kMinSizes[n]; ++j) c[kMinPolys[n]].push_back(v.at(i++));
  }
  c["s"] = v.at(i);
  return c;
}

constexpr const char* kForm =
    "E = y*max(0, A(y) + B(y)*c + G(y)*c^2), y = 1/(kappa + s); A = a[0] + a[1]*y + a[2]*y^2, "
    "B = b[0] + b[1]*y, G = g[0] + g[1]*y";

}  // namespace

FitOutcome fit_sglab_min(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "irradiance")
    throw std::invalid_argument(
        fmt::format("sglab-min has the one objective 'irradiance'; got '{}'", spec.objective));
  const double lo = spec.kappa_lo, hi = spec.kappa_hi;
  const auto train_k = log_midpoints(lo, hi, kRationalTrainKappas);
  const auto train_c = cosine_grid(kRationalTrainCosines);
  const auto range = rational_reference_grid(train_k, train_c);
  std::vector<double> limit_k(std::begin(kMinLimitKappas), std::end(kMinLimitKappas));
  auto train = range;
  for (const auto& r : rational_reference_grid(limit_k, train_c)) train.push_back(r);

  const std::string variant = std::string(io::to_string(spec.precision)) +
                              (spec.kappa_range_given ? fmt::format("-k{}-{}", lo, hi) : "");
  std::optional<std::vector<double>> committed;
  if (!spec.cold_start) committed = committed_start(variant, lo, hi);

  // 1. The per-κ floor over the fitted range (the limit rows are the y → 0 end of the form).
  std::vector<PerKappaShape> per(train_k.size());
  {
    std::optional<PerKappaShape> previous;
    for (std::size_t i = train_k.size(); i-- > 0;) {
      const std::vector<reference::ReferencePoint> at(
          range.begin() + static_cast<std::ptrdiff_t>(i * train_c.size()),
          range.begin() + static_cast<std::ptrdiff_t>((i + 1) * train_c.size()));
      per[i] = per_kappa_at(train_k[i], train_c, at, previous);
      previous = per[i];
    }
  }
  double floor = 0;
  for (const auto& p : per) floor = std::max(floor, p.error);

  Residuals residuals;
  for (const auto& r : train) residuals.push_back(model_residual(r));

  // 2. Start: the committed set, or the best least-squares start over s.
  Parameters params;
  for (std::size_t n = 0; n < 3; ++n)
    for (std::size_t j = 0; j < kMinSizes[n]; ++j)
      params.names.push_back(fmt::format("{}{}", kMinPolys[n], j));
  params.names.push_back("s");
  // s > 0 keeps y finite for every κ ≥ 0.
  params.lower.assign(kMinParameters, -std::numeric_limits<double>::infinity());
  params.upper.assign(kMinParameters, std::numeric_limits<double>::infinity());
  params.lower.back() = 1e-3;
  if (committed) {
    params.values = *committed;
  } else {
    const auto error_at = [&](double log_s) {
      return max_error(residuals, best_at(train, std::exp(log_s)));
    };
    // A log grid of s (0.25 … 16), then golden-section search around its best.
    int best = 0;
    std::vector<double> grid;
    for (int i = 0; i <= 16; ++i) grid.push_back(error_at(std::log(0.25) + 0.26 * i));
    best = int(std::min_element(grid.begin(), grid.end()) - grid.begin());
    double a = std::log(0.25) + 0.26 * std::max(best - 1, 0),
           b = std::log(0.25) + 0.26 * std::min(best + 1, 16);
    const double g = (std::sqrt(5.0) - 1) / 2;
    double c = b - g * (b - a), d = a + g * (b - a), fc = error_at(c), fd = error_at(d);
    while (b - a > 1e-4) {
      if (fc < fd) {
        b = d, d = c, fd = fc, c = b - g * (b - a), fc = error_at(c);
      } else {
        a = c, c = d, fc = fd, d = a + g * (b - a), fd = error_at(d);
      }
    }
    params.values = best_at(train, std::exp(fc < fd ? c : d));
  }
  const double start_error = max_error(residuals, params.values);

  // 3. Joint minimax on the runtime function.
  FitResult result = fit(residuals, params, polish_options(true));
  if (!(result.max_abs < start_error)) {
    result.values = params.values, result.max_abs = start_error;
    result.converged = true;  // the exact optimum at the searched s
  }
  const auto model = [p = min_params<double>([&](std::size_t i) { return result.values[i]; })](
                         auto c, auto k) { return irradiance_sglab_min(c, k, p); };
  const MeasuringGrids grids = measuring_grids(spec);
  const Measurements m = measure_all(model, train, grids);
  const ordered_json coefficients = coefficients_json(result.values);
  const ordered_json achieved = achieved_json(result.max_abs, floor, m, grids);

  // 4. Certificate: at the fitted s the seven coefficients enter linearly.
  std::vector<std::size_t> linear(kMinLinear);
  std::iota(linear.begin(), linear.end(), std::size_t(0));
  const std::string kind =
      "lp_at_fitted_s: the coefficients of A, B and G free, s as fitted; bound min(LP optimum, L)";
  const ordered_json certificate =
      clamped_lp_certificate(train, result.values, linear, model_residual, kind);

  FitSpec recorded = spec;
  recorded.kappa_count = kRationalTrainKappas;
  recorded.cosine_count = kRationalTrainCosines;
  FitOutcome out;
  out.converged = result.converged;
  out.constant_sets.push_back(make_constant_set(
      recorded, "sglab-min", variant, "SglabMinParams<double>", kForm, coefficients,
      fmt::format("minimax of the sglab_min irradiance peak_rel error (double) over a training "
                  "grid of {} kappa (log-midpoints of {} cells of [{}, {}]) and kappa 1e5, 1e6, "
                  "1e8, 1e20 x {} uniform cosines; start: {}",
                  kRationalTrainKappas, kRationalTrainKappas, lo, hi, kRationalTrainCosines,
                  committed ? "the committed set (polish)"
                            : "exact LP coefficients at fixed s, s by golden-section search"),
      achieved));
  out.constant_sets.back()["provenance"]["certificate"] = certificate;
  out.report = {{"target", "sglab-min"},
                {"variant", variant},
                {"converged", result.converged},
                {"start", committed ? "committed constant set" : "exact LP over s"},
                {"per_kappa_floor", floor},
                {"start_error", start_error},
                {"objective_error", result.max_abs},
                {"achieved", achieved},
                {"certificate", certificate},
                {"coefficients", coefficients},
                {"per_kappa", per_kappa_json(per)}};
  out.text = rational_fit_text("sglab-min", variant, floor, committed.has_value(), start_error,
                               result.max_abs, grids, m, certificate, "A, B and G", "s");
  return out;
}

}  // namespace sglab::fit
