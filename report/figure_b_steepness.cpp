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

// ---- (b) steepness ------------------------------------------------------------
Figure figure_b(const FiguresOptions& opt) {
  Figure f{"b_steepness",
           "Optimal steepness t*(κ) vs fitted t(κ) and √(κ/2)",
           "Top: per-κ optimal t*(κ) (dots; fit::optimal_steepness, 40 log-spaced κ in [1e-2, "
           "1e3]), the published t(κ) ([Tokuyoshi2022] Eq. 6), sglab's refit "
           "steepness2022_optimal_t, and the asymptote √(κ/2) ([Tokuyoshi2022] supplementary Fig. "
           "2). Bottom: relative difference |t/t* − 1| of each curve.",
           {},
           false,
           ""};
  std::vector<double> ks;
  for (int i = 0; i < 40; ++i) ks.push_back(std::pow(10.0, -2 + 5.0 * i / 39));
  std::vector<double> ts(ks.size(), std::nan(""));
  if (opt.optimal_steepness)
    ts = opt.optimal_steepness(ks);
  else
    f.note = "t*(κ) not available (no optimal-steepness function given)";
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const double tp = steepness2022(ks[i]),
                 tr = steepness2022(ks[i], constants::steepness2022_optimal_t);
    const double ta = std::sqrt(ks[i] / 2);
    rows.push_back({ks[i], ts[i], tp, tr, ta, std::abs(tp / ts[i] - 1), std::abs(tr / ts[i] - 1),
                    std::abs(ta / ts[i] - 1)});
  }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(
      opt.out / csv,
      numeric_csv({"kappa", "t_optimal", "t_published", "t_refit_optimal_t", "sqrt_kappa_over_2",
                   "reldiff_published", "reldiff_refit_optimal_t", "reldiff_sqrt_kappa_over_2"},
                  rows));
  const std::string body = fmt::format(
      "set multiplot title '[Tokuyoshi2022] supp. Fig. 2: steepness t(κ) of the normalized "
      "hemispherical integral'\n"
      "set lmargin at screen 0.10\nset rmargin at screen 0.97\n"
      "set tmargin at screen 0.93\nset bmargin at screen 0.42\n"
      "set ylabel 't(κ)'\nset logscale xy\nset grid\nset key top left box opaque\n"
      "set format x ''\nset format y '{0}'\nunset xlabel\n"
      "plot {1} u 1:5 w l lw 2 dt 2 lc rgb '#7f7f7f' title '√(κ/2)', \\\n"
      "     '' u 1:3 w l lw 3 lc rgb '#ff7f0e' title 'published t(κ), Eq. 6', \\\n"
      "     '' u 1:4 w l lw 2 dt (8,4) lc rgb '#2ca02c' title 'refit steepness2022_optimal_t', \\\n"
      "     '' u 1:2 w p pt 7 ps 1.2 lc rgb '#1f77b4' title 'optimal t*(κ)'\n"
      "set tmargin at screen 0.38\nset bmargin at screen 0.08\n"
      "set format x '{0}'\nset xlabel 'κ'\nset ylabel '|t / t* − 1|'\nset yrange [1e-5:10]\n"
      "set key bottom left box opaque\n"
      "plot {1} u 1:8 w l lw 2 dt 2 lc rgb '#7f7f7f' title '√(κ/2)', \\\n"
      "     '' u 1:6 w lp lw 3 pt 7 ps 0.6 lc rgb '#ff7f0e' title 'published t(κ), Eq. 6', \\\n"
      "     '' u 1:7 w lp lw 2 pt 5 ps 0.6 dt (8,4) lc rgb '#2ca02c' title 'refit "
      "steepness2022_optimal_t'\n",
      kLogFormat, gp_quote(csv));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 900)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
