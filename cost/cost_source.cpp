// cost/cost_source.cpp — see cost_source.hpp.
#include "cost/cost_source.hpp"

#include <fmt/format.h>

#include "common/args.hpp"
#include "cost/gpu_report.hpp"

namespace sglab::cost {

std::string CostSource::name() const {
  switch (kind) {
    case CostSourceKind::gpu:
      return (figure == GpuFigure::single ? "gpu-single:" : "gpu:") + family;
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
      return figure == GpuFigure::single
                 ? fmt::format(
                       "GPU cycles of one call on {} (ACO's inverse throughput per wave of one "
                       "unsplit call per invocation; a compiler estimate)",
                       family)
                 : fmt::format(
                       "GPU cycles per light per pixel on {0} (ACO's inverse throughput per wave "
                       "of a per-pixel loop over {1} lights, divided by {1}; the split form where "
                       "the method has one; a compiler estimate)",
                       family, gpu::kRendererLights);
    case CostSourceKind::cpu_batch:
      return "CPU batch ns/eval";
    case CostSourceKind::cpu_scalar:
      return "CPU scalar ns/eval";
  }
  return "?";
}

std::string CostSource::label() const {
  if (kind != CostSourceKind::gpu) return describe();
  return fmt::format("GPU cycles {} on {} (ACO estimate)",
                     figure == GpuFigure::single ? "of one call" : "per light per pixel", family);
}

CostMode CostSource::cpu_mode() const {
  return kind == CostSourceKind::cpu_scalar ? CostMode::scalar : CostMode::batch;
}

bool is_gpu_family_name(std::string_view name) {
  return !name.empty() && name.size() <= 32 &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789") == std::string_view::npos;
}

CostSource default_cost_source(io::Precision precision) {
  if (precision == io::Precision::float32)
    return {CostSourceKind::gpu, std::string(kDefaultGpuFamily)};
  return {CostSourceKind::cpu_batch, {}};
}

std::variant<CostSource, std::string> parse_cost_source(std::string_view text) {
  if (text == "cpu-batch") return CostSource{CostSourceKind::cpu_batch, {}};
  if (text == "cpu-scalar") return CostSource{CostSourceKind::cpu_scalar, {}};
  for (const GpuFigure figure : {GpuFigure::renderer, GpuFigure::single}) {
    const std::string_view prefix = figure == GpuFigure::single ? "gpu-single:" : "gpu:";
    if (text.substr(0, prefix.size()) != prefix) continue;
    const std::string_view family = text.substr(prefix.size());
    if (!is_gpu_family_name(family))
      return fmt::format(
          "{} does not name a GPU family (gpu:FAMILY or gpu-single:FAMILY, FAMILY a chip name of "
          "lower-case letters and digits, e.g. gpu:navi21)",
          io::quote_escaped(text));
    return CostSource{CostSourceKind::gpu, std::string(family), figure};
  }
  return fmt::format(
      "{} is not a cost source (expected gpu:FAMILY, e.g. gpu:navi21, gpu-single:FAMILY, "
      "cpu-batch or cpu-scalar)",
      io::quote_escaped(text));
}

}  // namespace sglab::cost
