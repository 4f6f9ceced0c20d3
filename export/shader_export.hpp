// export/shader_export.hpp — `sglab export`: one irradiance method as
// self-contained GLSL 4.50, HLSL (Shader Model 6) or C++ source with its
// constants baked in.
//
// Shading languages have no erf, erfc or expm1, so an export carries its own
// elementary functions, chosen here for the accuracy the model needs
// (ElementaryTier). Every method body is one entry of one table in
// export/shader_methods.cpp (shader_methods()): adding a method is adding one
// entry. The export is split along its seams: constant-set adapters
// (shader_constants), elementary functions (shader_elementary), source text and
// its half translation (shader_text), method snippets (shader_methods,
// shader_split_forms), emit (shader_export.cpp) and the compute wrappers
// (shader_wrappers.cpp).
//
// The C++ form is the same code as the shader forms (same templates, same
// literals), so compiling it in a test and comparing it to the runtime checks
// the exporter independently of any GPU.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/vocabulary.hpp"

namespace sglab::shader {

// The language of an export (io::Language: glsl, hlsl, cpp).
using io::Language;
using io::to_string;

// The arithmetic of the exported code: float (binary32), or half (binary16:
// GLSL float16_t through GL_EXT_shader_explicit_arithmetic_types_float16, HLSL
// `half` with glslang's 16-bit types). The half form is the float form with
// every type, literal and constant in binary16, except where a method has a
// half form of its own (sglab_fast, sglab_mid: their κ-only part stays float). C++ has no
// half export. An export is float32 or float16 (io::Precision).
using io::Precision;

// One constant set as a method body sees it: the parameter type of
// include/sglab/params.hpp it is (e.g. "Steepness2024Params<double>"), its
// name in sglab/constants.hpp and its members by name (arrays as several
// values), plus a one-line provenance for the header comment.
struct ConstantSet {
  std::string cpp_type;
  std::string cpp_name;
  std::vector<std::pair<std::string, std::vector<double>>> members;
  std::string provenance;
  // The irradiance max peak_rel the set's fit achieved, when recorded.
  std::optional<double> achieved_irradiance_error;
};

// The elementary functions an export carries (erf/erfc, and the series that
// stand in for expm1): a tier per accuracy. The exporter takes the cheapest
// tier whose measured erf/erfc error is at most 1/100 of the model's error.
struct ElementaryTier {
  std::string id;           // "as7125", "listing5" (export/shader_elementary.cpp)
  std::string description;  // for the header comment
};

// Measured error of the exported elementary functions, evaluated in float by
// the C++ twin of the shader code against std:: functions in double.
struct ElementaryError {
  double erf_abs = 0;           // max |erf~(x) − erf(x)|, x ∈ [−6, 6]
  double erf_rel_small = 0;     // max relative error of erf~ for 1e−6 ≤ |x| ≤ 1
  double erfc_abs = 0;          // max |erfc~(x) − erfc(x)|, x ∈ [−6, 10]
  double expm1_over_x_rel = 0;  // max relative error of (e^x − 1)/x, x ∈ [−100, 0]
  double max_abs() const { return erf_abs > erfc_abs ? erf_abs : erfc_abs; }
};

// The error budget printed in the header comment and by `sglab export`.
struct ErrorBudget {
  std::optional<double> model;      // double-precision runtime vs reference (max peak_rel)
  std::optional<double> float_cpp;  // float runtime vs reference (max peak_rel)
  ElementaryError elementary;       // of the tier used (erf-free methods: expm1 only)
  std::optional<double> vulkan;     // measured on a Vulkan device, from a committed results file
  std::string vulkan_device;
};

// The GPU cost of the exported code on one AMD family: ACO's inverse
// throughput (cycles one wave keeps a SIMD busy, `sglab gpucost`), nullopt
// when it was not measured for this very code.
struct GpuCost {
  std::string family;  // e.g. "navi21"
  std::optional<std::int64_t> inverse_throughput;
};

struct ExportRequest {
  Language lang = Language::glsl;
  std::string method;
  Precision precision = Precision::float32;
  // Constant sets replacing the compiled-in set of the same cpp_type.
  std::vector<ConstantSet> overrides;
  // The exact command that produced the output, for the header comment.
  std::string command;
  // One-line provenance of compiled-in constant sets by cpp_name (from the
  // JSON they were generated from), where known.
  std::map<std::string, std::string> provenance;
  // Budget entries measured elsewhere (model and float errors from a sweep,
  // the Vulkan error from a results file); the elementary error is filled in.
  ErrorBudget budget;
  // The GPU cost by family, for the header of GLSL and HLSL exports (none
  // measured: the header says so), and where it was read (driver, file).
  std::vector<GpuCost> gpu_cost;
  std::string gpu_cost_source;
  // The per-light split form (`sglab export --split`): a light struct,
  // sglab_light_<ID>(float kappa) that fills it and the per-pixel
  // sglab_irradiance_<ID>(light, float cosine). Methods without one: invalid_argument.
  bool split = false;
};

struct ExportResult {
  std::string source;
  std::string entry_point;  // sglab_irradiance_<ID>
  ElementaryTier tier;      // empty id when the method needs no erf
  ErrorBudget budget;
  // Split form only (empty / 0 otherwise): sglab_light_<ID>, SglabLight_<ID>
  // and its number of floats (std430: 4 bytes each, no padding).
  std::string light_function;
  std::string light_struct;
  std::size_t light_floats = 0;
};

// Method ids that can be exported, in registry order.
std::vector<std::string> exportable_methods();

// The entry point name for a method id: non-alphanumerics become '_'.
std::string entry_point_name(std::string_view method);

// Method ids that have a per-light split form (ExportRequest::split), in registry order.
std::vector<std::string> split_methods();
// The light struct of a method's split form: SglabLight_<ID>.
std::string light_struct_name(std::string_view method);

// The compiled-in constant sets a method uses (before overrides).
std::vector<ConstantSet> method_constants(std::string_view method);

// The source. Every text of the request (provenance, command, device) enters
// it only through comment_text (common/comment_text.hpp), inside // comments.
// Throws std::invalid_argument for an unknown method, an override no constant
// slot of the method accepts, or a coefficient that is not finite in float (the
// precision of the exported code; in half for a half export), naming the set
// and the key, and for a C++ half export.
ExportResult export_source(const ExportRequest& request);

// The model error (double) and the C++ float error of a registered
// irradiance method over the standard sweep grid, for the budget and the
// choice of tier (both nullopt for an id not in the registry).
ErrorBudget runtime_budget(std::string_view method);

// The request `sglab export --lang L --method ID` makes with the compiled-in
// constants: runtime budget filled in, command written out.
// With `precision` half: `sglab export ... --precision half`.
ExportRequest standard_request(Language lang, std::string_view method,
                               Precision precision = Precision::float32);

// The measured error of one tier's elementary functions (cached).
ElementaryError measure_elementary(std::string_view tier_id);

// The tier the exporter picks for a model error (nullopt model error: the
// most accurate tier).
ElementaryTier choose_tier(std::optional<double> model_error);

// How a wrapper is dispatched. any_size: over buffers of any length, each
// invocation checks its index against the buffer's length (the Vulkan sweep).
// whole_groups: over exactly a whole number of 64-thread workgroups, so no
// invocation checks anything and the method's call is in no branch (the
// harnesses of `sglab gpucost`: ACO's estimate weights the code under a
// divergent branch by 0.75, which would discount the method's cost).
enum class Dispatch { any_size, whole_groups };

// The sweep-grid wrapper: a compute shader (GLSL) or compute entry point
// `main` (HLSL) reading float2 (cosine, kappa) from binding 0 and writing the
// method's value to binding 1, both storage buffers of set 0, 64 threads per
// group. Used by the Vulkan backend of `sglab sweep`. For a half export the
// buffers stay float: the wrapper converts (cosine, kappa) to half before the
// call and the result back to float after it.
std::string compute_shader(Language lang, std::string_view exported_source,
                           std::string_view entry_point, Precision precision = Precision::float32,
                           Dispatch dispatch = Dispatch::any_size);

// The wrapper of a split export's per-pixel function: binding 0 holds the
// cosines (float), binding 2 the lights (the export's struct, std430), binding
// 1 receives result[l * n + i] = sglab_irradiance_<ID>(lights[l], cosines[i])
// for the n cosines; dispatched as (ceil(n / 64), number of lights, 1)
// workgroups of 64 threads, so the light index is the workgroup's (uniform).
std::string split_compute_shader(Language lang, std::string_view exported_source,
                                 const ExportResult& exported,
                                 Dispatch dispatch = Dispatch::any_size);

// The pre-pass of a split export: binding 0 holds kappas (float), binding 1
// receives lights[i] = sglab_light_<ID>(kappas[i]) (light_floats floats each),
// 64 threads per group.
std::string light_compute_shader(Language lang, std::string_view exported_source,
                                 const ExportResult& exported,
                                 Dispatch dispatch = Dispatch::any_size);

// The per-pixel loop of a renderer over `lights` SG lights (1 to 64), one
// invocation per pixel, dispatched in whole workgroups of 64 threads: binding 0
// holds each pixel's normal (float4, xyz), binding 2 each light's axis and
// amplitude (float4: xyz axis, w amplitude), binding 3 each light's state,
// binding 1 receives the pixel's irradiance, sum over the lights of amplitude
// times the method at cosine dot(axis, normal). With `light_struct` empty the
// state is the light's kappa (float) and `entry_point` is the unsplit
// (cosine, kappa) function; otherwise it is the split export's struct of that
// name and `entry_point` its per-pixel (light, cosine) function. The light
// index is the same in every invocation (wave-uniform loads). The lights are
// written out one statement each, not as a loop: ACO's estimate counts the
// body of any loop as 8 iterations whatever its trip count (Mesa's
// aco_statistics.cpp), so only written-out lights make its figure the cost of
// exactly `lights` lights.
std::string loop_compute_shader(Language lang, std::string_view exported_source,
                                std::string_view entry_point, std::string_view light_struct,
                                int lights);

}  // namespace sglab::shader
