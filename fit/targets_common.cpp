#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include <fmt/format.h>

#include "common/args.hpp"
#include "fit/constants_schema.hpp"
#include "fit/targets.hpp"

namespace sglab::fit {

double machine_epsilon(WorkingPrecision p) {
  switch (p) {
    case WorkingPrecision::half:
      return std::ldexp(1.0, -10);
    case WorkingPrecision::single:
      return std::ldexp(1.0, -23);
    case WorkingPrecision::dbl:
      return std::ldexp(1.0, -52);
  }
  return 0;
}

std::string precision_name(WorkingPrecision p) {
  switch (p) {
    case WorkingPrecision::half:
      return "half";
    case WorkingPrecision::single:
      return "float";
    case WorkingPrecision::dbl:
      return "double";
  }
  return "?";
}

std::optional<WorkingPrecision> parse_precision(const std::string& name) {
  if (name == "half") return WorkingPrecision::half;
  if (name == "float") return WorkingPrecision::single;
  if (name == "double") return WorkingPrecision::dbl;
  return std::nullopt;
}

std::vector<double> kappa_grid(double lo, double hi, int count) {
  return io::log_spaced(lo, hi, count);
}

std::vector<double> cosine_grid(int count) {
  std::vector<double> c;
  for (int i = 0; i < count; ++i) c.push_back(-1.0 + 2.0 * i / (count - 1));
  return c;
}

ordered_json make_constant_set(const FitSpec& spec, const std::string& target,
                               const std::string& variant, const std::string& cpp_type,
                               const std::string& form, ordered_json coefficients,
                               ordered_json objective, ordered_json achieved) {
  std::string cpp_name = target + "_" + variant;
  for (char& ch : cpp_name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
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
  prov["precision"] = precision_name(spec.precision);
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

// name, fitter, help; precision, objective, kappa, max_error, alpha_free, cold_start, costs; fit
// all
constexpr FitTarget kTargets[] = {
    {"clamped-cosine", fit_clamped_cosine,
     "λ, α of max(cos θ, 0) ≈ α(e^{λ cos θ} − 1) ([Tokuyoshi2022] Listing 1)", true, true, true,
     false, true, false, false, kClampedCosineAll},
    {"steepness2022", fit_steepness,
     "rational steepness t(κ) of [Tokuyoshi2022] Eq. 5/6 (optimal-t | irradiance)", false, true,
     true, true, false, false, false, kSteepnessAll},
    {"steepness2024", fit_steepness,
     "rational steepness t(κ) of [Tokuyoshi2024] (optimal-t | irradiance)", false, true, true, true,
     false, false, false, kSteepnessAll},
    {"erf", fit_erf, "erf approximations (listing5 | as7125)", true, true, false, true, false,
     false, false, kDefaultAll},
    // --kappa only with --objective irradiance: checked by the CLI
    {"lambda-d", fit_lambda_d,
     "diffuse SG sharpness λd (sphere-ls | hemisphere-ls | free-amplitude | irradiance)", false,
     true, true, false, false, false, false, kDefaultAll},
    {"sglab-fast", fit_sglab_fast, "sglab_fast's rational coefficients", false, false, true, false,
     false, true, false, kDefaultAll},
    {"sglab-mid", fit_sglab_mid, "sglab_mid's rational coefficients", false, false, true, false,
     false, true, false, kDefaultAll},
    // --kappa with --max-error: the model order for a range
    {"sglab-acc", fit_sglab_acc,
     "the sglab_acc ladder, or with --max-error the smallest member meeting it", false, false, true,
     true, false, false, true, kDefaultAll},
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

}  // namespace sglab::fit
