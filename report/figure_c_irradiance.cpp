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

#include "reference/reference.hpp"

#include "report/figure_style.hpp"
#include "report/gnuplot.hpp"

namespace sglab::report::figures_detail {

namespace {
constexpr double kPi = std::numbers::pi;
}  // namespace

// ---- (c) irradiance at κ = 4 ------------------------------------------------------
Figure figure_c(const FiguresOptions& opt) {
  Figure f{"c_irradiance_kappa4",
           "Irradiance vs angle at κ = 4, every method, and its peak-relative error",
           "Top: E(θ) of the reference (quadrature) and Ê(θ) of every registered irradiance method "
           "(double) for a unit-amplitude SG light with κ = 4, θ ∈ [0°, 180°] (the chart of "
           "[Pettineo2016]). Bottom: |Ê − E| / E(1, κ) on a log scale (the peak_rel error of "
           "docs/quantities.md). Solid: published constants; dashed: sglab refits; thick dash-dot: "
           "sglab's own models.",
           {},
           false,
           ""};
  const double kappa = 4;
  const int n = 181;
  std::vector<reference::Query> q;
  for (int i = 0; i < n; ++i)
    q.push_back({kappa, std::clamp(std::cos(kPi * i / (n - 1)), -1.0, 1.0)});
  const auto ref = reference::reference_engine().evaluate(q);
  const double peak = ref[0].irradiance;  // θ = 0: E(1, κ)
  std::vector<std::string> header = {"theta_deg", "reference"}, eheader = {"theta_deg"};
  for (const Method& m : irradiance_methods) {
    header.emplace_back(m.id);
    eheader.emplace_back(m.id);
  }
  std::vector<std::vector<double>> rows, erows;
  for (int i = 0; i < n; ++i) {
    std::vector<double> r = {180.0 * i / (n - 1), ref[i].irradiance}, e = {180.0 * i / (n - 1)};
    for (const Method& m : irradiance_methods) {
      const double v = m.f64(q[i].cosine, kappa);
      r.push_back(v);
      const double pr = std::abs(v - ref[i].irradiance) / peak;
      e.push_back(pr > 0 ? pr : std::nan(""));  // exact zeros have no place on a log axis
    }
    rows.push_back(std::move(r));
    erows.push_back(std::move(e));
  }
  const std::string csv = f.id + ".csv", ecsv = f.id + "_peak_rel.csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  io::write_file_atomic(opt.out / ecsv, numeric_csv(eheader, erows));
  std::string top = fmt::format("plot {} u 1:2 w l lw 5 lc rgb '#000000' dt 3 title 'reference E'",
                                gp_quote(csv));
  std::string bottom = "plot ";
  std::vector<std::string_view> ids;
  for (const Method& m : irradiance_methods) ids.push_back(m.id);
  const std::vector<std::size_t> fam = family_indices(ids);
  std::size_t i = 0;
  for (const Method& m : irradiance_methods) {
    const std::string style = line_style(fam[i], m.origin);
    top += fmt::format(", \\\n     '' u 1:{} w l {} title {}", i + 3, style,
                       gp_quote(std::string(m.id) + origin_suffix(m.origin)));
    bottom += fmt::format("{}{} u 1:{} w l {} notitle", i ? ", \\\n     " : "",
                          i ? "''" : gp_quote(ecsv), i + 2, style);
    ++i;
  }
  const std::string body = fmt::format(
      "set multiplot title 'Irradiance from a unit SG light at κ = 4, double (after the chart of "
      "[Pettineo2016])'\n"
      "set grid\nset xrange [0:180]\nset xtics 30\n"
      "set lmargin at screen 0.08\nset rmargin at screen 0.72\n"
      "set tmargin at screen 0.94\nset bmargin at screen 0.56\n"
      "set key at screen 0.735, screen 0.94 left top Left reverse font ',10' samplen 5 spacing "
      "1.1\n"
      "set xlabel 'θ (degrees) between light axis and normal'\nset ylabel 'E'\nset format y "
      "'%g'\n{}\n"
      "set tmargin at screen 0.47\nset bmargin at screen 0.07\nunset key\n"
      "set ylabel '|Ê − E| / E(1, κ)'\nset logscale y\nset yrange [1e-8:1]\nset format y "
      "'{}'\n{}\n",
      top, kLogFormat, bottom);
  f.files.push_back(csv);
  f.files.push_back(ecsv);
  for (auto& x : render(opt, f.id, body, 1300, 1050)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
