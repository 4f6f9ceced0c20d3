// report/figure_units.hpp — the figures of `sglab figures`, one unit each
// (report/figure_<id>.cpp): each computes its own data, writes it as CSV and
// renders it with the gnuplot driver (report/gnuplot.hpp).
#pragma once

#include <vector>

#include "report/figures.hpp"
#include "validate/sweep.hpp"

namespace sglab::report::figures_detail {

Figure figure_a(const FiguresOptions& opt);  // clamped cosine
Figure figure_b(const FiguresOptions& opt);  // steepness
Figure figure_c(const FiguresOptions& opt);  // irradiance at κ = 4
// Heat maps and max peak_rel against κ, from the sweep they share (irradiance_sweep).
Figure figure_d(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods,
                const validate::SweepResult& res);
Figure figure_g(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods,
                const validate::SweepResult& res);
Figure figure_e(const FiguresOptions& opt);  // Pareto
Figure figure_f(const FiguresOptions& opt);  // erf ulp

// The float and double sweep over the standard grid that figures (d) and (g) share.
validate::SweepResult irradiance_sweep(std::vector<validate::SweepMethod>& methods);

}  // namespace sglab::report::figures_detail
