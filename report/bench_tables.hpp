// report/bench_tables.hpp — the tables `sglab bench` writes (bench.{csv,md},
// bench_summary.{csv,md}) from the costs it measured (cost/cpu_timing.hpp).
#pragma once

#include <string>
#include <vector>

#include "cost/cpu_timing.hpp"
#include "validate/table.hpp"

namespace sglab::report {

// One row per case: kind, method, precision, mode, ns_per_eval.
validate::Table bench_table(const std::vector<cost::Cost>& costs,
                            std::string title = "Cost per evaluation (median of repetitions)");

// One row per (kind, method, precision): scalar and batch ns/eval, their
// ratio, and for methods with the per-light split the float setup ns per
// light and eval ns per shading point (empty otherwise).
validate::Table bench_summary_table(const std::vector<cost::Cost>& costs);

}  // namespace sglab::report
