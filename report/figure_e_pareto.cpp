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

#include "cost/cost_source.hpp"
#include "cost/gpu_report.hpp"
#include "report/figure_style.hpp"
#include "report/gnuplot.hpp"
#include "report/pareto.hpp"

namespace sglab::report::figures_detail {

namespace fs = std::filesystem;

namespace {

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
  double py(double y) const {
    return bottom - (std::log10(y) - ly0) / (ly1 - ly0) * (bottom - top);
  }
};

// The x-axis label of a cost source ("gpu:navi21" → GPU cycles per light per pixel …).
std::string cost_axis_label(const ParetoPanel& p) {
  const auto parsed = cost::parse_cost_source(p.source);
  if (const auto* s = std::get_if<cost::CostSource>(&parsed)) return s->label();
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
  std::stable_sort(by_cost.begin(), by_cost.end(),
                   [&](std::size_t a, std::size_t b) { return rows[a].cost < rows[b].cost; });
  std::string labels;
  int label_id = 10;
  for (std::size_t idx : by_cost) {
    const ParetoRow& r = rows[idx];
    const bool fails = r.max_peak_rel > kParetoFail;
    const std::string text =
        (fails ? fmt::format("{} ({:.2g})", r.method, r.max_peak_rel) : r.method) +
        (r.origin == Origin::sglab ? " [sglab]" : "");
    const double cx = g.px(r.cost), cy = g.py(fails ? band_y : r.max_peak_rel);
    const double w = 6.2 * static_cast<double>(text.size()) + 4, h = 14;
    // Candidate boxes: (left edge, top edge) relative to the point.
    const double cand[][2] = {{11, -h / 2},      {-11 - w, -h / 2}, {-w / 2, -11 - h},
                              {-w / 2, 11},      {9, -9 - h},       {9, 9},
                              {-9 - w, -9 - h},  {-9 - w, 9},       {11, -h / 2 - 14},
                              {11, -h / 2 + 14}, {-w / 2, -25 - h}, {-w / 2, 25}};
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
    const Box chosen =
        free     ? *free
        : inside ? *inside
                 : Box{cx + cand[0][0], cy + cand[0][1], cx + cand[0][0] + w, cy + cand[0][1] + h};
    taken.push_back(chosen);
    // Back to data coordinates: the label's left end, vertically centred.
    const double ax =
        std::pow(10.0, g.lx0 + (chosen.x0 + 2 - g.left) / (g.right - g.left) * (g.lx1 - g.lx0));
    const double ay = std::pow(10.0, g.ly0 + (g.bottom - (chosen.y0 + chosen.y1) / 2) /
                                                 (g.bottom - g.top) * (g.ly1 - g.ly0));
    labels += fmt::format("set label {} {} at first {:.6g}, first {:.6g} left font ',9'{}\n",
                          label_id++, gp_quote(text), ax, ay,
                          r.origin == Origin::sglab ? " tc rgb '#000000' front" : " front");
  }
  return labels;
}

// Open/filled point-type pairs: circle, square, triangle up, triangle down, diamond, pentagon.
constexpr int kOpen[] = {6, 4, 8, 10, 12, 14};

// How a row is drawn, the same in every panel and in the legend: shape and colour per method
// family (`families`, family_of), open = published, filled = refit or sglab's own (larger).
struct PointStyle {
  int shape;
  double size;
  const char* colour;
};
PointStyle point_style(const ParetoRow& r, const std::vector<std::string>& families) {
  const std::size_t fam = static_cast<std::size_t>(
      std::find(families.begin(), families.end(), family_of(r.method)) - families.begin());
  return {kOpen[fam % 6] + (r.origin == Origin::published ? 0 : 1),
          r.origin == Origin::sglab ? 2.5 : (r.origin == Origin::published ? 2.2 : 1.5),
          kPalette[fam % kPaletteSize]};
}

// The rows of every panel, each (method, precision) once, for the legend: a method a panel
// lacks (no cost of that kind yet) is still named. Each panel's order is kept (registry
// order): a row missing from the rows so far goes right after the one it follows in its panel.
std::vector<ParetoRow> legend_rows(const std::vector<ParetoPanel>& panels) {
  std::vector<ParetoRow> legend;
  for (const ParetoPanel& p : panels) {
    std::size_t at = 0;
    for (const ParetoRow& r : p.rows) {
      const auto it = std::find_if(legend.begin(), legend.end(), [&](const ParetoRow& x) {
        return x.method == r.method && x.precision == r.precision;
      });
      if (it != legend.end()) {
        at = static_cast<std::size_t>(it - legend.begin()) + 1;
        continue;
      }
      legend.insert(legend.begin() + static_cast<std::ptrdiff_t>(at++), r);
    }
  }
  return legend;
}

// Writes the points and frontier CSVs of one panel (file names in `files`) and
// returns its gnuplot `plot` command; with `legend`, an entry for each of its rows too.
std::string pareto_plot(const FiguresOptions& opt, const std::string& stem,
                        const std::vector<ParetoRow>& rows,
                        const std::vector<std::string>& families, double band_y,
                        const std::vector<ParetoRow>* legend, std::vector<fs::path>& files) {
  const bool key = legend != nullptr;
  std::vector<std::string> precisions;
  for (const ParetoRow& r : rows)
    if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end())
      precisions.push_back(r.precision);
  // Points file: failing methods are moved into the band (plot_y); their true error stays in
  // max_peak_rel.
  std::string pts = "cost,max_peak_rel,plot_y,method,origin,precision,frontier,label\n";
  for (const ParetoRow& r : rows) {
    const bool fails = r.max_peak_rel > kParetoFail;
    pts += fmt::format(
        "{},{},{},{},{},{},{},{}\n", r.cost, r.max_peak_rel, fails ? band_y : r.max_peak_rel,
        csv_field(r.method), to_string(r.origin), csv_field(r.precision), r.frontier ? 1 : 0,
        csv_field(fails ? fmt::format("{} ({:.2g})", r.method, r.max_peak_rel) : r.method));
  }
  // Frontier: per precision, sorted by cost; two blank lines between precisions (gnuplot data
  // blocks, `index`).
  std::string fr;
  std::vector<std::size_t> frontier_blocks;  // precision index of each data block (gnuplot `index`)
  for (std::size_t pi = 0; pi < precisions.size(); ++pi) {
    std::vector<ParetoRow> fp;
    for (const ParetoRow& r : rows)
      if (r.frontier && r.precision == precisions[pi] && r.max_peak_rel <= kParetoFail)
        fp.push_back(r);
    std::sort(fp.begin(), fp.end(),
              [](const ParetoRow& a, const ParetoRow& b) { return a.cost < b.cost; });
    if (fp.empty()) continue;
    // a header per block
    fr += std::string(frontier_blocks.empty() ? "" : "\n\n") + "cost,max_peak_rel,precision\n";
    frontier_blocks.push_back(pi);
    for (const ParetoRow& r : fp)
      fr += fmt::format("{},{},{}\n", r.cost, r.max_peak_rel, csv_field(r.precision));
  }
  const std::string csv = stem + "_points.csv", fcsv = stem + "_frontier.csv";
  io::write_file_atomic(opt.out / csv, pts);
  io::write_file_atomic(opt.out / fcsv, fr.empty() ? "cost,max_peak_rel,precision\n" : fr);
  files.push_back(csv);
  files.push_back(fcsv);
  static const char* kFrontier[] = {"#444444", "#d62728", "#2ca02c", "#9467bd"};
  std::string plot = "plot ";
  for (std::size_t b = 0; b < frontier_blocks.size(); ++b)
    plot += fmt::format(
        "{} index {} u 1:2 w l lw 1.5 lc rgb '{}' {}, \\\n     ", gp_quote(fcsv), b,
        kFrontier[frontier_blocks[b] % 4],
        key ? "title " +
                  gp_quote("Pareto frontier" +
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
  for (std::size_t idx : order) {
    const ParetoRow& r = rows[idx];
    const PointStyle style = point_style(r, families);
    const std::string sel = fmt::format("($0 == {} ? $3 : 1/0)", idx);
    if (r.origin == Origin::sglab)
      plot += fmt::format("{} u 1:{} w p pt 7 ps 3.4 lc rgb '#000000' notitle, \\\n     ",
                          gp_quote(csv), sel);
    plot += fmt::format("{} u 1:{} w p pt {} ps {} lw 2 lc rgb '{}' notitle, \\\n     ",
                        gp_quote(csv), sel, style.shape, style.size, style.colour);
  }
  if (!key || legend->empty()) return plot + "1/0 notitle\n";
  // The legend (keyentry: a key line without data).
  for (std::size_t i = 0; i < legend->size(); ++i) {
    const ParetoRow& r = (*legend)[i];
    const PointStyle style = point_style(r, families);
    const std::string title =
        r.method + origin_suffix(r.origin) + (precisions.size() > 1 ? ", " + r.precision : "");
    plot +=
        fmt::format("keyentry w p pt {} ps {} lw 2 lc rgb '{}' title {}{}", style.shape, style.size,
                    style.colour, gp_quote(title), i + 1 < legend->size() ? ", \\\n     " : "\n");
  }
  return plot;
}

// The GPU panel's companion: the same GPU figure (gpu_row, gpu_cost: per light
// per pixel for gpu:FAMILY, one call for gpu-single:FAMILY) of its methods on
// every other family of the cost table's "gpu" section, written as
// <stem>_families.csv and drawn as a monospaced table at screen position
// (x, y) downwards. Empty when there is no other family.
std::string gpu_family_table(const FiguresOptions& opt, const ParetoPanel& p,
                             const std::string& stem, double x, double y, double line,
                             std::vector<fs::path>& files) {
  const auto parsed = cost::parse_cost_source(p.source);
  const auto* source = std::get_if<cost::CostSource>(&parsed);
  if (!opt.gpu || !source || source->kind != cost::CostSourceKind::gpu) return "";
  std::vector<std::string> others;
  for (const cost::gpu::Row& r : opt.gpu->rows)
    if (r.family != source->family &&
        std::find(others.begin(), others.end(), r.family) == others.end())
      others.push_back(r.family);
  std::map<std::pair<std::string, std::string>, double> cycles;  // (method, family)
  for (const std::string& family : others)
    for (const ParetoRow& r : p.rows) {
      cost::CostSource other = *source;
      other.family = family;
      if (const cost::gpu::Row* row = gpu_row(*opt.gpu, r.method, other))
        cycles[{r.method, family}] = gpu_cost(*row);
    }
  if (others.empty()) return "";
  std::string csv = "method," + fmt::format("{}", fmt::join(others, ",")) + "\n";
  std::vector<std::string> lines = {
      source->figure == cost::GpuFigure::single ? "GPU cycles of one call (ACO estimate)"
                                                : "GPU cycles per light per pixel (ACO estimate)",
      fmt::format("on the other families, {}:", opt.gpu->driver), fmt::format("{:<22}", "method")};
  for (const std::string& family : others) lines.back() += fmt::format("{:>10}", family);
  for (const ParetoRow& r : p.rows) {
    csv += csv_field(r.method);
    lines.push_back(fmt::format("{:<22}", r.method));
    for (const std::string& family : others) {
      const auto it = cycles.find({r.method, family});
      csv += it == cycles.end() ? "," : fmt::format(",{:.4g}", it->second);
      lines.back() +=
          it == cycles.end() ? fmt::format("{:>10}", "-") : fmt::format("{:>10.3g}", it->second);
    }
    csv += "\n";
  }
  io::write_file_atomic(opt.out / (stem + "_families.csv"), csv);
  files.push_back(stem + "_families.csv");
  std::string labels;
  for (std::size_t i = 0; i < lines.size(); ++i)
    labels += fmt::format(
        "set label {} {} at screen {:.5f}, screen {:.5f} left font 'DejaVu Sans Mono,8'\n",
        1000 + i, gp_quote(lines[i]), x, y - line * static_cast<double>(i));
  return labels;
}

// The plottable rows of the Pareto CSVs, one panel per cost source in order of
// first appearance; `note` says what was left out.
std::vector<ParetoPanel> pareto_panels(const FiguresOptions& opt, std::string& note,
                                       std::vector<std::string>& read) {
  std::vector<ParetoPanel> panels;
  std::size_t all = 0, kept = 0;
  for (const fs::path& path : opt.pareto) {
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    read.push_back(path.string());
    for (ParetoRow& r : read_pareto_csv(path)) {
      ++all;
      if (!(r.cost > 0 && std::isfinite(r.cost) && r.max_peak_rel > 0 &&
            !std::isnan(r.max_peak_rel)))
        continue;
      ++kept;
      auto it = std::find_if(panels.begin(), panels.end(),
                             [&](const ParetoPanel& p) { return p.source == r.cost_source; });
      if (it == panels.end())
        it = panels.insert(panels.end(), ParetoPanel{r.cost_source, r.cost_unit, {}});
      it->rows.push_back(std::move(r));
    }
  }
  if (kept < all)
    note = fmt::format("{} of {} rows without a positive finite cost and error are not plotted",
                       all - kept, all);
  return panels;
}

// Draws the panels side by side (the legend right of the last), sharing the
// error axis, into f.id.{png,svg}.
Figure render_pareto(const FiguresOptions& opt, const std::vector<ParetoPanel>& panels, Figure f) {
  // families (family_of) in order of first appearance
  std::vector<std::string> families, precisions;
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
      if (r.max_peak_rel > kParetoFail)
        any_fail = true;
      else
        ymin = std::min(ymin, r.max_peak_rel);
    }
  if (!std::isfinite(ymin)) ymin = 1e-3;
  const std::vector<ParetoRow> legend = legend_rows(panels);
  const std::string range = ranges.size() == 1
                                ? fmt::format("κ ∈ [{}, {}]", short_number(ranges.begin()->first),
                                              short_number(ranges.begin()->second))
                                : std::string("κ ranges differ per row");
  const double y_lo = std::pow(10.0, std::floor(std::log10(ymin)) - 0.5);
  const double band_lo = kParetoFail * 1.8, band_hi = kParetoFail * 60, band_y = kParetoFail * 10;
  const double y_hi = any_fail ? band_hi : kParetoFail * 3;
  // Layout in pixels: a 640-pixel slot per panel (80 of margin on its left), the legend after them
  // (wider when the GPU families' table goes under it).
  // The legend (one line per method and per frontier, about 17 pixels each at font 10 and
  // spacing 1.15) is at the top right, the GPU families' table (13 pixels a line) under it; the
  // image grows taller when the two would not fit in 800 pixels.
  std::size_t table_lines = 0;
  if (opt.gpu)
    for (const ParetoPanel& p : panels) table_lines = std::max(table_lines, 3 + p.rows.size());
  const double key_line = 17, table_line = 13, top = 80;
  const double table_top =
      top + key_line * static_cast<double>(legend.size() + precisions.size()) + 30;
  const double slot = 640, plot_w = 540, legend_w = opt.gpu ? 450 : 330,
               H = std::max(800.0, table_top + table_line * static_cast<double>(table_lines) + 20),
               bottom = H - 72;
  const double W = slot * static_cast<double>(panels.size()) + legend_w;
  std::string body = fmt::format(
      "set multiplot title 'Cost vs accuracy of the irradiance methods: {}, {} (29 κ × 41 c)' font "
      "',14'\n"
      "set ylabel 'max peak_rel error over the range'\nset logscale xy\nset grid\nset format x "
      "'%g'\n"
      "set format y '{}'\nset yrange [{}:{}]\nset tmargin at screen {}\nset bmargin at screen {}\n",
      fmt::join(precisions, ", "), range, kLogFormat, y_lo, y_hi, 1 - top / H, 1 - bottom / H);
  std::string band_label;  // `unset label` clears it with each panel's point labels
  if (any_fail) {
    body += fmt::format(
        "set object 2 rect from graph 0, first {} to graph 1, first {} behind fc rgb '#fde0dd' fs "
        "solid noborder\n",
        band_lo, band_hi);
    band_label = fmt::format(
        "set label 3 'fails on this range: max peak_rel > {} (true value in brackets)' at graph "
        "0.01, first {} left font ',9' tc rgb '#a50f15'\n",
        kParetoFail, band_hi / 1.6);
  }
  const auto stem_of = [&](std::size_t i) {
    return panels.size() == 1 ? f.id : fmt::format("{}_{}", f.id, i + 1);
  };
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const ParetoPanel& p = panels[i];
    double xmin = INFINITY, xmax = 0;
    for (const ParetoRow& r : p.rows) xmin = std::min(xmin, r.cost), xmax = std::max(xmax, r.cost);
    const double left = 80 + slot * static_cast<double>(i);
    const PanelFrame g{W,
                       H,
                       left,
                       left + plot_w,
                       top,
                       bottom,
                       std::log10(xmin / 2),
                       std::log10(xmax * 3),
                       std::log10(y_lo),
                       std::log10(y_hi)};
    const bool last = i + 1 == panels.size();
    const std::string stem = stem_of(i);
    body += fmt::format(
        "set title {} font ',12'\nset xlabel {}\nset xrange [{}:{}]\n"
        "set lmargin at screen {}\nset rmargin at screen {}\n{}\nunset label\n{}{}",
        gp_quote("--cost " + p.source), gp_quote(cost_axis_label(p)), xmin / 2, xmax * 3,
        g.left / W, g.right / W,
        last ? fmt::format("set key at screen {}, screen {} left top font ',10' spacing 1.15 box",
                           (g.right + 30) / W, 1 - top / H)
             : std::string("unset key"),
        band_label, pareto_labels(p.rows, g, band_y));
    // The other GPU families of the first GPU panel under the legend (screen positions: set with
    // the last panel).
    for (std::size_t k = 0; last && k < panels.size(); ++k) {
      const std::string table = gpu_family_table(opt, panels[k], stem_of(k), (g.right + 30) / W,
                                                 1 - table_top / H, table_line / H, f.files);
      body += table;
      if (!table.empty()) break;
    }
    body += pareto_plot(opt, stem, p.rows, families, band_y, last ? &legend : nullptr, f.files);
  }
  for (auto& x : render(opt, f.id, body, static_cast<int>(W), static_cast<int>(H)))
    f.files.push_back(x);
  return f;
}

}  // namespace

Figure figure_e(const FiguresOptions& opt) {
  std::vector<std::string> paths;
  for (const fs::path& p : opt.pareto) paths.push_back(p.string());
  Figure f{
      "e_pareto",
      "Pareto chart: cost vs accuracy",
      fmt::format(
          "cost vs max peak_rel (log-log) from `sglab pareto` ({}), one panel per cost source "
          "(`--cost`: GPU inverse throughput is ACO's estimate of the cycles one wave keeps a SIMD "
          "busy, a compiler estimate, not a timing; CPU ns/eval from `sglab bench`); marker shape "
          "and colour per method family, open = published constants, filled = sglab refit, large "
          "filled with a black ring = sglab's own model; frontier line per precision. Methods "
          "whose max peak_rel exceeds {} fail on the range and sit in the shaded band at the top, "
          "labelled with their error; the frontier line joins only the methods below the band.",
          fmt::join(paths, ", "), kParetoFail),
      {},
      false,
      ""};
  std::vector<std::string> read;
  const std::vector<ParetoPanel> panels = pareto_panels(opt, f.note, read);
  if (read.empty() || panels.empty()) {
    f.skipped = true;
    f.note =
        read.empty()
            ? fmt::format("skipped: {} not found (run `sglab pareto` first, or pass --pareto FILE)",
                          fmt::join(paths, ", "))
            : fmt::format("skipped: {} has no plottable rows", fmt::join(read, ", "));
    return f;
  }
  return render_pareto(opt, panels, std::move(f));
}

}  // namespace sglab::report::figures_detail
