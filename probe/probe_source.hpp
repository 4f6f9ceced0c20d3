// probe/probe_source.hpp — a fitted probe (envmap::Probe) as the export's terms
// (shader::ProbeTerms), the probe file `sglab export --probe` reads, and what
// its exported evaluation costs on a GPU (`envmap recommend --by gpu:FAMILY`).
#pragma once

#include <string>
#include <vector>

#include "envmap/probe.hpp"
#include "export/probe_export.hpp"

namespace sglab::probe {

// Largest probe file read (a probe of 256 lobes is about 60 kB of JSON).
inline constexpr std::size_t kMaxProbeFileBytes = std::size_t{1} << 22;

// One probe object as envmap::Probe::to_json writes it (and `envmap recommend
// --write-probe`). Throws io::InputError naming the file and the key.
envmap::Probe read_probe_file(const std::string& path);

// The probe's terms: SH coefficients, ZH3's zonal term along its derived
// axis, the lobes with the probe's method; `command` for the header comment.
shader::ProbeTerms probe_terms(const envmap::Probe& probe, const std::string& command);

// What `envmap recommend --by gpu:FAMILY --lang LANG` costs a probe by: ACO's
// inverse throughput (cycles per wave) of its exported probe_irradiance(n) in
// `lang`, GLSL or HLSL (export_probe, the text `sglab export --probe --lang
// LANG` writes, compiled by glslang) on
// RADV's null device for `family`, through `sglab gpucost`'s machinery
// (export/gpu_cost.hpp): gpu::probe_shader, one call per shading point in
// whole workgroups (no branch), minus the same harness around `return n;`.
// All probes are measured in one worker process, each distinct source once.
// `driver` receives the driver's name and version. Throws
// shader::gpu::Unavailable when RADV cannot make the null device.
std::vector<double> probe_gpu_costs(const std::string& family, shader::Language lang,
                                    const std::vector<const envmap::Probe*>& probes,
                                    std::string& driver);

}  // namespace sglab::probe
