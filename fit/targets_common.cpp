#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <exception>
#include <mutex>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <sglab/version.hpp>

#include "common/args.hpp"
#include "common/io.hpp"
#include "fit/constants_schema.hpp"
#include "fit/minimax.hpp"
#include "fit/solver_log.hpp"
#include "fit/targets.hpp"

namespace sglab::fit {

double machine_epsilon(io::Precision p) {
  switch (p) {
    case io::Precision::float16:
      return std::ldexp(1.0, -10);
    case io::Precision::float32:
      return std::ldexp(1.0, -23);
    case io::Precision::float64:
      return std::ldexp(1.0, -52);
  }
  return 0;
}

std::vector<double> kappa_grid(double lo, double hi, int count) {
  return io::log_spaced(lo, hi, count);
}

std::vector<double> cosine_grid(int count) {
  std::vector<double> c;
  for (int i = 0; i < count; ++i) c.push_back(-1.0 + 2.0 * i / (count - 1));
  return c;
}

std::string cpp_identifier(std::string text) {
  for (char& ch : text)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return text;
}

ordered_json make_constant_set(const FitSpec& spec, const std::string& target,
                               const std::string& variant, const std::string& cpp_type,
                               const std::string& form, ordered_json coefficients,
                               ordered_json objective, ordered_json achieved) {
  const std::string cpp_name = cpp_identifier(target + "_" + variant);
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  ordered_json set;
  set["format"] = std::string(kConstantSetFormat);
  set["version"] = kConstantSetVersion;
  set["target"] = target;
  set["variant"] = variant;
  set["cpp_name"] = cpp_name;
  set["cpp_type"] = cpp_type;
  set["form"] = form;
  set["coefficients"] = std::move(coefficients);
  ordered_json prov;
  prov["objective"] = std::move(objective);
  prov["precision"] = std::string(io::to_string(spec.precision));
  prov["kappa_range"] = {spec.kappa_lo, spec.kappa_hi};
  prov["grid"] = {{"kappa_count", spec.kappa_count}, {"cosine_count", spec.cosine_count}};
  prov["achieved"] = std::move(achieved);
  prov["command"] = spec.command;
  prov["tool"] = fmt::format("sglab {}", SGLAB_VERSION);
  prov["date"] = date;
  set["provenance"] = std::move(prov);
  return set;
}

namespace {

constexpr FitAllRun kClampedCosineAll[] = {
    {"", false, "half"}, {"", false, "float"}, {"", false, "double"}, {"", true, "float"}};
constexpr FitAllRun kSteepnessAll[] = {{"optimal-t", false, "float"},
                                       {"irradiance", false, "float"}};
constexpr FitAllRun kDefaultAll[] = {{"", false, "float"}};

constexpr FitTarget kTargets[] = {
    {.name = "clamped-cosine",
     .fit = fit_clamped_cosine,
     .help = "λ, α of max(cos θ, 0) ≈ α(e^{λ cos θ} − 1) ([Tokuyoshi2022] Listing 1)",
     .precision = true,
     .objective = true,
     .kappa = true,
     .alpha_free = true,
     .all = kClampedCosineAll},
    {.name = "steepness2022",
     .fit = fit_steepness,
     .help = "rational steepness t(κ) of [Tokuyoshi2022] Eq. 5/6 (optimal-t | irradiance)",
     .objective = true,
     .kappa = true,
     .max_error = true,
     .all = kSteepnessAll},
    {.name = "steepness2024",
     .fit = fit_steepness,
     .help = "rational steepness t(κ) of [Tokuyoshi2024] (optimal-t | irradiance)",
     .objective = true,
     .kappa = true,
     .max_error = true,
     .all = kSteepnessAll},
    {.name = "erf",
     .fit = fit_erf,
     .help = "erf approximations (listing5 | as7125)",
     .precision = true,
     .objective = true,
     .max_error = true,
     .all = kDefaultAll},
    // --kappa only with --objective irradiance: checked by the CLI
    {.name = "lambda-d",
     .fit = fit_lambda_d,
     .help = "diffuse SG sharpness λd (sphere-ls | hemisphere-ls | free-amplitude | irradiance)",
     .objective = true,
     .kappa = true,
     .all = kDefaultAll},
    {.name = "sglab-fast",
     .fit = fit_sglab_fast,
     .help = "sglab_fast's rational coefficients",
     .kappa = true,
     .cold_start = true,
     .all = kDefaultAll},
    {.name = "sglab-lite",
     .fit = fit_sglab_lite,
     .help = "sglab_lite's rational coefficients",
     .kappa = true,
     .cold_start = true,
     .all = kDefaultAll},
    {.name = "sglab-min",
     .fit = fit_sglab_min,
     .help = "sglab_min's coefficients",
     .kappa = true,
     .cold_start = true,
     .all = kDefaultAll},
    {.name = "sglab-mid",
     .fit = fit_sglab_mid,
     .help = "sglab_mid's rational coefficients",
     .kappa = true,
     .cold_start = true,
     .all = kDefaultAll},
    {.name = "sglab-tab",
     .fit = fit_sglab_tab,
     .help = "sglab_tab's table of cubics",
     .cold_start = true,
     .all = kDefaultAll},
    // --kappa with --max-error: the model order for a range
    {.name = "sglab-acc",
     .fit = fit_sglab_acc,
     .help = "the sglab_acc ladder, or with --max-error the smallest member meeting it",
     .kappa = true,
     .max_error = true,
     .costs = true,
     .all = kDefaultAll},
};

}  // namespace

std::span<const FitTarget> fit_targets() { return kTargets; }

const FitTarget* find_fit_target(std::string_view name) {
  for (const auto& t : kTargets)
    if (t.name == name) return &t;
  return nullptr;
}

std::string fit_target_names() {
  std::string list;
  for (const auto& t : kTargets) list += fmt::format("{}{}", list.empty() ? "" : ", ", t.name);
  return list;
}

FitOutcome run_fit(const FitSpec& spec) {
  if (const FitTarget* t = find_fit_target(spec.target)) return t->fit(spec);
  throw std::invalid_argument(
      fmt::format("unknown fit target '{}' (known: {}, all)", spec.target, fit_target_names()));
}

namespace {

// run_fit with the fit's diagnostics: the residual evaluations that were not
// finite and the messages the solver logged, both counted on this thread
// (the fit's: Ceres solves with one thread). Both 0 in a sound fit;
// otherwise a line is added to the fit's text.
FitOutcome run_fit_counted(const FitSpec& spec) {
  const std::size_t nonfinite_before = nonfinite_residual_evaluations_on_this_thread();
  const std::size_t messages_before = solver_messages_on_this_thread().count;
  FitOutcome outcome = run_fit(spec);
  const std::size_t nonfinite = nonfinite_residual_evaluations_on_this_thread() - nonfinite_before;
  const SolverMessages messages = solver_messages_on_this_thread();
  const std::size_t logged = messages.count - messages_before;
  if (nonfinite > 0)
    outcome.text += fmt::format(
        "  warning: {} residual evaluations were NaN or inf (a defect of the model on the search "
        "space)\n",
        nonfinite);
  if (logged > 0)
    outcome.text += fmt::format("  warning: the solver logged {} messages; the latest: {}\n",
                                logged, messages.last);
  outcome.report["diagnostics"] = {{"nonfinite_residual_evaluations", nonfinite},
                                   {"solver_messages", logged}};
  return outcome;
}

}  // namespace

void run_fits(const std::vector<FitSpec>& specs, std::size_t jobs, io::Progress& finished,
              const std::function<void(std::size_t, FitOutcome&)>& done) {
  if (jobs <= 1 || specs.size() <= 1) {
    for (std::size_t i = 0; i < specs.size(); ++i) {
      FitOutcome outcome;
      {
        // open-ended: counts Ceres solves
        io::Progress solves(fmt::format("fit {}, solves", specs[i].target), 0);
        FitProgressScope scope(solves);
        outcome = run_fit_counted(specs[i]);
      }
      finished.advance();
      done(i, outcome);
    }
    return;
  }
  // Up to `jobs` fits at once in an arena of that many threads; each task takes
  // the last spec not taken yet (the fit all runs end with the model ladders,
  // the longest fits: started first they do not finish alone at the end), none
  // once a fit has thrown. Whoever fills a slot hands every finished outcome
  // in spec order to `done`, under the lock: one call at a time, in order.
  struct Slot {
    std::optional<FitOutcome> outcome;
    std::exception_ptr error;
  };
  std::vector<Slot> slots(specs.size());
  std::mutex mutex;                  // guards everything below and the calls of `done`
  std::size_t left = specs.size();   // specs 0..left-1 are not taken yet
  std::size_t handed = 0;            // outcomes 0..handed-1 went to `done`
  bool stop = false;                 // a fit or `done` threw: take no more
  std::exception_ptr done_error;     // what `done` threw
  std::vector<std::size_t> running;  // the specs being fitted, shown as the progress note
  const auto show_running = [&] {
    std::string names;
    for (std::size_t k : running) names += (names.empty() ? "" : ", ") + specs[k].target;
    finished.note(names.empty() ? "" : "running " + names);
  };
  const auto fit_next = [&] {
    std::size_t i;
    {
      const std::lock_guard lock(mutex);
      if (stop || left == 0) return;
      i = --left;
      running.push_back(i);
      show_running();
    }
    Slot slot;
    // Isolated: while a fit waits on its own parallel loops (the erf scans),
    // its thread runs none of the other fits, whose counts and progress are
    // per thread.
    tbb::this_task_arena::isolate([&] {
      try {
        slot.outcome = run_fit_counted(specs[i]);
      } catch (...) {
        slot.error = std::current_exception();
      }
    });
    const std::lock_guard lock(mutex);
    stop = stop || slot.error;
    slots[i] = std::move(slot);
    running.erase(std::find(running.begin(), running.end(), i));
    show_running();
    finished.advance();
    for (; !done_error && handed < slots.size() && slots[handed].outcome; ++handed) {
      try {
        done(handed, *slots[handed].outcome);
      } catch (...) {
        done_error = std::current_exception();
        stop = true;
      }
    }
  };
  tbb::task_arena arena(static_cast<int>(std::min(jobs, specs.size())));
  tbb::task_group group;
  arena.execute([&] {
    for (std::size_t k = 0; k < specs.size(); ++k) group.run(fit_next);
    group.wait();
  });
  // The first failure in spec order: `done` was called only before any fit that threw.
  if (done_error) std::rethrow_exception(done_error);
  for (const Slot& slot : slots)
    if (slot.error) std::rethrow_exception(slot.error);
}

}  // namespace sglab::fit
