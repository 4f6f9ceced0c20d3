// export/gpu_cost.hpp — `sglab gpucost`: what an exported method costs on a
// GPU, from AMD's shader compiler, without a GPU.
//
// Mesa's radeon Vulkan driver (RADV) exposes a "Null hardware" device when
// RADV_FORCE_FAMILY names an AMD chip. It runs no work, but it compiles
// pipelines with AMD's own shader compiler (ACO), and
// VK_KHR_pipeline_executable_properties returns ACO's statistics for the
// compiled code: instructions, registers, code size, branches, and its
// scheduler's estimates of latency and inverse throughput (busy cycles to
// execute one wave). These are compiler estimates, not timings; they are the
// same on every run and every machine with the same driver.
//
// Each method's export (exactly what `sglab export --lang L --method ID`
// prints) is compiled in a harness, a compute shader around it, and the
// statistics of the same harness around a trivial body are subtracted, so each
// figure is the function's own. Register counts are a peak, not a sum: they
// are reported as the whole pipeline's. Every harness is dispatched in whole
// workgroups (shader::Dispatch::whole_groups), so the method's call is in no
// branch: ACO's estimate weights the code under a divergent branch by 0.75
// (aco_statistics.cpp), and a bounds check around the call would hide a
// quarter of its cost. The harnesses:
//   single  one call per invocation: (cosine, kappa) loaded, the value stored
//           (the split form: the light struct at the workgroup's index);
//   loop    a renderer's per-pixel loop: one normal per invocation, N lights
//           (axis, amplitude, and kappa or the split struct) read from buffers
//           at wave-uniform indices, the irradiance summed; the figures are
//           those of all N lights, a row's `lights` says N;
//   setup   the per-light setup of a split form (sglab_light_<ID>) as its own
//           kernel: one kappa in, one struct out per invocation.
// The SPIR-V is glslang's as it is (compile path none), or after SPIRV-Tools'
// optimizer, in-process, as HLSL users get it: `legalized` (HLSL only: the
// legalization passes glslangValidator and DXC run), `optimized` (the
// performance passes of `spirv-opt -O`, after legalization for HLSL, as DXC's
// default -O3).
//
// The driver reads RADV_FORCE_FAMILY when it is loaded, so every family is
// measured in its own process: this executable again, spawned with an
// argument vector and an explicit environment that selects the radeon driver
// by its manifest file (never whatever else is installed).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "export/shader_export.hpp"

namespace sglab::shader::gpu {

// RADV cannot create a null device here (no radeon driver, or it refused the
// family): callers report and skip, as with vulkan::Unavailable.
struct Unavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One AMD chip per GPU generation that Debian 12's Mesa (22.3) knows, oldest
// first: the default of `sglab gpucost --families`.
struct Family {
  const char* name;        // RADV_FORCE_FAMILY value
  const char* generation;  // "GCN4", "RDNA2", …
};
inline constexpr Family kDefaultFamilies[] = {{"polaris10", "GCN4"},
                                              {"vega10", "GCN5"},
                                              {"navi10", "RDNA1"},
                                              {"navi21", "RDNA2"},
                                              {"gfx1100", "RDNA3"}};
// Every family Debian 12's RADV (Mesa 22.3) makes a null device for: the names
// of Mesa's ac_get_family_name (amd_family.h, GFX6 to GFX11), lower case, that
// are chip names of letters and digits. `sglab gpucost --families` takes these.
inline constexpr const char* kKnownFamilies[] = {
    "tahiti",    "pitcairn",  "verde",     "oland",    "hainan",    "bonaire", "kaveri",
    "kabini",    "hawaii",    "tonga",     "iceland",  "carrizo",   "fiji",    "stoney",
    "polaris10", "polaris11", "polaris12", "vegam",    "vega10",    "vega12",  "vega20",
    "raven",     "raven2",    "renoir",    "arcturus", "aldebaran", "navi10",  "navi12",
    "navi14",    "navi21",    "navi22",    "navi23",   "navi24",    "vangogh", "rembrandt",
    "gfx1036",   "gfx1100",   "gfx1101",   "gfx1102"};

// ACO's statistics of one compiled function (after the harness's are
// subtracted, except vgprs and sgprs, which are the pipeline's).
struct Statistics {
  std::int64_t instructions = 0;
  std::int64_t inverse_throughput = 0;
  std::int64_t latency = 0;
  std::int64_t vgprs = 0;
  std::int64_t sgprs = 0;
  std::int64_t code_size = 0;  // bytes
  std::int64_t branches = 0;
};

// The compute shader around the method (see the top of this file).
enum class Harness { single, loop, setup };
constexpr std::array<io::EnumName<Harness>, 3> names_of(Harness) {
  return {{{Harness::single, "single"}, {Harness::loop, "loop"}, {Harness::setup, "setup"}}};
}
using io::to_string;

// What the SPIR-V went through after glslang (see the top of this file).
enum class CompilePath { none, legalized, optimized };
constexpr std::array<io::EnumName<CompilePath>, 3> names_of(CompilePath) {
  return {{{CompilePath::none, "none"},
           {CompilePath::legalized, "legalized"},
           {CompilePath::optimized, "optimized"}}};
}

// The lights of the loop harness: at most 64 are written out, and the default
// figure (`--cost gpu:FAMILY`) is read from 8 (the cycles per light are those
// of 64 lights within 2 %; data/results/gpu_loop_lights.md).
inline constexpr int kMaxLights = 64;
inline constexpr int kRendererLights = 8;

// glslang's SPIR-V (Vulkan 1.0) of `lang` through `compile` with SPIRV-Tools'
// optimizer in-process; the result is validated. Throws std::invalid_argument
// for `legalized` GLSL (GLSL needs no legalization), std::runtime_error with
// the optimizer's or validator's messages when it fails.
std::vector<std::uint32_t> apply_compile_path(shader::Language lang, CompilePath compile,
                                              std::vector<std::uint32_t> spirv);

// One compute shader to cost: a method's export in a harness.
struct Shader {
  std::string method;  // registry id; kBaseline for the trivial body
  shader::Language lang = shader::Language::glsl;
  std::vector<std::uint32_t> spirv;
  // The split export (ExportRequest::split): its per-pixel function in the
  // single and loop harnesses; the setup harness is always of a split export.
  bool split = false;
  // The export's precision: a half export is costed in the half wrapper
  // (conversions at the call) against the half baseline (single harness only).
  shader::Precision precision = shader::Precision::float32;
  Harness harness = Harness::single;
  int lights = 1;  // loop harness: the lights written out; 1 otherwise
  CompilePath compile = CompilePath::none;
};
inline constexpr std::string_view kBaseline = "(wrapper)";

// The storage buffers of a shader's harness (bindings 0 … n − 1 of set 0).
std::uint32_t binding_count(const Shader& s);

// A harness around its trivial body, the baseline of its rows: single and loop
// around `return cosine + kappa;` (both inputs used, so the loads are the
// same as for a real method; in half arithmetic for `precision` half, single
// only), setup around a struct holding kappa (so the stores of a method's
// larger struct count as its setup's).
Shader baseline_shader(shader::Language lang,
                       shader::Precision precision = shader::Precision::float32,
                       Harness harness = Harness::single, int lights = 1,
                       CompilePath compile = CompilePath::none);
// The standard export of `method` in the single harness.
Shader method_shader(std::string_view method, shader::Language lang,
                     shader::Precision precision = shader::Precision::float32,
                     CompilePath compile = CompilePath::none);
// The split export of `method` (ExportRequest::split) in the single harness
// (float: the split export has no half form).
Shader split_method_shader(std::string_view method, shader::Language lang,
                           CompilePath compile = CompilePath::none);
// The standard (`split` false: kappa per light) or split export of `method`
// in the loop harness over `lights` lights (1 to kMaxLights; float).
Shader loop_shader(std::string_view method, shader::Language lang, bool split, int lights,
                   CompilePath compile = CompilePath::none);
// The split export's per-light setup in the setup harness (float).
Shader setup_shader(std::string_view method, shader::Language lang,
                    CompilePath compile = CompilePath::none);
// An export (its source and entry point; comments do not reach the SPIR-V) in
// the single harness (the split one for a split export), compiled to SPIR-V:
// what `gpucost` costs for it.
Shader export_shader(std::string_view method, shader::Language lang,
                     const shader::ExportResult& exported,
                     shader::Precision precision = shader::Precision::float32);

// 64-bit FNV-1a of the SPIR-V words, as 16 hex digits: which code was costed.
std::string spirv_hash(const std::vector<std::uint32_t>& spirv);

struct Row {
  std::string method;
  std::string family;
  shader::Language lang = shader::Language::glsl;
  bool split = false;  // the split export (Shader::split)
  std::string precision = "float";
  Statistics stats;  // of all `lights` lights in the loop harness
  std::string spirv_hash;
  Harness harness = Harness::single;
  int lights = 1;
  CompilePath compile = CompilePath::none;
};

// ACO's inverse throughput of a row per light (per light per pixel for the
// loop harness; the row's own for the others).
double cycles_per_light(const Row& r);

struct Report {
  std::string driver;     // e.g. "radv Mesa 22.3.6"
  std::string command;    // how it was produced
  std::vector<Row> rows;  // family-major, in the order asked for
};

// The row `--cost gpu:FAMILY` reads for a method, the renderer's figure: the
// loop harness over kRendererLights lights, the split form where the method
// has one (else kappa per light), GLSL, compile path none, float; nullptr
// when the report has none.
const Row* renderer_row(const Report& report, std::string_view method, std::string_view family);
// The row `--cost gpu-single:FAMILY` reads: one unsplit call per invocation
// (single harness), GLSL, compile path none, float; nullptr when there is none.
const Row* single_row(const Report& report, std::string_view method, std::string_view family);
// Which form renderer_row picked: "8-light loop (split)" or "8-light loop (kappa per light)".
std::string renderer_form(const Row& r);

// The radeon driver's manifest (radeon_icd.<arch>.json) in the Vulkan
// loader's standard folders (XDG_DATA_DIRS, then /usr/local/share,
// /usr/share, /etc), or nullopt.
std::optional<std::filesystem::path> find_radv_manifest();

// The environment a family's process runs with: the radeon driver only,
// the family, no implicit layers, no on-disk shader cache.
std::vector<std::string> family_environment(const std::filesystem::path& manifest,
                                            std::string_view family);

// In this process, whose environment already selects RADV and the family:
// the raw statistics of each shader (nothing subtracted) and the driver's
// name and version. Throws Unavailable when no RADV device for `family` can
// be created.
struct Measured {
  std::string driver;
  std::vector<Statistics> stats;
};
Measured measure_here(std::string_view family, const std::vector<Shader>& shaders);

// Every family, each in its own process (`self` with
// `gpucost --worker-family F --worker-dir D`), with `progress` told each
// family as it starts. The baseline of each (language, precision, harness,
// lights, compile path) must come before its methods; rows are reported for
// the others, minus their baseline.
Report measure(const std::filesystem::path& self, const std::filesystem::path& manifest,
               const std::vector<std::string>& families, const std::vector<Shader>& shaders,
               const std::function<void(std::string_view family)>& progress = {});

// The compiled code of one shader on one family: ACO's final assembly of the
// whole pipeline (the harness around the method), as the driver prints it, in
// a process of its own as measure() does.
std::string disassemble(const std::filesystem::path& self, const std::filesystem::path& manifest,
                        std::string_view family, const Shader& shader);

// The worker's side of measure() and disassemble(): reads the shaders left in
// `dir`, measures (or disassembles) them here and writes the result next to them.
void run_worker(std::string_view family, const std::filesystem::path& dir);

// {"driver", "command", "harnesses", "rows": [{"method", "family", "lang",
// "compile", "harness", "lights", "split", "precision", "instructions",
// "inverse_throughput", "latency", "vgprs", "sgprs", "code_size", "branches",
// "spirv_hash"}, …]}
nlohmann::ordered_json to_json(const Report& report);
// Throws std::runtime_error naming `where` and the key at fault.
Report report_from_json(const nlohmann::ordered_json& j, std::string_view where);
// Markdown tables per family and harness (the loop's with cycles per light).
std::string to_markdown(const Report& report);

}  // namespace sglab::shader::gpu
