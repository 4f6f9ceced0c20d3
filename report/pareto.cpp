// report/pareto.cpp — see pareto.hpp.
#include "report/pareto.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "validate/kappa_range.hpp"

namespace sglab::report {

namespace {

// A point that may be recommended or on the frontier: finite cost and error, in its valid range.
bool usable(const MethodPoint& p) {
  return std::isfinite(p.cost) && std::isfinite(p.max_peak_rel) && p.in_valid_range;
}

}  // namespace

void mark_valid_range(std::vector<MethodPoint>& points, double kappa_lo, double kappa_hi) {
  for (MethodPoint& p : points) {
    const Method* m = find_method(irradiance_methods, p.method);
    p.in_valid_range = m != nullptr && m->valid.covers(kappa_lo, kappa_hi);
  }
}

std::string outside_valid_range_text(const std::vector<MethodPoint>& points) {
  std::vector<std::string> out;
  for (const MethodPoint& p : points) {
    if (p.in_valid_range) continue;
    const Method* m = find_method(irradiance_methods, p.method);
    out.push_back(
        m ? fmt::format("{} (valid for κ in {})", p.method, validate::kappa_range_text(m->valid))
          : fmt::format("{} (not registered)", p.method));
  }
  return fmt::format("{}", fmt::join(out, ", "));
}

std::string cost_text(const MethodPoint& p, bool with_form) {
  if (!std::isfinite(p.cost)) return "no cost";
  return p.cost_form.empty() || !with_form
             ? fmt::format("{:.3g} {}", p.cost, p.cost_unit)
             : fmt::format("{:.3g} {}, {}", p.cost, p.cost_unit, p.cost_form);
}

void mark_frontier(std::vector<MethodPoint>& points) {
  for (MethodPoint& p : points) {
    p.frontier = false;
    if (!usable(p)) continue;
    bool dominated = false;
    for (const MethodPoint& q : points) {
      if (&q == &p || !usable(q)) continue;
      if (q.cost <= p.cost && q.max_peak_rel <= p.max_peak_rel &&
          (q.cost < p.cost || q.max_peak_rel < p.max_peak_rel)) {
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
        (p.max_peak_rel == r.most_accurate->max_peak_rel && p.cost < r.most_accurate->cost))
      r.most_accurate = p;
    if (p.max_peak_rel <= budget) remaining.push_back(p);
  }
  while (!remaining.empty()) {
    double cheapest = std::numeric_limits<double>::infinity();
    for (const MethodPoint& p : remaining) cheapest = std::min(cheapest, p.cost);
    const double limit = cheapest * (1.0 + tie_margin);
    auto best = remaining.end();
    for (auto it = remaining.begin(); it != remaining.end(); ++it) {
      if (it->cost > limit) continue;
      if (best == remaining.end() || it->max_peak_rel < best->max_peak_rel ||
          (it->max_peak_rel == best->max_peak_rel &&
           (it->cost < best->cost || (it->cost == best->cost && it->method < best->method))))
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

std::vector<MethodPoint> irradiance_errors(double kappa_lo, double kappa_hi, io::Precision f) {
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
    const validate::SweepEntry* e =
        result.find(m.id, validate::Quantity::irradiance, io::on_cpu(f));
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
  mark_valid_range(out, kappa_lo, kappa_hi);
  return out;
}

void fill_costs(std::vector<MethodPoint>& points, io::Precision f, cost::CostMode mode,
                int repetitions, double min_time) {
  cost::CostOptions options;
  options.repetitions = repetitions;
  options.min_time = min_time;
  options.kinds = {cost::CostKind::irradiance};
  options.precisions = {f};
  options.modes = {mode};
  const std::vector<cost::Cost> costs = cost::measure_costs(options);
  for (MethodPoint& p : points) {
    p.cost = std::numeric_limits<double>::quiet_NaN();
    p.cost_unit = "ns";
    for (const cost::Cost& c : costs)
      if (c.method == p.method) p.cost = c.ns_per_eval;
  }
}

namespace {

// The gpu section of the table, refused (CostTableError) when it has no GLSL
// float row of `source`'s figure on its family (the families it has are named).
const cost::gpu::Report& gpu_report(const cost::CostTable& table, const cost::CostSource& source) {
  const std::string where =
      table.path.empty() ? std::string("the cost table") : table.path.string();
  if (!table.gpu)
    throw cost::CostTableError(
        fmt::format("--cost {}: {} has no \"gpu\" section (write it with `sglab gpucost --out "
                    "DIR`, or choose --cost cpu-batch)",
                    source.name(), where));
  std::vector<std::string> families;
  bool found = false;
  for (const cost::gpu::Row& r : table.gpu->rows) {
    if (std::find(families.begin(), families.end(), r.family) == families.end())
      families.push_back(r.family);
    found = found || (r.family == source.family && gpu_row(*table.gpu, r.method, source) == &r);
  }
  if (!found)
    throw cost::CostTableError(fmt::format(
        "--cost {}: {} has no GLSL rows {} for family '{}' (it has: {})", source.name(), where,
        source.figure == cost::GpuFigure::single ? "of one call (harness single)"
                                                 : "of the renderer's loop (harness loop)",
        source.family, families.empty() ? "none" : fmt::format("{}", fmt::join(families, ", "))));
  return *table.gpu;
}

}  // namespace

const cost::gpu::Row* gpu_row(const cost::gpu::Report& report, std::string_view method,
                              const cost::CostSource& source) {
  return source.figure == cost::GpuFigure::single
             ? cost::gpu::single_row(report, method, source.family)
             : cost::gpu::renderer_row(report, method, source.family);
}

double gpu_cost(const cost::gpu::Row& row) { return cost::gpu::cycles_per_light(row); }

std::vector<std::string> fill_costs(std::vector<MethodPoint>& points, io::Precision f,
                                    const cost::CostTable& table, const cost::CostSource& source) {
  std::vector<std::string> missing;
  const double none = std::numeric_limits<double>::quiet_NaN();
  if (source.kind == cost::CostSourceKind::gpu) {
    if (f != io::Precision::float32)
      throw std::invalid_argument(
          fmt::format("--cost {}: the GPU cost is that of the float shader export; use "
                      "--precision float or a cpu-* cost",
                      source.name()));
    const cost::gpu::Report& report = gpu_report(table, source);
    for (MethodPoint& p : points) {
      const cost::gpu::Row* row = gpu_row(report, p.method, source);
      p.cost = row ? gpu_cost(*row) : none;
      p.cost_unit = std::string(source.unit());
      p.cost_form =
          row ? (source.figure == cost::GpuFigure::single ? std::string("single call")
                                                          : cost::gpu::renderer_form(*row))
              : std::string();
      if (!row) missing.push_back(p.method);
    }
    return missing;
  }
  for (MethodPoint& p : points) {
    const cost::Cost* c = table.find(cost::CostKind::irradiance, p.method, f, source.cpu_mode());
    p.cost = c ? c->ns_per_eval : none;
    p.cost_unit = std::string(source.unit());
    if (!c) missing.push_back(p.method);
  }
  return missing;
}

MethodCostMap default_float_costs(const cost::CostTable& table) {
  std::vector<MethodPoint> points;
  for (const Method& m : irradiance_methods) points.push_back({.method = std::string(m.id)});
  MethodCostMap out{cost::default_cost_source(io::Precision::float32), {}};
  try {
    fill_costs(points, io::Precision::float32, table, out.source);
  } catch (const cost::CostTableError&) {  // no GPU rows for it: the CPU timing of `sglab bench`
    out.source = {.kind = cost::CostSourceKind::cpu_batch};
    fill_costs(points, io::Precision::float32, table, out.source);
  }
  for (const MethodPoint& p : points)
    if (std::isfinite(p.cost)) out.cost[p.method] = p.cost;
  return out;
}

validate::Table pareto_table(const std::vector<MethodPoint>& points, io::Precision f,
                             double kappa_lo, double kappa_hi, const cost::CostSource& source,
                             std::string_view cost_from) {
  const std::string outside = outside_valid_range_text(points);
  validate::Table t(
      fmt::format("Speed against accuracy ({}): {} against max peak_rel over κ in [{}, {}] "
                  "(29 κ × 41 c); frontier = not dominated{}{}",
                  to_string(f), source.describe(), kappa_lo, kappa_hi,
                  cost_from.empty() ? std::string() : fmt::format(". Cost: {}", cost_from),
                  outside.empty()
                      ? std::string()
                      : fmt::format(". Outside their valid κ range (registry card; their "
                                    "stated bound does not hold, never on the frontier): {}",
                                    outside)),
      {{"method"},
       {"origin"},
       {"precision"},
       {"kappa_lo", 4},
       {"kappa_hi", 4},
       {"cost", 3},
       {"cost_unit"},
       {"cost_source"},
       {"cost_form"},
       {"max_peak_rel", 3},
       {"frontier"},
       {"in_valid_range"}});
  for (const MethodPoint& p : points)
    t.add_row({validate::Table::text(p.method),
               validate::Table::text(std::string(to_string(p.origin))),
               validate::Table::text(to_string(f)), validate::Table::real(kappa_lo),
               validate::Table::real(kappa_hi), validate::Table::real(p.cost),
               validate::Table::text(p.cost_unit), validate::Table::text(source.name()),
               validate::Table::text(p.cost_form), validate::Table::real(p.max_peak_rel),
               validate::Table::integer(p.frontier ? 1 : 0),
               validate::Table::integer(p.in_valid_range ? 1 : 0)});
  return t;
}

// ---- reading `sglab pareto`'s CSV (figure e reads it back) -------------------------

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"')
          cur += '"', ++i;
        else
          quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

bool parse_bool(const std::string& s, bool& out) {
  std::string l;
  for (char c : s) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (l == "true" || l == "1" || l == "yes") return out = true, true;
  if (l == "false" || l == "0" || l == "no" || l.empty()) return out = false, true;
  return false;
}

double parse_number(const std::string& s, const std::filesystem::path& path, std::size_t line,
                    const char* col) {
  std::string t = s;
  if (t == "nan" || t.empty()) return std::nan("");
  if (t == "inf") return INFINITY;
  try {
    std::size_t pos = 0;
    const double x = std::stod(t, &pos);
    if (pos == t.size()) return x;
  } catch (...) {
  }
  throw std::invalid_argument(
      fmt::format("{}:{}: column {}: '{}' is not a number", path.string(), line, col, s));
}

}  // namespace

std::vector<ParetoRow> read_pareto_csv(const std::filesystem::path& path) {
  const std::string text = io::read_input_file(path, kMaxParetoCsvBytes, "a Pareto CSV");
  // a byte-order mark is not part of the header
  std::istringstream in(std::string(io::strip_utf8_bom(text)));
  std::string line;
  std::size_t lineno = 0;
  std::vector<std::string> header;
  std::map<std::string, std::size_t> col;
  std::vector<ParetoRow> rows;
  static const char* kRequired[] = {"method",       "origin",  "precision", "kappa_lo",
                                    "kappa_hi",     "cost",    "cost_unit", "cost_source",
                                    "max_peak_rel", "frontier"};
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line == "\r") continue;
    auto cells = split_csv_line(line);
    if (header.empty()) {
      header = cells;
      for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
      for (const char* r : kRequired)
        if (!col.count(r))
          throw std::invalid_argument(
              fmt::format("{}: header lacks column '{}' (expected "
                          "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,"
                          "cost_form,max_peak_rel,frontier,in_valid_range)",
                          path.string(), r));
      continue;
    }
    if (cells.size() != header.size())
      throw std::invalid_argument(fmt::format("{}:{}: {} fields, the header has {}", path.string(),
                                              lineno, cells.size(), header.size()));
    ParetoRow r;
    r.method = cells[col["method"]];
    r.precision = cells[col["precision"]];
    const std::string& origin = cells[col["origin"]];
    if (origin == to_string(Origin::published))
      r.origin = Origin::published;
    else if (origin == to_string(Origin::refit))
      r.origin = Origin::refit;
    else if (origin == to_string(Origin::sglab))
      r.origin = Origin::sglab;
    else
      throw std::invalid_argument(
          fmt::format("{}:{}: origin '{}' is not one of published, refit, sglab", path.string(),
                      lineno, origin));
    if (!parse_bool(cells[col["frontier"]], r.frontier))
      throw std::invalid_argument(
          fmt::format("{}:{}: frontier must be true/false", path.string(), lineno));
    if (col.count("in_valid_range") && !parse_bool(cells[col["in_valid_range"]], r.in_valid_range))
      throw std::invalid_argument(
          fmt::format("{}:{}: in_valid_range must be true/false", path.string(), lineno));
    r.kappa_lo = parse_number(cells[col["kappa_lo"]], path, lineno, "kappa_lo");
    r.kappa_hi = parse_number(cells[col["kappa_hi"]], path, lineno, "kappa_hi");
    r.cost = parse_number(cells[col["cost"]], path, lineno, "cost");
    r.cost_unit = cells[col["cost_unit"]];
    r.cost_source = cells[col["cost_source"]];
    if (col.count("cost_form")) r.cost_form = cells[col["cost_form"]];
    r.max_peak_rel = parse_number(cells[col["max_peak_rel"]], path, lineno, "max_peak_rel");
    rows.push_back(std::move(r));
  }
  if (header.empty())
    throw std::invalid_argument(fmt::format("{}: empty file (no header)", path.string()));
  return rows;
}

}  // namespace sglab::report
