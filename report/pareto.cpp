// report/pareto.cpp — see pareto.hpp.
#include "report/pareto.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include <sglab/registry.hpp>

namespace sglab::report {

namespace {

bool usable(const MethodPoint& p) { return std::isfinite(p.ns_per_eval) && std::isfinite(p.max_peak_rel); }

}  // namespace

void mark_frontier(std::vector<MethodPoint>& points) {
  for (MethodPoint& p : points) {
    p.frontier = false;
    if (!usable(p)) continue;
    bool dominated = false;
    for (const MethodPoint& q : points) {
      if (&q == &p || !usable(q)) continue;
      if (q.ns_per_eval <= p.ns_per_eval && q.max_peak_rel <= p.max_peak_rel &&
          (q.ns_per_eval < p.ns_per_eval || q.max_peak_rel < p.max_peak_rel)) {
        dominated = true;
        break;
      }
    }
    p.frontier = !dominated;
  }
}

Recommendation recommend(const std::vector<MethodPoint>& points, double budget, double tie_margin) {
  Recommendation r;
  r.budget = budget;
  std::vector<MethodPoint> remaining;
  for (const MethodPoint& p : points) {
    if (!usable(p)) continue;
    if (!r.most_accurate || p.max_peak_rel < r.most_accurate->max_peak_rel ||
        (p.max_peak_rel == r.most_accurate->max_peak_rel && p.ns_per_eval < r.most_accurate->ns_per_eval))
      r.most_accurate = p;
    if (p.max_peak_rel <= budget) remaining.push_back(p);
  }
  while (!remaining.empty()) {
    double cheapest = std::numeric_limits<double>::infinity();
    for (const MethodPoint& p : remaining) cheapest = std::min(cheapest, p.ns_per_eval);
    const double limit = cheapest * (1.0 + tie_margin);
    auto best = remaining.end();
    for (auto it = remaining.begin(); it != remaining.end(); ++it) {
      if (it->ns_per_eval > limit) continue;
      if (best == remaining.end() || it->max_peak_rel < best->max_peak_rel ||
          (it->max_peak_rel == best->max_peak_rel &&
           (it->ns_per_eval < best->ns_per_eval ||
            (it->ns_per_eval == best->ns_per_eval && it->method < best->method))))
        best = it;
    }
    r.ranked.push_back(*best);
    remaining.erase(best);
  }
  if (!r.ranked.empty()) r.choice = r.ranked[0];
  if (r.ranked.size() > 1) r.runner_up = r.ranked[1];
  return r;
}

validate::SweepGrid pareto_grid(double kappa_lo, double kappa_hi) {
  validate::SweepGrid g;
  g.kappa_lo = kappa_lo;
  g.kappa_hi = kappa_hi;
  g.kappa_count = 29;
  g.cosine_count = 41;
  return g;
}

std::vector<MethodPoint> irradiance_errors(double kappa_lo, double kappa_hi, validate::FloatFormat f) {
  const validate::SweepGrid grid = pareto_grid(kappa_lo, kappa_hi);
  grid.validate();
  std::vector<validate::SweepMethod> methods;
  for (const Method& m : irradiance_methods) methods.push_back({validate::Quantity::irradiance, m});
  validate::SweepOptions options;
  options.precisions = {f};
  options.keep_points = false;
  const validate::SweepResult result = sweep(grid, methods, options);
  std::vector<MethodPoint> out;
  for (const Method& m : irradiance_methods) {
    const validate::SweepEntry* e = result.find(m.id, validate::Quantity::irradiance, f);
    MethodPoint p;
    p.method = std::string(m.id);
    p.origin = m.origin;
    if (!e)
      p.max_peak_rel = std::numeric_limits<double>::quiet_NaN();
    else if (e->summary.nonfinite > 0)
      p.max_peak_rel = std::numeric_limits<double>::infinity();
    else
      p.max_peak_rel = e->summary.peak_rel.max;
    out.push_back(std::move(p));
  }
  return out;
}

void fill_costs(std::vector<MethodPoint>& points, validate::FloatFormat f, int repetitions, double min_time) {
  CostOptions options;
  options.repetitions = repetitions;
  options.min_time = min_time;
  options.kinds = {CostKind::irradiance};
  options.precisions = {f};
  options.modes = {CostMode::batch};
  const std::vector<Cost> costs = measure_costs(options);
  for (MethodPoint& p : points) {
    p.ns_per_eval = std::numeric_limits<double>::quiet_NaN();
    for (const Cost& c : costs)
      if (c.method == p.method) p.ns_per_eval = c.ns_per_eval;
  }
}

std::vector<std::string> fill_costs(std::vector<MethodPoint>& points, validate::FloatFormat f, const CostTable& table) {
  std::vector<std::string> missing;
  for (MethodPoint& p : points) {
    const Cost* c = table.find(CostKind::irradiance, p.method, f, CostMode::batch);
    p.ns_per_eval = c ? c->ns_per_eval : std::numeric_limits<double>::quiet_NaN();
    if (!c) missing.push_back(p.method);
  }
  return missing;
}

validate::Table pareto_table(const std::vector<MethodPoint>& points, validate::FloatFormat f, double kappa_lo, double kappa_hi) {
  validate::Table t(fmt::format("Speed against accuracy ({}): batch ns/eval against max peak_rel over κ in [{}, {}] "
                      "(29 κ × 41 c); frontier = not dominated",
                      to_string(f), kappa_lo, kappa_hi),
          {{"method"},
           {"origin"},
           {"precision"},
           {"kappa_lo", 4},
           {"kappa_hi", 4},
           {"ns_per_eval", 3},
           {"max_peak_rel", 3},
           {"frontier"}});
  for (const MethodPoint& p : points)
    t.add_row({validate::Table::text(p.method), validate::Table::text(std::string(to_string(p.origin))), validate::Table::text(to_string(f)),
               validate::Table::real(kappa_lo), validate::Table::real(kappa_hi), validate::Table::real(p.ns_per_eval),
               validate::Table::real(p.max_peak_rel), validate::Table::integer(p.frontier ? 1 : 0)});
  return t;
}

bool parse_number(std::string_view s, double& out) {
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  double v = 0;
  auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return false;
  out = v;
  return true;
}

std::optional<validate::FloatFormat> parse_precision(std::string_view text) {
  if (text == "float") return validate::FloatFormat::binary32;
  if (text == "double") return validate::FloatFormat::binary64;
  return std::nullopt;
}

}  // namespace sglab::report
