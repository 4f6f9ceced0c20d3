#include "export/shader_export.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace sglab::shader {

namespace {

void require_shader_language(Language lang, const char* who) {
  if (lang == Language::cpp)
    throw std::invalid_argument(fmt::format("{}: C++ is not a shader language", who));
}

void require_split(const ExportResult& exported, const char* who) {
  if (exported.light_struct.empty() || exported.light_function.empty())
    throw std::invalid_argument(
        fmt::format("{}: the export is not a split form (ExportRequest::split)", who));
}

// entry(x, y) in the wrapper's float: a half export takes half arguments and
// its result is converted back to the float buffer.
std::string call_text(Language lang, std::string_view entry, std::string_view x, std::string_view y,
                      Precision precision) {
  if (precision == Precision::float32) return fmt::format("{}({}, {})", entry, x, y);
  if (lang == Language::glsl)
    return fmt::format("float({}(float16_t({}), float16_t({})))", entry, x, y);
  return fmt::format("(float){}((half){}, (half){})", entry, x, y);
}

// The prologue of a split wrapper (the per-pixel function and the light
// pre-pass): in GLSL the version and workgroup size before the export, whose
// light struct the buffers below it use.
std::string split_prologue(Language lang, std::string_view exported) {
  if (lang == Language::glsl)
    return fmt::format("#version 450\nlayout(local_size_x = 64) in;\n\n{}\n", exported);
  return fmt::format("{}\n", exported);
}

}  // namespace

std::string compute_shader(Language lang, std::string_view exported, std::string_view entry,
                           Precision precision) {
  require_shader_language(lang, "compute_shader");
  if (lang == Language::glsl) {
    const std::string call =
        call_text(lang, entry, "cosine_kappa[i].x", "cosine_kappa[i].y", precision);
    // The half call is long: its assignment goes on a line of its own.
    const char* sep = precision == Precision::float16 ? "\n    " : " ";
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(cosine_kappa.length())){}result[i] = {};
}}
)",
                       exported, sep, call);
  }
  return fmt::format(
      R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  cosine_kappa.GetDimensions(n, stride);
  if (id.x < n) result[id.x] = {};
}}
)",
      exported, call_text(lang, entry, "cosine_kappa[id.x].x", "cosine_kappa[id.x].y", precision));
}

std::string split_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "split_compute_shader");
  require_shader_language(lang, "split_compute_shader");
  if (lang == Language::glsl)
    return split_prologue(lang, exported) +
           fmt::format(
               R"(layout(std430, set = 0, binding = 0) readonly buffer Cosines {{ float cosines[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};
layout(std430, set = 0, binding = 2) readonly buffer Lights {{ {0} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_WorkGroupID.y;
  uint n = uint(cosines.length());
  if (i < n) result[l * n + i] = {1}(lights[l], cosines[i]);
}}
)",
               ex.light_struct, ex.entry_point);
  return split_prologue(lang, exported) +
         fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float> cosines;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;
[[vk::binding(2, 0)]] StructuredBuffer<{0}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID, uint3 group : SV_GroupID) {{
  uint n, stride;
  cosines.GetDimensions(n, stride);
  if (id.x < n) result[group.y * n + id.x] = {1}(lights[group.y], cosines[id.x]);
}}
)",
                     ex.light_struct, ex.entry_point);
}

std::string light_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "light_compute_shader");
  require_shader_language(lang, "light_compute_shader");
  if (lang == Language::glsl)
    return split_prologue(lang, exported) +
           fmt::format(
               R"(layout(std430, set = 0, binding = 0) readonly buffer Kappas {{ float kappas[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Lights {{ {0} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(kappas.length())) lights[i] = {1}(kappas[i]);
}}
)",
               ex.light_struct, ex.light_function);
  return split_prologue(lang, exported) +
         fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float> kappas;
[[vk::binding(1, 0)]] RWStructuredBuffer<{0}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  kappas.GetDimensions(n, stride);
  if (id.x < n) lights[id.x] = {1}(kappas[id.x]);
}}
)",
                     ex.light_struct, ex.light_function);
}

}  // namespace sglab::shader
