// app/costs_option.hpp — where `sglab pareto` and `sglab recommend` take
// their costs from: the cost table `sglab bench` wrote (--costs FILE, by
// default data/results/costs.json of the project holding the working
// directory), or, only when asked with --live-timing, a fresh measurement.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "report/cost_table.hpp"
#include "report/pareto.hpp"

namespace sglab::app {

struct CostsOption {
  std::string costs;  // empty: the project's data/results/costs.json
  bool live_timing = false;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--costs", costs,
                    "cost table written by `sglab bench` (default: data/results/costs.json of the project "
                    "holding the working directory)");
    cmd->add_flag("--live-timing", live_timing,
                  "time the methods now instead of reading a cost table (answers vary from run to run)");
  }

  // Fills ns_per_eval of `points`; returns a one-line description of the
  // source for the output. Missing methods are named on stderr. Throws
  // InputError (exit 2) for a missing or malformed table.
  std::string fill(std::vector<report::MethodPoint>& points, validate::FloatFormat f, int repetitions,
                   double min_time) const {
    if (live_timing) {
      if (!costs.empty()) throw InputError("--costs and --live-timing exclude each other");
      report::fill_costs(points, f, repetitions, min_time);
      return fmt::format("live timing now: median batch ns/eval of {} repetitions (varies from run to run)",
                         repetitions);
    }
    std::filesystem::path path = costs;
    if (costs.empty()) {
      const auto found = report::default_cost_table_path();
      if (!found)
        throw InputError(
            "no cost table: no project folder (with data/results and include/sglab) above the working directory; "
            "pass --costs FILE (written by `sglab bench`) or --live-timing");
      path = *found;
    }
    const report::CostTable table = report::read_cost_table(path);
    const std::vector<std::string> missing = report::fill_costs(points, f, table);
    for (const std::string& m : missing)
      fmt::print(stderr,
                 "sglab: warning: cost table {} has no irradiance/{}/batch cost for method '{}'; it is left out "
                 "(run `sglab bench` to measure it)\n",
                 path.string(), validate::to_string(f), m);
    return fmt::format("cost table {} (sglab bench, {}; {}, {} cores; {} {} {})", path.string(), table.info.date,
                       table.info.cpu, table.info.cores, table.info.compiler_id, table.info.compiler_version,
                       table.info.build_type);
  }
};

}  // namespace sglab::app
