// cost/gpu_report.hpp — what a method costs on a GPU, as AMD's shader
// compiler (ACO) estimates it: the statistics of one compiled function, a row
// per (method, family, language, harness, compile path), the report of a run
// and its JSON ("gpu" section of the cost table, cost/cost_table.hpp) and
// Markdown forms. `sglab gpucost` measures them on RADV's null devices
// (export/gpu_cost.hpp); everything here is plain data, no driver.
//
// The statistics are compiler estimates, not timings: instructions,
// registers, code size, branches, and ACO's scheduler's latency and inverse
// throughput (busy cycles to execute one wave); they are the same on every run
// and every machine with the same driver. Each row is its function's own: the
// statistics of the same harness around a trivial body are subtracted, except
// the register counts, which are a peak, the whole pipeline's. The harnesses:
//   single  one call per invocation: (cosine, kappa) loaded, the value stored
//           (the split form: the light struct at the workgroup's index);
//   loop    a renderer's per-pixel loop: one normal per invocation, N lights
//           (axis, amplitude, and kappa or the split struct) read from buffers
//           at wave-uniform indices, the irradiance summed; the figures are
//           those of all N lights, a row's `lights` says N;
//   setup   the per-light setup of a split form (sglab_light_<ID>) as its own
//           kernel: one kappa in, one struct out per invocation.
// The compile path says what the SPIR-V went through after glslang: none,
// `legalized` (HLSL only: the legalization passes glslangValidator and DXC
// run), `optimized` (the performance passes of `spirv-opt -O`, after
// legalization for HLSL, as DXC's default -O3).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/vocabulary.hpp"

namespace sglab::cost::gpu {

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

// Each statistic: its name in ACO's report (radv_pipeline.c, Mesa 22.3), its
// JSON key, and whether a baseline's is subtracted (registers are a peak: not).
struct StatisticField {
  const char* aco;
  const char* json_key;
  std::int64_t Statistics::*member;
  bool additive;
};
inline constexpr StatisticField kStatisticFields[] = {
    {"Instructions", "instructions", &Statistics::instructions, true},
    {"Inverse Throughput", "inverse_throughput", &Statistics::inverse_throughput, true},
    {"Latency", "latency", &Statistics::latency, true},
    {"VGPRs", "vgprs", &Statistics::vgprs, false},
    {"SGPRs", "sgprs", &Statistics::sgprs, false},
    {"Code size", "code_size", &Statistics::code_size, true},
    {"Branches", "branches", &Statistics::branches, true},
};

// `measured` minus `baseline` in the additive statistics.
Statistics subtract(const Statistics& measured, const Statistics& baseline);
// {"instructions": …, …, "branches": …}
nlohmann::ordered_json to_json(const Statistics& s);
// Throws std::runtime_error "WHERE.KEY: must be an integer".
Statistics statistics_from_json(const nlohmann::ordered_json& j, const std::string& where);

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

struct Row {
  std::string method;
  std::string family;
  io::Language lang = io::Language::glsl;
  bool split = false;  // the split export (ExportRequest::split)
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

// {"driver", "command", "harnesses", "rows": [{"method", "family", "lang",
// "compile", "harness", "lights", "split", "precision", "instructions",
// "inverse_throughput", "latency", "vgprs", "sgprs", "code_size", "branches",
// "spirv_hash"}, …]}
nlohmann::ordered_json to_json(const Report& report);
// Throws std::runtime_error naming `where` and the key at fault.
Report report_from_json(const nlohmann::ordered_json& j, std::string_view where);
// Markdown tables per family and harness (the loop's with cycles per light).
std::string to_markdown(const Report& report);

}  // namespace sglab::cost::gpu
