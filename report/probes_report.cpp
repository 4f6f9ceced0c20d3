// report/probes_report.cpp — the probe table (probes_report.hpp).
#include "report/probes_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include <unistd.h>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "envmap/probe.hpp"
#include "report/figures.hpp"

namespace sglab::report {

namespace {

using envmap::Probe;
using io::InputError;

constexpr const char* kBlenderWorlds = "/usr/share/blender/datafiles/studiolights/world";

struct Row {
  std::string
      family;  // "SH projection", "SH fit", "ZH3 projection", ..., "SG lobes", "hybrid", "baseline"
  Probe probe;
  envmap::DenseError error;
};

struct MapResult {
  std::string name;
  std::size_t width = 0, height = 0;
  std::vector<Row> rows;
  std::vector<envmap::LadderStep> lobes, hybrid;
  double seconds = 0;
};

// Largest configuration of a family within a budget (floats ≤ budget + 3).
std::size_t lobes_within(std::size_t budget, std::size_t fixed) {
  return budget + 3 >= fixed ? (budget + 3 - fixed) / 7 : 0;
}
int sh_order_within(std::size_t budget) {
  int order = 0;
  for (int l = 1; l <= envmap::kMaxShOrder; ++l)
    if (3 * envmap::sh_count(l) <= budget + 3) order = l;
  return order;
}

MapResult run_map(const std::filesystem::path& file, const std::vector<std::size_t>& budgets) {
  const auto t0 = std::chrono::steady_clock::now();
  MapResult r;
  r.name = file.stem().string();
  const envmap::Map map = envmap::read_map(file);
  r.width = map.width;
  r.height = map.height;
  const envmap::Map work = envmap::working_copy(map);
  const envmap::MapIrradiance field(map);
  const envmap::DenseTruth truth = envmap::dense_truth(field);
  const auto normals = reference::fibonacci_normals(envmap::kFitNormals);
  const auto exact = field.at(normals);
  const auto radiance = envmap::radiance_sh(map, envmap::kMaxShOrder);
  const auto judge = [&](const Probe& p) {
    return envmap::dense_error(truth, envmap::probe_irradiance(p)).max_rel;
  };
  auto add = [&](const std::string& family, const Probe& p) {
    r.rows.push_back({family, p, envmap::dense_error(truth, envmap::probe_irradiance(p))});
  };
  std::size_t max_lobes = 0, max_hybrid = 0;
  for (std::size_t b : budgets) {
    max_lobes = std::max(max_lobes, lobes_within(b, 0));
    max_hybrid = std::max(max_hybrid, lobes_within(b, 27));
  }
  for (int l = 1; l <= envmap::kMaxShOrder; ++l) {
    bool used = false;
    for (std::size_t b : budgets) used = used || sh_order_within(b) == l;
    if (!used) continue;
    add("SH projection", envmap::project_sh(radiance, l));
    add("SH fit", envmap::fit_sh(normals, exact, l));
    add("SH minimax", envmap::fit_sh(normals, exact, l, envmap::LinearFit::minimax));
  }
  add("SH L1 non-negative", envmap::project_sh_nonneg(radiance));
  const Probe zh3 = envmap::project_zh3(radiance);
  add("ZH3 projection", zh3);
  add("ZH3 fit", envmap::fit_zh3(normals, exact, zh3.zonal_axis()));
  add("ZH3 minimax", envmap::fit_zh3(normals, exact, zh3.zonal_axis(), envmap::LinearFit::minimax));
  r.lobes = envmap::fit_lobe_ladder(work, normals, exact, max_lobes, judge);
  for (const auto& s : r.lobes) add("SG lobes", s.probe);
  if (max_hybrid > 0) {
    r.hybrid = envmap::fit_hybrid_ladder(work, normals, exact, r.lobes, max_hybrid, judge);
    for (const auto& s : r.hybrid) add("SH L2 + SG lobes", s.probe);
  }
  for (std::size_t b : budgets) {
    const std::size_t n = lobes_within(b, 0);
    Probe p;
    p.kind = envmap::ProbeKind::lobes;
    p.fit = "BakingLab fixed axes, NNLS on the radiance";
    p.lobes = envmap::fit_baseline(work, n);
    add("fixed-axis baseline", p);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The row of a family at a budget: its largest within budget + 3 floats and
// above the budget before (`below`, + 3); nullptr when it has none there.
const Row* pick(const MapResult& r, const std::string& family, std::size_t budget,
                std::size_t below = 0) {
  const Row* best = nullptr;
  for (const Row& row : r.rows) {
    if (row.family != family || row.probe.floats() > budget + 3) continue;
    if (below > 0 && row.probe.floats() <= below + 3) continue;
    if (!best || row.probe.floats() > best->probe.floats()) best = &row;
  }
  return best;
}

const std::vector<std::string> kFamilies = {
    "SH projection", "SH fit",      "SH minimax", "SH L1 non-negative", "ZH3 projection",
    "ZH3 fit",       "ZH3 minimax", "SG lobes",   "SH L2 + SG lobes",   "fixed-axis baseline"};

std::string markdown(const std::vector<MapResult>& results, const std::vector<std::size_t>& budgets,
                     const std::string& maps_note, bool quick) {
  std::string md = "# Probes: SH, ZH3, SG lobes and SH + lobes at equal storage\n\n";
  md += fmt::format("Written by `sglab envmap baselines --probes{}` from {}.\n\n",
                    quick ? " --quick" : "", maps_note);
  md += fmt::format(
      "Error = |E_probe(n) − E_map(n)| over RGB relative to the map's largest irradiance, where "
      "E_map sums every pixel of the full-resolution map with its solid angle "
      "(envmap::MapIrradiance). **max**: over {} Fibonacci normals, then a local maximization "
      "(pattern search down to 1e−4 rad, the exact E_map at every step) from the 8 worst; **RMS**: "
      "over the {} normals. Storage: floats, 4 bytes each (IEEE binary32): 3 per SH coefficient, "
      "15 for ZH3 (its axis is the L1 luminance direction, not stored), 7 per lobe (axis 3, "
      "sharpness 1, RGB 3). Each family is shown at its largest size within the budget + 3 floats. "
      "Fits: least squares of the full map's irradiance at {} other Fibonacci normals (SH, ZH3: "
      "linear; lobes and SH + lobes: Ceres, derivatives of sglab_acc3 by Jets); lobe counts grow "
      "one at a time, each kept fit the best (by the max error) of a fresh fit, the previous count "
      "plus a new lobe, the better of those two refined toward the minimax at the fit normals ({} "
      "rounds of Lawson's iteration [Lawson1961]), and the previous count unchanged. SH and ZH3 "
      "minimax: {} rounds of Lawson's iteration from their least squares. Projection: "
      "E_lm = Â_l L_lm [Ramamoorthi2001]; ZH3 [Roughton2024].\n\n",
      envmap::kDenseNormals, envmap::kDenseNormals, envmap::kFitNormals, envmap::kMinimaxRounds,
      envmap::kLinearMinimaxRounds);
  md += "## Targets at 27 and 75 floats\n\n";
  md +=
      "| map | floats | SH max | SG lobes max | SH + lobes max | best / SH | SG / SH |\n"
      "|---|---:|---:|---:|---:|---:|---:|\n";
  std::size_t met_best = 0, met_sg = 0, cases = 0;
  for (const MapResult& r : results)
    for (std::size_t b : budgets) {
      if (b != 27 && b != 75) continue;
      const Row* sh = pick(r, "SH projection", b);
      for (const char* fit : {"SH fit", "SH minimax"}) {
        const Row* shf = pick(r, fit, b);
        if (shf && (!sh || shf->error.max_rel < sh->error.max_rel)) sh = shf;
      }
      const Row* sg = pick(r, "SG lobes", b);
      const Row* hy = pick(r, "SH L2 + SG lobes", b);
      if (!sh || !sg) continue;
      double best = sg->error.max_rel;
      if (hy) best = std::min(best, hy->error.max_rel);
      ++cases;
      if (best <= 0.5 * sh->error.max_rel) ++met_best;
      if (sg->error.max_rel <= sh->error.max_rel) ++met_sg;
      md += fmt::format(
          "| {} | {} | {:.3e} ({}) | {:.3e} ({}) | {} | {:.2f} | {:.2f} |\n", r.name, b,
          sh->error.max_rel, sh->probe.label(), sg->error.max_rel, sg->probe.label(),
          hy ? fmt::format("{:.3e} ({})", hy->error.max_rel, hy->probe.label()) : std::string("—"),
          best / sh->error.max_rel, sg->error.max_rel / sh->error.max_rel);
    }
  md += fmt::format(
      "\nSH is the best of its projection, its least-squares fit and its minimax fit. Best of "
      "sglab's (lobes or SH + lobes) "
      "≤ 0.5 × SH: {} of {} cases; SG lobes alone ≤ SH: {} of {}.\n\n",
      met_best, cases, met_sg, cases);
  md += "## Every representation at every budget\n\n";
  md += "| map | budget | representation | fit | floats | max | RMS | max on the set alone |\n";
  md += "|---|---:|---|---|---:|---:|---:|---:|\n";
  for (const MapResult& r : results)
    for (std::size_t bi = 0; bi < budgets.size(); ++bi)
      for (const std::string& f : kFamilies) {
        const std::size_t b = budgets[bi];
        const Row* row = pick(r, f, b, bi > 0 ? budgets[bi - 1] : 0);
        if (!row) continue;
        md += fmt::format("| {} | {} | {} | {} | {} | {:.3e} | {:.3e} | {:.3e} |\n", r.name, b,
                          row->probe.label(), f, row->probe.floats(), row->error.max_rel,
                          row->error.rms_rel, row->error.dense_max_rel);
      }
  md += "\n## Max error against lobe count (SG lobes)\n\n| map |";
  std::size_t n_max = 0;
  for (const MapResult& r : results) n_max = std::max(n_max, r.lobes.size());
  for (std::size_t n = 1; n <= n_max; ++n) md += fmt::format(" {} |", n);
  md += " non-increasing |\n|---|";
  for (std::size_t n = 0; n <= n_max; ++n) md += "---:|";
  md += "\n";
  for (const MapResult& r : results) {
    md += "| " + r.name + " |";
    bool mono = true;
    for (std::size_t n = 0; n < r.lobes.size(); ++n) {
      md += fmt::format(" {:.3e} |", r.lobes[n].judged);
      if (n > 0 && r.lobes[n].judged > r.lobes[n - 1].judged) mono = false;
    }
    md += mono ? " yes |\n" : " **no** |\n";
  }
  md += "\n![max error against floats, every map](probes.png)\n";
  return md;
}

std::string csv(const std::vector<MapResult>& results) {
  std::string s = "map,representation,family,fit,floats,bytes,max_rel,rms_rel,dense_max_rel\n";
  for (const MapResult& r : results)
    for (const Row& row : r.rows)
      s += fmt::format("{},{},{},{},{},{},{:.6e},{:.6e},{:.6e}\n", r.name, row.probe.label(),
                       row.family, row.probe.fit, row.probe.floats(), row.probe.bytes(),
                       row.error.max_rel, row.error.rms_rel, row.error.dense_max_rel);
  return s;
}

void figure(const std::filesystem::path& out, const std::vector<MapResult>& results) {
  const std::vector<std::pair<std::string, std::string>> series = {
      {"SH projection", "SH (projection)"},
      {"SH fit", "SH (fit)"},
      {"SH minimax", "SH (minimax)"},
      {"ZH3 fit", "ZH3 (fit)"},
      {"SG lobes", "SG lobes"},
      {"SH L2 + SG lobes", "SH L2 + lobes"},
      {"fixed-axis baseline", "fixed-axis baseline"}};
  std::string dat;
  for (const MapResult& r : results)
    for (const auto& [family, title] : series) {
      dat += fmt::format("# {} {}\n", r.name, title);
      bool any = false;
      for (const Row& row : r.rows)
        if (row.family == family) {
          dat += fmt::format("{} {:.6e}\n", row.probe.floats(), row.error.max_rel);
          any = true;
        }
      if (!any) dat += "nan nan\n";
      dat += "\n\n";
    }
  io::write_file_atomic(out / "probes.dat", dat);
  const std::size_t cols = std::min<std::size_t>(4, results.size());
  const std::size_t rows = (results.size() + cols - 1) / cols;
  std::string gp = fmt::format(
      "set terminal pngcairo size {},{} font 'sans,9'\nset output 'probes.png'\n"
      "set logscale y\nset grid\nset xrange [0:85]\nset xtics (15, 27, 48, 75)\n"
      "set xlabel 'floats'\nset ylabel 'max |E - E_{{map}}| / max E_{{map}}'\n"
      "set multiplot layout {},{} title 'Probe error against storage (full maps, {} normals + "
      "local search; sglab envmap baselines --probes)'\n",
      360 * cols, 300 * rows + 40, rows, cols, envmap::kDenseNormals);
  for (std::size_t m = 0; m < results.size(); ++m) {
    gp += fmt::format("set title '{}'\n", results[m].name);
    gp += m == 0 ? "set key top right font ',7'\n" : "unset key\n";
    gp += "plot ";
    for (std::size_t s = 0; s < series.size(); ++s)
      gp += fmt::format(
          "{}'probes.dat' index {} using 1:2 with linespoints pt 7 ps 0.6 lc {} title '{}'",
          s ? ", " : "", m * series.size() + s, s + 1, series[s].second);
    gp += "\n";
  }
  gp += "unset multiplot\n";
  io::write_file_atomic(out / "probes.gp", gp);
  if (io::run_program({"gnuplot", "probes.gp"}, out, {}) != 0)
    throw std::runtime_error(fmt::format("gnuplot failed on {}", (out / "probes.gp").string()));
}

}  // namespace

void run_probe_table(const std::string& maps_arg, const std::string& out_arg, bool quick) {
  const auto root = io::find_project_root(std::filesystem::current_path());
  std::filesystem::path maps_dir = maps_arg, out = out_arg;
  std::string maps_note;
  if (maps_dir.empty()) {
    if (std::filesystem::is_directory(kBlenderWorlds)) {
      maps_dir = kBlenderWorlds;
      maps_note =
          "Blender's studio-light worlds at full resolution (Debian's blender-data, "
          "/usr/share/blender/datafiles/studiolights/world; data/envmaps/README.md)";
    } else {
      if (!root)
        throw InputError("--maps: no project folder above the working directory; name the maps");
      maps_dir = *root / "data" / "envmaps";
      maps_note =
          "the 128 × 64 copies in data/envmaps (blender-data, with the full-resolution maps, is "
          "not installed)";
    }
  } else {
    maps_note = "the maps in " + maps_dir.string();
  }
  if (out.empty()) {
    if (!root) throw InputError("--out: no project folder above the working directory");
    out = *root / "data" / "results";
  }
  io::check_output_folder(out);
  std::vector<std::filesystem::path> files = envmap::map_files(maps_dir, "--maps");
  // quick: every fourth map at 27 floats (the envmap step of `sglab run`: two maps, one per core).
  const std::vector<std::size_t> budgets =
      quick ? std::vector<std::size_t>{27} : std::vector<std::size_t>{15, 27, 48, 75};
  if (quick) {
    std::vector<std::filesystem::path> some;
    for (std::size_t m = 0; m < files.size(); m += 4) some.push_back(files[m]);
    files = some;
  }
  std::vector<MapResult> results(files.size());
  io::Progress progress("envmap baselines --probes", files.size());
  const auto t0 = std::chrono::steady_clock::now();
  tbb::parallel_for(std::size_t{0}, files.size(), [&](std::size_t m) {
    results[m] = run_map(files[m], budgets);
    progress.advance();
  });
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string md = markdown(results, budgets, maps_note, quick);
  io::write_file_atomic(out / "probes.md", md);
  io::write_file_atomic(out / "probes.csv", csv(results));
  std::filesystem::create_directories(out / "probes");
  for (const MapResult& r : results) {
    nlohmann::ordered_json doc;
    doc["map"] = r.name;
    doc["map_size"] = {r.width, r.height};
    doc["probes"] = nlohmann::ordered_json::array();
    for (const Row& row : r.rows) {
      auto j = row.probe.to_json();
      j["family"] = row.family;
      j["max_rel"] = row.error.max_rel;
      j["rms_rel"] = row.error.rms_rel;
      doc["probes"].push_back(j);
    }
    io::write_file_atomic(out / "probes" / (r.name + ".json"), doc.dump(1) + "\n");
  }
  if (report::gnuplot_available()) figure(out, results);
  // Times: printed only (the committed table stays deterministic).
  fmt::print("fit times (s, wall, every candidate of a step; {} maps in parallel):\n",
             results.size());
  for (const MapResult& r : results) {
    fmt::print("  {:<10} map {:6.1f}  lobes", r.name, r.seconds);
    for (const auto& s : r.lobes) fmt::print(" {:.1f}", s.seconds);
    fmt::print("  hybrid");
    for (const auto& s : r.hybrid) fmt::print(" {:.1f}", s.seconds);
    fmt::print("\n");
  }
  fmt::print("all maps: {:.1f} s wall\n", wall);
  fmt::print("{}", md);
}

}  // namespace sglab::report
