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

// ---- (g) max peak_rel against κ ------------------------------------------------------
Figure figure_g(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods,
                const validate::SweepResult& res) {
  Figure f{"g_peak_rel_vs_kappa",
           "Max peak_rel over c against κ, every method, float and double",
           "For each of the 29 κ of the standard grid, the max over the 41 cosines of peak_rel = "
           "|Ê − E|/E(1, κ), one line per registered irradiance method (log-log), in float (left) "
           "and double (right). A gap: the method returned a non-finite value at that κ. The "
           "dotted line at 1 is an error as large as the peak itself. Solid: published constants; "
           "dashed: sglab refits; thick dash-dot: sglab's own models.",
           {},
           false,
           ""};
  std::vector<std::string> header = {"kappa"};
  for (const char* prec : {"float", "double"})
    for (const validate::SweepMethod& m : methods)
      header.push_back(fmt::format("{}_{}", m.method.id, prec));
  std::vector<std::vector<double>> rows;
  std::size_t gaps = 0;
  for (std::size_t k = 0; k < res.kappas.size(); ++k) {
    std::vector<double> r = {res.kappas[k]};
    for (io::Precision fm : {io::Precision::float32, io::Precision::float64})
      for (const validate::SweepMethod& m : methods) {
        const validate::SweepEntry* e =
            res.find(m.method.id, validate::Quantity::irradiance, io::on_cpu(fm));
        double v = std::nan("");
        if (e && k < e->per_kappa.size()) {
          const validate::MetricSummary& s = e->per_kappa[k];
          if (s.nonfinite == 0)
            v = s.peak_rel.max;
          else
            ++gaps;
        }
        r.push_back(v > 0 ? v : std::nan(""));
      }
    rows.push_back(std::move(r));
  }
  if (gaps)
    f.note = fmt::format(
        "{} (method, precision, κ) cells with a non-finite output are left as gaps", gaps);
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  const std::size_t nm = methods.size();
  std::vector<std::string_view> ids;
  for (const validate::SweepMethod& m : methods) ids.push_back(m.method.id);
  const std::vector<std::size_t> fam = family_indices(ids);
  auto panel = [&](std::size_t offset, bool titles) {
    std::string s = "plot 1 w l lw 1.5 dt 3 lc rgb '#000000' notitle";
    for (std::size_t i = 0; i < nm; ++i) {
      const Method& m = methods[i].method;
      s += fmt::format(", \\\n     {} u 1:{} w l {} {}", gp_quote(csv), offset + i + 2,
                       line_style(fam[i], m.origin),
                       titles ? "title " + gp_quote(std::string(m.id) + origin_suffix(m.origin))
                              : std::string("notitle"));
    }
    return s + "\n";
  };
  const std::string body = fmt::format(
      "set multiplot title 'Where each method fails: max over c of |Ê − E| / E(1, κ) against κ, "
      "standard grid' font ',14'\n"
      "set logscale xy\nset grid\nset format x '{0}'\nset format y '{0}'\nset xrange "
      "[1e-3:1e4]\nset yrange [1e-10:1e8]\n"
      "set xlabel 'κ'\nset ytics 100\n"
      "set tmargin at screen 0.92\nset bmargin at screen 0.09\n"
      "set lmargin at screen 0.06\nset rmargin at screen 0.40\n"
      "set title 'float'\nset ylabel 'max peak_rel over c'\nunset key\n{1}"
      "set lmargin at screen 0.44\nset rmargin at screen 0.78\n"
      "set title 'double'\nunset ylabel\nset format y ''\n"
      "set key at screen 0.795, screen 0.92 left top Left reverse font ',10' samplen 5 spacing "
      "1.1\n{2}",
      kLogFormat, panel(0, false), panel(nm, true));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1600, 800)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
