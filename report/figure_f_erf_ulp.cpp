#include "report/figure_units.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sglab/constants.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/registry.hpp>

#include "validate/erf_check.hpp"

#include "report/figure_style.hpp"
#include "report/gnuplot.hpp"

namespace sglab::report::figures_detail {

// ---- (f) erf ulp ------------------------------------------------------------------
Figure figure_f(const FiguresOptions& opt) {
  Figure f{"f_erf_ulp",
           "erf error in float ulps over x",
           "Max ulp error per bin of x ∈ [0, 4) (400 bins) of the erf variants listing5 "
           "([Tokuyoshi2022] Listing 5), as7125 ([AS1964] 7.1.25) and std evaluated in float, "
           "against the correctly rounded float erf (validate/erf_check, sample mode: every 257th "
           "float pattern plus a uniform grid of 2^20 points).",
           {},
           false,
           ""};
  validate::ErfFloatOptions eo;
  eo.bins = 400;
  std::vector<std::string> header = {"x_mid"};
  std::vector<validate::ErfReport> reports;
  for (const char* id : {"listing5", "as7125", "std"}) {
    const ErfVariant* v = find_erf_variant(id);
    if (!v) continue;
    reports.push_back(validate::check_erf_float(v->f32, eo, v->id));
    header.emplace_back(v->id);
  }
  std::vector<std::vector<double>> rows;
  const std::size_t nb = reports.empty() ? 0 : reports.front().series.size();
  for (std::size_t b = 0; b < nb; ++b) {
    std::vector<double> r = {0.5 *
                             (reports.front().series[b].x_lo + reports.front().series[b].x_hi)};
    for (const validate::ErfReport& rep : reports)
      r.push_back(b < rep.series.size() && rep.series[b].count ? rep.series[b].max_ulp
                                                               : std::nan(""));
    rows.push_back(std::move(r));
  }
  std::string maxes;
  for (const validate::ErfReport& rep : reports)
    maxes += fmt::format("{}{} max {:.3g} ulp", maxes.empty() ? "" : ", ", rep.variant,
                         rep.stats.max_ulp);
  f.note = maxes;
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  const std::string body = fmt::format(
      "set title 'erf in float: max error per bin (ulps of the exact erf(x))'\n"
      "set xlabel 'x'\nset ylabel 'max ulp error in bin'\nset logscale y\nset grid\nset xrange "
      "[0:4]\n"
      "set key top right box opaque\nset format y '{}'\nset format x '%g'\n"
      "plot for [i=2:{}] {} u 1:(column(i) > 0 ? column(i) : 1/0) w l lw 2 title columnheader(i)",
      kLogFormat, header.size(), gp_quote(csv));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 650)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
