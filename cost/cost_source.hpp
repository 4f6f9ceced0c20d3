// cost/cost_source.hpp — which cost `sglab pareto`, `sglab recommend` and
// the Pareto figure put on their speed axis: one option, `--cost SOURCE`,
// parsed by one function (parse_cost_source), as κ ranges are by
// common/args.hpp.
//
//   gpu:FAMILY  what a renderer pays per light per pixel on the RADV null
//               device of FAMILY (e.g. navi21): ACO's inverse throughput (the
//               estimated cycles one wave keeps a SIMD busy) of the method's
//               GLSL export (float) in a per-pixel loop over 8 lights, divided
//               by 8, in the split form where the method has one (the per-light
//               setup is paid once per light, not per pixel), from the "gpu"
//               section of the cost table (`sglab gpucost --out DIR`,
//               cost/gpu_report.hpp, gpu::renderer_row). Unit "cycles". A
//               compiler estimate, not a timing.
//   gpu-single:FAMILY  the same estimate for one unsplit call per invocation
//               (gpu::single_row).
//   cpu-batch   batch ns per evaluation of the cost table (`sglab bench`).
//   cpu-scalar  scalar ns per evaluation (registry function pointer per call).
//
// The default is gpu:navi21 (RDNA2) for float; the shaders are float, so
// under --precision double (and for live timing) it is cpu-batch.
#pragma once

#include <string>
#include <string_view>
#include <variant>

#include "cost/cpu_timing.hpp"

namespace sglab::cost {

enum class CostSourceKind { gpu, cpu_batch, cpu_scalar };

// Which GPU figure: the renderer's (per light per pixel in a per-pixel loop,
// split where the method has one) or one unsplit call per invocation.
enum class GpuFigure { renderer, single };

struct CostSource {
  CostSourceKind kind = CostSourceKind::gpu;
  std::string family = "navi21";           // gpu only: the RADV_FORCE_FAMILY chip name
  GpuFigure figure = GpuFigure::renderer;  // gpu only

  // "gpu:navi21", "gpu-single:navi21", "cpu-batch", "cpu-scalar" (what --cost takes)
  std::string name() const;
  std::string_view unit() const;  // "cycles" (gpu) or "ns" (cpu-*)
  // "GPU cycles per light per pixel on navi21 (…)", "CPU batch ns/eval", …
  std::string describe() const;
  // describe() without its explanation, for an axis: "GPU cycles per light per
  // pixel on navi21 (ACO estimate)", "CPU batch ns/eval", …
  std::string label() const;
  CostMode cpu_mode() const;  // batch or scalar (cpu-* only)
  bool operator==(const CostSource&) const = default;
};

// The family of the default GPU source: RDNA2, the generation of most GPUs in use.
inline constexpr std::string_view kDefaultGpuFamily = "navi21";

// gpu:navi21 for float; cpu-batch for double (the shader exports are float).
CostSource default_cost_source(io::Precision precision);

// A chip name as RADV_FORCE_FAMILY takes it: 1 to 32 lower-case letters and
// digits (`sglab gpucost --families`, `--cost gpu:FAMILY`).
bool is_gpu_family_name(std::string_view name);

// `text` as a cost source: "gpu:FAMILY" or "gpu-single:FAMILY" (FAMILY a chip
// name: 1 to 32 lower-case letters and digits), "cpu-batch" or "cpu-scalar",
// nothing else.
// On failure, why (quoting the text escaped; the caller prefixes the option).
std::variant<CostSource, std::string> parse_cost_source(std::string_view text);

}  // namespace sglab::cost
