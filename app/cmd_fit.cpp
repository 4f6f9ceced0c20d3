// `sglab fit TARGET`: refit a constant set (fit/targets.hpp), write it to
// <out>/<target>-<variant>.json with provenance and regenerate the runtime
// header, both as one unit (--out defaults to the project's data/constants;
// with another --out the header goes there too, never into the checkout).
// `sglab fit all` runs every target at its standard settings.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <thread>
#include <variant>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "common/args.hpp"
#include "common/atomic_files.hpp"
#include "common/io.hpp"
#include "cost/cost_source.hpp"
#include "cost/cost_table.hpp"
#include "fit/constants_io.hpp"
#include "fit/minimax.hpp"
#include "fit/solver_log.hpp"
#include "fit/targets.hpp"
#include "report/pareto.hpp"

namespace sglab::app {

namespace {

struct FitCliOptions {
  std::string target;
  std::string precision = "float";
  std::string objective;
  std::string kappa;
  double max_error = 0;
  bool alpha_free = false, json = false, force = false, dry_run = false, cold_start = false;
  std::string out_dir;  // default: the project's data/constants
  std::string header;   // default: fit::default_header_for(out_dir)
  std::string costs;    // default: the project's data/results/costs.json, if any
  // fits run at once (fit all): one per core
  std::size_t jobs = std::max(1u, std::thread::hardware_concurrency());
};

struct GivenOptions {
  bool precision, objective, kappa, max_error, alpha_free, cold_start, costs;
};

// "TARGET, …": the targets that take an option.
std::string users_of(bool fit::FitTarget::*flag) {
  std::string users;
  for (const auto& t : fit::fit_targets())
    if (t.*flag) users += fmt::format("{}{}", users.empty() ? "" : ", ", t.name);
  return users;
}

// " (TARGET, …)", for an option's help.
std::string taken_by(bool fit::FitTarget::*flag) { return " (" + users_of(flag) + ")"; }

// Any option the target does not take (fit::FitTarget) is refused, never
// silently ignored; `all` passes --kappa, --cold-start and --costs on to the
// targets that take them.
void refuse_inapplicable(const std::string& target, const GivenOptions& given,
                         const std::string& objective) {
  using Flag = bool fit::FitTarget::*;
  const fit::FitTarget* row = fit::find_fit_target(target);
  if (!row && target != "all") return;  // unknown targets are reported by the caller
  const auto check = [&](bool is_given, Flag applies, const char* option) {
    const bool all_takes = applies == &fit::FitTarget::kappa ||
                           applies == &fit::FitTarget::cold_start ||
                           applies == &fit::FitTarget::costs;
    if (!is_given || (row ? row->*applies : all_takes)) return;
    throw InputError(fmt::format("{} does not apply to `fit {}` (it applies to: {})", option,
                                 target, users_of(applies)));
  };
  check(given.precision, &fit::FitTarget::precision, "--precision");
  check(given.objective, &fit::FitTarget::objective, "--objective");
  check(given.kappa, &fit::FitTarget::kappa, "--kappa");
  check(given.max_error, &fit::FitTarget::max_error, "--max-error");
  check(given.alpha_free, &fit::FitTarget::alpha_free, "--alpha-free");
  check(given.cold_start, &fit::FitTarget::cold_start, "--cold-start");
  check(given.costs, &fit::FitTarget::costs, "--costs");
  if (target == "lambda-d" && given.kappa && objective != "irradiance")
    throw InputError(
        "--kappa does not apply to `fit lambda-d` without --objective irradiance (the other "
        "lambda-d objectives are integrals over the sphere, independent of κ)");
}

fit::FitSpec make_spec(const FitCliOptions& o, const std::string& target,
                       const std::string& command) {
  fit::FitSpec spec;
  spec.target = target;
  spec.precision = io::parse_option<io::Precision>("--precision", o.precision);
  spec.objective = o.objective;
  spec.alpha_free = o.alpha_free;
  spec.cold_start = o.cold_start;
  spec.command = command;
  if (!o.kappa.empty()) {
    // κ must survive the precision the constants are fitted for.
    io::KappaRangeRules rules;
    rules.format = io::number_format(spec.precision);
    const auto parsed = io::parse_kappa_range(o.kappa, rules);
    if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--kappa: " + *why);
    spec.kappa_lo = std::get<io::KappaRange>(parsed).lo;
    spec.kappa_hi = std::get<io::KappaRange>(parsed).hi;
    spec.kappa_range_given = true;
  }
  if (o.max_error != 0) {
    if (!(o.max_error > 0) || !std::isfinite(o.max_error))
      throw InputError(fmt::format("--max-error must be a positive number; got {}", o.max_error));
    spec.max_error = o.max_error;
  }
  return spec;
}

// The costs of the cost table (`sglab bench`, `sglab gpucost`): --costs FILE,
// else the project's data/results/costs.json when there is one, else none (the
// report then says so). In the default cost source of `pareto` and `recommend`
// (cost/cost_source.hpp: GPU cycles on navi21, a compiler estimate with no
// run-to-run noise) when the table has a "gpu" section for it, else CPU batch
// ns/eval (report::default_float_costs). A malformed table is bad input.
fit::MethodCosts read_method_costs(const std::string& option) {
  std::filesystem::path path = option;
  if (option.empty()) {
    const auto found = cost::default_cost_table_path();
    std::error_code ec;
    if (!found || !std::filesystem::exists(*found, ec)) return {};
    path = *found;
  }
  const cost::CostTable table = cost::read_cost_table(path);
  const report::MethodCostMap found = report::default_float_costs(table);
  fit::MethodCosts costs;
  costs.what = found.source.describe();
  costs.source = found.source.kind == cost::CostSourceKind::gpu
                     ? fmt::format("{} (sglab gpucost, {})", path.string(), table.gpu->driver)
                     : fmt::format("{} (sglab bench, {}; {}, {} cores)", path.string(),
                                   table.info.date, table.info.cpu, table.info.cores);
  costs.per_method = found.cost;
  return costs;
}

double achieved_objective(const fit::ordered_json& set) {
  const auto& prov = set["provenance"];
  if (!prov.contains("achieved") || !prov["achieved"].contains("objective"))
    return std::numeric_limits<double>::infinity();
  return prov["achieved"]["objective"].get<double>();
}

// The sets to write: each converged set unless an existing file in the output
// folder is better (then only with --force). Appends a line per set to `log`.
std::vector<fit::ConstantSetFile> sets_to_write(const fit::FitOutcome& outcome,
                                                const std::filesystem::path& out_dir, bool force,
                                                std::string& log) {
  namespace fs = std::filesystem;
  std::vector<fit::ConstantSetFile> out;
  for (const auto& set : outcome.constant_sets) {
    const fs::path path = out_dir / fmt::format("{}-{}.json", set["target"].get<std::string>(),
                                                set["variant"].get<std::string>());
    if (!outcome.converged) {
      log += fmt::format("  not written: the fit did not converge ({})\n", path.string());
      continue;
    }
    std::error_code ec;
    if (fs::exists(path, ec) && !force) {
      try {
        const fit::ordered_json old = fit::load_constant_set(path);
        // Objectives compare only for the same form and the same objective
        // (sglab-acc's weight names its target): otherwise the new set replaces.
        const auto field = [](const fit::ordered_json& j, const char* pointer) {
          return j.value(fit::ordered_json::json_pointer(pointer), std::string());
        };
        const bool comparable =
            field(old, "/cpp_type") == field(set, "/cpp_type") &&
            field(old, "/provenance/objective") == field(set, "/provenance/objective");
        if (!comparable)
          log += fmt::format("  replacing {}: its form or objective differs from the new fit's\n",
                             path.string());
        else if (achieved_objective(old) < achieved_objective(set)) {
          log += fmt::format(
              "  kept {}: its objective {:.6e} beats the new {:.6e} (use --force to replace)\n",
              path.string(), achieved_objective(old), achieved_objective(set));
          continue;
        }
      } catch (const fit::ConstantsError& e) {
        log += fmt::format("  replacing an invalid file: {}\n", e.what());
      }
    }
    out.push_back({path, set});
  }
  return out;
}

namespace fs = std::filesystem;

// The command line of one fit as its provenance records it.
std::string command_of(const FitCliOptions& o, std::string_view target) {
  std::string c = fmt::format("sglab fit {}", target);
  if (o.precision != "float") c += " --precision " + o.precision;
  if (!o.objective.empty()) c += " --objective " + o.objective;
  if (!o.kappa.empty()) c += " --kappa " + o.kappa;
  if (o.max_error != 0) c += fmt::format(" --max-error {}", o.max_error);
  if (o.alpha_free) c += " --alpha-free";
  if (o.cold_start) c += " --cold-start";
  return c;
}

// The fits to run: the one target, or for `all` every run of the target table.
std::vector<fit::FitSpec> fit_specs(const FitCliOptions& o) {
  std::vector<fit::FitSpec> specs;
  if (o.target == "all") {
    for (const auto& target : fit::fit_targets())
      for (const auto& run : target.all) {
        FitCliOptions each = o;
        each.objective = run.objective;
        each.alpha_free = run.alpha_free;
        each.precision = run.precision;
        // lambda-d takes --kappa only with --objective irradiance, not its fit all run
        if (!target.kappa || target.name == "lambda-d") each.kappa.clear();
        if (!target.cold_start) each.cold_start = false;
        specs.push_back(make_spec(each, std::string(target.name), command_of(each, target.name)));
      }
  } else {
    if (!fit::find_fit_target(o.target))
      throw InputError(fmt::format("unknown fit target '{}' (known: {}, all)", o.target,
                                   fit::fit_target_names()));
    specs.push_back(make_spec(o, o.target, command_of(o, o.target)));
  }
  const bool needs_costs = std::any_of(specs.begin(), specs.end(), [](const fit::FitSpec& s) {
    return fit::find_fit_target(s.target)->costs;
  });
  if (needs_costs) {
    const fit::MethodCosts costs = read_method_costs(o.costs);
    for (auto& s : specs) s.costs = costs;
  }
  return specs;
}

// Where the results go.
struct Destination {
  fs::path out_dir, header;
  std::optional<fs::path> base_dir;       // the project's data/constants, if any
  std::vector<fit::SkippedFile> skipped;  // files of the folders read that are not constant sets
};

// Resolved and checked before the (long) fits so that a missing project or an
// unusable output is reported at once. A dry run writes nothing and needs none.
Destination resolve_destination(const FitCliOptions& o) {
  Destination d;
  try {
    if (!o.dry_run || !o.out_dir.empty()) {
      d.out_dir = o.out_dir.empty() ? fit::default_constants_dir() : fs::path(o.out_dir);
      d.header = o.header.empty() ? fit::default_header_for(d.out_dir) : fs::path(o.header);
    }
    if (!o.dry_run) {
      // The outputs, before the fits: a folder that is not one, or a header
      // that is not a regular file, is refused now rather than after them.
      io::check_output_folder(d.out_dir);
      io::check_output_path(d.header);
    }
    std::error_code ec;
    if (const auto root = fit::find_project_root(fs::current_path(ec)); root && !ec)
      d.base_dir = *root / "data" / "constants";
    if (!o.dry_run && !d.base_dir) {
      // Outside a project the header can only come from --out itself: it
      // must already hold every set the code uses.
      std::vector<fit::ordered_json> sets;
      std::vector<std::string> files;
      if (fs::exists(d.out_dir, ec))
        for (auto& f : fit::load_constant_set_files(d.out_dir, &d.skipped)) {
          files.push_back(f.file.string());
          sets.push_back(std::move(f.set));
        }
      try {
        fit::validate_header_sets(sets, files);
      } catch (const fit::ConstantsError& e) {
        throw fit::ConstantsError(
            fmt::format("no sglab project at or above the working directory, so the header would "
                        "hold only the sets in {}, and {}: run inside a checkout, or use --dry-run",
                        d.out_dir.string(), e.what()));
      }
    }
  } catch (const fit::ConstantsError& e) {
    throw InputError(e.what());
  }
  return d;
}

// What the fits produced.
struct FitRuns {
  fit::ordered_json reports = fit::ordered_json::array();
  std::vector<fit::ConstantSetFile> to_write;
  std::string log;
  bool all_converged = true;
};

// Runs the fits, --jobs at a time (fit::run_fits; progress on a terminal);
// prints each fit's text in order unless the output is JSON.
FitRuns run_fits(const std::vector<fit::FitSpec>& specs, const FitCliOptions& o,
                 const Destination& d) {
  FitRuns runs;
  io::Progress progress("fit", specs.size());
  try {
    fit::run_fits(specs, o.jobs, progress, [&](std::size_t i, fit::FitOutcome& outcome) {
      runs.all_converged = runs.all_converged && outcome.converged;
      if (!o.json) {
        fmt::print("{}", outcome.text);
        std::fflush(stdout);
      }
      if (!o.dry_run)
        for (auto& f : sets_to_write(outcome, d.out_dir, o.force, runs.log))
          runs.to_write.push_back(std::move(f));
      outcome.report["command"] = specs[i].command;
      runs.reports.push_back(std::move(outcome.report));
    });
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  progress.finish();
  return runs;
}

// Writes the sets and the header as one unit; the files written, in order.
fit::ordered_json write_results(FitRuns& runs, Destination& d) {
  fit::ordered_json written = fit::ordered_json::array();
  try {
    d.skipped.clear();  // read again, with the sets written
    fit::write_sets_and_header(runs.to_write, d.out_dir, d.base_dir, d.header, &d.skipped);
  } catch (const fit::ConstantsError& e) {
    throw InputError(fmt::format("nothing was written: {}", e.what()));
  }
  for (const auto& f : d.skipped)
    runs.log += fmt::format("  skipped {}: not a constant set: {}\n", f.file.string(), f.reason);
  for (const auto& f : runs.to_write) {
    runs.log += fmt::format("  wrote {}\n", f.file.string());
    written.push_back(f.file.string());
  }
  runs.log += fmt::format("regenerated {}\n", d.header.string());
  written.push_back(d.header.string());
  return written;
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto o = std::make_shared<FitCliOptions>();
  auto* cmd = app.add_subcommand(
      "fit", "Refit constants with Ceres and write data/constants/*.json + the runtime header");
  std::string targets_help = "what to fit:";
  for (const auto& t : fit::fit_targets())
    targets_help += fmt::format("\n  {:<15} {}", t.name, t.help);
  targets_help += fmt::format("\n  {:<15} every target at its standard settings", "all");
  cmd->add_option("target", o->target, targets_help)->required();
  auto* precision = cmd->add_option("--precision", o->precision,
                                    "working precision: half | float | double" +
                                        taken_by(&fit::FitTarget::precision))
                        ->capture_default_str();
  auto* objective = cmd->add_option(
      "--objective", o->objective,
      "the target's objective (see the list above)" + taken_by(&fit::FitTarget::objective));
  auto* kappa = cmd->add_option(
      "--kappa", o->kappa,
      "κ range LO:HI of the fit (default 1e-3:1e4; LO must not round to 0 in the working "
      "precision; lambda-d only with --objective irradiance)" +
          taken_by(&fit::FitTarget::kappa));
  auto* max_error =
      cmd->add_option("--max-error", o->max_error,
                      "model order: the smallest model meeting this error (erf: degrees and split; "
                      "steepness: rational order of t; sglab-acc: the member)" +
                          taken_by(&fit::FitTarget::max_error));
  auto* alpha_free = cmd->add_flag(
      "--alpha-free", o->alpha_free,
      "α free instead of tied by energy conservation" + taken_by(&fit::FitTarget::alpha_free));
  auto* cold_start =
      cmd->add_flag("--cold-start", o->cold_start,
                    "fit from scratch instead of polishing the committed constant set" +
                        taken_by(&fit::FitTarget::cold_start));
  cmd->add_flag("--json", o->json, "print the fit results as JSON");
  auto* costs = add_path_option(cmd, "--costs", o->costs,
                                "cost table for the cost column: its GPU cycles on navi21 (`sglab "
                                "gpucost --out DIR`), else "
                                "its CPU batch ns (`sglab bench`) (default: "
                                "data/results/costs.json of the project holding "
                                "the working directory, if any)" +
                                    taken_by(&fit::FitTarget::costs));
  cmd->add_flag("--force", o->force, "replace an existing constant set even when it is better");
  cmd->add_flag("--dry-run", o->dry_run, "fit and report, write nothing");
  cmd->add_option("--jobs", o->jobs,
                  "fits to run at once (fit all), each on a thread of its own; the results do not "
                  "depend on it (default: the number of cores)")
      ->check(count_in(1, 1024));
  add_path_option(cmd, "--out", o->out_dir,
                  "directory of constant-set JSON files (default: data/constants of the sglab "
                  "project found at or above the working directory)");
  add_path_option(
      cmd, "--header", o->header,
      "runtime header to regenerate (default: the project's include/sglab/constants.hpp when "
      "--out is its data/constants, else OUT/constants.hpp; a fit into another folder never "
      "touches the checkout). The header holds the project's sets with those of --out in their "
      "place");
  cmd->callback([o, precision, objective, kappa, max_error, alpha_free, cold_start, costs] {
    const GivenOptions given{precision->count() > 0,  objective->count() > 0,
                             kappa->count() > 0,      max_error->count() > 0,
                             alpha_free->count() > 0, cold_start->count() > 0,
                             costs->count() > 0};
    refuse_inapplicable(o->target, given, o->objective);
    const std::vector<fit::FitSpec> specs = fit_specs(*o);
    Destination dest = resolve_destination(*o);

    const auto start = std::chrono::steady_clock::now();
    FitRuns runs = run_fits(specs, *o, dest);
    const fit::ordered_json written =
        o->dry_run ? fit::ordered_json::array() : write_results(runs, dest);
    // The report (stdout) is the same for the same inputs: no timing in it.
    // The time taken is a terminal's progress information.
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o->json) {
      fit::ordered_json out =
          runs.reports.size() == 1 ? runs.reports[0] : fit::ordered_json{{"fits", runs.reports}};
      out["dry_run"] = o->dry_run;
      out["written"] = written;
      out["skipped"] = fit::ordered_json::array();
      for (const auto& f : dest.skipped)
        out["skipped"].push_back({{"file", f.file.string()}, {"reason", f.reason}});
      fmt::print("{}\n", out.dump(2));
    } else {
      fmt::print("{}", runs.log);
      if (o->dry_run) fmt::print("dry run: nothing was written\n");
    }
    std::fflush(stdout);
    if (io::stderr_is_terminal()) fmt::print(stderr, "fit took {:.1f} s\n", secs);
    if (!runs.all_converged)
      throw std::runtime_error("a fit did not converge (see above); nothing was written for it");
  });
}

}  // namespace sglab::app
