// report/erf_report.hpp — the writers of the erf checker's results
// (validate/erf_check.hpp): one writer per format, every format from the same
// ErfReport values.
#pragma once

#include <string>
#include <vector>

#include "validate/erf_check.hpp"

namespace sglab::report {

// {"results": [{"variant", "precision", "max_abs", "max_ulp", "worst_x", …}, …]}
std::string erf_reports_json(const std::vector<validate::ErfReport>& reports, bool exhaustive);
// Summary table, histogram table, specials and notes as Markdown.
std::string erf_reports_markdown(const std::vector<validate::ErfReport>& reports, bool exhaustive);
// One row per report.
std::string erf_summary_csv(const std::vector<validate::ErfReport>& reports);
// One row per histogram bucket per report.
std::string erf_histogram_csv(const std::vector<validate::ErfReport>& reports);
// The downsampled series of one report: x_lo,x_hi,count,max_ulp,max_ulp_x,rms_ulp,max_abs.
std::string erf_series_csv(const validate::ErfReport& report);

}  // namespace sglab::report
