// report/erf_report.cpp — JSON, Markdown and CSV of the erf checker's
// results (validate/erf_report.hpp).
#include "report/erf_report.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace sglab::report {

namespace {

using validate::detail::group_digits;

std::string hex(double x) { return fmt::format("{:a}", x); }

// Shortest decimal that reads back as the same float / double.
std::string shortest(double x, const std::string& precision) {
  return precision == "float" ? fmt::format("{}", static_cast<float>(x)) : fmt::format("{}", x);
}

double max_or_zero(double v) { return v < 0 ? 0.0 : v; }

nlohmann::json stats_json(const validate::ErfStats& st) {
  nlohmann::json j;
  j["max_abs"] = max_or_zero(st.max_abs);
  j["max_ulp"] = max_or_zero(st.max_ulp);
  j["worst_x"] = st.worst_x;
  j["worst_x_hex"] = hex(st.worst_x);
  j["worst_x_abs"] = st.worst_abs_x;
  j["rms_ulp"] = st.rms_ulp();
  j["count"] = st.count;
  j["nonfinite"] = st.nonfinite;
  j["correctly_rounded"] = st.correctly_rounded;
  if (st.nonfinite) j["first_nonfinite_x"] = st.first_nonfinite_x;
  return j;
}

std::string percent(std::uint64_t n, std::uint64_t total) {
  if (n == 0) return "-";
  const double p = 100.0 * static_cast<double>(n) / static_cast<double>(total ? total : 1);
  if (p < 0.01) return fmt::format("<0.01% ({})", n);
  return fmt::format("{:.2f}%", p);
}

std::string fmt_ulp(double v) { return v < 0 ? "-" : fmt::format("{:.4g}", v); }
std::string fmt_abs(double v) { return v < 0 ? "-" : fmt::format("{:.3e}", v); }
std::string fmt_value(double v) {
  if (std::isnan(v)) return "nan";
  return fmt::format("{:a}", v);
}

}  // namespace

std::string erf_reports_json(const std::vector<validate::ErfReport>& reports, bool exhaustive) {
  nlohmann::json root;
  root["mode"] = exhaustive ? "exhaustive" : "sample";
  root["ulp_definition"] =
      "|f(x) - erf(x)| / ulp(erf(x)), exact erf(x); ulp(y) = 2^(floor(log2|y|) - p + 1) (p = 24 "
      "float, 53 double), 2^-149 / 2^-1074 below the normal range";
  nlohmann::json results = nlohmann::json::array();
  for (const validate::ErfReport& r : reports) {
    nlohmann::json j = stats_json(r.stats);
    j["variant"] = r.variant;
    j["precision"] = r.precision;
    nlohmann::json hist = nlohmann::json::array();
    for (std::size_t i = 0; i < validate::kErfHistBuckets; ++i) {
      const double up = validate::erf_histogram_upper(i);
      hist.push_back({{"bucket", validate::erf_histogram_label(i)},
                      {"max_ulp", std::isinf(up) ? nlohmann::json(nullptr) : nlohmann::json(up)},
                      {"count", r.stats.histogram[i]}});
    }
    j["histogram"] = hist;
    nlohmann::json tail = stats_json(r.tail);
    tail["from_x"] = r.tail_from;
    tail["not_correctly_rounded"] = r.tail.count - r.tail.correctly_rounded;
    j["constant_region"] = tail;
    j["oddness"] = {{"checked", r.oddness.checked}, {"violations", r.oddness.violations}};
    if (r.oddness.violations) j["oddness"]["first_violation_x"] = r.oddness.first_violation_x;
    nlohmann::json specials = nlohmann::json::array();
    for (const validate::ErfSpecial& sp : r.specials)
      specials.push_back({{"x", fmt_value(sp.x)},
                          {"expected", fmt_value(sp.expected)},
                          {"got", fmt_value(sp.got)},
                          {"ok", sp.ok}});
    j["specials"] = specials;
    j["ambiguous_resolved"] = r.ambiguous_resolved;
    j["reference_selfcheck_ulps"] = r.reference_selfcheck_ulps;
    j["coverage"] = r.coverage;
    j["reference"] = r.reference;
    j["seconds"] = r.seconds;
    results.push_back(std::move(j));
  }
  root["results"] = std::move(results);
  return root.dump(2) + "\n";
}

std::string erf_reports_markdown(const std::vector<validate::ErfReport>& reports, bool exhaustive) {
  std::string md;
  md += fmt::format("# erf accuracy against the correctly rounded erf ({})\n\n",
                    exhaustive ? "exhaustive" : "sample");
  md +=
      "err_ulp = |f(x) - erf(x)| / ulp(erf(x)) with the exact erf(x) (not its rounding); ulp(y) = "
      "2^(floor(log2|y|) - 23) in float, - 52 in double (subnormal spacing below the normal "
      "range). `cr` = correctly rounded results. Non-finite outputs are counted apart and excluded "
      "from the rest.\n\n";
  md +=
      "| variant | precision | max ulp | worst x | worst x (hex) | max abs | worst x (abs) | rms "
      "ulp | cr | points | nonfinite | time |\n";
  md += "|---|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const validate::ErfReport& r : reports) {
    const validate::ErfStats& s = r.stats;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.4g} | {} | {} | {} | {:.2f} s |\n",
                      r.variant, r.precision, fmt_ulp(s.max_ulp), shortest(s.worst_x, r.precision),
                      hex(s.worst_x), fmt_abs(s.max_abs), shortest(s.worst_abs_x, r.precision),
                      s.rms_ulp(), percent(s.correctly_rounded, s.count), group_digits(s.count),
                      group_digits(s.nonfinite), r.seconds);
  }

  // Histogram: rows = buckets (non-empty in some report), columns = reports.
  md +=
      "\n## ulp error distribution (share of points; bucket `<=2^k` holds 2^(k-1) < err <= "
      "2^k)\n\n| bucket |";
  for (const validate::ErfReport& r : reports)
    md += fmt::format(" {} {} |", r.variant, r.precision);
  md += "\n|---|";
  for (std::size_t i = 0; i < reports.size(); ++i) md += "--:|";
  md += "\n";
  for (std::size_t b = 0; b < validate::kErfHistBuckets; ++b) {
    bool any = false;
    for (const validate::ErfReport& r : reports) any |= r.stats.histogram[b] != 0;
    if (!any) continue;
    md += fmt::format("| {} |", validate::erf_histogram_label(b));
    for (const validate::ErfReport& r : reports)
      md += fmt::format(" {} |", percent(r.stats.histogram[b], r.stats.count));
    md += "\n";
  }

  md += "\n## Constant region, oddness, references\n\n";
  md +=
      "| variant | precision | constant region from | points | not RN (= not exactly 1) | max ulp "
      "there | odd checked | odd violations | midpoints resolved | reference self-check (double "
      "ulps) |\n";
  md += "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const validate::ErfReport& r : reports) {
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {}{} | {} | {:.3g} |\n", r.variant,
                      r.precision, r.tail_from, group_digits(r.tail.count),
                      group_digits(r.tail.count - r.tail.correctly_rounded + r.tail.nonfinite),
                      fmt_ulp(r.tail.max_ulp), group_digits(r.oddness.checked),
                      group_digits(r.oddness.violations),
                      r.oddness.violations
                          ? fmt::format(" (first x = {})", hex(r.oddness.first_violation_x))
                          : "",
                      group_digits(r.ambiguous_resolved), r.reference_selfcheck_ulps);
  }

  for (const char* prec : {"float", "double"}) {
    std::vector<const validate::ErfReport*> rs;
    for (const validate::ErfReport& r : reports)
      if (r.precision == prec) rs.push_back(&r);
    if (rs.empty()) continue;
    md += fmt::format(
        "\n## Special values ({}; expected = correctly rounded, sign of zero kept; x marks a "
        "mismatch)\n\n| x | expected |",
        prec);
    for (const validate::ErfReport* r : rs) md += fmt::format(" {} |", r->variant);
    md += "\n|---|---|";
    for (std::size_t i = 0; i < rs.size(); ++i) md += "---|";
    md += "\n";
    for (std::size_t k = 0; k < rs.front()->specials.size(); ++k) {
      const validate::ErfSpecial& sp = rs.front()->specials[k];
      md += fmt::format("| {} | {} |", fmt_value(sp.x), fmt_value(sp.expected));
      for (const validate::ErfReport* r : rs)
        md += fmt::format(" {}{} |", fmt_value(r->specials[k].got), r->specials[k].ok ? "" : " x");
      md += "\n";
    }
  }

  md += "\n## Coverage and reference\n\n";
  std::vector<std::string> seen;
  for (const validate::ErfReport& r : reports) {
    const std::pair<const char*, const std::string*> items[] = {{"coverage", &r.coverage},
                                                                {"reference", &r.reference}};
    for (const auto& [what, text] : items) {
      if (std::find(seen.begin(), seen.end(), r.precision + *text) != seen.end()) continue;
      seen.push_back(r.precision + *text);
      md += fmt::format("- {} ({}): {}\n", r.precision, what, *text);
    }
  }
  return md;
}

std::string erf_summary_csv(const std::vector<validate::ErfReport>& reports) {
  std::string csv =
      "variant,precision,max_ulp,worst_x,worst_x_hex,max_abs,worst_x_abs,rms_ulp,count,correctly_"
      "rounded,nonfinite,tail_from,tail_count,tail_not_rn,odd_checked,odd_violations,ambiguous_"
      "resolved,seconds\n";
  for (const validate::ErfReport& r : reports) {
    const validate::ErfStats& s = r.stats;
    csv += fmt::format(
        "{},{},{:.17g},{:.17g},{},{:.17g},{:.17g},{:.17g},{},{},{},{},{},{},{},{},{},{:.3f}\n",
        r.variant, r.precision, max_or_zero(s.max_ulp), s.worst_x, hex(s.worst_x),
        max_or_zero(s.max_abs), s.worst_abs_x, s.rms_ulp(), s.count, s.correctly_rounded,
        s.nonfinite, r.tail_from, r.tail.count, r.tail.count - r.tail.correctly_rounded,
        r.oddness.checked, r.oddness.violations, r.ambiguous_resolved, r.seconds);
  }
  return csv;
}

std::string erf_histogram_csv(const std::vector<validate::ErfReport>& reports) {
  std::string csv = "variant,precision,bucket,max_ulp,count\n";
  for (const validate::ErfReport& r : reports)
    for (std::size_t i = 0; i < validate::kErfHistBuckets; ++i)
      csv +=
          fmt::format("{},{},{},{},{}\n", r.variant, r.precision, validate::erf_histogram_label(i),
                      validate::erf_histogram_upper(i), r.stats.histogram[i]);
  return csv;
}

std::string erf_series_csv(const validate::ErfReport& r) {
  std::string csv = "x_lo,x_hi,count,max_ulp,max_ulp_x,rms_ulp,max_abs\n";
  for (const validate::ErfBin& b : r.series) {
    const double rms = b.count ? std::sqrt(b.sum_sq_ulp / static_cast<double>(b.count)) : 0.0;
    csv += fmt::format("{:.17g},{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g}\n", b.x_lo, b.x_hi,
                       b.count, b.max_ulp, b.max_ulp_x, rms, b.max_abs);
  }
  return csv;
}

}  // namespace sglab::report
