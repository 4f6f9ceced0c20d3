// report/pareto.hpp — speed against accuracy: the Pareto frontier of the
// irradiance methods (`sglab pareto`) and the cheapest method meeting an
// error budget (`sglab recommend`).
//
// Error of a method over a κ range: max peak_rel over the sweep grid
// {LO, HI, 29 log-spaced κ, 41 cosines} in one precision — exactly what
// `sglab sweep --kappa LO:HI:29 --cosines 41 --method ID` reports as
// max_peak_rel — except that a method with any non-finite output on the grid
// gets error +inf (it cannot meet any budget and is never on the frontier).
// Cost: from a cost source (cost/cost_source.hpp: gpu:FAMILY inverse throughput in
// cycles, cpu-batch or cpu-scalar ns per evaluation) of the cost table that
// `sglab bench` and `sglab gpucost` wrote (cost/cost_table.hpp), or CPU ns measured
// live (cost::measure_costs, cost/cpu_timing.hpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cost/cost_source.hpp"
#include "cost/cost_table.hpp"
#include "cost/cpu_timing.hpp"
#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::report {

// Costs within this fraction of each other are ties, broken by error.
inline constexpr double kCostTieMargin = 0.05;

struct MethodPoint {
  std::string method;
  Origin origin = Origin::published;  // from the registry (Method::origin)
  double cost = 0;                    // in cost_unit; NaN: no cost in the chosen source
  std::string cost_unit = "ns";       // CostSource::unit(): "cycles" or "ns"
  // Which GPU figure the cost is: "8-light loop (split)", "8-light loop (kappa
  // per light)" (gpu:FAMILY, gpu::renderer_form) or "single call"
  // (gpu-single:FAMILY); empty for CPU costs and methods without a cost.
  std::string cost_form{};
  double max_peak_rel = 0;  // +inf on non-finite output, NaN if nothing was measured
  bool frontier = false;
  // Whether every κ asked about lies in the method's valid range (its registry
  // card, sglab::ValidRange; mark_valid_range): outside it the method's stated
  // bound does not hold, so the point is listed and flagged but never
  // recommended nor on the frontier.
  bool in_valid_range = true;
};

// Sets each point's in_valid_range: whether [kappa_lo, kappa_hi] lies in the
// valid range on its method's registry card (false for an id not registered).
void mark_valid_range(std::vector<MethodPoint>& points, double kappa_lo, double kappa_hi);

// The ids of the points outside their valid range, each with its range:
// "sglab_fast (valid for κ in [0, 1.1e+04])", joined by ", "; empty when none.
std::string outside_valid_range_text(const std::vector<MethodPoint>& points);

// "83.6 cycles, 8-light loop (split)", "15.1 ns" (3 significant digits, then
// the GPU figure's form unless `with_form` is false, for a table that gives it
// a column of its own), or "no cost" when the cost is not finite: how every
// text output shows a point's cost.
std::string cost_text(const MethodPoint& p, bool with_form = true);

// Marks the Pareto frontier in place: a point is on it iff its cost and error
// are finite, it is in its valid range, and no other such point dominates it
// (cost ≤ and error ≤, at least one strictly). NaN/inf error: never on it.
void mark_frontier(std::vector<MethodPoint>& points);

struct Recommendation {
  double budget = 0;
  std::optional<MethodPoint> choice;         // cheapest qualifying (error ≤ budget)
  std::optional<MethodPoint> runner_up;      // next in the same ranking
  std::optional<MethodPoint> most_accurate;  // smallest finite error (ties: cheaper)
  std::vector<MethodPoint> ranked;           // every qualifying point, in ranking order
};

// Ranking of the qualifying points (finite error ≤ budget, in their valid
// range; most_accurate is taken among those in range too): repeatedly take
// the cheapest remaining cost C, and among the remaining points costing
// ≤ C·(1 + tie_margin) pick the one with the smallest error (then the cheaper,
// then the id). Timing noise of a few percent therefore cannot put a less
// accurate method ahead of a practically equally fast, more accurate one.
Recommendation recommend(const std::vector<MethodPoint>& points, double budget,
                         double tie_margin = kCostTieMargin);

// Max peak_rel of every irradiance method in precision `f` over the grid
// {lo, hi, 29, 41} (see above), with in_valid_range marked for [lo, hi]. In
// registry order; cost left 0.
// Throws std::invalid_argument on an invalid range.
validate::SweepGrid pareto_grid(double kappa_lo, double kappa_hi);
std::vector<MethodPoint> irradiance_errors(double kappa_lo, double kappa_hi, io::Precision f);

// Fills cost (ns) with the median CPU cost in precision `f` and `mode` (batch
// or scalar; measure_costs, `repetitions` × `min_time` s per method): live
// timing, which differs from run to run.
void fill_costs(std::vector<MethodPoint>& points, io::Precision f, cost::CostMode mode,
                int repetitions = 5, double min_time = 0.01);

// The row of the gpu section a GPU source reads for `method`
// (gpu::renderer_row for gpu:FAMILY, gpu::single_row for gpu-single:FAMILY),
// or nullptr; and its cost in cycles (per light: gpu::cycles_per_light).
const cost::gpu::Row* gpu_row(const cost::gpu::Report& report, std::string_view method,
                              const cost::CostSource& source);
double gpu_cost(const cost::gpu::Row& row);

// Fills cost, cost_unit and cost_form from a cost table (cost/cost_table.hpp) in
// `source`: cpu-*: the irradiance batch/scalar ns of precision `f`;
// gpu:FAMILY, gpu-single:FAMILY: gpu_cost of gpu_row (the shaders are float:
// f must be float). A method without its row gets NaN ("no cost": it is
// listed but neither recommended nor on the frontier); returns the ids of
// those methods. Throws CostTableError naming the table when the source has no
// rows at all (no "gpu" section, no row of the figure on FAMILY: the families
// it has are named), std::invalid_argument for gpu:* with f double.
std::vector<std::string> fill_costs(std::vector<MethodPoint>& points, io::Precision f,
                                    const cost::CostTable& table, const cost::CostSource& source);

// Every irradiance method's float cost in `table`, in the default source
// (gpu:navi21, default_cost_source) when the table has GPU rows for it, else
// in cpu-batch: the source used, and method id → cost (a method without a row
// is left out). What `sglab fit sglab-acc` puts in its cost column.
struct MethodCostMap {
  cost::CostSource source;
  std::map<std::string, double> cost;
};
MethodCostMap default_float_costs(const cost::CostTable& table);

// method, origin, precision, kappa_lo, kappa_hi, cost, cost_unit, cost_source,
// cost_form, max_peak_rel, frontier, in_valid_range (origin
// published/refit/sglab, frontier and in_valid_range 0/1, cost_source
// CostSource::name(), cost_form MethodPoint::cost_form); the title names the
// source and, when given, where its costs came from (`cost_from`: table,
// driver or machine), and the methods outside their valid range.
validate::Table pareto_table(const std::vector<MethodPoint>& points, io::Precision f,
                             double kappa_lo, double kappa_hi, const cost::CostSource& source,
                             std::string_view cost_from = {});

// Parses `sglab pareto`'s CSV (RFC 4180; header
// method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,cost_form,max_peak_rel,
// frontier and optionally in_valid_range; origin is published, refit or sglab,
// frontier and in_valid_range true/false or 1/0, in_valid_range true when
// absent; cost_form may be absent).
struct ParetoRow {
  std::string method, precision;
  Origin origin = Origin::published;
  double kappa_lo = 0, kappa_hi = 0, cost = 0, max_peak_rel = 0;
  std::string cost_unit = "ns", cost_source = "cpu-batch", cost_form;
  bool frontier = false;
  bool in_valid_range = true;
};
// The largest Pareto CSV read (io::read_input_file); `sglab pareto` writes a few KB.
inline constexpr std::size_t kMaxParetoCsvBytes = 16 << 20;
std::vector<ParetoRow> read_pareto_csv(const std::filesystem::path& path);

}  // namespace sglab::report
