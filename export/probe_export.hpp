// export/probe_export.hpp — `sglab export --probe`: a fitted diffuse probe
// (spherical harmonics, ZH3, SG lobes or SH + lobes; envmap/probe.hpp) as one
// self-contained GLSL, HLSL or C++ function probe_irradiance(n) with its
// coefficients baked in. Lobes call the exported irradiance method the probe
// names (export_source: the same text `sglab export --method ID` prints), so
// no method body is written twice.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "export/shader_export.hpp"

namespace sglab::shader {

// The terms of a probe's irradiance E(n), RGB, as plain numbers (the export
// library does not depend on envmap; the caller converts envmap::Probe).
struct ProbeTerms {
  using Rgb = std::array<double, 3>;
  // Irradiance SH coefficients E_lm (Funk–Hecke factors applied), index
  // l² + l + m, of the real orthonormal basis of envmap::sh_basis (no
  // Condon–Shortley phase); empty: no SH part. 1, 4, 9, 16 or 25 entries.
  std::vector<Rgb> sh;
  // ZH3 [Roughton2024]: E += zonal · Y_20(axis·n), Y_20(t) = √(5/16π)(3t² − 1).
  bool has_zonal = false;
  Rgb zonal{0, 0, 0};
  Rgb zonal_axis{0, 0, 1};
  struct Lobe {
    Rgb axis;  // unit
    double sharpness;
    Rgb amplitude;
  };
  // E += amplitude · method(clamp(axis·n, −1, 1), sharpness) per lobe.
  std::vector<Lobe> lobes;
  std::string method;  // the lobes' irradiance method (an exportable id)
  // For the header comment (through comment_text): what the probe is and the
  // command that produced the source.
  std::string label;
  std::string command;
};

struct ProbeExport {
  std::string source;
  std::string entry_point = "probe_irradiance";
};

// The function `vec3 probe_irradiance(vec3 n)` (HLSL and C++: float3; n unit),
// preceded by the lobes' method export when there are lobes. C++: in
// namespace sglab_probe, with a using-declaration at global scope.
// Throws std::invalid_argument for an SH count that is no (order + 1)² with
// order ≤ 4, lobes without an exportable method, or a coefficient that is not
// finite in float, naming it.
ProbeExport export_probe(Language lang, const ProbeTerms& probe);

// A compute shader over the exported probe: binding 0 holds normals (vec4,
// xyz), binding 1 receives probe_irradiance(normal) (vec4, xyz; w = the
// normal's x, so that every harness loads the normal, as a shading point has
// it anyway: a probe that ignores it, SH L0's constant, is not credited with
// the load and costs no less than `return n;`), 64 threads per group.
// Dispatch::any_size: any buffer length (each invocation checks its index);
// whole_groups: no check, the call in no branch (the harness `envmap recommend
// --by gpu:FAMILY` costs a probe in).
std::string probe_compute_shader(Language lang, std::string_view exported_source,
                                 Dispatch dispatch = Dispatch::any_size);

}  // namespace sglab::shader
