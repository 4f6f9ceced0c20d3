// export/vulkan_runner.hpp — shader source to SPIR-V with the glslang
// library (GLSL and HLSL front ends, in-process), and one compute dispatch on
// the first Vulkan device (the Vulkan loader; Mesa's lavapipe on a CPU-only
// machine).
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "export/shader_export.hpp"
#include "validate/sweep.hpp"

namespace sglab::shader::vulkan {

// No Vulkan instance or device could be created (no loader ICD, no device
// with a compute queue): callers report and skip rather than fail.
struct Unavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The source did not compile or link; what() carries glslang's log.
struct CompileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// GLSL (#version 450) or HLSL (entry point `main`) compute shader → SPIR-V 1.0
// for Vulkan 1.0; HLSL with `precision` half is read with 16-bit types (`half`
// is binary16). Throws CompileError with the info log.
std::vector<std::uint32_t> compile_compute(
    shader::Language lang, std::string_view source,
    shader::Precision precision = shader::Precision::float32);

// Checks that a shader-language export compiles on its own: GLSL as a
// compute-stage translation unit (it has no main, so parse only), HLSL
// likewise through the HLSL front end. Throws CompileError with the log.
void check_compiles(shader::Language lang, std::string_view exported_source,
                    shader::Precision precision = shader::Precision::float32);

// One statistic the driver's shader compiler reports for a pipeline
// (VK_KHR_pipeline_executable_properties), e.g. RADV/ACO's "Instructions",
// "Inverse Throughput", "VGPRs". Only integer statistics are kept.
struct PipelineStatistic {
  std::string name;
  std::uint64_t value = 0;
};

// The first Vulkan device with a compute queue, and a compute dispatch on it.
class Device {
 public:
  // Throws Unavailable when no instance or device can be created.
  Device();
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  std::string name() const;
  // The driver's name and version as it reports them (VkPhysicalDeviceDriverProperties,
  // e.g. "radv" and "Mesa 22.3.6"); empty when the device predates Vulkan 1.2.
  std::string driver_name() const;
  std::string driver_info() const;
  // Whether pipeline_statistics() is available (the device offers
  // VK_KHR_pipeline_executable_properties).
  bool has_pipeline_statistics() const;
  // Whether half arithmetic in shaders (shaderFloat16 of
  // VK_KHR_shader_float16_int8) is offered, and so enabled on this device.
  bool has_float16() const;

  // Builds the compute pipeline of `spirv` (the layout run() uses) and returns
  // the integer statistics of its compute executable, in the driver's order.
  // Throws Unavailable when the device does not offer them, std::runtime_error
  // naming the failed call otherwise.
  // `bindings` storage buffers at bindings 0 … bindings − 1 of set 0 (3 for
  // shader::split_compute_shader).
  std::vector<PipelineStatistic> pipeline_statistics(const std::vector<std::uint32_t>& spirv,
                                                     std::uint32_t bindings = 2);
  // The same pipeline's internal representations as text, by the driver's
  // name for each (RADV: "NIR Shader(s)", "ACO IR", "Assembly").
  std::vector<std::pair<std::string, std::string>> pipeline_representations(
      const std::vector<std::uint32_t>& spirv, std::uint32_t bindings = 2);

  // Runs a compute shader built by shader::compute_shader over the points:
  // binding 0 holds (cosine, kappa) pairs as float2, binding 1 receives one
  // float per point. Throws std::runtime_error naming the failed call.
  std::vector<float> run(const std::vector<std::uint32_t>& spirv,
                         const std::vector<float>& cosine_kappa_pairs);

  // Runs any compute shader over storage buffers of floats: binding 1
  // receives `out_floats` floats, `inputs` fill bindings 0, 2, 3, … in that
  // order; `groups` workgroups in x and y. Throws std::runtime_error naming the failed call.
  std::vector<float> dispatch(const std::vector<std::uint32_t>& spirv,
                              const std::vector<std::vector<float>>& inputs, std::size_t out_floats,
                              std::uint32_t groups_x, std::uint32_t groups_y = 1);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Adds a `vulkan` (GLSL) or `vulkan_hlsl` (HLSL) entry to r for every
// irradiance method of `methods` that `sglab export` can export: the export
// with its compiled-in constants (exactly what `sglab export --lang L --method
// ID` prints), compiled with glslang and run on `device` over r's grid.
// Returns the ids that were skipped because they cannot be exported.
// With `precision` half: the half exports (`--precision half`), as `vulkan_half`
// / `vulkan_hlsl_half`; throws Unavailable when the device has no shaderFloat16.
std::vector<std::string> add_device_entries(
    validate::SweepResult& r, std::span<const validate::SweepMethod> methods, shader::Language lang,
    Device& device, bool keep_points = true,
    shader::Precision precision = shader::Precision::float32);

// The lights of a split export for the given kappas, light_floats floats
// each, from its sglab_light_<ID> run on `device` (shader::light_compute_shader).
std::vector<float> device_lights(const shader::ExportResult& exported, shader::Language lang,
                                 const std::vector<float>& kappas, Device& device);

// The same from the C++ runtime's per-light setup (registry.hpp light_setup32,
// whose state the struct is) where the runtime splits the method, otherwise
// from sglab_light_<ID> run on `device` (shader::light_compute_shader).
std::vector<float> split_lights(const sglab::Method& method, const shader::ExportResult& exported,
                                shader::Language lang, const std::vector<float>& kappas,
                                Device& device);

// The per-pixel function of a split export on `device` for every light
// (light_floats floats each) and cosine: values[l * cosines.size() + i]
// (shader::split_compute_shader).
std::vector<float> run_split(const shader::ExportResult& exported, shader::Language lang,
                             const std::vector<float>& lights, const std::vector<float>& cosines,
                             Device& device);

// Adds a `vulkan_split` (GLSL) or `vulkan_hlsl_split` (HLSL) entry to r for
// every irradiance method of `methods` with a split export: the lights filled
// by split_lights and uploaded in a buffer, the per-pixel function run on
// `device` over r's grid (shader::split_compute_shader). Returns the ids that
// were skipped because they have no split form.
std::vector<std::string> add_split_device_entries(validate::SweepResult& r,
                                                  std::span<const validate::SweepMethod> methods,
                                                  shader::Language lang, Device& device,
                                                  bool keep_points = true);

}  // namespace sglab::shader::vulkan
