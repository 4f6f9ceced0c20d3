// report/probe_recommend.hpp — `sglab envmap recommend MAP --budget E --by
// storage`: the probe of fewest floats whose dense max error on the full map
// meets a budget, among the representations of envmap/probe.hpp.
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
};

struct ProbeRecommendation {
  std::vector<ProbeCandidate> tried;         // in the order tried
  std::optional<std::size_t> choice;         // index into tried
  std::optional<std::size_t> runner_up;      // the next cheapest of another representation
  std::size_t lobe_cap = 0, hybrid_cap = 0;  // the largest lobe counts the ladders fitted
};

// Candidates, each judged by envmap::dense_error on the full map with its
// lobes through the probe's method (envmap::probe_irradiance_method): SH L0 …
// L4 (projection and least squares), the non-negative L1, ZH3 (projection and
// least squares), then the lobe ladder and the SH L2 + lobes ladder
// (envmap::fit_lobe_ladder, fit_hybrid_ladder, judged by the same error) up to
// the lobe counts that can still be among the two cheapest meeting `budget`
// (at most `max_lobes`). The choice is the candidate of fewest floats with
// max error ≤ budget (ties: the smaller error), the runner-up the next such
// candidate of another representation (label). Deterministic.
ProbeRecommendation recommend_probe_by_storage(const envmap::Map& map, double budget,
                                               std::size_t max_lobes,
                                               const std::function<void(const std::string&)>& note);

}  // namespace sglab::report
