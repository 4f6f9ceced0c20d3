// report/probe_recommend.hpp — `sglab envmap recommend MAP --budget E --by
// storage|gpu:FAMILY`: the cheapest probe whose dense max error on the full
// map meets a budget, among the representations of envmap/probe.hpp, cheapest
// by stored floats or by a cost the caller measures (the GPU's, app/).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "envmap/probe.hpp"

namespace sglab::report {

struct ProbeCandidate {
  std::string family;  // "SH projection", "SH fit", "ZH3 fit", "SG lobes", "SH L2 + SG lobes", ...
  envmap::Probe probe;
  envmap::DenseError error;  // lobes through the probe's method, as exported
  // By cost: the measured cost of the candidates meeting the budget (nullopt
  // for the others, and by storage).
  std::optional<double> cost;
};

struct ProbeRecommendation {
  std::vector<ProbeCandidate> tried;         // in the order tried
  std::optional<std::size_t> choice;         // index into tried
  std::optional<std::size_t> runner_up;      // the next cheapest of another representation
  std::size_t lobe_cap = 0, hybrid_cap = 0;  // the largest lobe counts the ladders fitted
};

// The same irradiance function: equal kind, order, SH, zonal term, method and
// lobes once the lobes of zero amplitude are left out (a ladder's "kept n-1"
// step is its n − 1 solution plus such a lobe).
bool same_probe_function(const envmap::Probe& a, const envmap::Probe& b);

// Candidates, each judged by envmap::dense_error on the full map with its
// lobes through the probe's method (envmap::probe_irradiance_method): SH L0 …
// L4 (projection and least squares), the non-negative L1, ZH3 (projection and
// least squares), then the lobe ladder and the SH L2 + lobes ladder
// (envmap::fit_lobe_ladder, fit_hybrid_ladder, judged by the same error) up to
// the lobe counts that can still be among the two cheapest meeting `budget`
// (at most `max_lobes`): the lobe ladder, below the floats of SH's runner-up,
// from 4 counts, doubling, until a count meeting the budget is followed by
// another (a later count has more floats; one of another function meeting the
// budget bounds the runner-up, one of the same function means the fits found
// nothing better), as recommend_probe_by_cost does; the hybrid below the
// runner-up's floats then. The choice is the candidate of fewest floats with
// max error ≤ budget (ties: the smaller error), the runner-up the next such
// candidate of another representation: another label, and not the choice's
// function (same_probe_function). `restarts`: the lobe ladder's
// (envmap::fit_lobe_ladder). Deterministic.
ProbeRecommendation recommend_probe_by_storage(const envmap::Map& map, double budget,
                                               std::size_t max_lobes,
                                               const std::function<void(const std::string&)>& note,
                                               int restarts = 0);

// The cost of each probe, in the order given (by the GPU: ACO's inverse
// throughput of its exported evaluation per shading point).
using ProbeCosts = std::function<std::vector<double>(const std::vector<const envmap::Probe*>&)>;

// The same candidates, the choice the one of least `cost` meeting the budget
// (ties: the smaller error, then the order tried), the runner-up the next
// of another representation as above. Only the candidates meeting the budget
// are costed, in one call. Each lobe adds a call of the method to the probe's
// evaluation, so a ladder (from 4 counts, doubling, at most `max_lobes`; the
// hybrid at most the lobe ladder's length) is fitted until two counts of
// different functions meet the budget (a larger count costs at least as much
// as either: measured along both ladders on navi21 by
// tests/test_probe_recommend.cpp, LadderCostGrowsWithTheLobeCount, not a
// bound), or until the counts after the first meeting one only add lobes of
// zero amplitude to it.
ProbeRecommendation recommend_probe_by_cost(const envmap::Map& map, double budget,
                                            std::size_t max_lobes, const ProbeCosts& cost,
                                            const std::function<void(const std::string&)>& note,
                                            int restarts = 0);

}  // namespace sglab::report
