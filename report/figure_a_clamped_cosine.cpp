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

// ---- (a) clamped cosine ---------------------------------------------------------
Figure figure_a(const FiguresOptions& opt) {
  Figure f{"a_clamped_cosine",
           "Clamped-cosine approximation error and float numerical error",
           "α(e^{λu}−1) − u in double (approximation error, line) and float evaluation of "
           "α(exp(λu)−1) minus its double value (numerical error: one dot per float u, thin lines "
           "= min and max per 1/80 of the interval), u = cos θ ∈ [0, 1], published λ, α "
           "([Tokuyoshi2022] supplementary Fig. 1).",
           {},
           false,
           ""};
  const auto p = constants::clamped_cosine_published;
  const float lf = static_cast<float>(p.lambda), af = static_cast<float>(p.alpha);
  std::vector<std::vector<double>> rows;
  const int n = 4001;
  const int bins = 80;
  std::vector<double> lo(bins, INFINITY), hi(bins, -INFINITY);
  double max_a = 0, max_n = 0;
  for (int i = 0; i < n; ++i) {
    const float uf = static_cast<float>(static_cast<double>(i) / (n - 1));
    const double u = uf;
    const double model = p.alpha * std::expm1(p.lambda * u);
    const double fl = af * (std::exp(lf * uf) - 1.0f);
    rows.push_back({u, model - u, fl - model});
    max_a = std::max(max_a, std::abs(model - u));
    max_n = std::max(max_n, std::abs(fl - model));
    const int b = std::min(bins - 1, static_cast<int>(u * bins));
    lo[b] = std::min(lo[b], fl - model);
    hi[b] = std::max(hi[b], fl - model);
  }
  std::vector<std::vector<double>> env;
  for (int b = 0; b < bins; ++b) env.push_back({(b + 0.5) / bins, lo[b], hi[b]});
  const std::string csv = f.id + ".csv", ecsv = f.id + "_envelope.csv";
  io::write_file_atomic(opt.out / csv,
                        numeric_csv({"u", "approximation_error", "numerical_error_float"}, rows));
  io::write_file_atomic(opt.out / ecsv,
                        numeric_csv({"u_mid", "numerical_min", "numerical_max"}, env));
  const std::string body = fmt::format(
      "set title '[Tokuyoshi2022] supp. Fig. 1: clamped cosine ≈ α(exp(λu) − 1), λ = {:.6g}, α = "
      "{:.6g}; float vs double'\n"
      "set xlabel 'u = cos θ'\nset ylabel 'difference from u'\nset grid\nset key top left box "
      "opaque\n"
      "set format y '%.1te%T'\nset format x '%g'\n"
      "plot {} u 1:3 w p pt 7 ps 0.25 lc rgb '#a01f77b4' title 'numerical error (float − double), "
      "max {:.3g}', \\\n"
      "     {} u 1:2 w l lw 1 lc rgb '#1f77b4' title 'numerical error, min and max per bin', \\\n"
      "     '' u 1:3 w l lw 1 lc rgb '#1f77b4' notitle, \\\n"
      "     {} u 1:2 w l lw 3 lc rgb '#ff7f0e' title 'approximation error (double), max {:.3g}'",
      p.lambda, p.alpha, gp_quote(csv), max_n, gp_quote(ecsv), gp_quote(csv), max_a);
  f.files.push_back(csv);
  f.files.push_back(ecsv);
  for (auto& x : render(opt, f.id, body, 1000, 650)) f.files.push_back(x);
  return f;
}

}  // namespace sglab::report::figures_detail
