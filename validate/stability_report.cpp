#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "validate/stability.hpp"

// The report of the stability table: the prose of each row (where it fails,
// the first failing input, why) and the tables.

namespace sglab::validate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string kappa_span(const FailureStats& f) {
  std::string s;
  if (!std::isnan(f.kappa_min)) {
    s = f.kappa_min == f.kappa_max ? fmt::format("κ = {:g}", f.kappa_min)
                                   : fmt::format("κ in [{:g}, {:g}]", f.kappa_min, f.kappa_max);
  }
  if (f.at_nan_kappa) s += s.empty() ? "κ = nan" : ", κ = nan";
  return s;
}

std::string findings(const StabilityRow& row) {
  std::string s;
  for (std::size_t i = 0; i < kFailureKinds; ++i) {
    const FailureStats& f = row.failures[i];
    if (f.count == 0) continue;
    if (!s.empty()) s += "; ";
    const auto kind = static_cast<FailureKind>(i);
    s += fmt::format("{} {}/{} ({}){}", to_string(kind), f.count, row.evaluations, kappa_span(f),
                     row.is_failure(kind) ? "" : " [not a failure]");
  }
  return s.empty() ? "none" : s;
}

// The first input of the most important kind found: failures first.
std::string first_failure(const StabilityRow& row) {
  for (std::size_t i = 0; i < kFailureKinds; ++i)
    if (row.failures[i].count && row.is_failure(static_cast<FailureKind>(i)))
      return row.failures[i].example;
  for (const FailureStats& f : row.failures)
    if (f.count) return f.example;
  return {};
}

// Why a row has outcomes: invalid inputs, outcomes that are not failures,
// and for published formulas on valid inputs why they are reported and not
// patched (sglab transcribes published methods as written; it fixes only
// transcription-level numerical defects that leave the function unchanged:
// wang2009's 0/0 and cancelling exponent, Hill's 0/0 at c = 0, and Meder's s,
// which is evaluated as the normalized logistic of [Meder2018]).
std::string why(const StabilityRow& row) {
  if (!row.valid_inputs)
    return "invalid input (outside finite κ ≥ 0, c in [-1, 1], unit axes, finite x)";
  if (row.failure_count() == 0)
    return "not a failure (overflow of an exact result beyond the largest finite value, "
           "or an approximation exceeding the exact range by its error)";
  const std::string_view f = row.function;
  // f is `id` or ends in "/id" (GCC 12 reports a false -Wrestrict on "/" + std::string(id) here).
  const auto is = [&](std::string_view id) {
    return f == id ||
           (f.size() > id.size() && f.ends_with(id) && f[f.size() - id.size() - 1] == '/');
  };
  if (row.origin == Origin::sglab) return "sglab primitive or model failing on valid input: a bug";
  if (row.origin == Origin::refit)
    return "sglab refit of a published formula failing on valid input: a bug";
  if (f == "sphere_integral_approx" || is("punctual"))
    return "published approximation 2π/κ [Pettineo2016]: infinite at κ = 0 (and NaN where 0·inf) "
           "by construction";
  if (f == "sg_inner_product_iwasaki" || is("vsgl2015") || is("vsgl2015_refit"))
    return "published approximate product integral [Iwasaki2012]: 2π/(κ1 + κ2) is infinite at κ1 = "
           "κ2 = 0; transcribed as published (κ1κ2/(κ1 + κ2) formed without overflow)";
  if (f == "steepness_meder2018" || is("meder2018"))
    return "published t(κ) = √κ(a2κ² + a1κ)/(κ² + b1κ + b0) forms κ² (inf/inf for κ ≳ 1.8e19 in "
           "float, 1.3e154 in double); the published cosine fit a·G(λm) − b makes Ê a difference "
           "that goes negative; both kept as published";
  if (is("hill") || is("hill_exact"))
    return "Hill's published curve [Pettineo2016] is fitted for larger κ: 1/κ is infinite at κ = 0 "
           "and the curve goes negative below κ ≈ 0.5 (its c = 0 limit at large κ is fixed)";
  if (f.starts_with("erf/")) return "published erf approximation";
  return "published formula, transcribed as written";
}

bool any_outcome(const StabilityRow& row) {
  for (const FailureStats& f : row.failures)
    if (f.count) return true;
  return false;
}

}  // namespace

std::vector<const StabilityRow*> own_failures_on_valid_inputs(const StabilityReport& report) {
  std::vector<const StabilityRow*> out;
  for (const StabilityRow& r : report.rows)
    if (r.origin != Origin::published && r.valid_inputs && r.failure_count() > 0) out.push_back(&r);
  return out;
}

Table stability_table(const StabilityReport& report) {
  std::vector<Column> cols = {{"function"}, {"origin"}, {"precision"}, {"inputs"}, {"evaluations"}};
  for (std::size_t i = 0; i < kFailureKinds; ++i) {
    const std::string k(to_string(static_cast<FailureKind>(i)));
    cols.push_back({k});
    cols.push_back({k + "_kappa_min", 3});
    cols.push_back({k + "_kappa_max", 3});
  }
  cols.push_back({"range"});
  cols.push_back({"approximation"});
  cols.push_back({"findings"});
  cols.push_back({"first_failure"});
  Table t(
      "Stability: NaN / Inf / negative / out-of-range outputs over special inputs (valid inputs: "
      "finite κ ≥ 0, c in [-1, 1], unit axes, finite x)",
      std::move(cols));
  for (const StabilityRow& r : report.rows) {
    std::vector<Cell> row = {Table::text(r.function), Table::text(to_string(r.origin)),
                             Table::text(to_string(r.precision)),
                             Table::text(r.valid_inputs ? "valid" : "invalid"),
                             Table::count(r.evaluations)};
    for (std::size_t i = 0; i < kFailureKinds; ++i) {
      const FailureStats& f = r.failures[i];
      const bool applies = i != static_cast<std::size_t>(FailureKind::negative) || r.sign_checked;
      row.push_back(applies ? Table::count(f.count) : Cell{});
      row.push_back(f.count && !std::isnan(f.kappa_min) ? Table::real(f.kappa_min) : Cell{});
      row.push_back(f.count && !std::isnan(f.kappa_max) ? Table::real(f.kappa_max) : Cell{});
    }
    row.push_back(Table::text(r.range));
    row.push_back(Cell{r.approximation});
    row.push_back(Table::text(findings(r)));
    row.push_back(Table::text(first_failure(r)));
    t.add_row(std::move(row));
  }
  return t;
}

Table stability_findings_table(const StabilityReport& report) {
  Table t(
      "Stability findings (rows with any NaN / Inf / overflow / negative / out-of-range / "
      "inaccurate output)",
      {{"function"},
       {"origin"},
       {"precision"},
       {"inputs"},
       {"findings"},
       {"first_failure"},
       {"why"}});
  for (const StabilityRow& r : report.rows) {
    if (!any_outcome(r)) continue;
    t.add_row({Table::text(r.function), Table::text(to_string(r.origin)),
               Table::text(to_string(r.precision)),
               Table::text(r.valid_inputs ? "valid" : "invalid"), Table::text(findings(r)),
               Table::text(first_failure(r)), Table::text(why(r))});
  }
  return t;
}

namespace {

// What half does at one κ of the grid: "" (survived), or the first of nan, inf,
// negative, off (beyond the tolerance) over the cosines; and the largest
// finite |E_half − E_float|/E(1, κ).
struct HalfAtKappa {
  std::string failure;
  double diff = 0;
};
HalfAtKappa half_at_kappa(const SweepResult& r, const SweepEntry& f, const SweepEntry& h,
                          std::size_t k, double tolerance) {
  HalfAtKappa out;
  const double peak = r.peak_value(f.quantity, k);
  for (std::size_t j = 0; j < r.cosines.size(); ++j) {
    const double x = h.values[r.index(k, j)], y = f.values[r.index(k, j)];
    const double d = std::abs(x - y) / peak;
    std::string why = std::isnan(x)       ? "nan"
                      : std::isinf(x)     ? "inf"
                      : x < 0             ? "negative"
                      : !(d <= tolerance) ? "off"
                                          : "";
    if (std::isfinite(d)) out.diff = std::max(out.diff, d);
    if (out.failure.empty()) out.failure = std::move(why);
  }
  return out;
}

}  // namespace

Table half_ranges_table(const SweepResult& r, double tolerance) {
  Table t(fmt::format("Half precision: κ range each method's half export survives on the device "
                      "(every cosine finite, non-negative and within {:g} of its float export, "
                      "relative to E(1, κ))",
                      tolerance),
          {{"method"},
           {"survives_kappa_lo", 4},
           {"survives_kappa_hi", 4},
           {"fails_below_kappa", 4},
           {"below"},
           {"fails_above_kappa", 4},
           {"above"},
           {"max_diff_in_range", 3},
           {"max_diff_grid", 3}});
  for (const SweepEntry& h : r.entries) {
    if (h.precision != io::on_vulkan(io::Language::glsl, io::Precision::float16)) continue;
    const SweepEntry* f =
        r.find(h.method, h.quantity, io::on_vulkan(io::Language::glsl, io::Precision::float32));
    if (!f || f->values.size() != h.values.size()) continue;
    std::vector<HalfAtKappa> at;
    for (std::size_t k = 0; k < r.kappas.size(); ++k)
      at.push_back(half_at_kappa(r, *f, h, k, tolerance));
    // The largest run of survived κ (the first, on ties).
    std::size_t best_lo = 0, best_len = 0;
    for (std::size_t k = 0; k < at.size();) {
      std::size_t e = k;
      while (e < at.size() && at[e].failure.empty()) ++e;
      if (e - k > best_len) best_lo = k, best_len = e - k;
      k = e == k ? k + 1 : e;
    }
    double in_range = 0, grid = 0;
    for (std::size_t k = 0; k < at.size(); ++k) {
      grid = std::max(grid, at[k].diff);
      if (k >= best_lo && k < best_lo + best_len) in_range = std::max(in_range, at[k].diff);
    }
    const bool any = best_len > 0, below = any && best_lo > 0,
               above = any && best_lo + best_len < at.size();
    t.add_row({Table::text(h.method), Table::real(any ? r.kappas[best_lo] : kNaN),
               Table::real(any ? r.kappas[best_lo + best_len - 1] : kNaN),
               Table::real(below ? r.kappas[best_lo - 1] : kNaN),
               Table::text(below ? at[best_lo - 1].failure : "-"),
               Table::real(above ? r.kappas[best_lo + best_len] : kNaN),
               Table::text(above ? at[best_lo + best_len].failure : "-"),
               Table::real(any ? in_range : kNaN), Table::real(grid)});
  }
  return t;
}

}  // namespace sglab::validate
