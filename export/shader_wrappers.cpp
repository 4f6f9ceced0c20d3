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

// The HLSL bounds check of an any_size dispatch, up to the guarded statement:
// the buffer's length and `if (index < n) `.
std::string hlsl_bounds_check(std::string_view buffer, std::string_view index) {
  return fmt::format("uint n, stride;\n  {}.GetDimensions(n, stride);\n  if ({} < n) ", buffer,
                     index);
}

// The prologue of a split wrapper (the per-pixel function and the light
// pre-pass): in GLSL the version and workgroup size before the export, whose
// light struct the buffers below it use.
std::string split_prologue(Language lang, std::string_view exported) {
  if (lang == Language::glsl)
    return fmt::format("#version 450\nlayout(local_size_x = 64) in;\n\n{}\n", exported);
  return fmt::format("{}\n", exported);
}

// A split-form wrapper's text in one language: a fmt template of {0} the light
// struct, {1} the export's function it calls and {2} `check`, the bounds check
// an any_size dispatch puts before the guarded statement.
struct WrapperText {
  std::string_view body;
  std::string check;
};

// A compute wrapper of a split export (`who` names it in errors): its
// prologue, then the text of `lang`.
std::string split_wrapper(const char* who, Language lang, std::string_view exported,
                          const ExportResult& ex, std::string_view function, Dispatch dispatch,
                          const WrapperText& glsl, const WrapperText& hlsl) {
  require_split(ex, who);
  require_shader_language(lang, who);
  const WrapperText& text = lang == Language::glsl ? glsl : hlsl;
  return split_prologue(lang, exported) +
         fmt::format(fmt::runtime(text.body), ex.light_struct, function,
                     dispatch == Dispatch::any_size ? text.check : "");
}

}  // namespace

std::string compute_shader(Language lang, std::string_view exported, std::string_view entry,
                           Precision precision, Dispatch dispatch) {
  require_shader_language(lang, "compute_shader");
  const bool checked = dispatch == Dispatch::any_size;
  if (lang == Language::glsl) {
    const std::string call =
        call_text(lang, entry, "cosine_kappa[i].x", "cosine_kappa[i].y", precision);
    // The half call is long: its assignment goes on a line of its own.
    const char* sep = precision == Precision::float16 ? "\n    " : " ";
    return fmt::format(
        R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  {}result[i] = {};
}}
)",
        exported, checked ? fmt::format("if (i < uint(cosine_kappa.length())){}", sep) : "", call);
  }
  return fmt::format(
      R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  {}result[id.x] = {};
}}
)",
      exported, checked ? hlsl_bounds_check("cosine_kappa", "id.x") : "",
      call_text(lang, entry, "cosine_kappa[id.x].x", "cosine_kappa[id.x].y", precision));
}

std::string split_compute_shader(Language lang, std::string_view exported, const ExportResult& ex,
                                 Dispatch dispatch) {
  return split_wrapper(
      "split_compute_shader", lang, exported, ex, ex.entry_point, dispatch,
      {R"(layout(std430, set = 0, binding = 0) readonly buffer Cosines {{ float cosines[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};
layout(std430, set = 0, binding = 2) readonly buffer Lights {{ {0} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_WorkGroupID.y;
  uint n = uint(cosines.length());
  {2}result[l * n + i] = {1}(lights[l], cosines[i]);
}}
)",
       "if (i < n) "},
      {R"([[vk::binding(0, 0)]] StructuredBuffer<float> cosines;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;
[[vk::binding(2, 0)]] StructuredBuffer<{0}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID, uint3 group : SV_GroupID) {{
  uint n, stride;
  cosines.GetDimensions(n, stride);
  {2}result[group.y * n + id.x] = {1}(lights[group.y], cosines[id.x]);
}}
)",
       "if (id.x < n) "});
}

std::string light_compute_shader(Language lang, std::string_view exported, const ExportResult& ex,
                                 Dispatch dispatch) {
  return split_wrapper(
      "light_compute_shader", lang, exported, ex, ex.light_function, dispatch,
      {R"(layout(std430, set = 0, binding = 0) readonly buffer Kappas {{ float kappas[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Lights {{ {0} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  {2}lights[i] = {1}(kappas[i]);
}}
)",
       "if (i < uint(kappas.length())) "},
      {R"([[vk::binding(0, 0)]] StructuredBuffer<float> kappas;
[[vk::binding(1, 0)]] RWStructuredBuffer<{0}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  {2}lights[id.x] = {1}(kappas[id.x]);
}}
)",
       hlsl_bounds_check("kappas", "id.x")});
}

std::string loop_compute_shader(Language lang, std::string_view exported, std::string_view entry,
                                std::string_view light_struct, int lights) {
  require_shader_language(lang, "loop_compute_shader");
  if (lights < 1 || lights > 64)
    throw std::invalid_argument(
        fmt::format("loop_compute_shader: {} lights (1 to 64 are written out)", lights));
  const bool glsl = lang == Language::glsl;
  const bool split = !light_struct.empty();
  std::string sum;
  for (int k = 0; k < lights; ++k) {
    const std::string cosine = fmt::format("dot(axes[{}].xyz, n)", k);
    sum += fmt::format("  e += axes[{}].w * {}({});\n", k, entry,
                       split ? fmt::format("lights[{}], {}", k, cosine)
                             : fmt::format("{}, kappas[{}]", cosine, k));
  }
  const std::string state =
      split ? fmt::format("{} lights[]", light_struct) : std::string("float kappas[]");
  if (glsl)
    return split_prologue(lang, exported) +
           fmt::format(
               R"(layout(std430, set = 0, binding = 0) readonly buffer Normals {{ vec4 normals[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};
layout(std430, set = 0, binding = 2) readonly buffer Axes {{ vec4 axes[]; }};
layout(std430, set = 0, binding = 3) readonly buffer States {{ {0}; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  vec3 n = normals[i].xyz;
  float e = 0.0f;
{1}  result[i] = e;
}}
)",
               state, sum);
  return split_prologue(lang, exported) +
         fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float4> normals;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;
[[vk::binding(2, 0)]] StructuredBuffer<float4> axes;
[[vk::binding(3, 0)]] StructuredBuffer<{0}> {1};

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  float3 n = normals[id.x].xyz;
  float e = 0.0f;
{2}  result[id.x] = e;
}}
)",
                     split ? light_struct : "float", split ? "lights" : "kappas", sum);
}

}  // namespace sglab::shader
