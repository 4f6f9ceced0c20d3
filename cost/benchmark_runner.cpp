// cost/benchmark_runner.cpp — see benchmark_runner.hpp.
#include "cost/benchmark_runner.hpp"

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "common/io.hpp"
#include "cost/cost_table.hpp"  // load_average_1min

namespace sglab::cost {

namespace {

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

// Google Benchmark's --benchmark_enable_random_interleaving, set through
// Initialize (the flag has no setter). Once per process.
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

}  // namespace

BenchmarkTimings time_with_google_benchmark(const std::vector<CostCase>& cases, int repetitions,
                                            double min_time) {
  enable_random_interleaving();
  benchmark::ClearRegisteredBenchmarks();
  for (const CostCase& c : cases) {
    const CostCase* pc = &c;
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
        ->MinTime(min_time)
        ->Repetitions(repetitions)
        ->ReportAggregatesOnly(true);
  }
  CollectingReporter reporter(cases.size());
  BenchmarkTimings t;
  t.load_start = load_average_1min();
  benchmark::RunSpecifiedBenchmarks(&reporter);
  t.load_end = load_average_1min();
  benchmark::ClearRegisteredBenchmarks();
  for (const CostCase& c : cases) {
    const double ns = reporter.ns_per_iteration(c.name());
    if (ns < 0) throw std::runtime_error(fmt::format("bench: no result for {}", c.name()));
    t.costs.push_back(Cost{static_cast<const CostOf&>(c), ns / static_cast<double>(c.evaluations)});
  }
  return t;
}

}  // namespace sglab::cost
