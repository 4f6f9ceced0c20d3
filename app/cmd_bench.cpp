// `sglab bench`: ns per evaluation of every irradiance method, hemispherical
// method and erf variant, float and double, scalar and batch (and, for methods
// with the per-light split, float setup ns per light and eval ns per shading
// point), timed with Google Benchmark inside the process (one thread,
// wall-clock time, the median of --repetitions). The cases and the workload
// are validate/cost.hpp's: 2^20 inputs, κ log-uniform in [1e-3, 1e4], c
// uniform in [-1, 1] (erf: x uniform in [0, 4]), fixed seed; "scalar" calls
// the registry function pointer once per element, "batch" calls the batch
// pointer once over all inputs.
// Writes into --out: bench.csv and bench.md (every case), bench_summary.csv/.md
// (one row per method and precision: scalar, batch, batch speed-up, setup,
// eval) and costs.json, the cost table `sglab pareto` and `sglab recommend`
// read (validate/cost_table.hpp). --json prints the table as JSON.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "report/cost.hpp"
#include "report/cost_table.hpp"
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

double find_ns(const std::vector<report::Cost>& costs, report::CostKind kind,
               const std::string& method, io::Precision f, report::CostMode mode) {
  for (const report::Cost& c : costs)
    if (c.kind == kind && c.method == method && c.precision == f && c.mode == mode)
      return c.ns_per_eval;
  return std::numeric_limits<double>::quiet_NaN();
}

// One row per (kind, method, precision): scalar and batch ns/eval, their
// ratio, and for methods with the per-light split the float setup ns per
// light and eval ns per shading point (empty otherwise).
validate::Table summary_table(const std::vector<report::Cost>& costs) {
  validate::Table t(
      "Per method: ns/eval scalar and batch, batch speed-up, per-light setup ns/light and eval "
      "ns/point (methods with the split)",
      {{"kind"},
       {"method"},
       {"precision"},
       {"scalar_ns", 3},
       {"batch_ns", 3},
       {"batch_speedup", 3},
       {"setup_ns_per_light", 3},
       {"eval_ns_per_point", 3}});
  std::vector<std::tuple<report::CostKind, std::string, io::Precision>> keys;
  for (const report::Cost& c : costs) {
    const auto key = std::make_tuple(c.kind, c.method, c.precision);
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  using report::CostMode;
  using validate::Table;
  const auto cell = [](double x) { return std::isnan(x) ? validate::Cell{} : Table::real(x); };
  for (const auto& [kind, method, f] : keys) {
    const double scalar = find_ns(costs, kind, method, f, CostMode::scalar);
    const double batch = find_ns(costs, kind, method, f, CostMode::batch);
    t.add_row({Table::text(report::to_string(kind)), Table::text(method),
               Table::text(io::to_string(f)), cell(scalar), cell(batch), cell(scalar / batch),
               cell(find_ns(costs, kind, method, f, CostMode::light_setup)),
               cell(find_ns(costs, kind, method, f, CostMode::light_eval))});
  }
  return t;
}

// Collects, per benchmark name, the median aggregate (or the single run when
// there is one repetition); prints nothing but a progress line.
class CollectingReporter : public benchmark::BenchmarkReporter {
 public:
  explicit CollectingReporter(std::size_t total) : progress_("bench", total) {}
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const std::string& name = r.run_name.function_name;
      if (r.run_type == Run::RT_Aggregate) {
        if (r.aggregate_name == "median") {
          median_[name] = r.GetAdjustedRealTime();
          progress_.advance();
        }
      } else if (!single_.count(name)) {
        single_[name] = r.GetAdjustedRealTime();
      }
    }
  }
  void Finalize() override { progress_.finish(); }
  // ns per iteration, or a negative value when the case produced nothing.
  double ns_per_iteration(const std::string& name) const {
    if (auto it = median_.find(name); it != median_.end()) return it->second;
    if (auto it = single_.find(name); it != single_.end()) return it->second;
    return -1;
  }

 private:
  io::Progress progress_;
  std::map<std::string, double> median_, single_;
};

// The cases --filter selects (all without one).
std::vector<report::CostCase> selected_cases(
    const BenchArgs& args, const std::shared_ptr<report::CostWorkload>& workload) {
  std::regex filter;
  try {
    if (!args.filter.empty()) filter = std::regex(args.filter);
  } catch (const std::regex_error& e) {
    throw InputError(
        fmt::format("--filter: '{}' is not a valid regex ({})", args.filter, e.what()));
  }
  std::vector<report::CostCase> cases;
  for (auto& c : report::cost_cases(workload))
    if (args.filter.empty() || std::regex_search(c.name(), filter)) cases.push_back(std::move(c));
  if (cases.empty()) throw InputError(fmt::format("--filter: '{}' matches no case", args.filter));
  return cases;
}

// Google Benchmark with its repetitions of all cases run in a random order
// (its --benchmark_enable_random_interleaving, set through Initialize: the flag
// has no setter), so that a drift of the machine's speed during the run spreads
// over every case instead of biasing the cases timed last (their ratios are
// what the tables compare). Once per process.
void enable_random_interleaving() {
  static const bool initialized = [] {
    // static: the library may keep argv[0]
    static char name[] = "sglab", flag[] = "--benchmark_enable_random_interleaving=true";
    char* argv[] = {name, flag, nullptr};
    int argc = 2;
    benchmark::Initialize(&argc, argv);
    return true;
  }();
  (void)initialized;
}

// Times every case with Google Benchmark (the median of the repetitions, in
// random order), and the 1-min load average before and after.
struct Timings {
  std::vector<report::Cost> costs;
  double load_start = 0, load_end = 0;
};
Timings time_cases(const std::vector<report::CostCase>& cases, const BenchArgs& args) {
  enable_random_interleaving();
  benchmark::ClearRegisteredBenchmarks();
  for (const report::CostCase& c : cases) {
    const report::CostCase* pc = &c;
    benchmark::RegisterBenchmark(
        c.name().c_str(),
        [pc](benchmark::State& state) {
          for (auto _ : state) pc->run();
          state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                                  static_cast<std::int64_t>(pc->evaluations));
        })
        ->Unit(benchmark::kNanosecond)
        ->UseRealTime()
        ->Threads(1)
        ->MinTime(args.min_time)
        ->Repetitions(args.repetitions)
        ->ReportAggregatesOnly(true);
  }
  CollectingReporter reporter(cases.size());
  Timings t;
  t.load_start = report::load_average_1min();
  benchmark::RunSpecifiedBenchmarks(&reporter);
  t.load_end = report::load_average_1min();
  benchmark::ClearRegisteredBenchmarks();
  for (const report::CostCase& c : cases) {
    const double ns = reporter.ns_per_iteration(c.name());
    if (ns < 0) throw std::runtime_error(fmt::format("bench: no result for {}", c.name()));
    t.costs.push_back(report::Cost{c.kind, c.method, c.refit, c.precision, c.mode,
                                   ns / static_cast<double>(c.evaluations)});
  }
  return t;
}

// Writes bench.{csv,md}, bench_summary.{csv,md} and costs.json (keeping the
// GPU section `sglab gpucost` wrote) and prints the tables.
void write_bench(const BenchArgs& args, const Timings& t,
                 const std::optional<shader::gpu::Report>& kept_gpu_costs) {
  const std::filesystem::path dir(args.out);
  const std::string timer = fmt::format(
      "Google Benchmark, 1 thread, wall-clock, median of {} repetitions x {} s, repetitions of all "
      "cases interleaved in random order; scalar = registry "
      "function pointer per element, batch = batch pointer over all inputs, light_setup = ns per "
      "light, light_eval = ns per shading point",
      args.repetitions, args.min_time);
  const validate::Table table = report::cost_table(
      t.costs, fmt::format("ns per evaluation ({}; {})", timer, report::cost_input_description()));
  const validate::Table summary = summary_table(t.costs);

  report::CostTable cost_table;
  cost_table.info = report::current_cost_table_info();
  cost_table.info.command = args.command_line;
  cost_table.info.timer = timer;
  cost_table.info.inputs = report::cost_input_description();
  cost_table.info.load_start = t.load_start;
  cost_table.info.load_end = t.load_end;
  cost_table.costs = t.costs;
  cost_table.gpu = kept_gpu_costs;
  using validate::TableFormat;
  validate::write_table(table, dir, "bench", {TableFormat::csv, TableFormat::markdown});
  validate::write_table(summary, dir, "bench_summary", {TableFormat::csv, TableFormat::markdown});
  report::write_cost_table(cost_table, dir / "costs.json");
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
  cmd->add_option("--out", args->out, "output directory")
      ->check(non_empty_path())
      ->capture_default_str();
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
    std::optional<shader::gpu::Report> kept_gpu_costs;
    if (const auto existing =
            report::read_existing_cost_table(std::filesystem::path(args->out) / "costs.json"))
      kept_gpu_costs = existing->gpu;
    const auto workload = report::make_cost_workload();
    const std::vector<report::CostCase> cases = selected_cases(*args, workload);
    write_bench(*args, time_cases(cases, *args), kept_gpu_costs);
  });
}

}  // namespace sglab::app
