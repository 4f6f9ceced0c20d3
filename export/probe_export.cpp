// export/probe_export.cpp — a fitted probe as GLSL, HLSL or C++ source
// (probe_export.hpp).
#include "export/probe_export.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "common/comment_text.hpp"
#include "export/shader_text.hpp"

namespace sglab::shader {

namespace {

using detail::lit;
using Rgb = ProbeTerms::Rgb;

void check_float(double v, const std::string& what) {
  if (!std::isfinite(v) || std::abs(v) > std::numeric_limits<float>::max())
    throw std::invalid_argument(fmt::format("probe: {} = {} is not finite in float", what, v));
}

// r, g, b += c · term (c alone for an empty term), the coefficient per channel.
std::string accumulate(const Rgb& c, const std::string& term, const std::string& what) {
  std::string s;
  const char* ch = "rgb";
  for (std::size_t k = 0; k < 3; ++k) {
    check_float(c[k], what);
    s += term.empty() ? fmt::format("  {} += {};\n", ch[k], lit(c[k]))
                      : fmt::format("  {} += {} * {};\n", ch[k], lit(c[k]), term);
  }
  return s;
}

Rgb scaled(const Rgb& c, double s) { return {c[0] * s, c[1] * s, c[2] * s}; }

// The SH part, straight-line code of the basis of envmap::sh_basis
// ([Ramamoorthi2001] eq. 3 with real harmonics, no Condon–Shortley phase):
// Y_l0 = K_l0 P̄_l^0(z), Y_l±m = √2 K_lm P̄_l^m(z) (Re, Im)(x + iy)^m. Every
// P̄_l^m of one m is (2m − 1)!! times the recurrence started from 1, and that
// factor and the normalization are folded into the baked coefficient, so the
// code computes c_m + i s_m = (x + iy)^m and
// p_l = ((2l − 1) z p_{l−1} − (l + m − 1) p_{l−2}) / (l − m) from p_m = 1.
std::string sh_code(const std::vector<Rgb>& sh) {
  int order = -1;
  for (int o = 0; o <= 4; ++o)
    if (sh.size() == static_cast<std::size_t>((o + 1) * (o + 1))) order = o;
  if (order < 0)
    throw std::invalid_argument(
        fmt::format("probe: {} SH coefficients; an SH part has (order + 1)^2 of them, order 0 to 4",
                    sh.size()));
  std::string s =
      fmt::format("  // SH L{}: E_lm [Ramamoorthi2001] times the basis' constants\n", order);
  if (order >= 1) s += "  float c1 = n.x;\n  float s1 = n.y;\n";
  for (int m = 2; m <= order; ++m)
    s += fmt::format(
        "  float c{m} = c{p} * n.x - s{p} * n.y;\n  float s{m} = c{p} * n.y + s{p} * n.x;\n",
        fmt::arg("m", m), fmt::arg("p", m - 1));
  double pmm = 1;  // (2m − 1)!!
  for (int m = 0; m <= order; ++m) {
    if (m > 0) pmm *= 2 * m - 1;
    for (int l = m; l <= order; ++l) {
      const std::string p = fmt::format("p{}_{}", l, m);
      if (l == m) {
        // p = 1: no variable.
      } else if (l == m + 1) {
        s += l == 1 ? fmt::format("  float {} = n.z;\n", p)
                    : fmt::format("  float {} = {} * n.z;\n", p, lit(2 * l - 1));
      } else {
        const double a = static_cast<double>(2 * l - 1) / (l - m);
        const double b = static_cast<double>(l + m - 1) / (l - m);
        const std::string p1 = fmt::format("p{}_{}", l - 1, m);
        const std::string p2 = l - 2 == m ? std::string("1.0f") : fmt::format("p{}_{}", l - 2, m);
        s += fmt::format("  float {} = {} * n.z * {} - {} * {};\n", p, lit(a), p1, lit(b), p2);
      }
      double ratio = 1;  // (l − m)!/(l + m)!
      for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
      const double K = std::sqrt((2 * l + 1) / (4 * M_PI) * ratio) * pmm;
      const std::string pl = l == m ? std::string() : p + " * ";
      if (m == 0) {
        const std::size_t idx = static_cast<std::size_t>(l * l + l);
        s += accumulate(scaled(sh[idx], K), l == 0 ? std::string() : p, fmt::format("sh[{}]", idx));
      } else {
        const double w = std::sqrt(2.0) * K;
        const std::size_t plus = static_cast<std::size_t>(l * l + l + m);
        const std::size_t minus = static_cast<std::size_t>(l * l + l - m);
        s += accumulate(scaled(sh[plus], w), fmt::format("{}c{}", pl, m),
                        fmt::format("sh[{}]", plus));
        s += accumulate(scaled(sh[minus], w), fmt::format("{}s{}", pl, m),
                        fmt::format("sh[{}]", minus));
      }
    }
  }
  return s;
}

std::string dot_text(const Rgb& a) {
  for (std::size_t k = 0; k < 3; ++k) check_float(a[k], "an axis component");
  return fmt::format("{} * n.x + {} * n.y + {} * n.z", lit(a[0]), lit(a[1]), lit(a[2]));
}

}  // namespace

ProbeExport export_probe(Language lang, const ProbeTerms& probe) {
  ProbeExport out;
  std::string head =
      "// probe_irradiance(n): the diffuse irradiance E(n) of a fitted probe, RGB, "
      "n a unit normal\n";
  head += "// probe: " + io::comment_text(probe.label) + "\n";
  if (!probe.command.empty()) head += "// command: " + io::comment_text(probe.command) + "\n";
  std::string method_source, entry;
  if (!probe.lobes.empty()) {
    const auto known = exportable_methods();
    if (std::find(known.begin(), known.end(), probe.method) == known.end())
      throw std::invalid_argument(fmt::format(
          "probe: the lobes' method '{}' is not an exportable irradiance method", probe.method));
    const ExportResult m = export_source(standard_request(lang, probe.method));
    method_source = m.source + "\n";
    entry = m.entry_point;
    head += fmt::format(
        "// lobes: E += a_k {}(clamp(mu_k . n, -1, 1), kappa_k), the method below\n", entry);
  }
  const char* vec3 = lang == Language::glsl ? "vec3" : "float3";
  std::string body;
  if (!probe.sh.empty()) body += sh_code(probe.sh);
  if (probe.has_zonal) {
    body += "  // ZH3 [Roughton2024]: zonal l = 2 term along the L1 luminance direction\n";
    body += fmt::format("  float t = {};\n  float zh = 3.0f * t * t - 1.0f;\n",
                        dot_text(probe.zonal_axis));
    body += accumulate(scaled(probe.zonal, std::sqrt(5 / (16 * M_PI))), "zh", "zonal");
  }
  for (std::size_t k = 0; k < probe.lobes.size(); ++k) {
    const auto& l = probe.lobes[k];
    check_float(l.sharpness, fmt::format("lobes[{}].sharpness", k));
    body += fmt::format("  float e{k} = {entry}(clamp({dot}, -1.0f, 1.0f), {kappa});\n",
                        fmt::arg("k", k), fmt::arg("entry", entry),
                        fmt::arg("dot", dot_text(l.axis)), fmt::arg("kappa", lit(l.sharpness)));
    body += accumulate(l.amplitude, fmt::format("e{}", k), fmt::format("lobes[{}].amplitude", k));
  }
  const std::string fn = fmt::format(
      "{inl}{v} probe_irradiance({v} n) {{\n  float r = 0.0f;\n  float g = 0.0f;\n  float b = "
      "0.0f;\n{body}  return {v}(r, g, b);\n}}\n",
      fmt::arg("inl", lang == Language::cpp ? "inline " : ""), fmt::arg("v", vec3),
      fmt::arg("body", body));
  if (lang == Language::cpp) {
    out.source = head + "\n" + (method_source.empty() ? "#include <cmath>\n\n" : method_source) +
                 "namespace sglab_probe {\n"
                 "struct float3 {\n  float x, y, z;\n  float3(float a, float b, float c) : x(a), "
                 "y(b), z(c) {}\n};\n"
                 "inline float clamp(float x, float lo, float hi) { return x < lo ? lo : hi < x ? "
                 "hi : x; }\n\n" +
                 fn + "}  // namespace sglab_probe\nusing sglab_probe::probe_irradiance;\n";
  } else {
    out.source = head + "\n" + method_source + fn;
  }
  return out;
}

std::string probe_compute_shader(Language lang, std::string_view exported, Dispatch dispatch) {
  if (lang == Language::cpp)
    throw std::invalid_argument("probe_compute_shader: C++ is not a shader language");
  const bool checked = dispatch == Dispatch::any_size;
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec4 normals[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ vec4 result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  {}{{
    vec3 normal = normals[i].xyz;
    result[i] = vec4(probe_irradiance(normal), normal.x);
  }}
}}
)",
                       exported, checked ? "if (i < uint(normals.length())) " : "");
  return fmt::format(
      R"([[vk::binding(0, 0)]] StructuredBuffer<float4> normals;
[[vk::binding(1, 0)]] RWStructuredBuffer<float4> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
{}{{
    float3 normal = normals[id.x].xyz;
    result[id.x] = float4(probe_irradiance(normal), normal.x);
  }}
}}
)",
      exported,
      checked ? "  uint n, stride;\n  normals.GetDimensions(n, stride);\n  if (id.x < n) " : "  ");
}

}  // namespace sglab::shader
