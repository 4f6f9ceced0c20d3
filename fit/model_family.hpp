// fit/model_family.hpp — what the fitters of sglab's own models (sglab-fast,
// fit/fit_sglab_fast.cpp; sglab-acc, fit/fit_sglab_acc.cpp) share: the two grids a
// fitted set is measured on and that no fit uses, the measurement itself (max
// peak_rel in float and double, where it is, and the per-κ rule "never worse
// than tokuyoshi2024"), its record in a constant set's provenance, the
// log-spaced κ at half-step offsets their training grids start from, the
// warm start from a committed constant set, and the LP certificate of a model
// E(1, κ)·max(0, s') whose numerators enter s' linearly (sglab-fast, sglab-mid).
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include <sglab/irradiance.hpp>

#include "fit/minimax.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit {

// The held-out grid: kHeldOutKappas κ log-spaced over [1.1·lo, 0.97·hi] ×
// kHeldOutCosines uniform cosines over [−1, 1]. Strictly inside the range, so
// it shares no κ with a training grid that holds the ends; for the default
// range it is the held-out grid of docs/models.md (`sglab sweep --kappa 1.1e-3:9.7e3:217
// --cosines 401`, data/results/heldout_sweep.json).
inline constexpr int kHeldOutKappas = 217, kHeldOutCosines = 401;
inline constexpr double kHeldOutLoFactor = 1.1, kHeldOutHiFactor = 0.97;

// Every (κ, c) of kappas × cosines, κ-major (the order `measure` expects).
std::vector<reference::Query> product_grid(const std::vector<double>& kappas,
                                           const std::vector<double>& cosines);

// The two measuring grids of a fit over [spec.kappa_lo, spec.kappa_hi], with
// the reference engine's values, and how provenance names them.
struct MeasuringGrids {
  std::vector<reference::ReferencePoint> standard, held_out;
  std::string standard_name, held_out_name;
};
// standard: spec.kappa_count log-spaced κ × spec.cosine_count cosines over
// the range (the grid of `sglab sweep`); held-out as above.
MeasuringGrids measuring_grids(const FitSpec& spec);

// κ at the log-midpoints of `count` cells of [lo, hi] (half-step offsets:
// never a point of a log-spaced measuring grid of the same range).
std::vector<double> log_midpoints(double lo, double hi, int count);

// A fitted model's errors on one grid.
struct Measured {
  double float_max = 0, double_max = 0;      // max peak_rel |Ê − E|/E(1, κ)
  double float_kappa = 0, float_cosine = 0;  // where float_max is
  // The rule "never worse than tokuyoshi2024" (float): the max over κ of the
  // model's max error over c at κ divided by max(tokuyoshi2024's there, 1e−6);
  // ≤ 1 when the rule holds. never_worse_kappa: where the max is.
  double never_worse = 0, never_worse_kappa = 0;
};

// The float peak_rel error of tokuyoshi2024 (published constants) at (κ, c),
// where the exact irradiance is `reference`.
double error_tokuyoshi2024_float(double kappa, double cosine, double reference);

// `model(c, κ)` is called with float and with double arguments (a generic
// lambda over the runtime function); `ref` comes κ-major (product_grid). A
// non-finite output counts as an infinite error.
template <class Model>
Measured measure(const Model& model, const std::vector<reference::ReferencePoint>& ref) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Measured m;
  double at_kappa = 0, base_at_kappa = 0;  // max over c at the current κ: model, tokuyoshi2024
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const auto& r = ref[i];
    const double peak = irradiance_upper(r.kappa);
    const double errd = std::abs(double(model(r.cosine, r.kappa)) - r.irradiance) / peak;
    const double errf =
        std::abs(double(model(float(r.cosine), float(r.kappa))) - r.irradiance) / peak;
    m.double_max = std::isfinite(errd) ? std::max(m.double_max, errd) : kInf;
    if (!(errf <= m.float_max))
      m.float_max = std::isfinite(errf) ? errf : kInf, m.float_kappa = r.kappa,
      m.float_cosine = r.cosine;
    at_kappa = std::isfinite(errf) ? std::max(at_kappa, errf) : kInf;
    base_at_kappa =
        std::max(base_at_kappa, error_tokuyoshi2024_float(r.kappa, r.cosine, r.irradiance));
    if (i + 1 == ref.size() || ref[i + 1].kappa != r.kappa) {
      const double ratio = at_kappa / std::max(base_at_kappa, 1e-6);
      if (!(ratio <= m.never_worse)) m.never_worse = ratio, m.never_worse_kappa = r.kappa;
      at_kappa = base_at_kappa = 0;
    }
  }
  return m;
}

// The measurement as provenance records it ("achieved"): each grid's name, its
// max peak_rel in float and double, where the held-out float max is, and the
// never-worse ratio on the held-out grid.
ordered_json measured_json(const MeasuringGrids& grids, const Measured& standard,
                           const Measured& held_out);

// The coefficients of the committed constant set data/constants/<target>-<variant>.json
// of the project around the working directory, when it exists, loads (bounded
// and strict, as every constants file) and was fitted over [lo, hi]: the warm
// start of a refit. nullopt otherwise (no project, no file, another range, a
// foreign file): the caller fits from scratch.
std::optional<ordered_json> committed_set(const std::string& target, const std::string& variant,
                                          double lo, double hi);
// Its "coefficients" object.
std::optional<ordered_json> committed_coefficients(const std::string& target,
                                                   const std::string& variant, double lo,
                                                   double hi);

// The parameter layout of the rational-shape fitters (sglab-fast,
// sglab-mid): the numerators named `numerators`, each of degree `degree`
// (lowest order first), then q₀ … q_{degree−1} of the shared monic
// denominator; their constant sets hold one array per numerator, "q" and
// "kappa_max".
struct RationalLayout {
  std::string target;  // the fit target whose committed sets these are
  std::vector<std::string> numerators;
  std::size_t degree;
  // "a0", "a1", …, "q0", …: the names of the parameters in fit order
  std::vector<std::string> parameter_names() const;
  // The coefficients object of a constant set of `values` (fit order).
  ordered_json coefficients_json(const std::vector<double>& values, double kappa_max) const;
  // The committed coefficients of `variant` over [lo, hi] in fit order, if
  // the set exists with this layout (committed_coefficients).
  std::optional<std::vector<double>> committed_start(const std::string& variant, double lo,
                                                     double hi) const;
  // The certificate of a fit in this layout (clamped_lp_certificate below):
  // the first `free_numerators` numerators free, the rest of `values` as
  // fitted. `Residual` is the fit's residual, made as Residual{κ, c, E,
  // E(1, κ), kappa_max}.
  template <class Residual>
  ordered_json lp_certificate(const std::vector<reference::ReferencePoint>& train,
                              const std::vector<double>& values, std::size_t free_numerators,
                              double kappa_max, const std::string& kind) const;
  // The joint minimax of every parameter on the training points from
  // `params` (a polish when `polish`, polish_options), with the same
  // Residual: the solver's result and the max |residual| at the start.
  struct JointFit {
    FitResult result;
    double start_error = 0;
  };
  template <class Residual>
  JointFit joint_minimax(const std::vector<reference::ReferencePoint>& train,
                         const Parameters& params, double kappa_max, bool polish) const;
  // The start of a fit from scratch (in fit order): the monic denominator
  // Q = Π(κ + r_i) with the r_i log-spaced over [lo, hi] (at the midpoints of
  // `degree` equal steps of log κ), then numerator n by the weighted linear
  // least squares of targets[n][i] ≈ N_n(κ_i)/Q(κ_i), residual i times
  // weights[n][i] (one target and weight per κ).
  std::vector<double> least_squares_start(const std::vector<double>& kappa,
                                          const std::vector<std::vector<double>>& targets,
                                          const std::vector<std::vector<double>>& weights,
                                          double lo, double hi) const;
};

// The certificate of a model Ê = E(1, κ)·max(0, s'(c, κ)) at
// its fitted nonlinear parameters, where s' is linear in the parameters
// `linear` (the numerators of the shape values that multiply fixed functions
// of c; sglab-fast: A, B, C at the fitted Q and V; sglab-mid: A, B, D at the
// fitted Q, S and V). The residual is max(0, s') − y, y = E/E(1, κ). On the
// training points with y ≥ L (= kCertificateLevel) the LP (fit/lp_minimax.hpp)
// gives the best those numerators can do for |s' − y|, LP_R; since
// |max(0, s') − y| ≥ min(|s' − y|, y) for y ≥ 0 (s' < 0 makes the error
// y ≤ |s' − y|), every member with these nonlinear parameters errs by at
// least min(LP_R, L) on those points: a lower bound for the family there; the
// fit's max there is achieved. `residual(r)` makes the fit's residual (the
// peak_rel of the runtime function, all parameters in the fit's order) at the
// training point r, where the linearization is taken at `values`. Returns the
// certificate as provenance records it: kind (`kind`), grid, achieved,
// lower_bound, within_percent_of_best_member and the LP's statistics.
inline constexpr double kCertificateLevel = 0.05;
ordered_json clamped_lp_certificate(
    const std::vector<reference::ReferencePoint>& train, const std::vector<double>& values,
    const std::vector<std::size_t>& linear,
    const std::function<std::unique_ptr<ceres::CostFunction>(const reference::ReferencePoint&)>&
        residual,
    const std::string& kind);

template <class Residual>
ordered_json RationalLayout::lp_certificate(const std::vector<reference::ReferencePoint>& train,
                                            const std::vector<double>& values,
                                            std::size_t free_numerators, double kappa_max,
                                            const std::string& kind) const {
  std::vector<std::size_t> linear(free_numerators * (degree + 1));
  std::iota(linear.begin(), linear.end(), std::size_t(0));
  return clamped_lp_certificate(
      train, values, linear,
      [&](const reference::ReferencePoint& r) {
        return make_residual(
            Residual{r.kappa, r.cosine, r.irradiance, irradiance_upper(r.kappa), kappa_max},
            values.size());
      },
      kind);
}

// The solver options of a fit from a committed set (`polish`: one reweighting
// round, then the penalty form for 10^2 … 10^5, each solve capped, to keep
// `sglab fit all` short) or from scratch (the engine's defaults).
FitOptions polish_options(bool polish);

template <class Residual>
RationalLayout::JointFit RationalLayout::joint_minimax(
    const std::vector<reference::ReferencePoint>& train, const Parameters& params, double kappa_max,
    bool polish) const {
  Residuals residuals;
  for (const auto& r : train)
    residuals.push_back(make_residual(
        Residual{r.kappa, r.cosine, r.irradiance, irradiance_upper(r.kappa), kappa_max},
        params.values.size()));
  JointFit out;
  for (double r : evaluate_residuals(residuals, params.values))
    out.start_error = std::max(out.start_error, std::abs(r));
  out.result = fit(residuals, params, polish_options(polish));
  return out;
}

// A fitted model's errors on its training grid and on the two measuring grids.
struct Measurements {
  Measured train, standard, held_out;
};
template <class Model>
Measurements measure_all(const Model& model, const std::vector<reference::ReferencePoint>& train,
                         const MeasuringGrids& grids) {
  return {measure(model, train), measure(model, grids.standard), measure(model, grids.held_out)};
}

// "achieved" of a rational-shape fit's provenance: its objective, its float
// max on the training grid, the family's per-κ floor, then measured_json.
ordered_json achieved_json(double objective, double floor, const Measurements& m,
                           const MeasuringGrids& grids);

// The summary of a rational-shape fit as `sglab fit` prints it: the floor, the
// start and joint minimax errors (training), both measuring grids and the
// certificate ("within x% of the best numerators of `numerators` at the fitted
// `fixed`").
std::string rational_fit_text(const std::string& target, const std::string& variant, double floor,
                              bool committed, double start_error, double objective,
                              const MeasuringGrids& grids, const Measurements& m,
                              const ordered_json& certificate, const std::string& numerators,
                              const std::string& fixed);
}  // namespace sglab::fit
