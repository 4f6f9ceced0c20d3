// report/cost_source.cpp — see cost_source.hpp.
#include "report/cost_source.hpp"

#include <fmt/format.h>

#include "common/args.hpp"

namespace sglab::report {

std::string CostSource::name() const {
  switch (kind) {
    case CostSourceKind::gpu:
      return "gpu:" + family;
    case CostSourceKind::cpu_batch:
      return "cpu-batch";
    case CostSourceKind::cpu_scalar:
      return "cpu-scalar";
  }
  return "?";
}

std::string_view CostSource::unit() const { return kind == CostSourceKind::gpu ? "cycles" : "ns"; }

std::string CostSource::describe() const {
  switch (kind) {
    case CostSourceKind::gpu:
      return fmt::format("GPU inverse throughput on {} (cycles per wave, ACO estimate)", family);
    case CostSourceKind::cpu_batch:
      return "CPU batch ns/eval";
    case CostSourceKind::cpu_scalar:
      return "CPU scalar ns/eval";
  }
  return "?";
}

CostMode CostSource::cpu_mode() const {
  return kind == CostSourceKind::cpu_scalar ? CostMode::scalar : CostMode::batch;
}

bool is_gpu_family_name(std::string_view name) {
  return !name.empty() && name.size() <= 32 &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789") == std::string_view::npos;
}

CostSource default_cost_source(validate::FloatFormat precision) {
  if (precision == validate::FloatFormat::binary32)
    return {CostSourceKind::gpu, std::string(kDefaultGpuFamily)};
  return {CostSourceKind::cpu_batch, {}};
}

std::variant<CostSource, std::string> parse_cost_source(std::string_view text) {
  if (text == "cpu-batch") return CostSource{CostSourceKind::cpu_batch, {}};
  if (text == "cpu-scalar") return CostSource{CostSourceKind::cpu_scalar, {}};
  constexpr std::string_view prefix = "gpu:";
  if (text.substr(0, prefix.size()) == prefix) {
    const std::string_view family = text.substr(prefix.size());
    if (!is_gpu_family_name(family))
      return fmt::format(
          "{} does not name a GPU family (gpu:FAMILY, FAMILY a chip name of lower-case letters and "
          "digits, e.g. gpu:navi21)",
          io::quote_escaped(text));
    return CostSource{CostSourceKind::gpu, std::string(family)};
  }
  return fmt::format(
      "{} is not a cost source (expected gpu:FAMILY, e.g. gpu:navi21, cpu-batch or cpu-scalar)",
      io::quote_escaped(text));
}

}  // namespace sglab::report
