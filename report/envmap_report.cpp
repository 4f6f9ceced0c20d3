// report/envmap_report.cpp — `sglab envmap recommend`'s selector and `sglab envmap
// baselines` (envmap_report.hpp).
#include "report/envmap_report.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>

#include <unistd.h>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <sglab/registry.hpp>

#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "report/figures.hpp"
#include "validate/scene_errors.hpp"

namespace sglab::report {

namespace {

using io::InputError;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<envmap::Vec3> method_irradiance(const std::vector<envmap::Lobe>& lobes,
                                            const std::vector<envmap::Vec3>& normals,
                                            const Method& m, io::Precision precision) {
  double largest = 0;
  for (const envmap::Lobe& l : lobes)
    for (double a : l.amplitude) largest = std::max(largest, a);
  if (!(largest > 0)) return std::vector<envmap::Vec3>(normals.size(), envmap::Vec3{0, 0, 0});
  std::vector<envmap::Vec3> e =
      validate::scene_irradiance(envmap::to_scene(lobes), normals, m, precision);
  for (auto& v : e)
    for (double& x : v) x *= largest;
  return e;
}

// A method's irradiance of the lobes at one normal, as method_irradiance sums
// it (validate::method_value per lobe, in `precision`; amplitudes in double).
envmap::IrradianceFn method_irradiance_at(const std::vector<envmap::Lobe>& lobes, const Method& m,
                                          io::Precision precision) {
  return [lobes, &m, precision](const envmap::Vec3& n) {
    envmap::Vec3 e{0, 0, 0};
    for (const envmap::Lobe& l : lobes) {
      const double v =
          validate::method_value(m, precision, reference::scene_cosine(l.axis, n), l.sharpness);
      for (std::size_t ch = 0; ch < 3; ++ch) e[ch] += l.amplitude[ch] * v;
    }
    return e;
  };
}

}  // namespace

std::vector<std::size_t> lobe_ladder(std::size_t max_lobes) {
  std::vector<std::size_t> out;
  for (std::size_t n : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256})
    if (n <= max_lobes) out.push_back(n);
  if (out.empty() || out.back() != max_lobes) out.push_back(max_lobes);
  return out;
}

bool meets_budget(const EnvmapCandidate& c, double budget) {
  return c.dense && c.dense->max_rel <= budget;
}

EnvmapSelection select_envmap_method(const envmap::Map& map, const envmap::Map& work, double budget,
                                     std::size_t max_lobes, std::size_t normals_n,
                                     io::Precision precision,
                                     const std::vector<report::MethodPoint>& costs,
                                     const std::function<void(const std::string&)>& note) {
  EnvmapSelection sel;
  envmap::FitOptions options;
  options.objective = envmap::Objective::irradiance;
  const auto fit_normals = reference::fibonacci_normals(options.fit_normals);
  const auto normals = reference::fibonacci_normals(normals_n);
  note("exact irradiance of the map");
  const auto exact_fit = irradiance(map, fit_normals);
  const auto exact = irradiance(map, normals);
  double ranking_peak = 0;
  for (const auto& e : exact)
    for (double x : e) ranking_peak = std::max(ranking_peak, x);
  note("exact irradiance of the full map at the dense normals");
  const envmap::MapIrradiance field(map);
  const envmap::DenseTruth truth =
      envmap::dense_truth(field, std::max(normals_n, envmap::kDenseNormals));
  sel.dense_normals = truth.normals.size();
  for (std::size_t n : lobe_ladder(max_lobes)) {
    note(fmt::format("{} lobes: fit", n));
    options.lobes = n;
    const envmap::FitReport fit = envmap::fit(work, exact_fit, options);
    note(fmt::format("{} lobes: errors", n));
    sel.fit_error.emplace_back(
        n, envmap::irradiance_error(envmap::lobes_irradiance_exact(fit.lobes, normals), exact)
               .max_rel);
    std::vector<report::MethodPoint> points;
    const std::size_t first = sel.tried.size();
    for (const report::MethodPoint& c : costs) {
      if (!std::isfinite(c.cost)) continue;
      const Method* m = find_method(irradiance_methods, c.method);
      if (!m) continue;
      report::MethodPoint p = c;
      p.max_peak_rel =
          envmap::irradiance_error(method_irradiance(fit.lobes, normals, *m, precision), exact)
              .max_rel;
      EnvmapCandidate t{n,           p.method,    p.max_peak_rel,
                        p.cost,      p.cost_unit, static_cast<double>(n) * p.cost,
                        std::nullopt};
      // The max over the sphere is at least the max over the ranking normals
      // (here relative to the dense set's peak): a pair above the budget there
      // fails it; the others are measured densely and checked on that.
      const double lower_bound = p.max_peak_rel * ranking_peak / truth.peak;
      if (std::isfinite(p.max_peak_rel) && lower_bound <= budget) {
        t.dense = envmap::dense_error(truth, method_irradiance_at(fit.lobes, *m, precision));
        p.max_peak_rel = t.dense->max_rel;
      } else {
        p.max_peak_rel = std::max(p.max_peak_rel, lower_bound);
      }
      points.push_back(p);
      sel.tried.push_back(t);
    }
    const report::Recommendation r = report::recommend(points, budget);
    const auto candidate = [&](const report::MethodPoint& p) {
      for (std::size_t k = first; k < sel.tried.size(); ++k)
        if (sel.tried[k].method == p.method) return sel.tried[k];
      throw std::logic_error("select_envmap_method: a ranked method was not tried");
    };
    if (r.choice) {
      sel.choice = candidate(*r.choice);
      if (r.runner_up) sel.runner_up = candidate(*r.runner_up);
      sel.lobes = fit.lobes;
      break;
    }
  }
  return sel;
}

namespace {

struct Errors {
  envmap::ErrorStats baseline, radiance, irradiance;
  double t_baseline = 0, t_radiance = 0, t_irradiance = 0;
  std::vector<envmap::Lobe> irradiance_lobes;
};

std::string tonemap_rgb(double r, double g, double b, double exposure) {
  auto c = [&](double x) {
    const double t = std::max(0.0, x) * exposure;
    return static_cast<int>(std::lround(255 * std::pow(t / (1 + t), 1 / 2.2)));
  };
  return fmt::format("{} {} {}", c(r), c(g), c(b));
}

// The figure of one map: the map, its SG reconstruction, the irradiance over
// every normal direction (exact, fitted) and the error, each an equirect panel.
void write_map_figure(const std::filesystem::path& out, const std::string& name,
                      const envmap::Map& work, const std::vector<envmap::Lobe>& lobes,
                      std::size_t n_lobes) {
  const envmap::Map recon = envmap::reconstruct(lobes, work.width, work.height);
  const auto nonzero = std::count_if(lobes.begin(), lobes.end(), [](const envmap::Lobe& l) {
    return l.amplitude[0] > 0 || l.amplitude[1] > 0 || l.amplitude[2] > 0;
  });
  double mean = 0;
  for (float v : work.rgb) mean += v;
  mean /= static_cast<double>(work.rgb.size());
  const double exposure = 1 / (2 * mean);
  // Irradiance as an equirect image over normal directions (64 × 32).
  envmap::Map grid;
  grid.width = 64;
  grid.height = 32;
  std::vector<envmap::Vec3> dirs;
  for (std::size_t j = 0; j < grid.height; ++j)
    for (std::size_t i = 0; i < grid.width; ++i) dirs.push_back(pixel_direction(grid, i, j));
  const auto exact = irradiance(work, dirs);
  const auto fitted = envmap::lobes_irradiance_exact(lobes, dirs);
  double peak = 0;
  for (const auto& e : exact)
    for (double x : e) peak = std::max(peak, x);
  std::string data;
  auto panel = [&](const envmap::Map& m) {
    for (std::size_t j = 0; j < m.height; ++j)
      for (std::size_t i = 0; i < m.width; ++i)
        data += fmt::format("{} {} {}\n", i, m.height - 1 - j,
                            tonemap_rgb(m.at(i, j, 0), m.at(i, j, 1), m.at(i, j, 2), exposure));
    data += "\n\n";
  };
  panel(work);
  panel(recon);
  auto irr_panel = [&](const std::vector<envmap::Vec3>& e) {
    for (std::size_t j = 0; j < grid.height; ++j)
      for (std::size_t i = 0; i < grid.width; ++i) {
        const envmap::Vec3& v = e[j * grid.width + i];
        auto c = [&](double x) {
          return static_cast<int>(
              std::lround(255 * std::pow(std::clamp(x / peak, 0.0, 1.0), 1 / 2.2)));
        };
        data += fmt::format("{} {} {} {} {}\n", i, grid.height - 1 - j, c(v[0]), c(v[1]), c(v[2]));
      }
    data += "\n\n";
  };
  irr_panel(exact);
  irr_panel(fitted);
  double worst = 0;
  for (std::size_t j = 0; j < grid.height; ++j)
    for (std::size_t i = 0; i < grid.width; ++i) {
      double d = 0;
      for (std::size_t ch = 0; ch < 3; ++ch)
        d = std::max(
            d, std::abs(fitted[j * grid.width + i][ch] - exact[j * grid.width + i][ch]) / peak);
      worst = std::max(worst, d);
      data += fmt::format("{} {} {:.6g}\n", i, grid.height - 1 - j, d * 100);
    }
  const std::string stem = "envmap_" + name;
  io::write_file_atomic(out / (stem + ".dat"), data);
  const std::string script = fmt::format(
      "set terminal pngcairo size 1500,620 font 'sans,10'\n"
      "set output '{0}.png'\n"
      "set multiplot layout 2,3 title 'Environment map {1}: the {2}-lobe irradiance fit (c) of "
      "envmaps.md, {4} of its lobes of nonzero amplitude'\n"
      "unset key; unset xtics; unset ytics; set size ratio -1\n"
      "set title 'map (tone-mapped)'\nplot '{0}.dat' index 0 using 1:2:3:4:5 with rgbimage\n"
      "set title 'SG reconstruction'\nplot '{0}.dat' index 1 using 1:2:3:4:5 with rgbimage\n"
      "set multiplot next\n"
      "set title 'irradiance E(n), exact (every pixel)'\nplot '{0}.dat' index 2 using 1:2:3:4:5 "
      "with rgbimage\n"
      "set title 'irradiance of the lobes (exact SG)'\nplot '{0}.dat' index 3 using 1:2:3:4:5 with "
      "rgbimage\n"
      "set title sprintf('|error| / max E, %% (max %.2f %%)', {3})\nset palette rgbformulae "
      "34,35,36\nset colorbox\n"
      "plot '{0}.dat' index 4 using 1:2:3 with image\n"
      "unset multiplot\n",
      stem, name, n_lobes, worst * 100, nonzero);
  io::write_file_atomic(out / (stem + ".gp"), script);
  if (io::run_program({"gnuplot", stem + ".gp"}, out, {}) != 0)
    throw std::runtime_error(fmt::format("gnuplot failed on {}", (out / (stem + ".gp")).string()));
}

// A map's working copy and its exact irradiance (from the full map, which is
// not kept: memory holds one full map at a time, whatever the number of maps).
struct MapData {
  std::string name;
  envmap::Map work;
  std::vector<envmap::Vec3> exact_fit, exact_eval;
};

// The maps of --maps (every .exr and .hdr, sorted) and the output folder
// (default: the project's data/envmaps and data/results).
std::pair<std::vector<std::filesystem::path>, std::filesystem::path> baseline_paths(
    const std::string& maps_arg, const std::string& out_arg) {
  const auto root = io::find_project_root(std::filesystem::current_path());
  std::filesystem::path maps_dir = maps_arg, out = out_arg;
  if (maps_dir.empty()) {
    if (!root)
      throw InputError(
          "--maps: no project folder above the working directory; name the maps folder");
    maps_dir = *root / "data" / "envmaps";
  }
  if (out.empty()) {
    if (!root)
      throw InputError(
          "--out: no project folder above the working directory; name the output folder");
    out = *root / "data" / "results";
  }
  io::check_output_folder(out);
  return {envmap::map_files(maps_dir, "--maps"), out};
}

// Every map with its exact irradiance at the fit and the evaluation normals.
std::vector<MapData> load_maps(const std::vector<std::filesystem::path>& files,
                               const std::vector<envmap::Vec3>& fit_normals,
                               const std::vector<envmap::Vec3>& eval_normals) {
  std::vector<MapData> maps(files.size());
  for (std::size_t m = 0; m < files.size(); ++m) {
    maps[m].name = files[m].stem().string();
    const envmap::Map map = envmap::read_map(files[m]);
    maps[m].work = envmap::working_copy(map);
    maps[m].exact_fit = irradiance(map, fit_normals);
    maps[m].exact_eval = irradiance(map, eval_normals);
  }
  return maps;
}

// The three fits of every (map, lobe count) and their errors, in parallel;
// results[m * counts.size() + c].
struct BaselineRun {
  std::vector<std::size_t> counts, table_counts;
  std::vector<MapData> maps;
  std::vector<Errors> results;
  double wall = 0;
  bool quick = false;
  const Errors& at(std::size_t m, std::size_t n) const {
    const auto c =
        static_cast<std::size_t>(std::find(counts.begin(), counts.end(), n) - counts.begin());
    return results[m * counts.size() + c];
  }
};

void run_fits(BaselineRun& run, const envmap::FitOptions& base_options,
              const std::vector<envmap::Vec3>& eval_normals) {
  const std::size_t maps = run.maps.size(), counts = run.counts.size();
  run.results.assign(maps * counts, Errors{});
  const auto t_all = std::chrono::steady_clock::now();
  // Tasks: each map's irradiance ladder (the longest, first), then (a) and (b)
  // of every (map, count).
  const std::size_t tasks = maps + maps * counts;
  io::Progress progress("envmap baselines", tasks);
  tbb::parallel_for(std::size_t{0}, tasks, [&](std::size_t task) {
    if (task < maps) {
      const MapData& md = run.maps[task];
      const envmap::Judge judge = [&](const envmap::Probe& p) {
        return envmap::irradiance_error(envmap::lobes_irradiance_exact(p.lobes, eval_normals),
                                        md.exact_eval)
            .max_rel;
      };
      const auto ladder =
          envmap::fit_lobe_ladder(md.work, reference::fibonacci_normals(base_options.fit_normals),
                                  md.exact_fit, run.counts, judge, base_options.max_iterations);
      for (std::size_t c = 0; c < counts; ++c) {
        Errors& r = run.results[task * counts + c];
        r.t_irradiance = ladder[c].seconds;
        r.irradiance_lobes = ladder[c].probe.lobes;
        r.irradiance = envmap::irradiance_error(
            envmap::lobes_irradiance_exact(r.irradiance_lobes, eval_normals), md.exact_eval);
      }
      progress.advance();
      return;
    }
    const std::size_t job = task - maps;
    const MapData& md = run.maps[job / counts];
    const std::size_t n = run.counts[job % counts];
    Errors& r = run.results[job];
    auto t0 = std::chrono::steady_clock::now();
    const auto base = envmap::fit_baseline(md.work, n);
    r.t_baseline = seconds_since(t0);
    envmap::FitOptions o = base_options;
    o.lobes = n;
    o.objective = envmap::Objective::radiance;
    t0 = std::chrono::steady_clock::now();
    const envmap::FitReport rad = fit(md.work, md.exact_fit, o);
    r.t_radiance = seconds_since(t0);
    r.baseline =
        envmap::irradiance_error(envmap::lobes_irradiance_exact(base, eval_normals), md.exact_eval);
    r.radiance = envmap::irradiance_error(envmap::lobes_irradiance_exact(rad.lobes, eval_normals),
                                          md.exact_eval);
    progress.advance();
  });
  progress.finish();
  run.wall = seconds_since(t_all);
}

// envmaps.md: deterministic (no times).
std::string baselines_markdown(const BaselineRun& run) {
  std::string md;
  md += "# Environment maps: SG lobe fits against the BakingLab baseline\n\n";
  md += fmt::format(
      "Written by `sglab envmap baselines{}` from the maps in `data/envmaps/` (see its README: "
      "CC0, 128 × 64 area-averaged copies of Blender's studio-light worlds).\n\n",
      run.quick ? " --quick" : "");
  md += fmt::format(
      "Irradiance error = max (and RMS) over {} Fibonacci normals and RGB of |E_lobes(n) − "
      "E_map(n)| / max E_map, where E_map sums every pixel of the map with its solid angle and "
      "E_lobes is the lobes' exact SG irradiance (reference engine). (a) BakingLab baseline: fixed "
      "spiral axes, BakingLab's shared sharpness, NNLS amplitudes on the radiance; (b) sglab "
      "radiance fit: every parameter jointly (Ceres) on the solid-angle weighted radiance; (c) "
      "sglab irradiance fit: every parameter jointly on the irradiance at 1024 other Fibonacci "
      "normals, the lobe counts as a ladder (envmap::fit_lobe_ladder): at each count the best, by "
      "the max error here, of a fresh fit (a radiance fit as (b) on a 64 × 32 copy, then the "
      "irradiance), the previous count's lobes plus new ones refined jointly, the better of those "
      "two refined toward the minimax at the fit normals ({} rounds of Lawson's iteration "
      "[Lawson1961]), and the previous count unchanged; so (c) never rises with the count. Ratio = "
      "(a) max / (c) max; the "
      "target is ≥ 2.\n\n",
      envmap::kEvalNormals, envmap::kMinimaxRounds);
  std::size_t met = 0, total = 0;
  md +=
      "| map | lobes | (a) baseline max | (a) RMS | (b) radiance max | (b) RMS | (c) irradiance "
      "max | (c) RMS | ratio (a)/(c) |\n";
  md += "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t m = 0; m < run.maps.size(); ++m)
    for (std::size_t n : run.table_counts) {
      const Errors& e = run.at(m, n);
      const double ratio = e.baseline.max_rel / e.irradiance.max_rel;
      ++total;
      if (ratio >= 2) ++met;
      md += fmt::format(
          "| {} | {} | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:.1f}{} |\n",
          run.maps[m].name, n, e.baseline.max_rel, e.baseline.rms_rel, e.radiance.max_rel,
          e.radiance.rms_rel, e.irradiance.max_rel, e.irradiance.rms_rel, ratio,
          ratio >= 2 ? "" : " (below 2)");
    }
  md += fmt::format(
      "\n(c) has at least 2× lower max irradiance error than (a) in {} of {} (map, lobes) "
      "cases.\n\n",
      met, total);
  if (run.quick) return md;
  md += "## Lobes needed for a 1 % budget\n\n";
  md +=
      "Fewest lobes (of 1, 2, 3, 4, 6, 8, 12, 16, 24) whose fit has max irradiance error ≤ 1 % "
      "(exact SG irradiance; the error of a diffuse approximation comes on top: `sglab envmap "
      "recommend FILE --budget 0.01`).\n\n";
  md += "| map | (a) baseline | (b) radiance fit | (c) irradiance fit |\n|---|---:|---:|---:|\n";
  for (std::size_t m = 0; m < run.maps.size(); ++m) {
    auto need = [&](auto pick) {
      for (std::size_t n : run.counts)
        if (pick(run.at(m, n)).max_rel <= 0.01) return fmt::format("{}", n);
      return fmt::format("> {}", run.counts.back());
    };
    md += fmt::format("| {} | {} | {} | {} |\n", run.maps[m].name,
                      need([](const Errors& e) { return e.baseline; }),
                      need([](const Errors& e) { return e.radiance; }),
                      need([](const Errors& e) { return e.irradiance; }));
  }
  md += "\n## Figures\n\n![error vs lobes](envmap_curves.png)\n\n";
  md += "![one map: map, reconstruction, irradiance exact / fitted / error](envmap_" +
        run.maps[0].name + ".png)\n";
  return md;
}

std::string baselines_csv(const BaselineRun& run) {
  std::string csv = "map,lobes,fit,max_rel,rms_rel\n";
  for (std::size_t m = 0; m < run.maps.size(); ++m)
    for (std::size_t n : run.counts) {
      const Errors& e = run.at(m, n);
      const std::string& name = run.maps[m].name;
      csv += fmt::format("{},{},baseline,{:.6e},{:.6e}\n", name, n, e.baseline.max_rel,
                         e.baseline.rms_rel);
      csv += fmt::format("{},{},radiance,{:.6e},{:.6e}\n", name, n, e.radiance.max_rel,
                         e.radiance.rms_rel);
      csv += fmt::format("{},{},irradiance,{:.6e},{:.6e}\n", name, n, e.irradiance.max_rel,
                         e.irradiance.rms_rel);
    }
  return csv;
}

// envmap_curves.png: max error against lobes, every map, the three fits.
void write_curves_figure(const std::filesystem::path& out, const BaselineRun& run) {
  std::string dat;
  std::string names;
  for (std::size_t m = 0; m < run.maps.size(); ++m) {
    names += (m ? " " : "") + run.maps[m].name;
    dat += "# lobes baseline radiance irradiance (" + run.maps[m].name + ")\n";
    for (std::size_t n : run.counts) {
      const Errors& e = run.at(m, n);
      dat += fmt::format("{} {:.6e} {:.6e} {:.6e}\n", n, e.baseline.max_rel, e.radiance.max_rel,
                         e.irradiance.max_rel);
    }
    dat += "\n\n";
  }
  io::write_file_atomic(out / "envmap_curves.dat", dat);
  const std::size_t last = run.maps.size() - 1;
  const std::string gp = fmt::format(
      "set terminal pngcairo size 1300,520 font 'sans,10'\nset output 'envmap_curves.png'\n"
      "names = '{}'\nset logscale xy\nset xtics (1,2,3,4,6,8,12,16,24)\nset grid\n"
      "set xlabel 'lobes'\nset ylabel 'max |E_{{lobes}} - E_{{map}}| / max E_{{map}}'\nset key "
      "outside right\n"
      "set multiplot layout 1,2\n"
      "set title '(c) sglab irradiance fit (solid), (a) BakingLab baseline (dashed)'\n"
      "plot for [i=0:{}] 'envmap_curves.dat' index i using 1:4 with linespoints lc i+1 pt 7 title "
      "word(names, i+1), "
      "for [i=0:{}] '' index i using 1:2 with lines dt 2 lc i+1 notitle, 0.01 with lines lc "
      "'black' dt 3 title '1 %'\n"
      "set title '(b) sglab radiance fit'\n"
      "plot for [i=0:{}] 'envmap_curves.dat' index i using 1:3 with linespoints lc i+1 pt 7 title "
      "word(names, i+1), "
      "0.01 with lines lc 'black' dt 3 title '1 %'\n"
      "unset multiplot\n",
      names, last, last, last);
  io::write_file_atomic(out / "envmap_curves.gp", gp);
  if (io::run_program({"gnuplot", "envmap_curves.gp"}, out, {}) != 0)
    throw std::runtime_error(
        fmt::format("gnuplot failed on {}", (out / "envmap_curves.gp").string()));
}

// Times: on the terminal only (committed results stay deterministic).
void print_times(const BaselineRun& run) {
  if (::isatty(STDERR_FILENO) != 1) return;
  fmt::print(stderr, "fit times (s; (c) includes its radiance stage):\n");
  for (std::size_t m = 0; m < run.maps.size(); ++m)
    for (std::size_t n : run.table_counts) {
      const Errors& e = run.at(m, n);
      fmt::print(stderr, "  {:<10} {:>3} lobes  (a) {:6.2f}  (b) {:6.2f}  (c) {:6.2f}\n",
                 run.maps[m].name, n, e.t_baseline, e.t_radiance, e.t_irradiance);
    }
  fmt::print(stderr, "all fits: {:.1f} s wall\n", run.wall);
}

}  // namespace

void run_envmap_baselines(const std::string& maps_arg, const std::string& out_arg, bool quick) {
  const auto [files, out] = baseline_paths(maps_arg, out_arg);
  BaselineRun run;
  run.quick = quick;
  run.counts =
      quick ? std::vector<std::size_t>{12} : std::vector<std::size_t>{1, 2, 3, 4, 6, 8, 12, 16, 24};
  run.table_counts = quick ? std::vector<std::size_t>{12} : std::vector<std::size_t>{4, 8, 12, 24};
  const envmap::FitOptions base_options;
  const auto fit_normals = reference::fibonacci_normals(base_options.fit_normals);
  const auto eval_normals = reference::fibonacci_normals(envmap::kEvalNormals);
  run.maps = load_maps(files, fit_normals, eval_normals);
  run_fits(run, base_options, eval_normals);

  const std::string md = baselines_markdown(run);
  io::write_file_atomic(out / "envmaps.md", md);
  io::write_file_atomic(out / "envmaps.csv", baselines_csv(run));
  if (!quick && report::gnuplot_available()) {
    write_curves_figure(out, run);
    write_map_figure(out, run.maps[0].name, run.maps[0].work, run.at(0, 12).irradiance_lobes, 12);
  }
  print_times(run);
  fmt::print("{}", md);
}

}  // namespace sglab::report
