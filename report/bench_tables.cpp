// report/bench_tables.cpp — see bench_tables.hpp.
#include "report/bench_tables.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace sglab::report {

namespace {

double find_ns(const std::vector<cost::Cost>& costs, cost::CostKind kind, const std::string& method,
               io::Precision f, cost::CostMode mode) {
  for (const cost::Cost& c : costs)
    if (c.kind == kind && c.method == method && c.precision == f && c.mode == mode)
      return c.ns_per_eval;
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

validate::Table bench_table(const std::vector<cost::Cost>& costs, std::string title) {
  validate::Table t(std::move(title),
                    {{"kind"}, {"method"}, {"precision"}, {"mode"}, {"ns_per_eval", 3}});
  for (const cost::Cost& c : costs)
    t.add_row({validate::Table::text(io::to_string(c.kind)), validate::Table::text(c.method),
               validate::Table::text(io::to_string(c.precision)),
               validate::Table::text(io::to_string(c.mode)), validate::Table::real(c.ns_per_eval)});
  return t;
}

validate::Table bench_summary_table(const std::vector<cost::Cost>& costs) {
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
  std::vector<std::tuple<cost::CostKind, std::string, io::Precision>> keys;
  for (const cost::Cost& c : costs) {
    const auto key = std::make_tuple(c.kind, c.method, c.precision);
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  using cost::CostMode;
  using validate::Table;
  const auto cell = [](double x) { return std::isnan(x) ? validate::Cell{} : Table::real(x); };
  for (const auto& [kind, method, f] : keys) {
    const double scalar = find_ns(costs, kind, method, f, CostMode::scalar);
    const double batch = find_ns(costs, kind, method, f, CostMode::batch);
    t.add_row({Table::text(io::to_string(kind)), Table::text(method), Table::text(io::to_string(f)),
               cell(scalar), cell(batch), cell(scalar / batch),
               cell(find_ns(costs, kind, method, f, CostMode::light_setup)),
               cell(find_ns(costs, kind, method, f, CostMode::light_eval))});
  }
  return t;
}

}  // namespace sglab::report
