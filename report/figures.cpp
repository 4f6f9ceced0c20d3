#include "report/figures.hpp"

#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "report/figure_units.hpp"
#include "report/gnuplot.hpp"
#include "report/pareto.hpp"
#include "validate/sweep.hpp"

// `sglab figures`: the list of figures and their index. The gnuplot driver is
// report/gnuplot.cpp, the shared styles report/figure_style.cpp, and each
// figure is one unit, report/figure_<id>.cpp, computing its own data.

namespace sglab::report {

namespace fs = std::filesystem;

namespace figures_detail {

// The float and double sweep over the standard grid that figures (d) and (g) share.
validate::SweepResult irradiance_sweep(std::vector<validate::SweepMethod>& methods) {
  for (const validate::SweepMethod& m : validate::registered_sweep_methods())
    if (m.quantity == validate::Quantity::irradiance) methods.push_back(m);
  validate::SweepOptions so;
  so.precisions = {io::Precision::float32, io::Precision::float64};
  so.progress = false;
  so.keep_points = true;
  return sweep(validate::SweepGrid{}, methods, so);
}

}  // namespace figures_detail

std::vector<Figure> make_figures(const FiguresOptions& options) {
  if (!gnuplot_available(options.gnuplot))
    throw GnuplotMissing(
        fmt::format("gnuplot ('{}') is not installed or does not run; install it (e.g. apt-get "
                    "install gnuplot-nox) to render figures",
                    options.gnuplot));
  // Bad input and a bad output folder are refused before any figure is computed or written.
  io::check_output_folder(options.out);
  for (const fs::path& p : options.pareto)
    if (std::error_code ec; fs::exists(p, ec)) read_pareto_csv(p);
  fs::create_directories(options.out);
  using namespace figures_detail;
  std::vector<Figure> figs;
  figs.push_back(figure_a(options));
  figs.push_back(figure_b(options));
  figs.push_back(figure_c(options));
  std::vector<validate::SweepMethod> methods;
  const validate::SweepResult sweep_result = irradiance_sweep(methods);
  figs.push_back(figure_d(options, methods, sweep_result));
  figs.push_back(figure_e(options));
  figs.push_back(figure_f(options));
  figs.push_back(figure_g(options, methods, sweep_result));

  std::string md =
      "# sglab figures\n\nWritten by `sglab figures`. Each figure has its data CSV, the gnuplot "
      "script that renders it (run `gnuplot <name>.gp` in this directory), a PNG and an SVG.\n\n";
  for (const Figure& f : figs) {
    md += fmt::format("## {} — {}\n\n{}\n\n", f.id, f.title, f.description);
    if (f.skipped) {
      md += fmt::format("**Skipped:** {}\n\n", f.note);
      continue;
    }
    if (!f.note.empty()) md += fmt::format("Note: {}\n\n", f.note);
    for (const fs::path& p : f.files)
      if (p.extension() == ".png") md += fmt::format("![{}]({})\n\n", f.title, p.string());
    md += "Files: ";
    for (std::size_t i = 0; i < f.files.size(); ++i)
      md += fmt::format("{}[{}]({})", i ? ", " : "", f.files[i].string(), f.files[i].string());
    md += "\n\n";
  }
  io::write_file_atomic(options.out / "index.md", md);
  return figs;
}

}  // namespace sglab::report
