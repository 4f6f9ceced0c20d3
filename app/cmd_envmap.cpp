// `sglab envmap`: real lighting from HDR environment maps (envmap/envmap.hpp).
//   downsample IN OUT --width W   area-averaged copy (how data/envmaps/ was made)
//   irradiance FILE [--normals N] the map's exact diffuse irradiance, CSV
//   fit FILE --lobes N            SG lobes fitted with Ceres, --out scene.json
//   recommend FILE --budget E     fewest lobes × cheapest method meeting E (dense error)
//     … --by storage              the probe of fewest floats meeting E
//     … --by gpu:FAMILY           the probe of least GPU cost (ACO, RADV) meeting E
//   baselines [--maps DIR]        the BakingLab baseline against sglab's fits, all maps
// Every error is against the full map's exact irradiance (envmap::irradiance),
// relative to its largest value (max over normals and RGB channels); the
// errors a choice is made on are dense (envmap::dense_error: at least 20000
// Fibonacci normals and a local maximization from the worst); times are shown
// on a terminal only.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include <sglab/version.hpp>

#include "app/commands.hpp"
#include "app/costs_option.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "cost/gpu_report.hpp"
#include "envmap/envmap.hpp"
#include "envmap/probe.hpp"
#include "probe/probe_source.hpp"
#include "report/envmap_report.hpp"
#include "report/pareto.hpp"
#include "report/probe_recommend.hpp"
#include "report/probes_report.hpp"

namespace sglab::app {

namespace {

using envmap::Vec3;
using ordered_json = nlohmann::ordered_json;

bool terminal() { return ::isatty(STDERR_FILENO) == 1; }

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string command_line(const std::string& head, CLI::App* cmd) {
  std::string s = head;  // the command and its positional arguments
  for (const CLI::Option* o : cmd->get_options()) {
    if (o->count() == 0 || o->get_name() == "--help" || o->get_name().rfind("--", 0) != 0) continue;
    s += " " + o->get_name();
    if (o->get_type_size_min() > 0)
      for (const std::string& r : o->results()) s += " " + r;
  }
  return s;
}

ordered_json lobes_json(const std::vector<envmap::Lobe>& lobes) {
  ordered_json a = ordered_json::array();
  for (const auto& l : lobes)
    a.push_back({{"axis", {l.axis[0], l.axis[1], l.axis[2]}},
                 {"sharpness", l.sharpness},
                 {"amplitude", {l.amplitude[0], l.amplitude[1], l.amplitude[2]}}});
  return a;
}

void print_lobes(const std::vector<envmap::Lobe>& lobes) {
  fmt::print("  {:>3}  {:>28}  {:>10}  {:>36}\n", "#", "axis (x, y, z)", "sharpness",
             "amplitude (r, g, b)");
  for (std::size_t k = 0; k < lobes.size(); ++k) {
    const auto& l = lobes[k];
    fmt::print("  {:>3}  {:>8.4f} {:>8.4f} {:>8.4f}    {:>10.4g}  {:>11.5g} {:>11.5g} {:>11.5g}\n",
               k, l.axis[0], l.axis[1], l.axis[2], l.sharpness, l.amplitude[0], l.amplitude[1],
               l.amplitude[2]);
  }
}

struct DownsampleArgs {
  std::string in, out;
  std::size_t width = 128;
};

struct IrradianceArgs {
  std::string file;
  std::size_t normals = 1024;
};

struct FitArgs {
  std::string file, objective = "irradiance", out;
  std::size_t lobes = 0, normals = envmap::kEvalNormals;
  bool json = false;
};

struct EnvmapRecommendArgs {
  std::string file, budget, precision = "float", by, write_probe, lang = "glsl";
  bool lang_given = false;  // --lang on the command line (it needs --by)
  std::size_t max_lobes = 32, normals = envmap::kEvalNormals;
  int restarts = 0;
  bool json = false;
  CostsOption costs;
};

struct BaselinesArgs {
  std::string maps, out;
  bool quick = false, probes = false;
};

void run_fit(const FitArgs& a, const std::string& command) {
  const auto objective = io::parse_option<envmap::Objective>("--objective", a.objective);
  if (!a.out.empty()) io::check_output_path(a.out);
  const auto t0 = std::chrono::steady_clock::now();
  const envmap::Map map = envmap::read_map(a.file);
  const envmap::Map work = envmap::working_copy(map);
  envmap::FitOptions options;
  options.lobes = a.lobes;
  options.objective = objective;
  const auto fit_normals = reference::fibonacci_normals(options.fit_normals);
  envmap::check_lobe_count(work, a.lobes);
  io::Progress progress(fmt::format("envmap fit {}", a.file), 0);
  progress.note("exact irradiance of the map");
  const auto exact_fit = envmap::irradiance(map, fit_normals);
  progress.note("baseline and fit");
  const auto baseline = envmap::fit_baseline(work, a.lobes);
  const envmap::FitReport report = envmap::fit(work, exact_fit, options);
  progress.note("dense errors on the full map");
  const envmap::MapIrradiance field(map);
  const envmap::DenseTruth truth =
      envmap::dense_truth(field, std::max(a.normals, envmap::kDenseNormals));
  const auto dense = [&](const std::vector<envmap::Lobe>& lobes) {
    envmap::Probe p;
    p.kind = envmap::ProbeKind::lobes;
    p.lobes = lobes;
    const envmap::DenseError e = envmap::dense_error(truth, envmap::probe_irradiance(p));
    return envmap::ErrorStats{e.max_rel, e.rms_rel};
  };
  const auto e_base = dense(baseline);
  const auto e_fit = dense(report.lobes);
  progress.finish();

  ordered_json prov;
  prov["map"] = a.file;
  prov["map_size"] = {map.width, map.height};
  prov["fitted_at"] = {work.width, work.height};
  prov["lobes"] = a.lobes;
  prov["objective"] = a.objective;
  prov["fit_normals"] = options.fit_normals;
  prov["error_normals"] = truth.normals.size();
  prov["irradiance_error"] =
      "max over Fibonacci normals and a local maximization from the 8 worst, RMS over the "
      "normals, RGB, of |E_lobes - E_map| / max E_map; E_lobes exact (irradiance table), E_map "
      "every pixel of the full map with its solid angle";
  prov["max_rel"] = e_fit.max_rel;
  prov["rms_rel"] = e_fit.rms_rel;
  prov["baseline_max_rel"] = e_base.max_rel;
  prov["baseline_rms_rel"] = e_base.rms_rel;
  prov["ceres_iterations"] = report.iterations;
  prov["converged"] = report.converged;
  prov["command"] = command;
  prov["tool"] = std::string("sglab ") + SGLAB_VERSION;
  ordered_json scene;
  scene["lights"] = lobes_json(report.lobes);
  scene["provenance"] = prov;
  if (!a.out.empty()) io::write_file_atomic(a.out, scene.dump(2) + "\n");
  if (a.json) {
    fmt::print("{}\n", scene.dump(2));
  } else {
    fmt::print(
        "map {}: {} x {}, fitted at {} x {}; {} lobes, {} objective ({} Ceres iterations{})\n",
        a.file, map.width, map.height, work.width, work.height, a.lobes, a.objective,
        report.iterations, report.converged ? ", converged" : ", stopped before convergence");
    print_lobes(report.lobes);
    fmt::print(
        "irradiance error at {} Fibonacci normals + local search (|E_lobes − E_map| / max E_map, "
        "full map, lobes exact):\n",
        truth.normals.size());
    fmt::print("  {:<34} max {:.4g}  RMS {:.4g}\n", "BakingLab baseline (fixed axes, NNLS)",
               e_base.max_rel, e_base.rms_rel);
    fmt::print("  {:<34} max {:.4g}  RMS {:.4g}\n", fmt::format("sglab fit ({})", a.objective),
               e_fit.max_rel, e_fit.rms_rel);
    if (!a.out.empty())
      fmt::print("wrote {} (sglab recommend --scene {} --budget E)\n", a.out, a.out);
  }
  if (terminal()) fmt::print(stderr, "envmap fit: {:.2f} s\n", seconds_since(t0));
}

double parse_budget(const std::string& text) {
  double budget = 0;
  if (const auto parsed = io::parse_decimal(text);
      const auto* why = std::get_if<std::string>(&parsed))
    throw InputError("--budget: " + *why);
  else
    budget = std::get<double>(parsed);
  if (!(budget > 0)) throw InputError(fmt::format("--budget: must be > 0, got {}", budget));
  return budget;
}

ordered_json probe_candidate_json(const report::ProbeCandidate& c, bool by_gpu) {
  ordered_json j = {{"label", c.probe.label()},     {"family", c.family},
                    {"floats", c.probe.floats()},   {"bytes", c.probe.bytes()},
                    {"max_rel", c.error.max_rel},   {"rms_rel", c.error.rms_rel},
                    {"worst_normal", c.error.worst}};
  if (by_gpu) j["gpu_cost"] = c.cost ? ordered_json(*c.cost) : ordered_json(nullptr);
  return j;
}

// The family of `--by gpu:FAMILY` (nullopt for `--by storage`); anything else,
// or a family RADV does not know (cost::gpu::kKnownFamilies), is refused.
std::optional<std::string> gpu_family_of(const std::string& by) {
  if (by == "storage") return std::nullopt;
  constexpr std::string_view prefix = "gpu:";
  if (by.rfind(prefix, 0) != 0)
    throw InputError(fmt::format(
        "--by: 'storage' (fewest floats) or 'gpu:FAMILY' (least GPU cost on an AMD family, "
        "e.g. gpu:navi21); got {}",
        io::quote_escaped(by)));
  const std::string family = by.substr(prefix.size());
  if (std::find(std::begin(cost::gpu::kKnownFamilies), std::end(cost::gpu::kKnownFamilies),
                family) == std::end(cost::gpu::kKnownFamilies))
    throw InputError(fmt::format("--by gpu:FAMILY: unknown family {}; the families RADV knows: {}",
                                 io::quote_escaped(family),
                                 fmt::join(cost::gpu::kKnownFamilies, ",")));
  return family;
}

// `envmap recommend MAP --budget E --by storage|gpu:FAMILY`: the probe of
// fewest floats, or of least GPU cost (probe/probe_source.hpp's
// probe_gpu_costs), meeting E (report/probe_recommend.hpp).
void run_recommend_probe(const EnvmapRecommendArgs& a, const std::string& command) {
  const double budget = parse_budget(a.budget);
  const std::optional<std::string> family = gpu_family_of(a.by);
  const bool by_gpu = family.has_value();
  const auto lang = io::parse_option("--lang", a.lang, {io::Language::glsl, io::Language::hlsl});
  const std::string lang_name(io::to_string(lang));
  if (!a.write_probe.empty()) io::check_output_path(a.write_probe);
  const auto t0 = std::chrono::steady_clock::now();
  const envmap::Map map = envmap::read_map(a.file);
  io::Progress progress(fmt::format("envmap recommend {}", a.file), 0);
  const auto note = [&](const std::string& s) { progress.note(s); };
  std::string driver;
  const report::ProbeRecommendation rec =
      by_gpu ? report::recommend_probe_by_cost(
                   map, budget, a.max_lobes,
                   [&](const std::vector<const envmap::Probe*>& probes) {
                     return probe::probe_gpu_costs(*family, lang, probes, driver);
                   },
                   note, a.restarts)
             : report::recommend_probe_by_storage(map, budget, a.max_lobes, note, a.restarts);
  progress.finish();
  const auto& tried = rec.tried;
  if (rec.choice && !a.write_probe.empty()) {
    auto j = tried[*rec.choice].probe.to_json();
    j["map"] = a.file;
    j["max_rel"] = tried[*rec.choice].error.max_rel;
    j["rms_rel"] = tried[*rec.choice].error.rms_rel;
    if (by_gpu) j["gpu_cost"] = *tried[*rec.choice].cost;
    j["command"] = command;
    io::write_file_atomic(a.write_probe, j.dump(1) + "\n");
  }
  const std::string definition =
      "max over 20000 Fibonacci normals and a local maximization from the 8 worst (RMS: the "
      "normals) of |E_probe - E_map| over RGB / max E_map; E_map every pixel of the full map, "
      "lobes through the probe's method";
  const std::string cost_definition =
      by_gpu ? fmt::format(
                   "ACO's inverse throughput (cycles one wave keeps a SIMD busy, a compiler "
                   "estimate, not a timing) on RADV's null device for {} ({}) of the probe's "
                   "exported {} probe_irradiance(n) (`sglab export --probe FILE --lang {}`), "
                   "one call per shading point in `sglab gpucost`'s single harness (whole "
                   "workgroups, the call in no branch) minus the same harness around "
                   "`return n;`; costed for the probes meeting the budget",
                   *family, driver.empty() ? std::string("no probe costed") : driver,
                   lang == io::Language::glsl ? "GLSL" : "HLSL", lang_name)
             : std::string();
  if (a.json) {
    ordered_json doc;
    doc["map"] = a.file;
    doc["map_size"] = {map.width, map.height};
    doc["budget"] = budget;
    if (by_gpu) {
      doc["by"] = fmt::format("gpu:{}", *family);
      doc["gpu_family"] = *family;
      doc["lang"] = lang_name;
      doc["cost"] = cost_definition;
    } else {
      doc["by"] = "storage: floats (4 bytes each, IEEE binary32)";
    }
    doc["error"] = definition;
    doc["choice"] =
        rec.choice ? probe_candidate_json(tried[*rec.choice], by_gpu) : ordered_json(nullptr);
    doc["runner_up"] =
        rec.runner_up ? probe_candidate_json(tried[*rec.runner_up], by_gpu) : ordered_json(nullptr);
    doc["lobe_ladder_up_to"] = rec.lobe_cap;
    doc["hybrid_ladder_up_to"] = rec.hybrid_cap;
    ordered_json all = ordered_json::array();
    for (const auto& c : tried) all.push_back(probe_candidate_json(c, by_gpu));
    doc["tried"] = std::move(all);
    if (!a.write_probe.empty() && rec.choice) doc["wrote"] = a.write_probe;
    fmt::print("{}\n", doc.dump(2));
  } else {
    fmt::print("map {} ({} x {}): budget {} on the probe's max irradiance error, by {}\n", a.file,
               map.width, map.height, budget,
               by_gpu ? fmt::format("GPU cost on {}", *family) : std::string("storage"));
    fmt::print("error = {}\n", definition);
    if (by_gpu) fmt::print("cost = {}\n", cost_definition);
    fmt::print("\n");
    fmt::print("  {:<22} {:<20} {:>6} {:>10} {:>10}  {}{}\n", "probe", "family", "floats", "max",
               "RMS", "meets", by_gpu ? "  cycles" : "");
    for (const auto& c : tried)
      fmt::print("  {:<22} {:<20} {:>6} {:>10.4g} {:>10.4g}  {}{}\n", c.probe.label(), c.family,
                 c.probe.floats(), c.error.max_rel, c.error.rms_rel,
                 c.error.max_rel <= budget ? "yes" : "no",
                 !by_gpu  ? std::string()
                 : c.cost ? fmt::format("  {:>6}", *c.cost)
                          : "       -");
    const auto describe = [&](const report::ProbeCandidate& c) {
      return fmt::format(
          "{} ({}): {} floats, {} bytes; max error {:.4g}, RMS {:.4g}{}", c.probe.label(), c.family,
          c.probe.floats(), c.probe.bytes(), c.error.max_rel, c.error.rms_rel,
          by_gpu && c.cost ? fmt::format("; {} cycles per wave on {}", *c.cost, *family)
                           : std::string());
    };
    fmt::print("\n");
    if (rec.choice) {
      fmt::print("  choice:    {}\n", describe(tried[*rec.choice]));
      fmt::print("  runner-up: {}\n",
                 rec.runner_up ? describe(tried[*rec.runner_up]) : std::string("none"));
      if (!a.write_probe.empty())
        fmt::print("wrote {} (sglab export --probe {} --lang {})\n", a.write_probe, a.write_probe,
                   lang_name);
    } else {
      fmt::print("  no probe up to SH L4, ZH3, {} lobes and SH L2 + {} lobes meets the budget.\n",
                 rec.lobe_cap, rec.hybrid_cap);
    }
  }
  if (terminal()) fmt::print(stderr, "envmap recommend: {:.2f} s\n", seconds_since(t0));
}

void run_envmap_recommend(const EnvmapRecommendArgs& a) {
  if (!a.write_probe.empty())
    throw InputError(
        "--write-probe: needs --by storage or --by gpu:FAMILY (the lobes-and-method choice has "
        "no probe)");
  if (a.lang_given)
    throw InputError(
        "--lang: needs --by gpu:FAMILY (the language the probe is costed in) or --by storage "
        "(the language of the export it names); the lobes-and-method choice has no probe");
  if (a.restarts > 0)
    throw InputError(
        "--restarts: needs --by storage or --by gpu:FAMILY (the lobe ladder it restarts); the "
        "lobes-and-method choice fits each count once");
  const double budget = parse_budget(a.budget);
  const auto precision = io::parse_option("--precision", a.precision,
                                          {io::Precision::float32, io::Precision::float64});
  const auto t0 = std::chrono::steady_clock::now();
  const envmap::Map map = envmap::read_map(a.file);
  const envmap::Map work = envmap::working_copy(map);
  envmap::check_lobe_count(work, a.max_lobes);
  // Costs first: a missing or malformed cost table is reported before any fit.
  std::vector<report::MethodPoint> costs;
  for (const Method& m : irradiance_methods) {
    report::MethodPoint p;
    p.method = std::string(m.id);
    p.origin = m.origin;
    costs.push_back(p);
  }
  const std::string cost_source = a.costs.fill(costs, precision, 7, 0.01).text;
  io::Progress progress(fmt::format("envmap recommend {}", a.file), 0);
  const report::EnvmapSelection sel =
      report::select_envmap_method(map, work, budget, a.max_lobes, a.normals, precision, costs,
                                   [&](const std::string& s) { progress.note(s); });
  progress.finish();

  const std::string ranking = fmt::format(
      "at the {} ranking Fibonacci normals, max over normals and RGB of |E_method(lobes) - E_map| "
      "/ max E_map there",
      a.normals);
  const std::string dense = fmt::format(
      "max over {} Fibonacci normals and a local maximization from the 8 worst (RMS: the "
      "normals) of |E_method(lobes) - E_map| over RGB / max E_map, as `envmap baselines --probes`; "
      "measured for the pairs not above the budget at the ranking normals, and the budget is "
      "checked on it",
      sel.dense_normals);
  if (a.json) {
    ordered_json doc;
    doc["map"] = a.file;
    doc["budget"] = budget;
    doc["precision"] = std::string(io::to_string(precision));
    doc["normals"] = a.normals;
    doc["dense_normals"] = sel.dense_normals;
    doc["error"] =
        "lobe fit + approximation against every pixel of the full map; ranking_error: " + ranking +
        "; error, rms_error: the dense error, " + dense;
    doc["cost"] = "lobes x the method's cost per evaluation (--cost; unit per row)";
    doc["cost_source"] = cost_source;
    auto pair = [](const std::optional<report::EnvmapCandidate>& c) -> ordered_json {
      if (!c) return nullptr;
      return {{"lobes", c->lobes},
              {"method", c->method},
              {"error", c->dense ? ordered_json(c->dense->max_rel) : ordered_json(nullptr)},
              {"rms_error", c->dense ? ordered_json(c->dense->rms_rel) : ordered_json(nullptr)},
              {"ranking_error", c->error},
              {"cost", c->cost},
              {"cost_unit", c->cost_unit},
              {"total_cost", c->total_cost}};
    };
    doc["choice"] = pair(sel.choice);
    doc["runner_up"] = pair(sel.runner_up);
    ordered_json tried = ordered_json::array();
    for (const auto& c : sel.tried) tried.push_back(pair(c));
    doc["tried"] = std::move(tried);
    doc["lobe_fit_error"] = ordered_json::array();
    for (const auto& [n, e] : sel.fit_error)
      doc["lobe_fit_error"].push_back({{"lobes", n}, {"max_rel", e}});
    fmt::print("{}\n", doc.dump(2));
  } else {
    fmt::print(
        "map {} ({} x {}): budget {} on the irradiance error (lobe fit + method, {}), ranked at {} "
        "normals, checked at {} normals and a local search\n",
        a.file, map.width, map.height, budget, io::to_string(precision), a.normals,
        sel.dense_normals);
    fmt::print("ranking = {}\ndense = {}\ncost = lobes × cost per evaluation (--cost)\n\n", ranking,
               dense);
    fmt::print("  {:>5}  {:<24} {:>10} {:>10} {:>10} {:>9} {:>10}  {}\n", "lobes", "method",
               "ranking", "dense", "dense RMS", "per eval", "per point", "meets");
    for (const auto& c : sel.tried)
      fmt::print("  {:>5}  {:<24} {:>10.4g} {:>10} {:>10} {:>9.3g} {:>10.3g}  {}\n", c.lobes,
                 c.method, c.error, c.dense ? fmt::format("{:.4g}", c.dense->max_rel) : "-",
                 c.dense ? fmt::format("{:.4g}", c.dense->rms_rel) : "-", c.cost, c.total_cost,
                 report::meets_budget(c, budget) ? "yes" : "no");
    fmt::print("\n  lobe fit alone (exact SG irradiance, ranking normals):");
    for (const auto& [n, e] : sel.fit_error) fmt::print(" {} lobes {:.3g};", n, e);
    fmt::print("\n");
    auto describe = [](const report::EnvmapCandidate& c) {
      return fmt::format(
          "{} lobes with {} (dense max error {:.4g}, RMS {:.4g}; {:.3g} {} per "
          "shading point)",
          c.lobes, c.method, c.dense->max_rel, c.dense->rms_rel, c.total_cost, c.cost_unit);
    };
    if (sel.choice) {
      fmt::print("  choice:    {}\n", describe(*sel.choice));
      if (sel.runner_up)
        fmt::print("  runner-up: {}\n", describe(*sel.runner_up));
      else
        fmt::print("  runner-up: none\n");
    } else {
      fmt::print("  no (lobes, method) pair up to {} lobes meets the budget.\n", a.max_lobes);
    }
    fmt::print("(costs: {})\n", cost_source);
  }
  if (terminal()) fmt::print(stderr, "envmap recommend: {:.2f} s\n", seconds_since(t0));
}

}  // namespace

void add_envmap_command(CLI::App& app) {
  auto* env = app.add_subcommand(
      "envmap", "Real lighting: SG lobes fitted to HDR environment maps (OpenEXR, .hdr)");
  env->require_subcommand(1);
  env->footer(
      "Direction convention: equirectangular, +z up; row 0 at the zenith; column i at azimuth φ = "
      "2π(i + ½)/W, ω = (sin θ cos φ, −sin θ sin φ, cos θ) (docs/envmaps.md).");

  {
    auto a = std::make_shared<DownsampleArgs>();
    auto* cmd =
        env->add_subcommand("downsample", "Area-averaged copy of a map as float RGB OpenEXR");
    add_path_option(cmd, "IN", a->in, "input map (OpenEXR or Radiance .hdr)")->required();
    add_path_option(cmd, "OUT", a->out, "output OpenEXR file")->required();
    cmd->add_option("--width", a->width,
                    "output width (even, at most the input width; height width/2)")
        ->check(count_in(8, 1 << 20))
        ->capture_default_str();
    cmd->callback([a] {
      io::check_output_path(a->out);
      const envmap::Map map = envmap::read_map(a->in);
      envmap::write_exr(a->out, envmap::downsample(map, a->width));
    });
  }
  {
    auto a = std::make_shared<IrradianceArgs>();
    auto* cmd = env->add_subcommand("irradiance",
                                    "The map's exact diffuse irradiance at Fibonacci normals, CSV");
    add_path_option(cmd, "FILE", a->file, "map (OpenEXR or Radiance .hdr)")->required();
    cmd->add_option("--normals", a->normals, "number of Fibonacci normals")
        ->check(count_in(1, 1000000))
        ->capture_default_str();
    cmd->callback([a] {
      const envmap::Map map = envmap::read_map(a->file);
      const auto normals = reference::fibonacci_normals(a->normals);
      const auto e = envmap::irradiance(map, normals);
      std::string out = "nx,ny,nz,r,g,b\n";
      for (std::size_t k = 0; k < normals.size(); ++k)
        out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", normals[k][0],
                           normals[k][1], normals[k][2], e[k][0], e[k][1], e[k][2]);
      fmt::print("{}", out);
    });
  }
  {
    auto a = std::make_shared<FitArgs>();
    auto* cmd = env->add_subcommand(
        "fit", "SG lobes fitted to a map with Ceres; --out writes a scene file");
    add_path_option(cmd, "FILE", a->file, "map (OpenEXR or Radiance .hdr)")->required();
    cmd->add_option("--lobes", a->lobes, "number of SG lobes")
        ->required()
        ->check(count_in(0, 1 << 20));
    cmd->add_option("--objective", a->objective, "radiance or irradiance")->capture_default_str();
    cmd->add_option("--normals", a->normals,
                    "Fibonacci normals the error is measured at (at least 20000, then a local "
                    "search from the worst)")
        ->check(count_in(1, 100000))
        ->capture_default_str();
    add_path_option(cmd, "--out", a->out,
                    "scene JSON for `sglab recommend --scene`, with provenance");
    cmd->add_flag("--json", a->json, "print the scene file (with provenance) on stdout");
    cmd->callback([a, cmd] { run_fit(*a, command_line("sglab envmap fit " + a->file, cmd)); });
  }
  {
    auto a = std::make_shared<EnvmapRecommendArgs>();
    auto* cmd = env->add_subcommand(
        "recommend",
        "Fewest lobes and cheapest irradiance method whose combined error meets a budget");
    add_path_option(cmd, "FILE", a->file, "map (OpenEXR or Radiance .hdr)")->required();
    cmd->add_option("--budget", a->budget,
                    "max irradiance error allowed, relative to the largest irradiance (> 0)")
        ->required();
    cmd->add_option("--max-lobes", a->max_lobes, "largest lobe count tried")
        ->check(count_in(1, 256))
        ->capture_default_str();
    cmd->add_option("--normals", a->normals,
                    "without --by: Fibonacci normals the (lobes, method) pairs are ranked at; the "
                    "budget is checked on the dense error (at least 20000 normals, then a local "
                    "search from the worst)")
        ->check(count_in(1, 100000))
        ->capture_default_str();
    cmd->add_option("--precision", a->precision, "float or double")->capture_default_str();
    cmd->add_flag("--json", a->json, "print the answer as JSON");
    cmd->add_option("--by", a->by,
                    "storage: the probe (SH L0-L4, ZH3, N lobes, SH L2 + K lobes) of fewest floats "
                    "meeting the budget, dense error on the full map; gpu:FAMILY: the one whose "
                    "exported evaluation has the least ACO inverse throughput on that AMD family "
                    "(RADV null device, as `sglab gpucost`); without --by: lobes x cheapest "
                    "irradiance method");
    cmd->add_option("--restarts", a->restarts,
                    "with --by: also fit a second lobe ladder whose every step tries this many "
                    "starts drawn from the map's light, and keep the better of the two at each "
                    "count (slower; no lobe count's error rises, the SH + lobes ladder grown from "
                    "it may move either way)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    add_path_option(cmd, "--write-probe", a->write_probe,
                    "with --by: the chosen probe as JSON for `sglab export --probe`");
    auto* lang = cmd->add_option("--lang", a->lang,
                                 "with --by gpu:FAMILY: glsl or hlsl, the language the probe's "
                                 "evaluation is exported and costed in (as `sglab export --probe "
                                 "FILE --lang`); with --by storage: the export --write-probe names")
                     ->capture_default_str();
    a->costs.add_to(cmd);
    cmd->callback([a, cmd, lang] {
      a->lang_given = lang->count() > 0;
      if (!a->by.empty())
        run_recommend_probe(*a, command_line("sglab envmap recommend " + a->file, cmd));
      else
        run_envmap_recommend(*a);
    });
  }
  {
    auto a = std::make_shared<BaselinesArgs>();
    auto* cmd = env->add_subcommand(
        "baselines",
        "Every map: BakingLab baseline vs radiance and irradiance fits, tables and figures");
    add_path_option(cmd, "--maps", a->maps,
                    "folder of maps (default: data/envmaps of the project)");
    add_path_option(cmd, "--out", a->out, "output folder (default: data/results of the project)");
    cmd->add_flag("--quick", a->quick,
                  "12 lobes only, no curves or figures (--probes: every fourth map at 27 floats)");
    cmd->add_flag("--probes", a->probes,
                  "the probe table instead (probes.md: SH, ZH3, SG lobes, SH + lobes at 15, 27, "
                  "48, 75 floats on the full maps; default maps: blender-data's when installed)");
    cmd->callback([a] {
      if (a->probes)
        report::run_probe_table(a->maps, a->out, a->quick);
      else
        report::run_envmap_baselines(a->maps, a->out, a->quick);
    });
  }
}

}  // namespace sglab::app
