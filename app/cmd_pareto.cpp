// `sglab pareto`: speed against accuracy of every irradiance method (published
// and refit ids alike) in one precision over a κ range. Cost: --cost
// gpu:FAMILY (ACO's inverse throughput, cycles; default gpu:navi21), cpu-batch
// or cpu-scalar (ns/eval) from the cost table (--costs; data/results/costs.json
// by default), or CPU ns timed now with --live-timing (app/costs_option.hpp); error:
// max peak_rel over 29 log-spaced κ × 41 cosines on [LO, HI] (the sweep, so it
// equals `sglab sweep --kappa LO:HI:29 --cosines 41`; +inf when the method
// has non-finite outputs there). Marks the Pareto frontier and writes
// pareto.csv / pareto.md into --out; prints the Markdown table.
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "app/costs_option.hpp"
#include "common/args.hpp"
#include "report/pareto.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {

struct ParetoArgs {
  std::string kappa = "1e-3:1e4";
  std::string precision = "float";
  std::string out = "out/pareto";
  CostsOption costs;
};

}  // namespace

void add_pareto_command(CLI::App& app) {
  auto args = std::make_shared<ParetoArgs>();
  auto* cmd =
      app.add_subcommand("pareto",
                         "Cost (GPU cycles or CPU ns/eval, --cost) against max peak_rel of every "
                         "irradiance method, with the Pareto frontier");
  cmd->footer(
      "peak_rel = |Ê − E| / E(1, κ), the irradiance error relative to the lobe's peak "
      "(docs/quantities.md)");
  cmd->add_option("--kappa", args->kappa, "κ range LO:HI")->capture_default_str();
  cmd->add_option("--precision", args->precision, "float or double")->capture_default_str();
  add_path_option(cmd, "--out", args->out, "output directory")->capture_default_str();
  args->costs.add_to(cmd);
  cmd->callback([args] {
    double lo = 0, hi = 0;
    {
      // LO:HI, float
      const auto parsed = io::parse_kappa_range(args->kappa, io::KappaRangeRules{});
      if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--kappa: " + *why);
      lo = std::get<io::KappaRange>(parsed).lo;
      hi = std::get<io::KappaRange>(parsed).hi;
    }
    const auto precision = io::parse_option("--precision", args->precision,
                                            {io::Precision::float32, io::Precision::float64});

    // The (multi-threaded) reference sweep runs first; the single-threaded
    // timing afterwards, when its worker threads are idle.
    // a bad --cost before the sweep
    const cost::CostSource cost = args->costs.source(precision);
    std::vector<report::MethodPoint> points = report::irradiance_errors(lo, hi, precision);
    const CostsOption::From source =
        args->costs.fill(points, precision, /*repetitions=*/5, /*min_time=*/0.01);
    report::mark_frontier(points);

    const validate::Table table =
        report::pareto_table(points, precision, lo, hi, cost, source.provenance);
    const std::filesystem::path dir(args->out);
    using validate::TableFormat;
    validate::write_table(table, dir, "pareto", {TableFormat::csv, TableFormat::markdown});
    fmt::print("{}\nCost (--cost {}, in {}): {}\nWritten to {}: pareto.{{csv,md}}\n",
               validate::to_markdown(table), cost.name(), cost.unit(), source.text, dir.string());
  });
}

}  // namespace sglab::app
