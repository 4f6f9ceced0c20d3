// `sglab bench`: ns per evaluation of every irradiance method, hemispherical
// method and erf variant, float and double, scalar and batch, timed with
// Google Benchmark inside the process (one thread, wall-clock time, the
// median of --repetitions). The cases and the workload are validate/cost.hpp's:
// 4096 inputs, κ log-uniform in [1e-3, 1e4], c uniform in [-1, 1] (erf: x
// uniform in [0, 4]), fixed seed; "scalar" calls the registry function pointer
// once per element, "batch" calls the batch pointer once over all inputs.
// Writes bench.csv and bench.md into --out; --json prints the table as JSON.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "cost.hpp"
#include "io.hpp"
#include "table.hpp"

namespace sglab::app {

namespace {

struct BenchArgs {
  bool json = false;
  std::string out = "out/bench";
  int repetitions = 5;
  std::string filter;
  double min_time = 0.05;
};

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

}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand(
      "bench", "ns per evaluation of every method and erf variant (float/double, scalar/batch), Google Benchmark");
  cmd->add_flag("--json", args->json, "print the table as JSON on stdout");
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--repetitions", args->repetitions, "repetitions per case; the median is reported")
      ->capture_default_str();
  cmd->add_option("--filter", args->filter, "ECMAScript regex searched in kind/method/precision/mode");
  cmd->add_option("--min-time", args->min_time, "seconds per repetition")->capture_default_str();
  cmd->callback([args] {
    if (args->repetitions < 1)
      throw InputError(fmt::format("--repetitions: must be >= 1, got {}", args->repetitions));
    if (!(args->min_time > 0) || !(args->min_time <= 10))
      throw InputError(fmt::format("--min-time: must be in (0, 10] seconds, got {}", args->min_time));
    std::regex filter;
    try {
      if (!args->filter.empty()) filter = std::regex(args->filter);
    } catch (const std::regex_error& e) {
      throw InputError(fmt::format("--filter: '{}' is not a valid regex ({})", args->filter, e.what()));
    }

    const auto workload = validate::make_cost_workload();
    std::vector<validate::CostCase> cases;
    for (auto& c : validate::cost_cases(workload))
      if (args->filter.empty() || std::regex_search(c.name(), filter)) cases.push_back(std::move(c));
    if (cases.empty()) throw InputError(fmt::format("--filter: '{}' matches no case", args->filter));

    benchmark::ClearRegisteredBenchmarks();
    for (const validate::CostCase& c : cases) {
      const validate::CostCase* pc = &c;
      benchmark::RegisterBenchmark(c.name().c_str(),
                                   [pc](benchmark::State& state) {
                                     for (auto _ : state) pc->run();
                                     state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                                                             static_cast<std::int64_t>(pc->evaluations));
                                   })
          ->Unit(benchmark::kNanosecond)
          ->UseRealTime()
          ->Threads(1)
          ->MinTime(args->min_time)
          ->Repetitions(args->repetitions)
          ->ReportAggregatesOnly(true);
    }
    CollectingReporter reporter(cases.size());
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();

    std::vector<validate::Cost> costs;
    for (const validate::CostCase& c : cases) {
      const double ns = reporter.ns_per_iteration(c.name());
      if (ns < 0) throw std::runtime_error(fmt::format("bench: no result for {}", c.name()));
      costs.push_back(validate::Cost{c.kind, c.method, c.refit, c.precision, c.mode,
                                     ns / static_cast<double>(c.evaluations)});
    }
    const validate::Table table = validate::cost_table(
        costs, fmt::format("ns per evaluation (Google Benchmark, 1 thread, median of {} repetitions × {} s; "
                           "{} inputs; scalar = registry function pointer per element, batch = batch pointer)",
                           args->repetitions, args->min_time, validate::kCostInputs));
    const std::filesystem::path dir(args->out);
    using validate::TableFormat;
    validate::write_table(table, dir, "bench", {TableFormat::csv, TableFormat::markdown});
    if (args->json)
      fmt::print("{}\n", validate::to_json(table).dump(2));
    else
      fmt::print("{}\nWritten to {}: bench.{{csv,md}}\n", validate::to_markdown(table), dir.string());
  });
}

}  // namespace sglab::app
