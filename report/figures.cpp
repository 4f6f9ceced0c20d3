#include "report/figures.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sglab/constants.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/registry.hpp>

#include "common/atomic_files.hpp"
#include "report/cost_source.hpp"
#include "export/gpu_cost.hpp"
#include "validate/erf_check.hpp"
#include "common/io.hpp"
#include "validate/reference.hpp"
#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::report {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;

// gnuplot single-quoted string: only ' needs doubling.
std::string gp_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

// A CSV from a header and rows of numbers (full precision; NaN → "nan").
// `block` > 0 inserts a blank line every `block` rows (gnuplot scan lines).
std::string numeric_csv(const std::vector<std::string>& header, const std::vector<std::vector<double>>& rows,
                        std::size_t block = 0) {
  std::string s;
  for (std::size_t i = 0; i < header.size(); ++i) s += (i ? "," : "") + header[i];
  s += '\n';
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (block && r && r % block == 0) s += '\n';
    for (std::size_t i = 0; i < rows[r].size(); ++i) {
      const double x = rows[r][i];
      s += i ? "," : "";
      s += std::isfinite(x) ? fmt::format("{}", x) : (std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf"));
    }
    s += '\n';
  }
  return s;
}

// Writes <stem>.gp next to the data and runs gnuplot in `dir`; the body is
// rendered once to PNG and once to SVG. Returns the script, PNG and SVG paths.
std::vector<fs::path> render(const FiguresOptions& opt, const std::string& stem, const std::string& body, int width,
                             int height) {
  const fs::path& dir = opt.out;
  auto block = [&](const std::string& terminal, const std::string& ext) {
    return fmt::format(
        "reset\n"
        "set encoding utf8\n"
        "set datafile separator ','\n"
        "set key autotitle columnhead\n"
        "set terminal {} size {},{} noenhanced font 'DejaVu Sans,11' background rgb 'white'\n"
        "set output {}\n"
        "{}\n"
        "unset multiplot\n"
        "set output\n",
        terminal, width, height, gp_quote(stem + "." + ext), body);
  };
  const std::string script = fmt::format("# gnuplot script written by `sglab figures`; run in this directory.\n{}\n{}",
                                         block("pngcairo", "png"), block("svg", "svg"));
  const fs::path gp = dir / (stem + ".gp");
  const fs::path log = dir / (stem + ".gp.log");
  // gnuplot opens its outputs itself: refuse first what is not a regular file there.
  for (const fs::path& p : {log, dir / (stem + ".png"), dir / (stem + ".svg")}) io::check_output_path(p);
  io::write_file_atomic(gp, script);
  // No shell: gnuplot runs in `dir` with an argument vector.
  const int status = io::run_program({opt.gnuplot, stem + ".gp"}, dir, stem + ".gp.log");
  if (status != 0) {
    std::string tail;
    try {
      tail = io::read_file(log);
      if (tail.size() > 2000) tail = tail.substr(tail.size() - 2000);
    } catch (...) {
    }
    throw std::runtime_error(fmt::format("gnuplot failed on {} (exit status {}); log {}:\n{}", gp.string(), status,
                                         log.string(), tail));
  }
  {
    std::error_code ec;
    if (fs::file_size(log, ec) == 0 && !ec) fs::remove(log, ec);  // keep the log only when gnuplot said something
  }
  for (const char* ext : {"png", "svg"}) {
    const fs::path p = dir / (stem + "." + ext);
    std::error_code ec;
    if (!fs::exists(p, ec) || fs::file_size(p, ec) == 0)
      throw std::runtime_error(fmt::format("gnuplot ran {} but {} is missing or empty (log {})", gp.string(), p.string(),
                                           log.string()));
  }
  return {stem + ".gp", stem + ".png", stem + ".svg"};
}

// ---- shared styles ------------------------------------------------------------------
// Tick labels: "1e-2" style on every log axis.
constexpr const char* kLogFormat = "1e%T";

// 20 colours that stay apart on white (one per method in the line charts).
constexpr const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
                                    "#7f7f7f", "#bcbd22", "#17becf", "#393b79", "#637939", "#8c6d31", "#843c39",
                                    "#7b4173", "#3182bd", "#e6550d", "#31a354", "#756bb1", "#000080"};
constexpr std::size_t kPaletteSize = std::size(kPalette);

// Line style of a method of family `i`: the family's colour; solid for
// published constants, dashed for sglab's refits, thick dash-dot for sglab's
// own models (so they stand out). Colour and dash together tell every curve apart.
std::string line_style(std::size_t i, Origin origin) {
  switch (origin) {
    case Origin::published: return fmt::format("lw 1.6 dt 1 lc rgb '{}'", kPalette[i % kPaletteSize]);
    case Origin::refit: return fmt::format("lw 1.8 dt (8,4) lc rgb '{}'", kPalette[i % kPaletteSize]);
    case Origin::sglab: return fmt::format("lw 3.0 dt (12,4,3,4) lc rgb '{}'", kPalette[i % kPaletteSize]);
  }
  return "";
}

std::string origin_suffix(Origin o) {
  switch (o) {
    case Origin::published: return "";
    case Origin::refit: return " (refit)";
    case Origin::sglab: return " [sglab]";
  }
  return "";
}

// A method's family: its id without a trailing "_refit", so that a refit
// shares the colour (or marker shape) of the published method it refits.
std::string family_of(std::string_view id) {
  constexpr std::string_view suffix = "_refit";
  if (id.size() > suffix.size() && id.substr(id.size() - suffix.size()) == suffix) id.remove_suffix(suffix.size());
  return std::string(id);
}

// Index of each method's family, numbered in order of first appearance.
std::vector<std::size_t> family_indices(const std::vector<std::string_view>& ids) {
  std::vector<std::string> families;
  std::vector<std::size_t> out;
  for (std::string_view id : ids) {
    const std::string f = family_of(id);
    auto it = std::find(families.begin(), families.end(), f);
    if (it == families.end()) it = families.insert(families.end(), f);
    out.push_back(static_cast<std::size_t>(it - families.begin()));
  }
  return out;
}

// "1e-3" for a power of ten, else "%g".
std::string short_number(double x) {
  if (x > 0 && std::isfinite(x)) {
    const double e = std::round(std::log10(x));
    if (std::abs(x / std::pow(10.0, e) - 1) < 1e-9) return fmt::format("1e{}", static_cast<int>(e));
  }
  return fmt::format("{:g}", x);
}

// κ tic labels "1e-3" … "1e4" on an axis that carries log10 κ.
std::string log10_kappa_tics(int lo, int hi) {
  std::string s = "(";
  for (int e = lo; e <= hi; ++e) s += fmt::format("{}'1e{}' {}", e == lo ? "" : ", ", e, e);
  return s + ")";
}

// ---- (a) clamped cosine ---------------------------------------------------------
Figure figure_a(const FiguresOptions& opt) {
  Figure f{"a_clamped_cosine", "Clamped-cosine approximation error and float numerical error",
           "α(e^{λu}−1) − u in double (approximation error, line) and float evaluation of α(exp(λu)−1) minus its double "
           "value (numerical error: one dot per float u, thin lines = min and max per 1/80 of the interval), "
           "u = cos θ ∈ [0, 1], published λ, α ([Tokuyoshi2022] supplementary Fig. 1).",
           {}, false, ""};
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
  io::write_file_atomic(opt.out / csv, numeric_csv({"u", "approximation_error", "numerical_error_float"}, rows));
  io::write_file_atomic(opt.out / ecsv, numeric_csv({"u_mid", "numerical_min", "numerical_max"}, env));
  const std::string body = fmt::format(
      "set title '[Tokuyoshi2022] supp. Fig. 1: clamped cosine ≈ α(exp(λu) − 1), λ = {:.6g}, α = {:.6g}; float vs double'\n"
      "set xlabel 'u = cos θ'\nset ylabel 'difference from u'\nset grid\nset key top left box opaque\n"
      "set format y '%.1te%T'\nset format x '%g'\n"
      "plot {} u 1:3 w p pt 7 ps 0.25 lc rgb '#a01f77b4' title 'numerical error (float − double), max {:.3g}', \\\n"
      "     {} u 1:2 w l lw 1 lc rgb '#1f77b4' title 'numerical error, min and max per bin', \\\n"
      "     '' u 1:3 w l lw 1 lc rgb '#1f77b4' notitle, \\\n"
      "     {} u 1:2 w l lw 3 lc rgb '#ff7f0e' title 'approximation error (double), max {:.3g}'",
      p.lambda, p.alpha, gp_quote(csv), max_n, gp_quote(ecsv), gp_quote(csv), max_a);
  f.files.push_back(csv);
  f.files.push_back(ecsv);
  for (auto& x : render(opt, f.id, body, 1000, 650)) f.files.push_back(x);
  return f;
}

// ---- (b) steepness ------------------------------------------------------------
Figure figure_b(const FiguresOptions& opt) {
  Figure f{"b_steepness", "Optimal steepness t*(κ) vs fitted t(κ) and √(κ/2)",
           "Top: per-κ optimal t*(κ) (dots; fit::optimal_steepness, 40 log-spaced κ in [1e-2, 1e3]), the published "
           "t(κ) ([Tokuyoshi2022] Eq. 6), sglab's refit steepness2022_optimal_t, and the asymptote √(κ/2) "
           "([Tokuyoshi2022] supplementary Fig. 2). Bottom: relative difference |t/t* − 1| of each curve.",
           {}, false, ""};
  std::vector<double> ks;
  for (int i = 0; i < 40; ++i) ks.push_back(std::pow(10.0, -2 + 5.0 * i / 39));
  std::vector<double> ts(ks.size(), std::nan(""));
  if (opt.optimal_steepness)
    ts = opt.optimal_steepness(ks);
  else
    f.note = "t*(κ) not available (no optimal-steepness function given)";
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const double tp = steepness2022(ks[i]), tr = steepness2022(ks[i], constants::steepness2022_optimal_t);
    const double ta = std::sqrt(ks[i] / 2);
    rows.push_back({ks[i], ts[i], tp, tr, ta, std::abs(tp / ts[i] - 1), std::abs(tr / ts[i] - 1),
                    std::abs(ta / ts[i] - 1)});
  }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv,
                        numeric_csv({"kappa", "t_optimal", "t_published", "t_refit_optimal_t", "sqrt_kappa_over_2",
                                     "reldiff_published", "reldiff_refit_optimal_t", "reldiff_sqrt_kappa_over_2"},
                                    rows));
  const std::string body = fmt::format(
      "set multiplot title '[Tokuyoshi2022] supp. Fig. 2: steepness t(κ) of the normalized hemispherical integral'\n"
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
      "     '' u 1:7 w lp lw 2 pt 5 ps 0.6 dt (8,4) lc rgb '#2ca02c' title 'refit steepness2022_optimal_t'\n",
      kLogFormat, gp_quote(csv));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 900)) f.files.push_back(x);
  return f;
}

// ---- (c) irradiance at κ = 4 ------------------------------------------------------
Figure figure_c(const FiguresOptions& opt) {
  Figure f{"c_irradiance_kappa4", "Irradiance vs angle at κ = 4, every method, and its peak-relative error",
           "Top: E(θ) of the reference (quadrature) and Ê(θ) of every registered irradiance method (double) for a "
           "unit-amplitude SG light with κ = 4, θ ∈ [0°, 180°] (the chart of [Pettineo2016]). Bottom: "
           "|Ê − E| / E(1, κ) on a log scale (the peak_rel error of docs/quantities.md). Solid: published constants; "
           "dashed: sglab refits; thick dash-dot: sglab's own models.",
           {}, false, ""};
  const double kappa = 4;
  const int n = 181;
  std::vector<validate::Query> q;
  for (int i = 0; i < n; ++i) q.push_back({kappa, std::clamp(std::cos(kPi * i / (n - 1)), -1.0, 1.0)});
  const auto ref = validate::reference_engine().evaluate(q);
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
  std::string top = fmt::format("plot {} u 1:2 w l lw 5 lc rgb '#000000' dt 3 title 'reference E'", gp_quote(csv));
  std::string bottom = "plot ";
  std::vector<std::string_view> ids;
  for (const Method& m : irradiance_methods) ids.push_back(m.id);
  const std::vector<std::size_t> fam = family_indices(ids);
  std::size_t i = 0;
  for (const Method& m : irradiance_methods) {
    const std::string style = line_style(fam[i], m.origin);
    top += fmt::format(", \\\n     '' u 1:{} w l {} title {}", i + 3, style, gp_quote(std::string(m.id) + origin_suffix(m.origin)));
    bottom += fmt::format("{}{} u 1:{} w l {} notitle", i ? ", \\\n     " : "", i ? "''" : gp_quote(ecsv), i + 2, style);
    ++i;
  }
  const std::string body = fmt::format(
      "set multiplot title 'Irradiance from a unit SG light at κ = 4, double (after the chart of [Pettineo2016])'\n"
      "set grid\nset xrange [0:180]\nset xtics 30\n"
      "set lmargin at screen 0.08\nset rmargin at screen 0.72\n"
      "set tmargin at screen 0.94\nset bmargin at screen 0.56\n"
      "set key at screen 0.735, screen 0.94 left top Left reverse font ',10' samplen 5 spacing 1.1\n"
      "set xlabel 'θ (degrees) between light axis and normal'\nset ylabel 'E'\nset format y '%g'\n{}\n"
      "set tmargin at screen 0.47\nset bmargin at screen 0.07\nunset key\n"
      "set ylabel '|Ê − E| / E(1, κ)'\nset logscale y\nset yrange [1e-8:1]\nset format y '{}'\n{}\n",
      top, kLogFormat, bottom);
  f.files.push_back(csv);
  f.files.push_back(ecsv);
  for (auto& x : render(opt, f.id, body, 1300, 1050)) f.files.push_back(x);
  return f;
}

// The float and double sweep over the standard grid that figures (d) and (g) share.
validate::SweepResult irradiance_sweep(std::vector<validate::SweepMethod>& methods) {
  for (const validate::SweepMethod& m : validate::registered_sweep_methods())
    if (m.quantity == validate::Quantity::irradiance) methods.push_back(m);
  validate::SweepOptions so;
  so.precisions = {validate::FloatFormat::binary32, validate::FloatFormat::binary64};
  so.progress = false;
  so.keep_points = true;
  return sweep(validate::SweepGrid{}, methods, so);
}

// ---- (d) heat maps ---------------------------------------------------------------
Figure figure_d(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods, const validate::SweepResult& res) {
  Figure f{"d_peak_rel_heatmaps", "peak_rel error heat maps over (κ, c), float",
           "peak_rel = |Ê − E|/E(1, κ) of every registered irradiance method evaluated in float on the standard grid "
           "(29 κ log-spaced in [1e-3, 1e4] × 41 c, docs/quantities.md), one panel per method, one shared log colour "
           "scale clamped to [1e-7, 10] (errors above 10 show as 10; grey: non-finite output). The panel title gives "
           "the method's max.",
           {}, false, ""};
  std::vector<std::string> header = {"log10_kappa", "cosine"};
  std::vector<const validate::SweepEntry*> entries;
  for (const validate::SweepMethod& m : methods) {
    header.emplace_back(m.method.id);
    entries.push_back(res.find(m.method.id, validate::Quantity::irradiance, validate::FloatFormat::binary32));
  }
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < res.kappas.size(); ++k)
    for (std::size_t j = 0; j < res.cosines.size(); ++j) {
      std::vector<double> r = {std::log10(res.kappas[k]), res.cosines[j]};
      for (const validate::SweepEntry* e : entries) r.push_back(e ? e->peak_rel[res.index(k, j)] : std::nan(""));
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
      "set xlabel 'κ' offset 0,0.5\nset ylabel 'c = cos θ' offset 0.5,0\nset xrange [-3.125:4.125]\nset yrange [-1.025:1.025]\n"
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
      body += fmt::format("set colorbox user origin screen 0.91, screen 0.15 size screen 0.018, screen {:.4f}\n",
                          top - 0.2);
    body += fmt::format(
        "set title {} font ',12'\nplot {} u 1:2:(v=column({}), v!=v ? 1/0 : (v < 1e-7 ? 1e-7 : (v > 10 ? 10 : v))) with image\n",
        gp_quote(fmt::format("{}{} (max {})", methods[i].method.id, origin_suffix(methods[i].method.origin),
                             fmt::format("{:.2g}", mx))),
        gp_quote(csv), i + 3);
  }
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1600, height)) f.files.push_back(x);
  return f;
}

// ---- (g) max peak_rel against κ ------------------------------------------------------
Figure figure_g(const FiguresOptions& opt, const std::vector<validate::SweepMethod>& methods, const validate::SweepResult& res) {
  Figure f{"g_peak_rel_vs_kappa", "Max peak_rel over c against κ, every method, float and double",
           "For each of the 29 κ of the standard grid, the max over the 41 cosines of peak_rel = |Ê − E|/E(1, κ), one "
           "line per registered irradiance method (log-log), in float (left) and double (right). A gap: the method "
           "returned a non-finite value at that κ. The dotted line at 1 is an error as large as the peak itself. "
           "Solid: published constants; dashed: sglab refits; thick dash-dot: sglab's own models.",
           {}, false, ""};
  std::vector<std::string> header = {"kappa"};
  for (const char* prec : {"float", "double"})
    for (const validate::SweepMethod& m : methods) header.push_back(fmt::format("{}_{}", m.method.id, prec));
  std::vector<std::vector<double>> rows;
  std::size_t gaps = 0;
  for (std::size_t k = 0; k < res.kappas.size(); ++k) {
    std::vector<double> r = {res.kappas[k]};
    for (validate::FloatFormat fm : {validate::FloatFormat::binary32, validate::FloatFormat::binary64})
      for (const validate::SweepMethod& m : methods) {
        const validate::SweepEntry* e = res.find(m.method.id, validate::Quantity::irradiance, fm);
        double v = std::nan("");
        if (e && k < e->per_kappa.size()) {
          const validate::MetricSummary& s = e->per_kappa[k];
          if (s.nonfinite == 0) v = s.peak_rel.max;
          else ++gaps;
        }
        r.push_back(v > 0 ? v : std::nan(""));
      }
    rows.push_back(std::move(r));
  }
  if (gaps) f.note = fmt::format("{} (method, precision, κ) cells with a non-finite output are left as gaps", gaps);
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
      s += fmt::format(", \\\n     {} u 1:{} w l {} {}", gp_quote(csv), offset + i + 2, line_style(fam[i], m.origin),
                       titles ? "title " + gp_quote(std::string(m.id) + origin_suffix(m.origin)) : std::string("notitle"));
    }
    return s + "\n";
  };
  const std::string body = fmt::format(
      "set multiplot title 'Where each method fails: max over c of |Ê − E| / E(1, κ) against κ, standard grid' font ',14'\n"
      "set logscale xy\nset grid\nset format x '{0}'\nset format y '{0}'\nset xrange [1e-3:1e4]\nset yrange [1e-10:1e8]\n"
      "set xlabel 'κ'\nset ytics 100\n"
      "set tmargin at screen 0.92\nset bmargin at screen 0.09\n"
      "set lmargin at screen 0.06\nset rmargin at screen 0.40\n"
      "set title 'float'\nset ylabel 'max peak_rel over c'\nunset key\n{1}"
      "set lmargin at screen 0.44\nset rmargin at screen 0.78\n"
      "set title 'double'\nunset ylabel\nset format y ''\n"
      "set key at screen 0.795, screen 0.92 left top Left reverse font ',10' samplen 5 spacing 1.1\n{2}",
      kLogFormat, panel(0, false), panel(nm, true));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1600, 800)) f.files.push_back(x);
  return f;
}

// ---- (e) Pareto ------------------------------------------------------------------
// Methods whose max peak_rel exceeds this (an error larger than the lobe's peak
// value) fail on the range: drawn in a band above the chart, not on its axis.
constexpr double kParetoFail = 1.0;

// One panel of figure (e): the rows of one cost source (cost_source column).
struct ParetoPanel {
  std::string source, unit;
  std::vector<ParetoRow> rows;
};

// Where a panel's plot area sits, in pixels of the whole image (y down), and
// the axes' ranges it shows (log10 of x and y).
struct PanelFrame {
  double width, height;  // the image
  double left, right, top, bottom;
  double lx0, lx1, ly0, ly1;
  double px(double x) const { return left + (std::log10(x) - lx0) / (lx1 - lx0) * (right - left); }
  double py(double y) const { return bottom - (std::log10(y) - ly0) / (ly1 - ly0) * (bottom - top); }
};

// The x-axis label of a cost source ("gpu:navi21" → GPU inverse throughput …).
std::string cost_axis_label(const ParetoPanel& p) {
  const auto parsed = parse_cost_source(p.source);
  if (const auto* s = std::get_if<CostSource>(&parsed)) return s->describe();
  return fmt::format("cost ({})", p.unit);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

// Point labels of one panel, placed in pixel space so that no two overlap and
// none covers a point: for each point (cheapest first) the first free spot
// among right, left, above, below and the diagonals. gnuplot `set label`s.
std::string pareto_labels(const std::vector<ParetoRow>& rows, const PanelFrame& g, double band_y) {
  struct Box {
    double x0, y0, x1, y1;
    bool hits(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  };
  std::vector<Box> taken;
  for (const ParetoRow& r : rows) {
    const double y = r.max_peak_rel > kParetoFail ? band_y : r.max_peak_rel;
    taken.push_back({g.px(r.cost) - 8, g.py(y) - 8, g.px(r.cost) + 8, g.py(y) + 8});
  }
  std::vector<std::size_t> by_cost(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) by_cost[i] = i;
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](std::size_t a, std::size_t b) { return rows[a].cost < rows[b].cost; });
  std::string labels;
  int label_id = 10;
  for (std::size_t idx : by_cost) {
    const ParetoRow& r = rows[idx];
    const bool fails = r.max_peak_rel > kParetoFail;
    const std::string text = (fails ? fmt::format("{} ({:.2g})", r.method, r.max_peak_rel) : r.method) +
                             (r.origin == Origin::sglab ? " [sglab]" : "");
    const double cx = g.px(r.cost), cy = g.py(fails ? band_y : r.max_peak_rel);
    const double w = 6.2 * static_cast<double>(text.size()) + 4, h = 14;
    // Candidate boxes: (left edge, top edge) relative to the point.
    const double cand[][2] = {{11, -h / 2},      {-11 - w, -h / 2}, {-w / 2, -11 - h}, {-w / 2, 11},
                              {9, -9 - h},       {9, 9},            {-9 - w, -9 - h},  {-9 - w, 9},
                              {11, -h / 2 - 14}, {11, -h / 2 + 14}, {-w / 2, -25 - h}, {-w / 2, 25}};
    // The first free spot inside the panel; else the first inside it (panels sit side by side: a
    // label past the frame would run into the next one); else the right of the point.
    std::optional<Box> free, inside;
    for (const auto& c : cand) {
      const Box bx{cx + c[0], cy + c[1], cx + c[0] + w, cy + c[1] + h};
      if (bx.x0 < g.left || bx.x1 > g.right || bx.y0 < g.top || bx.y1 > g.bottom) continue;
      if (!inside) inside = bx;
      if (std::none_of(taken.begin(), taken.end(), [&](const Box& t) { return t.hits(bx); })) {
        free = bx;
        break;
      }
    }
    const Box chosen = free    ? *free
                       : inside ? *inside
                                : Box{cx + cand[0][0], cy + cand[0][1], cx + cand[0][0] + w, cy + cand[0][1] + h};
    taken.push_back(chosen);
    // Back to data coordinates: the label's left end, vertically centred.
    const double ax = std::pow(10.0, g.lx0 + (chosen.x0 + 2 - g.left) / (g.right - g.left) * (g.lx1 - g.lx0));
    const double ay = std::pow(10.0, g.ly0 + (g.bottom - (chosen.y0 + chosen.y1) / 2) / (g.bottom - g.top) * (g.ly1 - g.ly0));
    labels += fmt::format("set label {} {} at first {:.6g}, first {:.6g} left font ',9'{}\n", label_id++, gp_quote(text),
                          ax, ay, r.origin == Origin::sglab ? " tc rgb '#000000' front" : " front");
  }
  return labels;
}

// Writes the points and frontier CSVs of one panel (file names in `files`) and
// returns its gnuplot `plot` command; with `key`, the legend entries too.
std::string pareto_plot(const FiguresOptions& opt, const std::string& stem, const std::vector<ParetoRow>& rows,
                        const std::vector<std::string>& families, double band_y, bool key,
                        std::vector<fs::path>& files) {
  std::vector<std::string> precisions;
  for (const ParetoRow& r : rows)
    if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end()) precisions.push_back(r.precision);
  // Points file: failing methods are moved into the band (plot_y); their true error stays in max_peak_rel.
  std::string pts = "cost,max_peak_rel,plot_y,method,origin,precision,frontier,label\n";
  for (const ParetoRow& r : rows) {
    const bool fails = r.max_peak_rel > kParetoFail;
    pts += fmt::format("{},{},{},{},{},{},{},{}\n", r.cost, r.max_peak_rel, fails ? band_y : r.max_peak_rel,
                       csv_field(r.method), to_string(r.origin), csv_field(r.precision), r.frontier ? 1 : 0,
                       csv_field(fails ? fmt::format("{} ({:.2g})", r.method, r.max_peak_rel) : r.method));
  }
  // Frontier: per precision, sorted by cost; two blank lines between precisions (gnuplot data blocks, `index`).
  std::string fr;
  std::vector<std::size_t> frontier_blocks;  // precision index of each data block (gnuplot `index`)
  for (std::size_t pi = 0; pi < precisions.size(); ++pi) {
    std::vector<ParetoRow> fp;
    for (const ParetoRow& r : rows)
      if (r.frontier && r.precision == precisions[pi] && r.max_peak_rel <= kParetoFail) fp.push_back(r);
    std::sort(fp.begin(), fp.end(), [](const ParetoRow& a, const ParetoRow& b) { return a.cost < b.cost; });
    if (fp.empty()) continue;
    fr += std::string(frontier_blocks.empty() ? "" : "\n\n") + "cost,max_peak_rel,precision\n";  // a header per block
    frontier_blocks.push_back(pi);
    for (const ParetoRow& r : fp) fr += fmt::format("{},{},{}\n", r.cost, r.max_peak_rel, csv_field(r.precision));
  }
  const std::string csv = stem + "_points.csv", fcsv = stem + "_frontier.csv";
  io::write_file_atomic(opt.out / csv, pts);
  io::write_file_atomic(opt.out / fcsv, fr.empty() ? "cost,max_peak_rel,precision\n" : fr);
  files.push_back(csv);
  files.push_back(fcsv);
  // Open/filled point-type pairs: circle, square, triangle up, triangle down, diamond, pentagon.
  static const int kOpen[] = {6, 4, 8, 10, 12, 14};
  static const char* kFrontier[] = {"#444444", "#d62728", "#2ca02c", "#9467bd"};
  std::string plot = "plot ";
  for (std::size_t b = 0; b < frontier_blocks.size(); ++b)
    plot += fmt::format("{} index {} u 1:2 w l lw 1.5 lc rgb '{}' {}, \\\n     ", gp_quote(fcsv), b,
                        kFrontier[frontier_blocks[b] % 4],
                        key ? "title " + gp_quote("Pareto frontier" +
                                                  (precisions.size() > 1 ? ", " + precisions[frontier_blocks[b]] : ""))
                            : std::string("notitle"));
  // Plot elements, one per row, selecting its line of the points file ($0 is the data line number).
  // Refits and sglab models (filled) first, published (open, larger) on top: a published method and
  // its refit at nearly the same place read as a ring around a dot.
  std::vector<std::size_t> order(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return (rows[a].origin == Origin::published) < (rows[b].origin == Origin::published);
  });
  std::vector<std::string> elements(rows.size());
  for (std::size_t idx : order) {
    const ParetoRow& r = rows[idx];
    const std::size_t fam =
        static_cast<std::size_t>(std::find(families.begin(), families.end(), family_of(r.method)) - families.begin());
    const int shape = kOpen[fam % 6] + (r.origin == Origin::published ? 0 : 1);
    const char* colour = kPalette[fam % kPaletteSize];
    const std::string title = r.method + origin_suffix(r.origin) + (precisions.size() > 1 ? ", " + r.precision : "");
    const std::string sel = fmt::format("($0 == {} ? $3 : 1/0)", idx);
    if (r.origin == Origin::sglab)
      plot += fmt::format("{} u 1:{} w p pt 7 ps 3.4 lc rgb '#000000' notitle, \\\n     ", gp_quote(csv), sel);
    const double size = r.origin == Origin::sglab ? 2.5 : (r.origin == Origin::published ? 2.2 : 1.5);
    plot += fmt::format("{} u 1:{} w p pt {} ps {} lw 2 lc rgb '{}' notitle, \\\n     ", gp_quote(csv), sel, shape,
                        size, colour);
    elements[idx] = fmt::format("keyentry w p pt {} ps {} lw 2 lc rgb '{}' title {}", shape, size, colour,
                                gp_quote(title));
  }
  if (!key) return plot + "1/0 notitle\n";
  // The legend in the points' order (registry order; keyentry: a key line without data).
  for (std::size_t i = 0; i < rows.size(); ++i) plot += elements[i] + (i + 1 < rows.size() ? ", \\\n     " : "\n");
  return plot;
}

// The GPU panel's companion: the inverse throughput (cycles) of its methods on
// every other family of the cost table's "gpu" section (unsplit float GLSL
// rows), written as <stem>_families.csv and drawn as a monospaced table at
// screen position (x, y) downwards. Empty when there is no other family.
std::string gpu_family_table(const FiguresOptions& opt, const ParetoPanel& p, const std::string& stem, double x,
                             double y, double line, std::vector<fs::path>& files) {
  const auto parsed = parse_cost_source(p.source);
  const auto* source = std::get_if<CostSource>(&parsed);
  if (!opt.gpu || !source || source->kind != CostSourceKind::gpu) return "";
  std::vector<std::string> others;
  std::map<std::pair<std::string, std::string>, std::int64_t> cycles;  // (method, family)
  for (const shader::gpu::Row& r : opt.gpu->rows) {
    if (r.lang != shader::Language::glsl || r.split || r.precision != "float" || r.family == source->family) continue;
    if (std::find(others.begin(), others.end(), r.family) == others.end()) others.push_back(r.family);
    cycles[{r.method, r.family}] = r.stats.inverse_throughput;
  }
  if (others.empty()) return "";
  std::string csv = "method," + fmt::format("{}", fmt::join(others, ",")) + "\n";
  std::vector<std::string> lines = {"ACO inverse throughput (cycles per wave)",
                                    fmt::format("on the other families, {}:", opt.gpu->driver), fmt::format("{:<22}", "method")};
  for (const std::string& family : others) lines.back() += fmt::format("{:>10}", family);
  for (const ParetoRow& r : p.rows) {
    csv += csv_field(r.method);
    lines.push_back(fmt::format("{:<22}", r.method));
    for (const std::string& family : others) {
      const auto it = cycles.find({r.method, family});
      csv += it == cycles.end() ? "," : fmt::format(",{}", it->second);
      lines.back() += it == cycles.end() ? fmt::format("{:>10}", "-") : fmt::format("{:>10}", it->second);
    }
    csv += "\n";
  }
  io::write_file_atomic(opt.out / (stem + "_families.csv"), csv);
  files.push_back(stem + "_families.csv");
  std::string labels;
  for (std::size_t i = 0; i < lines.size(); ++i)
    labels += fmt::format("set label {} {} at screen {:.5f}, screen {:.5f} left font 'DejaVu Sans Mono,8'\n", 1000 + i,
                          gp_quote(lines[i]), x, y - line * static_cast<double>(i));
  return labels;
}

// The plottable rows of the Pareto CSVs, one panel per cost source in order of
// first appearance; `note` says what was left out.
std::vector<ParetoPanel> pareto_panels(const FiguresOptions& opt, std::string& note, std::vector<std::string>& read) {
  std::vector<ParetoPanel> panels;
  std::size_t all = 0, kept = 0;
  for (const fs::path& path : opt.pareto) {
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    read.push_back(path.string());
    for (ParetoRow& r : read_pareto_csv(path)) {
      ++all;
      if (!(r.cost > 0 && std::isfinite(r.cost) && r.max_peak_rel > 0 && !std::isnan(r.max_peak_rel))) continue;
      ++kept;
      auto it = std::find_if(panels.begin(), panels.end(), [&](const ParetoPanel& p) { return p.source == r.cost_source; });
      if (it == panels.end()) it = panels.insert(panels.end(), ParetoPanel{r.cost_source, r.cost_unit, {}});
      it->rows.push_back(std::move(r));
    }
  }
  if (kept < all) note = fmt::format("{} of {} rows without a positive finite cost and error are not plotted", all - kept, all);
  return panels;
}

// Draws the panels side by side (the legend right of the last), sharing the
// error axis, into f.id.{png,svg}.
Figure render_pareto(const FiguresOptions& opt, const std::vector<ParetoPanel>& panels, Figure f) {
  std::vector<std::string> families, precisions;  // families (family_of) in order of first appearance
  std::set<std::pair<double, double>> ranges;
  double ymin = INFINITY;
  bool any_fail = false;
  for (const ParetoPanel& p : panels)
    for (const ParetoRow& r : p.rows) {
      if (std::find(families.begin(), families.end(), family_of(r.method)) == families.end())
        families.push_back(family_of(r.method));
      if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end())
        precisions.push_back(r.precision);
      ranges.insert({r.kappa_lo, r.kappa_hi});
      if (r.max_peak_rel > kParetoFail) any_fail = true;
      else ymin = std::min(ymin, r.max_peak_rel);
    }
  if (!std::isfinite(ymin)) ymin = 1e-3;
  const std::string range = ranges.size() == 1 ? fmt::format("κ ∈ [{}, {}]", short_number(ranges.begin()->first),
                                                              short_number(ranges.begin()->second))
                                               : std::string("κ ranges differ per row");
  const double y_lo = std::pow(10.0, std::floor(std::log10(ymin)) - 0.5);
  const double band_lo = kParetoFail * 1.8, band_hi = kParetoFail * 60, band_y = kParetoFail * 10;
  const double y_hi = any_fail ? band_hi : kParetoFail * 3;
  // Layout in pixels: a 640-pixel slot per panel (80 of margin on its left), the legend after them
  // (wider when the GPU families' table goes under it).
  const double slot = 640, plot_w = 540, legend_w = opt.gpu ? 450 : 330, H = 800, top = 0.1 * H, bottom = 0.91 * H;
  const double W = slot * static_cast<double>(panels.size()) + legend_w;
  std::string body = fmt::format(
      "set multiplot title 'Cost vs accuracy of the irradiance methods: {}, {} (29 κ × 41 c)' font ',14'\n"
      "set ylabel 'max peak_rel error over the range'\nset logscale xy\nset grid\nset format x '%g'\n"
      "set format y '{}'\nset yrange [{}:{}]\nset tmargin at screen {}\nset bmargin at screen {}\n",
      fmt::join(precisions, ", "), range, kLogFormat, y_lo, y_hi, 1 - top / H, 1 - bottom / H);
  std::string band_label;  // `unset label` clears it with each panel's point labels
  if (any_fail) {
    body += fmt::format(
        "set object 2 rect from graph 0, first {} to graph 1, first {} behind fc rgb '#fde0dd' fs solid noborder\n",
        band_lo, band_hi);
    band_label = fmt::format("set label 3 'fails on this range: max peak_rel > {} (true value in brackets)' at graph "
                             "0.01, first {} left font ',9' tc rgb '#a50f15'\n",
                             kParetoFail, band_hi / 1.6);
  }
  const auto stem_of = [&](std::size_t i) { return panels.size() == 1 ? f.id : fmt::format("{}_{}", f.id, i + 1); };
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const ParetoPanel& p = panels[i];
    double xmin = INFINITY, xmax = 0;
    for (const ParetoRow& r : p.rows) xmin = std::min(xmin, r.cost), xmax = std::max(xmax, r.cost);
    const double left = 80 + slot * static_cast<double>(i);
    const PanelFrame g{W, H, left, left + plot_w, top, bottom, std::log10(xmin / 2), std::log10(xmax * 3),
                       std::log10(y_lo), std::log10(y_hi)};
    const bool last = i + 1 == panels.size();
    const std::string stem = stem_of(i);
    body += fmt::format(
        "set title {} font ',12'\nset xlabel {}\nset xrange [{}:{}]\n"
        "set lmargin at screen {}\nset rmargin at screen {}\n{}\nunset label\n{}{}",
        gp_quote("--cost " + p.source), gp_quote(cost_axis_label(p)), xmin / 2, xmax * 3, g.left / W, g.right / W,
        last ? fmt::format("set key at screen {}, screen {} left top font ',10' spacing 1.15 box", (g.right + 30) / W,
                           1 - top / H)
             : std::string("unset key"),
        band_label, pareto_labels(p.rows, g, band_y));
    // The other GPU families of the first GPU panel under the legend (screen positions: set with the last panel).
    for (std::size_t k = 0; last && k < panels.size(); ++k) {
      const std::string table = gpu_family_table(opt, panels[k], stem_of(k), (g.right + 30) / W, 0.43, 13 / H, f.files);
      body += table;
      if (!table.empty()) break;
    }
    body += pareto_plot(opt, stem, p.rows, families, band_y, last, f.files);
  }
  for (auto& x : render(opt, f.id, body, static_cast<int>(W), static_cast<int>(H))) f.files.push_back(x);
  return f;
}

Figure figure_e(const FiguresOptions& opt) {
  std::vector<std::string> paths;
  for (const fs::path& p : opt.pareto) paths.push_back(p.string());
  Figure f{"e_pareto", "Pareto chart: cost vs accuracy",
           fmt::format("cost vs max peak_rel (log-log) from `sglab pareto` ({}), one panel per cost source (`--cost`: "
                       "GPU inverse throughput is ACO's estimate of the cycles one wave keeps a SIMD busy, a compiler "
                       "estimate, not a timing; CPU ns/eval from `sglab bench`); marker shape and colour "
                       "per method family, open = published constants, filled = sglab refit, large filled with a "
                       "black ring = sglab's own model; frontier line per precision. Methods whose max peak_rel "
                       "exceeds {} fail on the range and sit in the shaded band at the top, labelled with their error; "
                       "the frontier line joins only the methods below the band.",
                       fmt::join(paths, ", "), kParetoFail),
           {}, false, ""};
  std::vector<std::string> read;
  const std::vector<ParetoPanel> panels = pareto_panels(opt, f.note, read);
  if (read.empty() || panels.empty()) {
    f.skipped = true;
    f.note = read.empty() ? fmt::format("skipped: {} not found (run `sglab pareto` first, or pass --pareto FILE)",
                                        fmt::join(paths, ", "))
                          : fmt::format("skipped: {} has no plottable rows", fmt::join(read, ", "));
    return f;
  }
  return render_pareto(opt, panels, std::move(f));
}

// ---- (f) erf ulp ------------------------------------------------------------------
Figure figure_f(const FiguresOptions& opt) {
  Figure f{"f_erf_ulp", "erf error in float ulps over x",
           "Max ulp error per bin of x ∈ [0, 4) (400 bins) of the erf variants listing5 ([Tokuyoshi2022] Listing 5), "
           "as7125 ([AS1964] 7.1.25) and std evaluated in float, against the correctly rounded float erf "
           "(validate/erf_check, sample mode: every 257th float pattern plus a uniform grid of 2^20 points).",
           {}, false, ""};
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
    std::vector<double> r = {0.5 * (reports.front().series[b].x_lo + reports.front().series[b].x_hi)};
    for (const validate::ErfReport& rep : reports)
      r.push_back(b < rep.series.size() && rep.series[b].count ? rep.series[b].max_ulp : std::nan(""));
    rows.push_back(std::move(r));
  }
  std::string maxes;
  for (const validate::ErfReport& rep : reports) maxes += fmt::format("{}{} max {:.3g} ulp", maxes.empty() ? "" : ", ", rep.variant, rep.stats.max_ulp);
  f.note = maxes;
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  const std::string body = fmt::format(
      "set title 'erf in float: max error per bin (ulps of the exact erf(x))'\n"
      "set xlabel 'x'\nset ylabel 'max ulp error in bin'\nset logscale y\nset grid\nset xrange [0:4]\n"
      "set key top right box opaque\nset format y '{}'\nset format x '%g'\n"
      "plot for [i=2:{}] {} u 1:(column(i) > 0 ? column(i) : 1/0) w l lw 2 title columnheader(i)",
      kLogFormat, header.size(), gp_quote(csv));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 650)) f.files.push_back(x);
  return f;
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"')
          cur += '"', ++i;
        else
          quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

bool parse_bool(const std::string& s, bool& out) {
  std::string l;
  for (char c : s) l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (l == "true" || l == "1" || l == "yes") return out = true, true;
  if (l == "false" || l == "0" || l == "no" || l.empty()) return out = false, true;
  return false;
}

double parse_number(const std::string& s, const fs::path& path, std::size_t line, const char* col) {
  std::string t = s;
  if (t == "nan" || t.empty()) return std::nan("");
  if (t == "inf") return INFINITY;
  try {
    std::size_t pos = 0;
    const double x = std::stod(t, &pos);
    if (pos == t.size()) return x;
  } catch (...) {
  }
  throw std::invalid_argument(fmt::format("{}:{}: column {}: '{}' is not a number", path.string(), line, col, s));
}

}  // namespace

std::vector<ParetoRow> read_pareto_csv(const fs::path& path) {
  const std::string text = io::read_input_file(path, kMaxParetoCsvBytes, "a Pareto CSV");
  std::istringstream in(std::string(io::strip_utf8_bom(text)));  // a byte-order mark is not part of the header
  std::string line;
  std::size_t lineno = 0;
  std::vector<std::string> header;
  std::map<std::string, std::size_t> col;
  std::vector<ParetoRow> rows;
  static const char* kRequired[] = {"method", "origin", "precision", "kappa_lo", "kappa_hi", "max_peak_rel",
                                     "frontier"};
  bool legacy = false;  // ns_per_eval instead of cost, cost_unit, cost_source
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line == "\r") continue;
    auto cells = split_csv_line(line);
    if (header.empty()) {
      header = cells;
      for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
      for (const char* r : kRequired)
        if (!col.count(r))
          throw std::invalid_argument(fmt::format("{}: header lacks column '{}' (expected "
                                                  "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,"
                                                  "cost_source,max_peak_rel,frontier)",
                                                  path.string(), r));
      legacy = !col.count("cost") && col.count("ns_per_eval");
      for (const char* r : {"cost", "cost_unit", "cost_source"})
        if (!legacy && !col.count(r))
          throw std::invalid_argument(fmt::format("{}: header lacks column '{}' (nor has it the ns_per_eval of an "
                                                  "older `sglab pareto`)",
                                                  path.string(), r));
      continue;
    }
    if (cells.size() != header.size())
      throw std::invalid_argument(
          fmt::format("{}:{}: {} fields, the header has {}", path.string(), lineno, cells.size(), header.size()));
    ParetoRow r;
    r.method = cells[col["method"]];
    r.precision = cells[col["precision"]];
    const std::string& origin = cells[col["origin"]];
    if (origin == to_string(Origin::published))
      r.origin = Origin::published;
    else if (origin == to_string(Origin::refit))
      r.origin = Origin::refit;
    else if (origin == to_string(Origin::sglab))
      r.origin = Origin::sglab;
    else
      throw std::invalid_argument(fmt::format("{}:{}: origin '{}' is not one of published, refit, sglab",
                                              path.string(), lineno, origin));
    if (!parse_bool(cells[col["frontier"]], r.frontier))
      throw std::invalid_argument(fmt::format("{}:{}: frontier must be true/false", path.string(), lineno));
    r.kappa_lo = parse_number(cells[col["kappa_lo"]], path, lineno, "kappa_lo");
    r.kappa_hi = parse_number(cells[col["kappa_hi"]], path, lineno, "kappa_hi");
    r.cost = parse_number(cells[col[legacy ? "ns_per_eval" : "cost"]], path, lineno, legacy ? "ns_per_eval" : "cost");
    r.cost_unit = legacy ? "ns" : cells[col["cost_unit"]];
    r.cost_source = legacy ? "cpu-batch" : cells[col["cost_source"]];
    r.max_peak_rel = parse_number(cells[col["max_peak_rel"]], path, lineno, "max_peak_rel");
    rows.push_back(std::move(r));
  }
  if (header.empty()) throw std::invalid_argument(fmt::format("{}: empty file (no header)", path.string()));
  return rows;
}

bool gnuplot_available(const std::string& gnuplot) {
  return !gnuplot.empty() && io::run_program({gnuplot, "--version"}) == 0;
}

std::vector<Figure> make_figures(const FiguresOptions& options) {
  if (!gnuplot_available(options.gnuplot))
    throw GnuplotMissing(fmt::format(
        "gnuplot ('{}') is not installed or does not run; install it (e.g. apt-get install gnuplot-nox) to render figures",
        options.gnuplot));
  // Bad input and a bad output folder are refused before any figure is computed or written.
  io::check_output_folder(options.out);
  for (const fs::path& p : options.pareto)
    if (std::error_code ec; fs::exists(p, ec)) read_pareto_csv(p);
  fs::create_directories(options.out);
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

  std::string md = "# sglab figures\n\nWritten by `sglab figures`. Each figure has its data CSV, the gnuplot script "
                   "that renders it (run `gnuplot <name>.gp` in this directory), a PNG and an SVG.\n\n";
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
