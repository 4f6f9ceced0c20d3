// fit/rational_shape_fit.hpp — the one fitter of sglab's rational-shape
// models Ê = E(1, κ)·max(0, s(c; shape values)), each shape value a rational
// P(κ)/Q(κ) over a shared monic denominator (sglab-fast, sglab-mid). A model
// configures it with its shape functor, its layout and its stage-1 solver
// (a `Shape` below); the driver runs the named steps, each warm-starting the
// next:
//   1. per κ of the training grid, the shape values that minimax the peak_rel
//      error over the training cosines — the family's floor, no model of the
//      κ dependence can do better on those points;
//   2. numerators of degree `degree` over a shared monic Q whose roots start
//      log-spaced over the κ range (−Q's roots on the negative axis, so Q > 0),
//      each numerator a linear least-squares fit to the stage-1 values;
//   3. a joint minimax of every coefficient on the peak_rel error of the
//      runtime function itself (Jets through the runtime template);
// then certified (clamped_lp_certificate, fit/model_family.hpp): at the
// fitted nonlinear parameters the first numerators enter linearly, and an LP
// bounds how well any of their values could do.
// Unless --cold-start, when the committed constant set of the same variant
// and κ range exists (data/constants/<target>-<variant>.json), steps 2 and 3
// start from it instead, with a short polish (polish_options).
// Training grid: κ at the midpoints of 56 log-spaced cells of [lo, hi] and
// 161 uniform cosines; it shares no (κ, c) point with the standard 29 × 41
// grid or with the held-out grid (fit/model_family.hpp) on which the result is
// measured (float and double) and recorded in the constant set's provenance.
//
// A `Shape` provides:
//   static const RationalLayout& layout();  the parameters and coefficients object
//                                            (its target names the runtime function, '-' as '_')
//   template <class T> using Params = …;     the runtime's parameter struct (a, …, q, kappa_max)
//   template <class T> static auto numerators(Params<T>&);  its numerator arrays, layout order
//   static auto irradiance(c, κ, const Params<…>&);          the runtime function
//   static constexpr const char* cpp_type, form;            (provenance)
//   static constexpr std::size_t certified;  the first numerators, which the certificate frees
//   static constexpr bool floor_from_committed;  a polish takes the floor its set records
//   static double start_target(std::size_t n, const PerKappaShape&);  step 2's value n
//   static double start_weight(std::size_t n, const PerKappaShape&);  and its weight
//   static PerKappaShape per_kappa_at(κ, cosines, ref at κ, previous optimum or nullopt);
#pragma once

#include <algorithm>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <sglab/irradiance.hpp>

#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit {

inline constexpr int kRationalTrainKappas = 56, kRationalTrainCosines = 161;

// The stage-1 optimum at one κ: the shape values in layout order and the max
// peak_rel they reach over the training cosines.
struct PerKappaShape {
  double kappa;
  std::vector<double> shape;
  double error;
};

// The runtime parameters of `Shape` at the values value(0), value(1), … in fit
// order: each numerator (layout order) lowest coefficient first, then Q's
// lower coefficients (Q monic: one fewer than a numerator's), then kappa_max.
template <class Shape, class T, class Value>
typename Shape::template Params<T> rational_params(Value value, T kappa_max) {
  typename Shape::template Params<T> p{};
  const std::size_t degree = std::size(p.q);
  std::size_t i = 0;
  for (T* numerator : Shape::numerators(p))
    for (std::size_t j = 0; j <= degree; ++j) numerator[j] = value(i++);
  for (std::size_t j = 0; j < degree; ++j) p.q[j] = value(i++);
  p.kappa_max = kappa_max;
  return p;
}

// Step 3's residual: peak_rel of the runtime function at one (κ, c), every
// coefficient a parameter (fit order).
template <class Shape>
struct RationalModelResidual {
  double kappa, cosine, reference, peak, kappa_max;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const auto params =
        rational_params<Shape>([p](std::size_t i) { return p[i][0]; }, T(kappa_max));
    r[0] = (Shape::irradiance(T(cosine), T(kappa), params) - T(reference)) / T(peak);
    return true;
  }
};

// The runtime function at `values` (fit order): a generic callable (c, κ) → Ê.
template <class Shape>
auto rational_model(const std::vector<double>& values, double kappa_max) {
  return [p = rational_params<Shape>([&values](std::size_t i) { return values[i]; }, kappa_max)](
             auto c, auto k) { return Shape::irradiance(c, k, p); };
}

// The words of the certificate at the fitted denominator, from the layout:
// the first `certified` numerators free, Q and the others as fitted.
struct CertificateTexts {
  std::string free;   // "A, B, C"
  std::string fixed;  // "Q and V"
  std::string kind;   // "lp_at_fitted_denominator_and_v: the numerators of A, B and C free, …"
};
CertificateTexts certificate_texts(const RationalLayout& layout, std::size_t certified);

// The reference engine's irradiance on kappas × cosines, κ-major.
std::vector<reference::ReferencePoint> rational_reference_grid(const std::vector<double>& kappas,
                                                               const std::vector<double>& cosines);

// The per-κ floor recorded in the committed set of `target`/`variant` over [lo, hi], if any.
std::optional<double> committed_floor(const std::string& target, const std::string& variant,
                                      double lo, double hi);

// The stage-1 table as the report prints it: [κ, shape values…, error] per κ.
ordered_json per_kappa_json(const std::vector<PerKappaShape>& per);

// Step 1 over the training κ, from the largest down, each κ started from the
// previous κ's optimum.
template <class Shape>
std::vector<PerKappaShape> per_kappa_optimum(const std::vector<double>& kappas,
                                             const std::vector<double>& cosines,
                                             const std::vector<reference::ReferencePoint>& ref) {
  std::vector<PerKappaShape> out(kappas.size());
  std::optional<PerKappaShape> previous;
  for (std::size_t i = kappas.size(); i-- > 0;) {
    const std::vector<reference::ReferencePoint> at(
        ref.begin() + static_cast<std::ptrdiff_t>(i * cosines.size()),
        ref.begin() + static_cast<std::ptrdiff_t>((i + 1) * cosines.size()));
    out[i] = Shape::per_kappa_at(kappas[i], cosines, at, previous);
    previous = out[i];
  }
  return out;
}

// Step 2: each numerator over the log-spaced Q by weighted linear least
// squares on the stage-1 values (Shape::start_target, Shape::start_weight).
template <class Shape>
std::vector<double> rational_start(const std::vector<PerKappaShape>& per, double lo, double hi) {
  const std::size_t values = Shape::layout().numerators.size();
  std::vector<double> kappa;
  std::vector<std::vector<double>> targets(values), weights(values);
  for (const PerKappaShape& p : per) {
    kappa.push_back(p.kappa);
    for (std::size_t n = 0; n < values; ++n) {
      targets[n].push_back(Shape::start_target(n, p));
      weights[n].push_back(Shape::start_weight(n, p));
    }
  }
  return Shape::layout().least_squares_start(kappa, targets, weights, lo, hi);
}

// The driver: steps 1–3, the measurements, the certificate, the constant set and the report.
template <class Shape>
FitOutcome fit_rational_shape(const FitSpec& spec) {
  const RationalLayout& layout = Shape::layout();
  if (!spec.objective.empty() && spec.objective != "irradiance")
    throw std::invalid_argument(fmt::format("{} has the one objective 'irradiance'; got '{}'",
                                            layout.target, spec.objective));
  const double lo = spec.kappa_lo, hi = spec.kappa_hi;
  const auto train_k = log_midpoints(lo, hi, kRationalTrainKappas);
  const auto train_c = cosine_grid(kRationalTrainCosines);
  const auto train = rational_reference_grid(train_k, train_c);

  const std::string variant = std::string(io::to_string(spec.precision)) +
                              (spec.kappa_range_given ? fmt::format("-k{}-{}", lo, hi) : "");
  std::optional<std::vector<double>> committed;
  if (!spec.cold_start) committed = layout.committed_start(variant, lo, hi);

  // 1. Per-κ floor (a polish may take the one its committed set records).
  const std::optional<double> recorded_floor = Shape::floor_from_committed && committed
                                                   ? committed_floor(layout.target, variant, lo, hi)
                                                   : std::nullopt;
  std::vector<PerKappaShape> per;
  double floor = 0;
  if (recorded_floor) {
    floor = *recorded_floor;
  } else {
    per = per_kappa_optimum<Shape>(train_k, train_c, train);
    for (const auto& p : per) floor = std::max(floor, p.error);
  }

  // 2. Rational start (or the committed set).
  Parameters params;
  params.names = layout.parameter_names();
  params.values = committed ? *committed : rational_start<Shape>(per, lo, hi);

  // 3. Joint minimax on the runtime function.
  using Residual = RationalModelResidual<Shape>;
  const auto [result, start_error] =
      layout.template joint_minimax<Residual>(train, params, hi, committed.has_value());
  const MeasuringGrids grids = measuring_grids(spec);
  const Measurements m = measure_all(rational_model<Shape>(result.values, hi), train, grids);
  const ordered_json coefficients = layout.coefficients_json(result.values, hi);
  const ordered_json achieved = achieved_json(result.max_abs, floor, m, grids);

  // 4. Certificate.
  const CertificateTexts texts = certificate_texts(layout, Shape::certified);
  const ordered_json certificate = layout.template lp_certificate<Residual>(
      train, result.values, Shape::certified, hi, texts.kind);

  FitSpec recorded = spec;
  recorded.kappa_count = kRationalTrainKappas;
  recorded.cosine_count = kRationalTrainCosines;
  FitOutcome out;
  out.converged = result.converged;
  out.constant_sets.push_back(make_constant_set(
      recorded, layout.target, variant, Shape::cpp_type, Shape::form, coefficients,
      fmt::format("minimax of the {} irradiance peak_rel error (double) over a training "
                  "grid of {} kappa (log-midpoints of {} cells of [{}, {}]) x {} uniform cosines; "
                  "start: {}",
                  cpp_identifier(layout.target), kRationalTrainKappas, kRationalTrainKappas, lo, hi,
                  kRationalTrainCosines,
                  committed ? "the committed set (polish)"
                            : "per-kappa optimum, then rational least squares"),
      achieved));
  out.constant_sets.back()["provenance"]["certificate"] = certificate;
  out.report = {{"target", layout.target},
                {"variant", variant},
                {"converged", result.converged},
                {"start", committed ? "committed constant set" : "rational least squares"},
                {"per_kappa_floor", floor}};
  if (Shape::floor_from_committed)
    out.report["per_kappa_floor_source"] =
        recorded_floor ? "the committed set's provenance (measured on --cold-start)"
                       : "measured (stage 1)";
  out.report["start_error"] = start_error;
  out.report["objective_error"] = result.max_abs;
  out.report["achieved"] = achieved;
  out.report["certificate"] = certificate;
  out.report["coefficients"] = coefficients;
  out.report["per_kappa"] = per_kappa_json(per);
  out.text = rational_fit_text(layout.target, variant, floor, committed.has_value(), start_error,
                               result.max_abs, grids, m, certificate, texts.free, texts.fixed);
  return out;
}

}  // namespace sglab::fit
