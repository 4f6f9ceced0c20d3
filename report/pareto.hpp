// report/pareto.hpp — speed against accuracy: the Pareto frontier of the
// irradiance methods (`sglab pareto`) and the cheapest method meeting an
// error budget (`sglab recommend`).
//
// Error of a method over a κ range: max peak_rel over the sweep grid
// {LO, HI, 29 log-spaced κ, 41 cosines} in one precision — exactly what
// `sglab sweep --kappa LO:HI:29 --cosines 41 --method ID` reports as
// max_peak_rel — except that a method with any non-finite output on the grid
// gets error +inf (it cannot meet any budget and is never on the frontier).
// Cost: the batch ns per evaluation from the cost table that `sglab bench`
// wrote (cost_table.hpp), or measured live (measure_costs, cost.hpp).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "report/cost.hpp"
#include "report/cost_table.hpp"
#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::report {

// Costs within this fraction of each other are ties, broken by error.
inline constexpr double kCostTieMargin = 0.05;

struct MethodPoint {
  std::string method;
  Origin origin = Origin::published;  // from the registry (Method::origin)
  double ns_per_eval = 0;
  double max_peak_rel = 0;  // +inf on non-finite output, NaN if nothing was measured
  bool frontier = false;
};

// Marks the Pareto frontier in place: a point is on it iff its cost and error
// are finite and no other point with finite cost and error dominates it
// (cost ≤ and error ≤, at least one strictly). NaN/inf error: never on it.
void mark_frontier(std::vector<MethodPoint>& points);

struct Recommendation {
  double budget = 0;
  std::optional<MethodPoint> choice;         // cheapest qualifying (error ≤ budget)
  std::optional<MethodPoint> runner_up;      // next in the same ranking
  std::optional<MethodPoint> most_accurate;  // smallest finite error (ties: cheaper)
  std::vector<MethodPoint> ranked;           // every qualifying point, in ranking order
};

// Ranking of the qualifying points (finite error ≤ budget): repeatedly take
// the cheapest remaining cost C, and among the remaining points costing
// ≤ C·(1 + tie_margin) pick the one with the smallest error (then the cheaper,
// then the id). Timing noise of a few percent therefore cannot put a less
// accurate method ahead of a practically equally fast, more accurate one.
Recommendation recommend(const std::vector<MethodPoint>& points, double budget,
                         double tie_margin = kCostTieMargin);

// Max peak_rel of every irradiance method in precision `f` over the grid
// {lo, hi, 29, 41} (see above). In registry order; ns_per_eval left 0.
// Throws std::invalid_argument on an invalid range.
validate::SweepGrid pareto_grid(double kappa_lo, double kappa_hi);
std::vector<MethodPoint> irradiance_errors(double kappa_lo, double kappa_hi, validate::FloatFormat f);

// Fills ns_per_eval with the median batch cost in precision `f`
// (measure_costs, `repetitions` × `min_time` s per method): live timing,
// which differs from run to run.
void fill_costs(std::vector<MethodPoint>& points, validate::FloatFormat f, int repetitions = 5, double min_time = 0.01);

// Fills ns_per_eval from a cost table (cost_table.hpp): the irradiance batch
// cost in precision `f`. A method without that row gets NaN (so it is neither
// recommended nor on the frontier); returns the ids of those methods.
std::vector<std::string> fill_costs(std::vector<MethodPoint>& points, validate::FloatFormat f, const CostTable& table);

// method, origin, precision, kappa_lo, kappa_hi, ns_per_eval, max_peak_rel,
// frontier (origin published/refit/sglab, frontier 0/1).
validate::Table pareto_table(const std::vector<MethodPoint>& points, validate::FloatFormat f, double kappa_lo, double kappa_hi);

// Whole-string finite number.
bool parse_number(std::string_view text, double& out);
// "float" / "double".
std::optional<validate::FloatFormat> parse_precision(std::string_view text);

}  // namespace sglab::report
