#include "figures.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <sglab/constants.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/registry.hpp>

#include "erf_check.hpp"
#include "io.hpp"
#include "reference.hpp"
#include "sweep.hpp"
#include "table.hpp"

namespace sglab::validate {

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
  io::write_file_atomic(gp, script);
  const fs::path log = dir / (stem + ".gp.log");
  // No shell: gnuplot runs in `dir` with an argument vector.
  const int status = io::run_program({opt.gnuplot, stem + ".gp"}, dir, stem + ".gp.log");
  if (status != 0) {
    std::string tail;
    try {
      tail = io::read_file(log);
      if (tail.size() > 2000) tail = tail.substr(tail.size() - 2000);
    } catch (...) {
    }
    throw std::runtime_error(fmt::format("gnuplot failed on {} (exit status {}); log {}:\n{}", gp.string(),
                                         status, log.string(), tail));
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

// ---- (a) clamped cosine ---------------------------------------------------------
Figure figure_a(const FiguresOptions& opt) {
  Figure f{"a_clamped_cosine", "Clamped-cosine approximation error and float numerical error",
           "α(e^{λu}−1) − u in double (approximation error) and float evaluation of α(exp(λu)−1) minus its double value "
           "(numerical error), u = cos θ ∈ [0, 1], published λ, α (seed 000 Fig. 1).",
           {}, false, ""};
  const auto p = constants::clamped_cosine_published;
  const float lf = static_cast<float>(p.lambda), af = static_cast<float>(p.alpha);
  std::vector<std::vector<double>> rows;
  const int n = 4001;
  double max_a = 0, max_n = 0;
  for (int i = 0; i < n; ++i) {
    const float uf = static_cast<float>(static_cast<double>(i) / (n - 1));
    const double u = uf;
    const double model = p.alpha * std::expm1(p.lambda * u);
    const double fl = af * (std::exp(lf * uf) - 1.0f);
    rows.push_back({u, model - u, fl - model});
    max_a = std::max(max_a, std::abs(model - u));
    max_n = std::max(max_n, std::abs(fl - model));
  }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv({"u", "approximation_error", "numerical_error_float"}, rows));
  const std::string body = fmt::format(
      "set title 'seed 000 Fig. 1: clamped cosine ≈ α(exp(λu) − 1), λ = {:.6g}, α = {:.6g}'\n"
      "set xlabel 'u = cos θ'\nset ylabel 'difference from u'\nset grid\nset key top left box opaque\n"
      "set format y '%.1e'\n"
      "plot {} u 1:3 w l lw 1 lc rgb '#1f77b4' title 'numerical error (float − double), max {:.3g}', \\\n"
      "     '' u 1:2 w l lw 3 lc rgb '#ff7f0e' title 'approximation error (double), max {:.3g}'",
      p.lambda, p.alpha, gp_quote(csv), max_n, max_a);
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 650)) f.files.push_back(x);
  return f;
}

// ---- (b) steepness ------------------------------------------------------------
Figure figure_b(const FiguresOptions& opt) {
  Figure f{"b_steepness", "Optimal steepness t*(κ) vs fitted t(κ) and √(κ/2)",
           "Dots: per-κ optimal t*(κ) (fit::optimal_steepness, 40 log-spaced κ in [1e-2, 1e3]); lines: published Eq. 6 "
           "t(κ), sglab's refit steepness2022_optimal_t, and the asymptote √(κ/2) (seed 000 Fig. 2).",
           {}, false, ""};
  std::vector<double> ks;
  for (int i = 0; i < 40; ++i) ks.push_back(std::pow(10.0, -2 + 5.0 * i / 39));
  std::vector<double> ts(ks.size(), std::nan(""));
  if (opt.optimal_steepness)
    ts = opt.optimal_steepness(ks);
  else
    f.note = "t*(κ) not available (no optimal-steepness function given)";
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < ks.size(); ++i)
    rows.push_back({ks[i], ts[i], steepness2022(ks[i]), steepness2022(ks[i], constants::steepness2022_optimal_t),
                    std::sqrt(ks[i] / 2)});
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv,
                        numeric_csv({"kappa", "t_optimal", "t_published", "t_refit_optimal_t", "sqrt_kappa_over_2"}, rows));
  const std::string body = fmt::format(
      "set title 'seed 000 Fig. 2: steepness t(κ) of the normalized hemispherical integral'\n"
      "set xlabel 'κ'\nset ylabel 't(κ)'\nset logscale xy\nset grid\nset key top left box opaque\n"
      "set format x '%.0e'\nset format y '%g'\n"
      "plot {} u 1:5 w l lw 2 dt 2 lc rgb '#7f7f7f' title '√(κ/2)', \\\n"
      "     '' u 1:3 w l lw 3 lc rgb '#ff7f0e' title 'published Eq. 6 t(κ)', \\\n"
      "     '' u 1:4 w l lw 2 lc rgb '#2ca02c' title 'refit steepness2022_optimal_t', \\\n"
      "     '' u 1:2 w p pt 7 ps 1.2 lc rgb '#1f77b4' title 'optimal t*(κ)'",
      gp_quote(csv));
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1000, 700)) f.files.push_back(x);
  return f;
}

// ---- (c) irradiance at κ = 4 ------------------------------------------------------
Figure figure_c(const FiguresOptions& opt) {
  Figure f{"c_irradiance_kappa4", "Irradiance vs angle at κ = 4, every method, and the error Ê − E",
           "Top: E(θ) of the reference (quadrature) and Ê(θ) of every registered irradiance method (double) for a "
           "unit-amplitude SG light with κ = 4, θ ∈ [0°, 180°] (seed 001's chart). Bottom: Ê − E.",
           {}, false, ""};
  const double kappa = 4;
  const int n = 181;
  std::vector<Query> q;
  for (int i = 0; i < n; ++i) q.push_back({kappa, std::clamp(std::cos(kPi * i / (n - 1)), -1.0, 1.0)});
  const auto ref = reference_engine().evaluate(q);
  std::vector<std::string> header = {"theta_deg", "reference"};
  for (const Method& m : irradiance_methods) header.emplace_back(m.id);
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < n; ++i) {
    std::vector<double> r = {180.0 * i / (n - 1), ref[i].irradiance};
    for (const Method& m : irradiance_methods) r.push_back(m.f64(q[i].cosine, kappa));
    rows.push_back(std::move(r));
  }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  const std::size_t last = header.size();
  const std::string body = fmt::format(
      "set multiplot layout 2,1 title 'Irradiance from a unit SG light, κ = 4 (seed 001 chart)'\n"
      "set grid\nset xrange [0:180]\nset xtics 30\nset key outside right top font ',9'\n"
      "set lmargin 12\nset rmargin 30\n"
      "set xlabel 'θ (degrees) between light axis and normal'\nset ylabel 'E'\n"
      "plot for [i=3:{2}] {1} u 1:i w l lw 1.5 title columnheader(i), \\\n"
      "     for [i={3}:{0}] {1} u 1:i w l lw 1.5 dt 2 title columnheader(i), \\\n"
      "     '' u 1:2 w l lw 4 lc rgb 'black' dt 3 title 'reference'\n"
      "set ylabel 'Ê − E'\nset format y '%.2f'\n"
      "plot for [i=3:{2}] {1} u 1:(column(i)-column(2)) w l lw 1.5 title columnheader(i), \\\n"
      "     for [i={3}:{0}] {1} u 1:(column(i)-column(2)) w l lw 1.5 dt 2 title columnheader(i), \\\n"
      "     0 w l lc rgb 'black' notitle\n",
      last, gp_quote(csv), std::min<std::size_t>(last, 10), std::min<std::size_t>(last, 10) + 1);
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1200, 1000)) f.files.push_back(x);
  return f;
}

// ---- (d) heat maps ---------------------------------------------------------------
Figure figure_d(const FiguresOptions& opt) {
  Figure f{"d_peak_rel_heatmaps", "peak_rel error heat maps over (log10 κ, c), float",
           "max peak_rel = |Ê − E|/E(1, κ) of every registered irradiance method evaluated in float on the SPEC §4 "
           "grid (29 κ in [1e-3, 1e4] × 41 c), log color scale clamped to [1e-7, 10] (errors above 10 show as 10; grey: "
           "non-finite output); one multiplot panel per method.",
           {}, false, ""};
  std::vector<SweepMethod> methods;
  for (const SweepMethod& m : registered_sweep_methods())
    if (m.quantity == Quantity::irradiance) methods.push_back(m);
  SweepOptions so;
  so.precisions = {FloatFormat::binary32};
  so.progress = false;
  so.keep_points = true;
  const SweepGrid grid;
  const SweepResult res = sweep(grid, methods, so);
  std::vector<std::string> header = {"log10_kappa", "cosine"};
  std::vector<const SweepEntry*> entries;
  for (const SweepMethod& m : methods) {
    header.emplace_back(m.method.id);
    entries.push_back(res.find(m.method.id, Quantity::irradiance, FloatFormat::binary32));
  }
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < res.kappas.size(); ++k)
    for (std::size_t j = 0; j < res.cosines.size(); ++j) {
      std::vector<double> r = {std::log10(res.kappas[k]), res.cosines[j]};
      for (const SweepEntry* e : entries) r.push_back(e ? e->peak_rel[res.index(k, j)] : std::nan(""));
      rows.push_back(std::move(r));
    }
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows, res.cosines.size()));
  const int cols = 4;
  const int nrows = static_cast<int>((methods.size() + cols - 1) / cols);
  std::string body = fmt::format(
      "set multiplot layout {},{} title 'peak_rel error |Ê − E| / E(1, κ), float, SPEC §4 grid (log color scale clamped to [1e-7, 10]; grey = non-finite)'\n"
      "set xlabel 'log10 κ'\nset ylabel 'c = cos θ'\nset xrange [-3.125:4.125]\nset yrange [-1.025:1.025]\n"
      "set logscale cb\nset cbrange [1e-7:10]\nset format cb '%.0e'\n"
      "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n"
      "set object 1 rect from graph 0,0 to graph 1,1 behind fc rgb '#bbbbbb' fs solid noborder\n"
      "set xtics 1 font ',8'\nset ytics 0.5 font ',8'\nset cbtics font ',8'\nunset key\n",
      nrows, cols);
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const double mx = entries[i] ? entries[i]->summary.peak_rel.max : std::nan("");
    body += fmt::format(
        "set title {}\nplot {} u 1:2:(v=column({}), v!=v ? 1/0 : (v < 1e-7 ? 1e-7 : (v > 10 ? 10 : v))) with image\n",
        gp_quote(fmt::format("{} (max {:.2g})", methods[i].method.id, mx)), gp_quote(csv), i + 3);
  }
  f.files.push_back(csv);
  for (auto& x : render(opt, f.id, body, 1600, 340 * nrows + 60)) f.files.push_back(x);
  return f;
}

// ---- (e) Pareto ------------------------------------------------------------------
Figure figure_e(const FiguresOptions& opt) {
  Figure f{"e_pareto", "Pareto chart: cost vs accuracy",
           fmt::format("ns per evaluation vs max peak_rel (log-log) from `sglab pareto` ({}); each point labelled with its "
                       "method, frontier line per precision.",
                       opt.pareto.string()),
           {}, false, ""};
  std::error_code ec;
  if (!fs::exists(opt.pareto, ec)) {
    f.skipped = true;
    f.note = fmt::format("skipped: {} not found (run `sglab pareto` first, or pass --pareto FILE)", opt.pareto.string());
    return f;
  }
  const auto all = read_pareto_csv(opt.pareto);
  std::vector<ParetoRow> rows;
  for (const ParetoRow& r : all)
    if (r.ns_per_eval > 0 && r.max_peak_rel > 0 && std::isfinite(r.ns_per_eval) && std::isfinite(r.max_peak_rel))
      rows.push_back(r);
  if (rows.size() < all.size())
    f.note = fmt::format("{} of {} rows without a positive finite cost and error are not plotted", all.size() - rows.size(),
                         all.size());
  if (rows.empty()) {
    f.skipped = true;
    f.note = fmt::format("skipped: {} has no plottable rows", opt.pareto.string());
    return f;
  }
  std::vector<std::string> precisions;
  for (const ParetoRow& r : rows)
    if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end()) precisions.push_back(r.precision);
  // Points file (text columns: written directly, quoted where needed).
  auto field = [](const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string o = "\"";
    for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
    return o + "\"";
  };
  std::string pts = "ns_per_eval,max_peak_rel,method,precision,frontier,label\n";
  for (const ParetoRow& r : rows)
    pts += fmt::format("{},{},{},{},{},{}\n", r.ns_per_eval, r.max_peak_rel, field(r.method), field(r.precision),
                       r.frontier ? 1 : 0, field(r.method + (r.refit ? "*" : "")));
  // Frontier: per precision, sorted by cost; two blank lines between precisions (gnuplot data blocks, `index`).
  std::string fr = "ns_per_eval,max_peak_rel,precision\n";
  bool any_frontier = false;
  std::vector<std::size_t> frontier_blocks;  // precision index of each data block (gnuplot `index`)
  for (std::size_t pi = 0; pi < precisions.size(); ++pi) {
    std::vector<ParetoRow> fp;
    for (const ParetoRow& r : rows)
      if (r.frontier && r.precision == precisions[pi]) fp.push_back(r);
    std::sort(fp.begin(), fp.end(), [](const ParetoRow& a, const ParetoRow& b) { return a.ns_per_eval < b.ns_per_eval; });
    if (fp.empty()) continue;
    if (any_frontier) fr += "\n\nns_per_eval,max_peak_rel,precision\n";  // each block has its header (columnhead)
    any_frontier = true;
    frontier_blocks.push_back(pi);
    for (const ParetoRow& r : fp) fr += fmt::format("{},{},{}\n", r.ns_per_eval, r.max_peak_rel, field(r.precision));
  }
  const std::string csv = f.id + "_points.csv", fcsv = f.id + "_frontier.csv";
  io::write_file_atomic(opt.out / csv, pts);
  io::write_file_atomic(opt.out / fcsv, fr);
  static const char* kPoint[] = {"7", "5", "9", "11", "13", "3"};
  static const char* kColor[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
  std::string plot = "plot ";
  for (std::size_t pi = 0; pi < precisions.size(); ++pi) {
    plot += fmt::format("{} u 1:(strcol(4) eq {} ? $2 : 1/0) w p pt {} ps 1.5 lc rgb '{}' title {}, \\\n     ",
                        gp_quote(csv), gp_quote(precisions[pi]), kPoint[pi % 6], kColor[pi % 6],
                        gp_quote(precisions[pi]));
  }
  for (std::size_t b = 0; b < frontier_blocks.size(); ++b)
    plot += fmt::format("{} index {} u 1:2 w l lw 2 lc rgb '{}' title {}, \\\n     ", gp_quote(fcsv), b,
                        kColor[frontier_blocks[b] % 6], gp_quote("Pareto frontier, " + precisions[frontier_blocks[b]]));
  plot += fmt::format("{} u 1:2:6 w labels left offset char 0.7,0.5 font ',8' notitle", gp_quote(csv));
  const std::string body = fmt::format(
      "set title 'Cost vs accuracy of the irradiance methods (* = refitted constants)'\n"
      "set xlabel 'cost (ns per evaluation)'\nset ylabel 'max peak_rel error'\nset logscale xy\nset grid\n"
      "set format y '%.0e'\nset key top right box opaque\nset offsets graph 0.05, graph 0.2, graph 0.1, graph 0.1\n{}",
      plot);
  f.files.push_back(csv);
  f.files.push_back(fcsv);
  for (auto& x : render(opt, f.id, body, 1200, 800)) f.files.push_back(x);
  return f;
}

// ---- (f) erf ulp ------------------------------------------------------------------
Figure figure_f(const FiguresOptions& opt) {
  Figure f{"f_erf_ulp", "erf error in float ulps over x",
           "Max ulp error per bin of x ∈ [0, 4) (400 bins) of the erf variants listing5, as7125 and std evaluated in "
           "float, against the correctly rounded float erf (validate/erf_check, sample mode: every 257th float "
           "pattern plus a uniform grid of 2^20 points).",
           {}, false, ""};
  ErfFloatOptions eo;
  eo.bins = 400;
  std::vector<std::string> header = {"x_mid"};
  std::vector<ErfReport> reports;
  for (const char* id : {"listing5", "as7125", "std"}) {
    const ErfVariant* v = find_erf_variant(id);
    if (!v) continue;
    reports.push_back(check_erf_float(v->f32, eo, v->id));
    header.emplace_back(v->id);
  }
  std::vector<std::vector<double>> rows;
  const std::size_t nb = reports.empty() ? 0 : reports.front().series.size();
  for (std::size_t b = 0; b < nb; ++b) {
    std::vector<double> r = {0.5 * (reports.front().series[b].x_lo + reports.front().series[b].x_hi)};
    for (const ErfReport& rep : reports)
      r.push_back(b < rep.series.size() && rep.series[b].count ? rep.series[b].max_ulp : std::nan(""));
    rows.push_back(std::move(r));
  }
  std::string maxes;
  for (const ErfReport& rep : reports) maxes += fmt::format("{}{} max {:.3g} ulp", maxes.empty() ? "" : ", ", rep.variant, rep.stats.max_ulp);
  f.note = maxes;
  const std::string csv = f.id + ".csv";
  io::write_file_atomic(opt.out / csv, numeric_csv(header, rows));
  const std::string body = fmt::format(
      "set title 'erf in float: max error per bin (ulps of the exact erf(x))'\n"
      "set xlabel 'x'\nset ylabel 'max ulp error in bin'\nset logscale y\nset grid\nset xrange [0:4]\n"
      "set key top right box opaque\nset format y '%g'\n"
      "plot for [i=2:{}] {} u 1:(column(i) > 0 ? column(i) : 1/0) w l lw 2 title columnheader(i)",
      header.size(), gp_quote(csv));
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
  const std::string text = io::read_file(path);
  std::istringstream in(std::string(io::strip_utf8_bom(text)));  // a byte-order mark is not part of the header
  std::string line;
  std::size_t lineno = 0;
  std::vector<std::string> header;
  std::map<std::string, std::size_t> col;
  std::vector<ParetoRow> rows;
  static const char* kRequired[] = {"method", "refit", "precision", "kappa_lo", "kappa_hi",
                                     "ns_per_eval", "max_peak_rel", "frontier"};
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
                                                  "method,refit,precision,kappa_lo,kappa_hi,ns_per_eval,max_peak_rel,frontier)",
                                                  path.string(), r));
      continue;
    }
    if (cells.size() != header.size())
      throw std::invalid_argument(
          fmt::format("{}:{}: {} fields, the header has {}", path.string(), lineno, cells.size(), header.size()));
    ParetoRow r;
    r.method = cells[col["method"]];
    r.precision = cells[col["precision"]];
    if (!parse_bool(cells[col["refit"]], r.refit) || !parse_bool(cells[col["frontier"]], r.frontier))
      throw std::invalid_argument(fmt::format("{}:{}: refit/frontier must be true/false", path.string(), lineno));
    r.kappa_lo = parse_number(cells[col["kappa_lo"]], path, lineno, "kappa_lo");
    r.kappa_hi = parse_number(cells[col["kappa_hi"]], path, lineno, "kappa_hi");
    r.ns_per_eval = parse_number(cells[col["ns_per_eval"]], path, lineno, "ns_per_eval");
    r.max_peak_rel = parse_number(cells[col["max_peak_rel"]], path, lineno, "max_peak_rel");
    rows.push_back(std::move(r));
  }
  if (header.empty()) throw std::invalid_argument(fmt::format("{}: empty file (no header)", path.string()));
  return rows;
}

bool gnuplot_available(const std::string& gnuplot) {
  return io::run_program({gnuplot, "--version"}) == 0;
}

std::vector<Figure> make_figures(const FiguresOptions& options) {
  if (!gnuplot_available(options.gnuplot))
    throw GnuplotMissing(fmt::format(
        "gnuplot ('{}') is not installed or does not run; install it (e.g. apt-get install gnuplot-nox) to render figures",
        options.gnuplot));
  fs::create_directories(options.out);
  std::vector<Figure> figs;
  figs.push_back(figure_a(options));
  figs.push_back(figure_b(options));
  figs.push_back(figure_c(options));
  figs.push_back(figure_d(options));
  figs.push_back(figure_e(options));
  figs.push_back(figure_f(options));

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

}  // namespace sglab::validate
