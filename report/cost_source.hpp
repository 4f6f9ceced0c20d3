// report/cost_source.hpp — which cost `sglab pareto`, `sglab recommend` and
// the Pareto figure put on their speed axis: one option, `--cost SOURCE`,
// parsed by one function (parse_cost_source), as κ ranges are by
// common/args.hpp.
//
//   gpu:FAMILY  ACO's inverse throughput of the method's GLSL export (float,
//               unsplit) on the RADV null device of FAMILY (e.g. navi21): the
//               estimated cycles one wave keeps a SIMD busy, from the "gpu"
//               section of the cost table (`sglab gpucost --out DIR`,
//               export/gpu_cost.hpp). Unit "cycles". A compiler estimate,
//               not a timing.
//   cpu-batch   batch ns per evaluation of the cost table (`sglab bench`).
//   cpu-scalar  scalar ns per evaluation (registry function pointer per call).
//
// The default is gpu:navi21 (RDNA2) for float; the shaders are float, so
// under --precision double (and for live timing) it is cpu-batch.
#pragma once

#include <string>
#include <string_view>
#include <variant>

#include "report/cost.hpp"

namespace sglab::report {

enum class CostSourceKind { gpu, cpu_batch, cpu_scalar };

struct CostSource {
  CostSourceKind kind = CostSourceKind::gpu;
  std::string family = "navi21";  // gpu only: the RADV_FORCE_FAMILY chip name

  std::string name() const;       // "gpu:navi21", "cpu-batch", "cpu-scalar" (what --cost takes)
  std::string_view unit() const;  // "cycles" (gpu) or "ns" (cpu-*)
  // "GPU inverse throughput on navi21 (cycles per wave)", "CPU batch ns/eval", …
  std::string describe() const;
  CostMode cpu_mode() const;  // batch or scalar (cpu-* only)
  bool operator==(const CostSource&) const = default;
};

// The family of the default GPU source: RDNA2, the generation of most GPUs in use.
inline constexpr std::string_view kDefaultGpuFamily = "navi21";

// gpu:navi21 for float; cpu-batch for double (the shader exports are float).
CostSource default_cost_source(validate::FloatFormat precision);

// A chip name as RADV_FORCE_FAMILY takes it: 1 to 32 lower-case letters and
// digits (`sglab gpucost --families`, `--cost gpu:FAMILY`).
bool is_gpu_family_name(std::string_view name);

// `text` as a cost source: "gpu:FAMILY" (FAMILY a chip name: 1 to 32
// lower-case letters and digits), "cpu-batch" or "cpu-scalar", nothing else.
// On failure, why (quoting the text escaped; the caller prefixes the option).
std::variant<CostSource, std::string> parse_cost_source(std::string_view text);

}  // namespace sglab::report
