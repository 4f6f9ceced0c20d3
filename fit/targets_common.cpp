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
    case WorkingPrecision::half: return std::ldexp(1.0, -10);
    case WorkingPrecision::single: return std::ldexp(1.0, -23);
    case WorkingPrecision::dbl: return std::ldexp(1.0, -52);
  }
  return 0;
}

std::string precision_name(WorkingPrecision p) {
  switch (p) {
    case WorkingPrecision::half: return "half";
    case WorkingPrecision::single: return "float";
    case WorkingPrecision::dbl: return "double";
  }
  return "?";
}

std::optional<WorkingPrecision> parse_precision(const std::string& name) {
  if (name == "half") return WorkingPrecision::half;
  if (name == "float") return WorkingPrecision::single;
  if (name == "double") return WorkingPrecision::dbl;
  return std::nullopt;
}

std::vector<double> kappa_grid(double lo, double hi, int count) { return io::log_spaced(lo, hi, count); }

std::vector<double> cosine_grid(int count) {
  std::vector<double> c;
  for (int i = 0; i < count; ++i) c.push_back(-1.0 + 2.0 * i / (count - 1));
  return c;
}

ordered_json make_constant_set(const FitSpec& spec, const std::string& target, const std::string& variant,
                               const std::string& cpp_type, const std::string& form, ordered_json coefficients,
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

const std::vector<std::string>& fit_targets() {
  static const std::vector<std::string> targets = {"clamped-cosine", "steepness2022", "steepness2024", "erf",
                                                   "lambda-d",       "sglab-fast",    "sglab-accurate"};
  return targets;
}

FitOutcome run_fit(const FitSpec& spec) {
  if (spec.target == "clamped-cosine") return fit_clamped_cosine(spec);
  if (spec.target == "steepness2022" || spec.target == "steepness2024") return fit_steepness(spec);
  if (spec.target == "lambda-d") return fit_lambda_d(spec);
  if (spec.target == "erf") return fit_erf(spec);
  if (spec.target == "sglab-fast") return fit_sglab_fast(spec);
  if (spec.target == "sglab-accurate") return fit_sglab_accurate(spec);
  std::string known;
  for (const auto& t : fit_targets()) known += (known.empty() ? "" : ", ") + t;
  throw std::invalid_argument(fmt::format("unknown fit target '{}' (known: {}, all)", spec.target, known));
}

}  // namespace sglab::fit
