// export/gpu_cost.hpp — `sglab gpucost`: what an exported method costs on a
// GPU, from AMD's shader compiler, without a GPU: the harnesses, their
// compilation and the driver's statistics; the rows and report they make are
// cost/gpu_report.hpp's (sglab::cost::gpu).
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
// quarter of its cost. The harnesses (single, loop, setup) and compile paths
// (none, legalized, optimized) are described with the rows they produce in
// cost/gpu_report.hpp; the SPIR-V of the compile paths is SPIRV-Tools'
// optimizer's, run in-process.
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

#include "cost/gpu_report.hpp"
#include "export/shader_export.hpp"

namespace sglab::shader::gpu {

// RADV cannot create a null device here (no radeon driver, or it refused the
// family): callers report and skip, as with vulkan::Unavailable.
struct Unavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// glslang's SPIR-V (Vulkan 1.0) of `lang` through `compile` with SPIRV-Tools'
// optimizer in-process; the result is validated. Throws std::invalid_argument
// for `legalized` GLSL (GLSL needs no legalization), std::runtime_error with
// the optimizer's or validator's messages when it fails.
std::vector<std::uint32_t> apply_compile_path(shader::Language lang, cost::gpu::CompilePath compile,
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
  cost::gpu::Harness harness = cost::gpu::Harness::single;
  int lights = 1;  // loop harness: the lights written out; 1 otherwise
  cost::gpu::CompilePath compile = cost::gpu::CompilePath::none;
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
                       cost::gpu::Harness harness = cost::gpu::Harness::single, int lights = 1,
                       cost::gpu::CompilePath compile = cost::gpu::CompilePath::none);
// The standard export of `method` in the single harness.
Shader method_shader(std::string_view method, shader::Language lang,
                     shader::Precision precision = shader::Precision::float32,
                     cost::gpu::CompilePath compile = cost::gpu::CompilePath::none);
// The split export of `method` (ExportRequest::split) in the single harness
// (float: the split export has no half form).
Shader split_method_shader(std::string_view method, shader::Language lang,
                           cost::gpu::CompilePath compile = cost::gpu::CompilePath::none);
// The standard (`split` false: kappa per light) or split export of `method`
// in the loop harness over `lights` lights (1 to cost::gpu::kMaxLights; float).
Shader loop_shader(std::string_view method, shader::Language lang, bool split, int lights,
                   cost::gpu::CompilePath compile = cost::gpu::CompilePath::none);
// The split export's per-light setup in the setup harness (float).
Shader setup_shader(std::string_view method, shader::Language lang,
                    cost::gpu::CompilePath compile = cost::gpu::CompilePath::none);
// An export (its source and entry point; comments do not reach the SPIR-V) in
// the single harness (the split one for a split export), compiled to SPIR-V:
// what `gpucost` costs for it.
Shader export_shader(std::string_view method, shader::Language lang,
                     const shader::ExportResult& exported,
                     shader::Precision precision = shader::Precision::float32);

// An exported probe's probe_irradiance(n) (export/probe_export.hpp: the text
// `sglab export --probe` writes) in the single harness of a probe:
// probe_compute_shader dispatched in whole groups, one normal loaded and one
// evaluation stored per invocation, the call in no branch; compile path none,
// float. `label` names its row. probe_baseline_shader is the same harness
// around `return n;`; its key in measure() is the single harness's, so probes
// are measured in a list of their own, the baseline first.
Shader probe_shader(std::string_view label, shader::Language lang,
                    std::string_view exported_probe_source);
Shader probe_baseline_shader(shader::Language lang);

// 64-bit FNV-1a of the SPIR-V words, as 16 hex digits: which code was costed.
std::string spirv_hash(const std::vector<std::uint32_t>& spirv);

// The radeon driver's manifest (radeon_icd.<arch>.json) in the Vulkan
// loader's standard folders (XDG_DATA_DIRS, then /usr/local/share,
// /usr/share, /etc), or nullopt.
std::optional<std::filesystem::path> find_radv_manifest();

// What `measure` needs to start its worker processes: this executable and the
// radeon driver's manifest. Throws Unavailable without the driver, and
// std::runtime_error (its message starting "`who`: ") when /proc/self/exe
// cannot be read.
struct WorkerSetup {
  std::filesystem::path self, manifest;
};
WorkerSetup worker_setup(std::string_view who);

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
  std::vector<cost::gpu::Statistics> stats;
};
Measured measure_here(std::string_view family, const std::vector<Shader>& shaders);

// Every family, each in its own process (`self` with
// `gpucost --worker-family F --worker-dir D`), with `progress` told each
// family as it starts. The baseline of each (language, precision, harness,
// lights, compile path) must come before its methods; rows are reported for
// the others, minus their baseline.
cost::gpu::Report measure(const std::filesystem::path& self, const std::filesystem::path& manifest,
                          const std::vector<std::string>& families,
                          const std::vector<Shader>& shaders,
                          const std::function<void(std::string_view family)>& progress = {});

// The compiled code of one shader on one family: ACO's final assembly of the
// whole pipeline (the harness around the method), as the driver prints it, in
// a process of its own as measure() does.
std::string disassemble(const std::filesystem::path& self, const std::filesystem::path& manifest,
                        std::string_view family, const Shader& shader);

// The worker's side of measure() and disassemble(): reads the shaders left in
// `dir`, measures (or disassembles) them here and writes the result next to them.
void run_worker(std::string_view family, const std::filesystem::path& dir);

}  // namespace sglab::shader::gpu
