// app/costs_option.hpp — where `sglab pareto` and `sglab recommend` take
// their costs from: a cost source (--cost gpu:FAMILY | cpu-batch | cpu-scalar,
// cost/cost_source.hpp; default gpu:navi21, cpu-batch under --precision
// double) of the cost table that `sglab bench` and `sglab gpucost` wrote
// (--costs FILE, by default data/results/costs.json of the project holding the
// working directory), or, only when asked with --live-timing, CPU ns measured
// now.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "cost/cost_source.hpp"
#include "cost/cost_table.hpp"
#include "report/pareto.hpp"

namespace sglab::app {

struct CostsOption {
  std::string costs;  // empty: the project's data/results/costs.json
  // when --cost is not given: cost::default_cost_source (cpu-batch with --live-timing)
  std::string cost;
  bool live_timing = false;
  // whether --cost was given (an empty value is refused, not the default)
  CLI::Option* cost_option = nullptr;

  void add_to(CLI::App* cmd) {
    cost_option = cmd->add_option(
        "--cost", cost,
        "speed axis: gpu:FAMILY (GPU cycles per light per pixel on that RADV family: ACO's "
        "inverse throughput of the GLSL export in an 8-light per-pixel loop, split where the "
        "method has one; from `sglab gpucost`), gpu-single:FAMILY (the same for one unsplit "
        "call), cpu-batch or cpu-scalar (ns/eval; from `sglab bench`). Default gpu:navi21; "
        "cpu-batch under --precision double or --live-timing");
    add_path_option(cmd, "--costs", costs,
                    "cost table written by `sglab bench` and `sglab gpucost` (default: "
                    "data/results/costs.json of the project holding the working directory; "
                    "outside a checkout, the one compiled into sglab)");
    cmd->add_flag("--live-timing", live_timing,
                  "time the methods on this CPU now instead of reading a cost table (answers vary "
                  "from run to run)");
  }

  // The chosen source (parsed once); throws InputError (exit 2) naming --cost.
  cost::CostSource source(io::Precision f) const {
    if (!cost_option || cost_option->count() == 0)
      return live_timing ? cost::CostSource{cost::CostSourceKind::cpu_batch, {}}
                         : cost::default_cost_source(f);
    const auto parsed = cost::parse_cost_source(cost);
    if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--cost: " + *why);
    const auto& s = std::get<cost::CostSource>(parsed);
    if (s.kind == cost::CostSourceKind::gpu && f != io::Precision::float32)
      throw InputError(
          fmt::format("--cost {}: the GPU cost is that of the float shader export; use --precision "
                      "float, or --cost cpu-batch / cpu-scalar",
                      s.name()));
    if (s.kind == cost::CostSourceKind::gpu && live_timing)
      throw InputError(fmt::format(
          "--cost {} and --live-timing exclude each other (live timing is CPU ns)", s.name()));
    return s;
  }

  // Where the costs came from: `text` for the output (what, file, driver or
  // machine), `provenance` the driver or machine alone (no path, for files
  // that are kept, e.g. pareto.md).
  struct From {
    std::string text, provenance;
  };

  // Fills cost and cost_unit of `points` from source(f); returns where they
  // came from (the file, or kBuiltinCostTableName). A method without a cost
  // there is named on stderr and keeps NaN ("no cost"). Throws InputError
  // (exit 2) for a bad --cost, a missing or malformed table, or a table
  // without the source (no gpu section, family absent).
  From fill(std::vector<report::MethodPoint>& points, io::Precision f, int repetitions,
            double min_time) const {
    const cost::CostSource s = source(f);
    if (live_timing) {
      if (!costs.empty()) throw InputError("--costs and --live-timing exclude each other");
      report::fill_costs(points, f, s.cpu_mode(), repetitions, min_time);
      const std::string provenance = fmt::format(
          "live timing now: median of {} repetitions (varies from run to run)", repetitions);
      return {fmt::format("{}, {}", s.describe(), provenance), provenance};
    }
    cost::CostTable table;
    if (!costs.empty())
      table = cost::read_cost_table(costs);
    else if (const auto found = cost::default_cost_table_path())
      table = cost::read_cost_table(*found);
    else
      table = cost::builtin_cost_table();  // outside a checkout
    const std::filesystem::path& path = table.path;
    const std::vector<std::string> missing = report::fill_costs(points, f, table, s);
    for (const std::string& m : missing)
      fmt::print(
          stderr,
          "sglab: warning: cost table {} has no {} cost for method '{}' ({}); it is listed as \"no "
          "cost\" and left out of the ranking (run `sglab {}` to measure it)\n",
          path.string(), s.name(), m,
          s.kind == cost::CostSourceKind::gpu
              ? (s.figure == cost::GpuFigure::single ? "GLSL, float, one call"
                                                     : "GLSL, float, 8-light loop")
              : io::to_string(f),
          s.kind == cost::CostSourceKind::gpu ? "gpucost" : "bench");
    const std::string provenance =
        s.kind == cost::CostSourceKind::gpu
            ? fmt::format("sglab gpucost, {}; a compiler estimate, not a timing", table.gpu->driver)
            : fmt::format("sglab bench, {}; {}, {} cores; {} {} {}", table.info.date,
                          table.info.cpu, table.info.cores, table.info.compiler_id,
                          table.info.compiler_version, table.info.build_type);
    return {fmt::format("{} from cost table {} ({})", s.describe(), path.string(), provenance),
            provenance};
  }
};

}  // namespace sglab::app
