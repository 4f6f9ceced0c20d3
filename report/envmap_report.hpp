// report/envmap_report.hpp — the selector of `sglab envmap recommend` and the
// baselines run of `sglab envmap baselines` (tables and figures).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "envmap/envmap.hpp"
#include "envmap/probe.hpp"
#include "report/pareto.hpp"
#include "validate/sweep.hpp"

namespace sglab::report {

struct EnvmapCandidate {
  std::size_t lobes = 0;
  std::string method;
  // The ranking error: max over the ranking normals and RGB of
  // |E_method(lobes) − E_map| / max E_map there.
  double error = 0;
  double cost = 0;  // the method's cost per evaluation, in cost_unit (report::MethodPoint::cost)
  std::string cost_unit;  // "cycles" (GPU inverse throughput) or "ns" (CPU)
  double total_cost = 0;  // lobes × cost: the irradiance cost of one shading point
  // The dense error on the full map (envmap::dense_error, the measure of
  // `envmap baselines --probes` and `envmap fit`), for the pairs that may meet
  // the budget (select_envmap_method); the budget is checked on its max_rel.
  std::optional<envmap::DenseError> dense;
};

// Whether the pair meets `budget`: its dense max error does (a pair not
// measured densely is above the budget at the ranking normals).
bool meets_budget(const EnvmapCandidate& c, double budget);

struct EnvmapSelection {
  std::optional<EnvmapCandidate> choice, runner_up;
  std::vector<EnvmapCandidate> tried;  // every (lobes, method) pair evaluated
  // lobes → max error with the exact SG irradiance at the ranking normals
  std::vector<std::pair<std::size_t, double>> fit_error;
  std::vector<envmap::Lobe> lobes;  // the fitted lobes of the choice's count
  std::size_t dense_normals = 0;    // the dense set's size
};

// Lobe counts tried, in order: 1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96,
// 128, 192, 256 up to max_lobes (and max_lobes itself).
std::vector<std::size_t> lobe_ladder(std::size_t max_lobes);

// Fewest lobes first: for each count of the ladder the irradiance-objective
// fit, then every method with a cost (`costs`: cost filled,
// report::MethodPoint) ranked on the full map's exact irradiance at `normals`
// Fibonacci normals. A pair whose error there (relative to the dense set's
// peak) exceeds `budget` fails it, since the max over the sphere is at least
// the max over any normals; every other pair is measured densely
// (envmap::dense_error at max(normals, envmap::kDenseNormals) Fibonacci
// normals and a local maximization from the worst) and the budget is checked
// on that. The first count at which a pair meets `budget` gives the choice
// (the cheapest there, ties within report::kCostTieMargin broken by the dense
// error) and the runner-up (the next in that ranking).
EnvmapSelection select_envmap_method(const envmap::Map& map, const envmap::Map& work, double budget,
                                     std::size_t max_lobes, std::size_t normals,
                                     io::Precision precision,
                                     const std::vector<report::MethodPoint>& costs,
                                     const std::function<void(const std::string&)>& note);

// `sglab envmap baselines`: every map in `maps` (default data/envmaps of the
// project) × lobe counts; writes envmaps.md, envmaps.csv and the figures into
// `out` (default data/results of the project). quick: 12 lobes only, no
// curves or figures (the envmap step of `sglab run --quick`).
void run_envmap_baselines(const std::string& maps, const std::string& out, bool quick);

}  // namespace sglab::report
