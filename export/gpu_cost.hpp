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
// prints) is compiled inside the sweep's compute wrapper (one float2 load, one
// float store; shader::compute_shader), and the statistics of the same
// wrapper around a trivial body are subtracted, so each figure is the
// function's own. Register counts are a peak, not a sum: they are reported as
// the whole pipeline's.
//
// The driver reads RADV_FORCE_FAMILY when it is loaded, so every family is
// measured in its own process: this executable again, spawned with an
// argument vector and an explicit environment that selects the radeon driver
// by its manifest file (never whatever else is installed).
#pragma once

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

// ACO's statistics of one compiled function (after the wrapper's are
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

// One compute shader to cost: a method's export in the wrapper.
struct Shader {
  std::string method;  // registry id; kBaseline for the trivial body
  shader::Language lang = shader::Language::glsl;
  std::vector<std::uint32_t> spirv;
  // The per-pixel function of a split export in shader::split_compute_shader
  // (the light struct loaded from a buffer at a wave-uniform index).
  bool split = false;
  // The export's precision: a half export is costed in the half wrapper
  // (conversions at the call) against the half baseline.
  shader::Precision precision = shader::Precision::float32;
};
inline constexpr std::string_view kBaseline = "(wrapper)";

// The wrapper with its trivial body, `return cosine + kappa;` (both inputs
// used, so the loads are the same as for a real method), in `lang` (in half
// arithmetic for `precision` half).
Shader baseline_shader(shader::Language lang,
                       shader::Precision precision = shader::Precision::float32);
// The standard export of `method` in the wrapper, compiled to SPIR-V.
Shader method_shader(std::string_view method, shader::Language lang,
                     shader::Precision precision = shader::Precision::float32);
// The split export of `method` (ExportRequest::split) in the split wrapper
// (float: the split export has no half form).
Shader split_method_shader(std::string_view method, shader::Language lang);
// An export (its source and entry point; comments do not reach the SPIR-V) in
// the wrapper (the split wrapper for a split export), compiled to SPIR-V: what
// `gpucost` costs for it.
Shader export_shader(std::string_view method, shader::Language lang,
                     const shader::ExportResult& exported,
                     shader::Precision precision = shader::Precision::float32);

// 64-bit FNV-1a of the SPIR-V words, as 16 hex digits: which code was costed.
std::string spirv_hash(const std::vector<std::uint32_t>& spirv);

struct Row {
  std::string method;
  std::string family;
  shader::Language lang = shader::Language::glsl;
  bool split = false;  // the per-pixel function of the split form (Shader::split)
  std::string precision = "float";
  Statistics stats;
  std::string spirv_hash;
};

struct Report {
  std::string driver;     // e.g. "radv Mesa 22.3.6"
  std::string command;    // how it was produced
  std::vector<Row> rows;  // family-major, in the order asked for
};

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
// family as it starts. Each language and precision's baseline must come before
// its methods; rows are reported for the others.
Report measure(const std::filesystem::path& self, const std::filesystem::path& manifest,
               const std::vector<std::string>& families, const std::vector<Shader>& shaders,
               const std::function<void(std::string_view family)>& progress = {});

// The compiled code of one shader on one family: ACO's final assembly of the
// whole pipeline (the wrapper around the method), as the driver prints it, in
// a process of its own as measure() does.
std::string disassemble(const std::filesystem::path& self, const std::filesystem::path& manifest,
                        std::string_view family, const Shader& shader);

// The worker's side of measure() and disassemble(): reads the shaders left in
// `dir`, measures (or disassembles) them here and writes the result next to them.
void run_worker(std::string_view family, const std::filesystem::path& dir);

// {"driver", "command", "wrapper", "rows": [{"method", "family", "lang",
// "split", "precision", "instructions", "inverse_throughput", "latency",
// "vgprs", "sgprs", "code_size", "branches", "spirv_hash"}, …]}
nlohmann::ordered_json to_json(const Report& report);
// Throws std::runtime_error naming `where` and the key at fault.
Report report_from_json(const nlohmann::ordered_json& j, std::string_view where);
// A Markdown table per family.
std::string to_markdown(const Report& report);

}  // namespace sglab::shader::gpu
