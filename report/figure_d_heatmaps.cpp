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

#include "report/figure_style.hpp"
#include "report/gnuplot.hpp"

namespace sglab::report::figures_detail {

// ---- (d) heat maps ---------------------------------------------------------------
Figure figure_d(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods,
                const validate::SweepResult& res) {
  Figure f{"d_peak_rel_heatmaps",
           "peak_rel error heat maps over (κ, c), float",
           "peak_rel = |Ê − E|/E(1, κ) of every registered irradiance method evaluated in float on "
           "the standard grid (29 κ log-spaced in [1e-3, 1e4] × 41 c, docs/quantities.md), one "
           "panel per method, one shared log colour scale clamped to [1e-7, 10] (errors above 10 "
           "show as 10; grey: non-finite output). The panel title gives the method's max.",
           {},
           false,
           ""};
  std::vector<std::string> header = {"log10_kappa", "cosine"};
  std::vector<const validate::SweepEntry*> entries;
  for (const validate::SweepMethod& m : methods) {
    header.emplace_back(m.method.id);
    entries.push_back(res.find(m.method.id, validate::Quantity::irradiance, io::kCpuFloat));
  }
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < res.kappas.size(); ++k)
    for (std::size_t j = 0; j < res.cosines.size(); ++j) {
      std::vector<double> r = {std::log10(res.kappas[k]), res.cosines[j]};
      for (const validate::SweepEntry* e : entries)
        r.push_back(e ? e->peak_rel[res.index(k, j)] : std::nan(""));
      rows.push_back(std::move(r));
    }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows, res.cosines.size()));
  const int cols = 4;
  const int nrows = static_cast<int>((methods.size() + cols - 1) / cols);
  const int height = 340 * nrows + 110;
  // Panels fill [0.06, 0.88] × [0.04, top]; the one colour bar sits right of them.
  const double top = 1.0 - 90.0 / height;
  std::string body = fmt::format(
      "set multiplot layout {},{} margins screen 0.06,0.88,0.04,{:.4f} spacing screen 0.055,{:.4f} "
      "title 'peak_rel error |Ê − E| / E(1, κ), float, standard grid: 29 κ in [1e-3, 1e4] × 41 c "
      "(grey = non-finite)' font ',14'\n"
      "set xlabel 'κ' offset 0,0.5\nset ylabel 'c = cos θ' offset 0.5,0\nset xrange "
      "[-3.125:4.125]\nset yrange [-1.025:1.025]\n"
      "set logscale cb\nset cbrange [1e-7:10]\nset format cb '{}'\nset cbtics font ',11'\n"
      "set cblabel 'peak_rel (clamped to [1e-7, 10])' font ',12'\n"
      "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n"
      "set object 1 rect from graph 0,0 to graph 1,1 behind fc rgb '#bbbbbb' fs solid noborder\n"
      "set xtics {} font ',10'\nset ytics 0.5 font ',10'\nset format y '%g'\nunset key\n"
      "unset colorbox\n",
      nrows, cols, top, 120.0 / height, kLogFormat, log10_kappa_tics(-3, 4));
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const double mx = entries[i] ? entries[i]->summary.peak_rel.max : std::nan("");
    if (i + 1 == methods.size())
      body += fmt::format(
          "set colorbox user origin screen 0.91, screen 0.15 size screen 0.018, screen {:.4f}\n",
          top - 0.2);
    body += fmt::format(
        "set title {} font ',12'\nplot {} u 1:2:(v=column({}), v!=v ? 1/0 : (v < 1e-7 ? 1e-7 : (v "
        "> 10 ? 10 : v))) with image\n",
        gp_quote(fmt::format("{}{} (max {})", methods[i].method.id,
                             origin_suffix(methods[i].method.origin), fmt::format("{:.2g}", mx))),
        gp_quote(csv), i + 3);
  }
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1600, height)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
