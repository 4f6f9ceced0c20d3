// fit/model_family.cpp — see model_family.hpp.
#include "fit/model_family.hpp"

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "common/io.hpp"
#include "fit/constants_io.hpp"
#include "fit/lp_minimax.hpp"

namespace sglab::fit {

std::vector<reference::Query> product_grid(const std::vector<double>& kappas,
                                           const std::vector<double>& cosines) {
  std::vector<reference::Query> q;
  q.reserve(kappas.size() * cosines.size());
  for (double k : kappas)
    for (double c : cosines) q.push_back({k, c});
  return q;
}

MeasuringGrids measuring_grids(const FitSpec& spec) {
  const double lo = spec.kappa_lo, hi = spec.kappa_hi;
  const double held_lo = kHeldOutLoFactor * lo, held_hi = kHeldOutHiFactor * hi;
  auto& engine = reference::reference_engine();
  MeasuringGrids g;
  g.standard = engine.evaluate(
      product_grid(kappa_grid(lo, hi, spec.kappa_count), cosine_grid(spec.cosine_count)));
  g.held_out = engine.evaluate(
      product_grid(kappa_grid(held_lo, held_hi, kHeldOutKappas), cosine_grid(kHeldOutCosines)));
  g.standard_name = fmt::format("{} log-spaced kappa x {} uniform cosines over [{}, {}]",
                                spec.kappa_count, spec.cosine_count, lo, hi);
  g.held_out_name = fmt::format(
      "{} log-spaced kappa x {} uniform cosines over [{:g}, {:g}], never used in fitting",
      kHeldOutKappas, kHeldOutCosines, held_lo, held_hi);
  return g;
}

std::vector<double> log_midpoints(double lo, double hi, int count) {
  std::vector<double> k;
  const double a = std::log(lo), b = std::log(hi);
  for (int i = 0; i < count; ++i) k.push_back(std::exp(a + (b - a) * (i + 0.5) / count));
  return k;
}

double error_tokuyoshi2024_float(double kappa, double cosine, double reference) {
  const float e = irradiance_tokuyoshi2024(float(cosine), float(kappa));
  return std::abs(double(e) - reference) / irradiance_upper(kappa);
}

ordered_json measured_json(const MeasuringGrids& grids, const Measured& standard,
                           const Measured& held_out) {
  return {{"standard_grid", grids.standard_name},
          {"standard_max_peak_rel_float", standard.float_max},
          {"standard_max_peak_rel_double", standard.double_max},
          {"held_out_grid", grids.held_out_name},
          {"held_out_max_peak_rel_float", held_out.float_max},
          {"held_out_max_peak_rel_double", held_out.double_max},
          {"held_out_worst_float", {held_out.float_kappa, held_out.float_cosine}},
          {"held_out_never_worse_ratio", held_out.never_worse}};
}

std::optional<ordered_json> committed_set(const std::string& target, const std::string& variant,
                                          double lo, double hi) {
  const auto root = io::find_project_root(std::filesystem::current_path());
  if (!root) return std::nullopt;
  const auto path = *root / "data" / "constants" / fmt::format("{}-{}.json", target, variant);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  try {
    ordered_json set = load_constant_set(path);
    const auto& range = set.at("provenance").at("kappa_range");
    if (range.at(0).get<double>() != lo || range.at(1).get<double>() != hi) return std::nullopt;
    return set;
  } catch (const std::exception&) {
    return std::nullopt;  // a placeholder or foreign file: fit from scratch
  }
}

std::optional<ordered_json> committed_coefficients(const std::string& target,
                                                   const std::string& variant, double lo,
                                                   double hi) {
  const auto set = committed_set(target, variant, lo, hi);
  if (!set || !set->contains("coefficients")) return std::nullopt;
  return set->at("coefficients");
}

ordered_json achieved_json(double objective, double floor, const Measurements& m,
                           const MeasuringGrids& grids) {
  ordered_json achieved = {{"objective", objective},
                           {"training_max_peak_rel_float", m.train.float_max},
                           {"per_kappa_floor", floor}};
  achieved.update(measured_json(grids, m.standard, m.held_out));
  return achieved;
}

std::string rational_fit_text(const std::string& target, const std::string& variant, double floor,
                              bool committed, double start_error, double objective,
                              const MeasuringGrids& grids, const Measurements& m,
                              const ordered_json& certificate, const std::string& numerators,
                              const std::string& fixed) {
  return fmt::format(
      "{} ({}): per-kappa floor {:.4e}, {} {:.4e}, joint minimax {:.4e} (training)\n"
      "  held-out ({}): float {:.4e} (at kappa {:.4g}, c {:.4g}), double {:.4e}\n"
      "  standard ({}): float {:.4e}, double {:.4e}\n"
      "  certificate: {:.4e} on {}, within {:.2f}% of the best numerators of {} at the fitted "
      "{} ({:.4e}, LP)\n",
      target, variant, floor, committed ? "committed start" : "rational start", start_error,
      objective, grids.held_out_name, m.held_out.float_max, m.held_out.float_kappa,
      m.held_out.float_cosine, m.held_out.double_max, grids.standard_name, m.standard.float_max,
      m.standard.double_max, certificate["achieved"].get<double>(),
      certificate["grid"].get<std::string>(),
      certificate["within_percent_of_best_member"].get<double>(), numerators, fixed,
      certificate["lower_bound"].get<double>());
}

FitOptions polish_options(bool polish) {
  FitOptions options;
  if (polish) {
    options.lawson_iterations = 1;
    options.penalty_decades = 5;
    options.solver_iterations = 50;
  }
  return options;
}

ordered_json clamped_lp_certificate(
    const std::vector<reference::ReferencePoint>& train, const std::vector<double>& values,
    const std::vector<std::size_t>& linear,
    const std::function<std::unique_ptr<ceres::CostFunction>(const reference::ReferencePoint&)>&
        residual,
    const std::string& kind) {
  Residuals residuals;
  for (const auto& r : train)
    if (r.irradiance >= kCertificateLevel * irradiance_upper(r.kappa))
      residuals.push_back(residual(r));
  const LinearSubproblem sub = linear_subproblem(residuals, values, linear);
  const LpMinimaxResult lp = lp_minimax(sub.a, sub.y, Eigen::VectorXd::Ones(sub.y.size()));
  const double achieved = max_abs_residual(evaluate_residuals(residuals, values));
  const double bound = std::min(lp.lower_bound, kCertificateLevel);
  return {
      {"kind", kind},
      {"grid", fmt::format("the {} training points with E/E(1) >= L = {} (of {})", residuals.size(),
                           kCertificateLevel, train.size())},
      {"achieved", achieved},
      {"lower_bound", bound},
      {"within_percent_of_best_member", 100 * (achieved / bound - 1)},
      {"lp",
       {{"working_rows", lp.working_rows}, {"rounds", lp.rounds}, {"converged", lp.converged}}}};
}

std::vector<std::string> RationalLayout::parameter_names() const {
  std::vector<std::string> names;
  for (const std::string& poly : numerators)
    for (std::size_t j = 0; j <= degree; ++j) names.push_back(fmt::format("{}{}", poly, j));
  for (std::size_t j = 0; j < degree; ++j) names.push_back(fmt::format("q{}", j));
  return names;
}

ordered_json RationalLayout::coefficients_json(const std::vector<double>& values,
                                               double kappa_max) const {
  ordered_json coefficients;
  std::size_t i = 0;
  for (const std::string& poly : numerators) {
    coefficients[poly] = ordered_json::array();
    for (std::size_t j = 0; j <= degree; ++j) coefficients[poly].push_back(values.at(i++));
  }
  coefficients["q"] = ordered_json::array();
  for (std::size_t j = 0; j < degree; ++j) coefficients["q"].push_back(values.at(i++));
  coefficients["kappa_max"] = kappa_max;
  return coefficients;
}

std::optional<std::vector<double>> RationalLayout::committed_start(const std::string& variant,
                                                                   double lo, double hi) const {
  const auto c = committed_coefficients(target, variant, lo, hi);
  if (!c) return std::nullopt;
  std::vector<double> values;
  for (const std::string& poly : numerators) {
    if (!c->contains(poly) || c->at(poly).size() != degree + 1) return std::nullopt;
    for (const auto& x : c->at(poly)) values.push_back(x.get<double>());
  }
  if (!c->contains("q") || c->at("q").size() != degree) return std::nullopt;
  for (const auto& x : c->at("q")) values.push_back(x.get<double>());
  return values;
}

std::vector<double> RationalLayout::least_squares_start(
    const std::vector<double>& kappa, const std::vector<std::vector<double>>& targets,
    const std::vector<std::vector<double>>& weights, double lo, double hi) const {
  if (targets.size() != numerators.size() || weights.size() != numerators.size())
    throw std::invalid_argument(fmt::format("{}: {} numerators, {} targets, {} weights", target,
                                            numerators.size(), targets.size(), weights.size()));
  std::vector<double> q = {1.0};  // ascending, monic
  const double a = std::log10(lo), b = std::log10(hi);
  for (std::size_t i = 0; i < degree; ++i) {
    const double root =
        std::pow(10.0, a + (b - a) * (static_cast<double>(i) + 0.5) / static_cast<double>(degree));
    std::vector<double> next(q.size() + 1, 0.0);
    for (std::size_t j = 0; j < q.size(); ++j) next[j] += root * q[j], next[j + 1] += q[j];
    q = next;
  }
  auto Q = [&](double k) {
    double y = 0;
    for (std::size_t j = q.size(); j-- > 0;) y = y * k + q[j];
    return y;
  };
  const auto rows = static_cast<Eigen::Index>(kappa.size());
  std::vector<double> values;
  for (std::size_t n = 0; n < numerators.size(); ++n) {
    if (targets[n].size() != kappa.size() || weights[n].size() != kappa.size())
      throw std::invalid_argument(fmt::format("{}: numerator {}: {} kappas, {} targets, {} weights",
                                              target, numerators[n], kappa.size(),
                                              targets[n].size(), weights[n].size()));
    Eigen::MatrixXd M(rows, static_cast<Eigen::Index>(degree + 1));
    Eigen::VectorXd y(rows);
    for (Eigen::Index i = 0; i < rows; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const double k = kappa[u], w = weights[n][u];
      double kp = 1;
      for (Eigen::Index j = 0; j < M.cols(); ++j, kp *= k) M(i, j) = w * kp / Q(k);
      y(i) = w * targets[n][u];
    }
    // Column scaling for conditioning (κ^degree spans many decades).
    Eigen::VectorXd s = M.colwise().norm().transpose();
    for (Eigen::Index j = 0; j < s.size(); ++j) s(j) = s(j) > 0 ? 1 / s(j) : 1;
    const Eigen::VectorXd x = (M * s.asDiagonal()).colPivHouseholderQr().solve(y);
    for (Eigen::Index j = 0; j < x.size(); ++j) values.push_back(x(j) * s(j));
  }
  for (std::size_t j = 0; j < degree; ++j) values.push_back(q[j]);
  return values;
}

}  // namespace sglab::fit
