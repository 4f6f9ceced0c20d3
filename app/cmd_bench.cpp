// `sglab bench`: ns per evaluation of every irradiance method, hemispherical
// method and erf variant, float and double, scalar and batch (and, for methods
// with the per-light split, float setup ns per light and eval ns per shading
// point), timed with Google Benchmark inside the process (one thread,
// wall-clock time, the median of --repetitions; cost/benchmark_runner.hpp).
// The cases and the workload are cost/cpu_timing.hpp's: 2^20 inputs, κ
// log-uniform in [1e-3, 1e4], c uniform in [-1, 1] (erf: x uniform in
// [0, 4]), fixed seed; "scalar" calls the registry function pointer once per
// element, "batch" calls the batch pointer once over all inputs.
// Writes into --out: bench.csv and bench.md (every case), bench_summary.csv/.md
// (one row per method and precision: scalar, batch, batch speed-up, setup,
// eval) and costs.json, the cost table `sglab pareto` and `sglab recommend`
// read (cost/cost_table.hpp). --json prints the table as JSON.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "cost/benchmark_runner.hpp"
#include "cost/cost_table.hpp"
#include "report/bench_tables.hpp"
#include "validate/table.hpp"

namespace sglab::app {

namespace {

struct BenchArgs {
  bool json = false;
  std::string out = "out/bench";
  int repetitions = 5;
  std::string filter;
  double min_time = 0.05;
  std::string command_line;  // as recorded in costs.json
};

// The cases --filter selects (all without one).
std::vector<cost::CostCase> selected_cases(const BenchArgs& args,
                                           const std::shared_ptr<cost::CostWorkload>& workload) {
  std::regex filter;
  try {
    if (!args.filter.empty()) filter = std::regex(args.filter);
  } catch (const std::regex_error& e) {
    throw InputError(
        fmt::format("--filter: '{}' is not a valid regex ({})", args.filter, e.what()));
  }
  std::vector<cost::CostCase> cases;
  for (auto& c : cost::cost_cases(workload))
    if (args.filter.empty() || std::regex_search(c.name(), filter)) cases.push_back(std::move(c));
  if (cases.empty()) throw InputError(fmt::format("--filter: '{}' matches no case", args.filter));
  return cases;
}

// Writes bench.{csv,md}, bench_summary.{csv,md} and costs.json (keeping the
// GPU section `sglab gpucost` wrote) and prints the tables.
void write_bench(const BenchArgs& args, const cost::BenchmarkTimings& t,
                 const std::optional<cost::gpu::Report>& kept_gpu_costs) {
  const std::filesystem::path dir(args.out);
  const std::string timer = fmt::format(
      "Google Benchmark, 1 thread, wall-clock, median of {} repetitions x {} s, repetitions of all "
      "cases interleaved in random order; scalar = registry "
      "function pointer per element, batch = batch pointer over all inputs, light_setup = ns per "
      "light, light_eval = ns per shading point",
      args.repetitions, args.min_time);
  const validate::Table table = report::bench_table(
      t.costs, fmt::format("ns per evaluation ({}; {})", timer, cost::cost_input_description()));
  const validate::Table summary = report::bench_summary_table(t.costs);

  cost::CostTable cost_table;
  cost_table.info = cost::current_cost_table_info();
  cost_table.info.command = args.command_line;
  cost_table.info.timer = timer;
  cost_table.info.inputs = cost::cost_input_description();
  cost_table.info.load_start = t.load_start;
  cost_table.info.load_end = t.load_end;
  cost_table.costs = t.costs;
  cost_table.gpu = kept_gpu_costs;
  using validate::TableFormat;
  validate::write_table(table, dir, "bench", {TableFormat::csv, TableFormat::markdown});
  validate::write_table(summary, dir, "bench_summary", {TableFormat::csv, TableFormat::markdown});
  cost::write_cost_table(cost_table, dir / "costs.json");
  if (args.json) {
    fmt::print("{}\n", validate::to_json(table).dump(2));
    return;
  }
  fmt::print(
      "{}\n{}\nMachine: {}, {} cores; {} {} {}; 1-min load average {:.2f} at start, {:.2f} at "
      "end\n",
      validate::to_markdown(summary), validate::to_markdown(table), cost_table.info.cpu,
      cost_table.info.cores, cost_table.info.compiler_id, cost_table.info.compiler_version,
      cost_table.info.build_type, t.load_start, t.load_end);
  fmt::print("Written to {}: bench.{{csv,md}}, bench_summary.{{csv,md}}, costs.json\n",
             dir.string());
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand("bench",
                                 "ns per evaluation of every method and erf variant (float/double, "
                                 "scalar/batch), Google Benchmark");
  cmd->add_flag("--json", args->json, "print the table as JSON on stdout");
  add_path_option(cmd, "--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--repetitions", args->repetitions,
                  "repetitions per case; the median is reported")
      ->check(count_in(1, std::numeric_limits<int>::max()))
      ->capture_default_str();
  cmd->add_option("--filter", args->filter,
                  "ECMAScript regex searched in kind/method/precision/mode");
  cmd->add_option("--min-time", args->min_time, "seconds per repetition")->capture_default_str();
  cmd->callback([args, cmd] {
    args->command_line = "sglab bench";
    for (const CLI::Option* o : cmd->get_options()) {
      if (o->count() == 0 || o->get_name() == "--help") continue;
      args->command_line += " " + o->get_name();
      if (o->get_type_size_min() > 0)
        for (const std::string& r : o->results()) args->command_line += " " + r;
    }
    if (args->repetitions < 1)
      throw InputError(fmt::format("--repetitions: must be >= 1, got {}", args->repetitions));
    if (!(args->min_time > 0) || !(args->min_time <= 10))
      throw InputError(
          fmt::format("--min-time: must be in (0, 10] seconds, got {}", args->min_time));
    // What `sglab gpucost` wrote into the same table stays (read before the
    // measurement, so a malformed table is reported at once).
    std::optional<cost::gpu::Report> kept_gpu_costs;
    if (const auto existing =
            cost::read_existing_cost_table(std::filesystem::path(args->out) / "costs.json"))
      kept_gpu_costs = existing->gpu;
    const auto workload = cost::make_cost_workload();
    const std::vector<cost::CostCase> cases = selected_cases(*args, workload);
    write_bench(*args, cost::time_with_google_benchmark(cases, args->repetitions, args->min_time),
                kept_gpu_costs);
  });
}

}  // namespace sglab::app
