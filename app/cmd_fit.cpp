// `sglab fit TARGET`: refit a constant set (fit/targets.hpp), write it to
// data/constants/<target>-<variant>.json with provenance and regenerate the
// runtime header. `sglab fit all` runs every target at its standard settings.
#include <chrono>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "commands.hpp"
#include "constants_io.hpp"
#include "io.hpp"
#include "targets.hpp"

namespace sglab::app {

namespace {

struct FitCliOptions {
  std::string target;
  std::string precision = "float";
  std::string objective;
  std::string kappa;
  double max_error = 0;
  bool alpha_free = false, json = false, force = false, dry_run = false;
  std::string out_dir = fit::default_constants_dir().string();
  std::string header = fit::default_header_path().string();
};

double parse_number(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(v))
    throw InputError(fmt::format("{}: '{}' is not a finite number", what, text));
  return v;
}

fit::FitSpec make_spec(const FitCliOptions& o, const std::string& target, const std::string& command) {
  fit::FitSpec spec;
  spec.target = target;
  const auto precision = fit::parse_precision(o.precision);
  if (!precision) throw InputError(fmt::format("--precision must be half, float or double; got '{}'", o.precision));
  spec.precision = *precision;
  spec.objective = o.objective;
  spec.alpha_free = o.alpha_free;
  spec.command = command;
  if (!o.kappa.empty()) {
    const auto colon = o.kappa.find(':');
    if (colon == std::string::npos) throw InputError(fmt::format("--kappa must be LO:HI; got '{}'", o.kappa));
    spec.kappa_lo = parse_number(o.kappa.substr(0, colon), "--kappa LO");
    spec.kappa_hi = parse_number(o.kappa.substr(colon + 1), "--kappa HI");
    if (!(spec.kappa_lo > 0) || !(spec.kappa_hi > spec.kappa_lo))
      throw InputError(fmt::format("--kappa needs 0 < LO < HI; got '{}'", o.kappa));
    spec.kappa_range_given = true;
  }
  if (o.max_error != 0) {
    if (!(o.max_error > 0) || !std::isfinite(o.max_error))
      throw InputError(fmt::format("--max-error must be a positive number; got {}", o.max_error));
    spec.max_error = o.max_error;
  }
  return spec;
}

double achieved_objective(const fit::ordered_json& set) {
  const auto& a = set["provenance"]["achieved"];
  return a.contains("objective") ? a["objective"].get<double>() : std::numeric_limits<double>::infinity();
}

// Writes each set unless the fit did not converge or an existing file is
// better (then only with --force). Returns a line per set.
std::string write_sets(const fit::FitOutcome& outcome, const FitCliOptions& o) {
  namespace fs = std::filesystem;
  std::string log;
  for (const auto& set : outcome.constant_sets) {
    const fs::path path =
        fs::path(o.out_dir) / fmt::format("{}-{}.json", set["target"].get<std::string>(), set["variant"].get<std::string>());
    if (!outcome.converged) {
      log += fmt::format("  not written: the fit did not converge ({})\n", path.string());
      continue;
    }
    if (fs::exists(path) && !o.force) {
      fit::ordered_json old;
      try {
        old = fit::ordered_json::parse(io::read_file(path));
      } catch (const std::exception&) {
      }
      if (old.is_object() && old.contains("provenance") && achieved_objective(old) < achieved_objective(set)) {
        log += fmt::format("  kept {}: its objective {:.6e} beats the new {:.6e} (use --force to replace)\n",
                           path.string(), achieved_objective(old), achieved_objective(set));
        continue;
      }
    }
    io::write_file_atomic(path, set.dump(2) + "\n");
    log += fmt::format("  wrote {}\n", path.string());
  }
  return log;
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto o = std::make_shared<FitCliOptions>();
  auto* cmd = app.add_subcommand("fit", "Refit constants with Ceres and write data/constants/*.json + the runtime header");
  cmd->add_option("target", o->target, "clamped-cosine | steepness2022 | steepness2024 | erf | lambda-d | sglab-accurate | all")
      ->required();
  cmd->add_option("--precision", o->precision, "working precision: half | float | double")->capture_default_str();
  cmd->add_option("--objective", o->objective,
                  "steepness: optimal-t | irradiance; lambda-d: sphere-ls | hemisphere-ls | free-amplitude | "
                  "irradiance; erf: listing5 | as7125");
  cmd->add_option("--kappa", o->kappa, "κ range LO:HI of the fit (default 1e-3:1e4)");
  cmd->add_option("--max-error", o->max_error, "model order: smallest model meeting this error (erf: degrees and split; steepness: rational order of t; sglab-accurate: correction terms and rational degree)");
  cmd->add_flag("--alpha-free", o->alpha_free, "clamped-cosine: α free instead of tied by energy conservation");
  cmd->add_flag("--json", o->json, "print the fit results as JSON");
  cmd->add_flag("--force", o->force, "replace an existing constant set even when it is better");
  cmd->add_flag("--dry-run", o->dry_run, "fit and report, write nothing");
  cmd->add_option("--out", o->out_dir, "directory of constant-set JSON files")->capture_default_str();
  cmd->add_option("--header", o->header, "runtime header regenerated from --out")->capture_default_str();
  cmd->callback([o] {
    std::string command = "sglab fit " + o->target;
    if (o->precision != "float") command += " --precision " + o->precision;
    if (!o->objective.empty()) command += " --objective " + o->objective;
    if (!o->kappa.empty()) command += " --kappa " + o->kappa;
    if (o->max_error != 0) command += fmt::format(" --max-error {}", o->max_error);
    if (o->alpha_free) command += " --alpha-free";

    std::vector<fit::FitSpec> specs;
    if (o->target == "all") {
      if (!o->objective.empty() || o->alpha_free || o->max_error != 0)
        throw InputError("`fit all` takes no --objective, --alpha-free or --max-error");
      auto add = [&](const std::string& target, const std::string& objective, bool alpha_free, const std::string& prec) {
        FitCliOptions each = *o;
        each.objective = objective;
        each.alpha_free = alpha_free;
        each.precision = prec;
        std::string c = "sglab fit " + target;
        if (prec != "float") c += " --precision " + prec;
        if (!objective.empty()) c += " --objective " + objective;
        if (alpha_free) c += " --alpha-free";
        if (!o->kappa.empty()) c += " --kappa " + o->kappa;
        specs.push_back(make_spec(each, target, c));
      };
      for (const char* prec : {"half", "float", "double"}) add("clamped-cosine", "", false, prec);
      add("clamped-cosine", "", true, "float");
      for (const char* t : {"steepness2022", "steepness2024"})
        for (const char* obj : {"optimal-t", "irradiance"}) add(t, obj, false, "float");
      add("erf", "", false, "float");
      add("lambda-d", "", false, "float");
      add("sglab-accurate", "", false, "float");
    } else {
      const auto& known = fit::fit_targets();
      if (std::find(known.begin(), known.end(), o->target) == known.end()) {
        std::string list;
        for (const auto& t : known) list += t + ", ";
        throw InputError(fmt::format("unknown fit target '{}' (known: {}all)", o->target, list));
      }
      specs.push_back(make_spec(*o, o->target, command));
    }

    fit::ordered_json reports = fit::ordered_json::array();
    bool all_converged = true;
    const auto start = std::chrono::steady_clock::now();
    io::Progress progress("fit", specs.size());
    for (const auto& spec : specs) {
      fit::FitOutcome outcome;
      try {
        outcome = fit::run_fit(spec);
      } catch (const std::invalid_argument& e) {
        throw InputError(e.what());
      }
      all_converged = all_converged && outcome.converged;
      std::string log = o->dry_run ? "" : write_sets(outcome, *o);
      progress.advance();
      if (!o->json) fmt::print("{}{}", outcome.text, log);
      outcome.report["command"] = spec.command;
      reports.push_back(outcome.report);
    }
    progress.finish();
    if (!o->dry_run) {
      fit::write_constants_header(o->out_dir, o->header);
      if (!o->json) fmt::print("regenerated {}\n", o->header);
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o->json) {
      fit::ordered_json out = reports.size() == 1 ? reports[0] : fit::ordered_json{{"fits", reports}};
      out["seconds"] = secs;
      fmt::print("{}\n", out.dump(2));
    } else {
      fmt::print("fit took {:.1f} s\n", secs);
    }
    if (!all_converged) throw std::runtime_error("a fit did not converge (see above); nothing was written for it");
  });
}

}  // namespace sglab::app
