// `sglab fit sglab-acc`: the sglab_acc ladder (include/sglab/sglab_acc.hpp), the
// [Tokuyoshi2024] lerp factor plus a faded even correction, members (N, D, M). Warm starts,
// the Ceres/LP alternation, the never-worse-than-tokuyoshi2024 weight, the training grid and
// the certificate: docs/models.md#sglab_acc1--sglab_acc4.
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "fit/fit_sglab_acc_family.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"

namespace sglab::fit {

namespace acc {
namespace {

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

ordered_json coefficients_json(const MemberFit& f) {
  const std::size_t k = steep_count(f.member.m), nn = f.member.n * (f.member.d + 1);
  return {{"steep", std::vector<double>(f.values.begin(), f.values.begin() + long(k))},
          {"num", std::vector<double>(f.values.begin() + long(k), f.values.begin() + long(k + nn))},
          {"scale", f.values.back()}};
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

// --max-error: the cheapest member meeting the budget, each warm-started from the previous one.
FitOutcome fit_model_order(const FitSpec& spec, const Grids& g) {
  const auto& [train, dense, measuring] = g;
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
                           weighted(dense, budget), measuring));
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
                weighted(train, rung.target), weighted(dense, rung.target), measuring,
                warm && warm->second);
    done.push_back(f);
    f.cost = member_cost(rung.member, spec.costs);
    if (!warm) f.floor = floors.floor(rung.member.n, train);
    out.converged = out.converged && f.converged;
    out.constant_sets.push_back(constant_set(spec, f, variant, measuring, rung.target));
    // A rung's constants are named as its method: sglab_acc1 … sglab_acc4.
    out.constant_sets.back()["cpp_name"] = cpp_identifier("sglab_" + variant);
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
}  // namespace acc

FitOutcome fit_sglab_acc(const FitSpec& spec) {
  if (!spec.objective.empty() && spec.objective != "peak-rel")
    throw std::invalid_argument(
        fmt::format("sglab-acc objective is 'peak-rel'; got '{}'", spec.objective));
  const acc::Grids g = acc::grids_for(spec);
  return spec.max_error ? acc::fit_model_order(spec, g) : acc::fit_ladder(spec, g);
}

}  // namespace sglab::fit
