#include "export/shader_export.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace sglab::shader {

namespace {

// The wrapper of a half export: float buffers, converted at the call.
std::string compute_shader_half(Language lang, std::string_view exported, std::string_view entry) {
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(cosine_kappa.length()))
    result[i] = float({}(float16_t(cosine_kappa[i].x), float16_t(cosine_kappa[i].y)));
}}
)",
                       exported, entry);
  if (lang == Language::hlsl)
    return fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  cosine_kappa.GetDimensions(n, stride);
  if (id.x < n) result[id.x] = (float){}((half)cosine_kappa[id.x].x, (half)cosine_kappa[id.x].y);
}}
)",
                       exported, entry);
  throw std::invalid_argument("compute_shader: C++ is not a shader language");
}

}  // namespace

std::string compute_shader(Language lang, std::string_view exported, std::string_view entry, Precision precision) {
  if (precision == Precision::float16) return compute_shader_half(lang, exported, entry);
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(cosine_kappa.length())) result[i] = {}(cosine_kappa[i].x, cosine_kappa[i].y);
}}
)",
                       exported, entry);
  if (lang == Language::hlsl)
    return fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  cosine_kappa.GetDimensions(n, stride);
  if (id.x < n) result[id.x] = {}(cosine_kappa[id.x].x, cosine_kappa[id.x].y);
}}
)",
                       exported, entry);
  throw std::invalid_argument("compute_shader: C++ is not a shader language");
}

namespace {
void require_split(const ExportResult& exported, const char* who) {
  if (exported.light_struct.empty() || exported.light_function.empty())
    throw std::invalid_argument(fmt::format("{}: the export is not a split form (ExportRequest::split)", who));
}
}  // namespace

std::string split_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "split_compute_shader");
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;

{0}
layout(std430, set = 0, binding = 0) readonly buffer Cosines {{ float cosines[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};
layout(std430, set = 0, binding = 2) readonly buffer Lights {{ {1} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_WorkGroupID.y;
  uint n = uint(cosines.length());
  if (i < n) result[l * n + i] = {2}(lights[l], cosines[i]);
}}
)",
                       exported, ex.light_struct, ex.entry_point);
  if (lang == Language::hlsl)
    return fmt::format(R"({0}
[[vk::binding(0, 0)]] StructuredBuffer<float> cosines;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;
[[vk::binding(2, 0)]] StructuredBuffer<{1}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID, uint3 group : SV_GroupID) {{
  uint n, stride;
  cosines.GetDimensions(n, stride);
  if (id.x < n) result[group.y * n + id.x] = {2}(lights[group.y], cosines[id.x]);
}}
)",
                       exported, ex.light_struct, ex.entry_point);
  throw std::invalid_argument("split_compute_shader: C++ is not a shader language");
}

std::string light_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "light_compute_shader");
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;

{0}
layout(std430, set = 0, binding = 0) readonly buffer Kappas {{ float kappas[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Lights {{ {1} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(kappas.length())) lights[i] = {2}(kappas[i]);
}}
)",
                       exported, ex.light_struct, ex.light_function);
  if (lang == Language::hlsl)
    return fmt::format(R"({0}
[[vk::binding(0, 0)]] StructuredBuffer<float> kappas;
[[vk::binding(1, 0)]] RWStructuredBuffer<{1}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  kappas.GetDimensions(n, stride);
  if (id.x < n) lights[id.x] = {2}(kappas[id.x]);
}}
)",
                       exported, ex.light_struct, ex.light_function);
  throw std::invalid_argument("light_compute_shader: C++ is not a shader language");
}

}  // namespace sglab::shader
