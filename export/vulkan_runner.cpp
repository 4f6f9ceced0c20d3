#include "export/vulkan_runner.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <vulkan/vulkan.h>

namespace sglab::shader::vulkan {

namespace {

// glslang's process-wide state, initialized once and never finalized (other
// threads may still compile at exit).
void init_glslang() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

}  // namespace

std::vector<std::uint32_t> compile_compute(shader::Language lang, std::string_view source,
                                           shader::Precision precision) {
  if (lang == shader::Language::cpp) throw CompileError("C++ is not a shader language");
  init_glslang();
  const bool hlsl = lang == shader::Language::hlsl;
  glslang::TShader sh(EShLangCompute);
  const char* text = source.data();
  const int length = static_cast<int>(source.size());
  sh.setStringsWithLengths(&text, &length, 1);
  sh.setEnvInput(hlsl ? glslang::EShSourceHlsl : glslang::EShSourceGlsl, EShLangCompute,
                 glslang::EShClientVulkan, 100);
  sh.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_0);
  sh.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
  if (hlsl) {
    sh.setEntryPoint("main");
    sh.setSourceEntryPoint("main");
  }
  const bool half16 = hlsl && precision == shader::Precision::float16;
  const auto messages = static_cast<EShMessages>(
      EShMsgSpvRules | EShMsgVulkanRules | (hlsl ? EShMsgReadHlsl : EShMsgDefault) |
      (half16 ? EShMsgHlslEnable16BitTypes : EShMsgDefault));
  if (!sh.parse(GetDefaultResources(), hlsl ? 100 : 450, false, messages))
    throw CompileError(fmt::format("{} compile failed:\n{}{}", shader::to_string(lang),
                                   sh.getInfoLog(), sh.getInfoDebugLog()));
  glslang::TProgram program;
  program.addShader(&sh);
  if (!program.link(messages))
    throw CompileError(fmt::format("{} link failed:\n{}{}", shader::to_string(lang),
                                   program.getInfoLog(), program.getInfoDebugLog()));
  std::vector<std::uint32_t> spirv;
  glslang::SpvOptions options;
  options.validate = true;
  glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
  if (spirv.empty()) throw CompileError("SPIR-V generation produced no code");
  return spirv;
}

void check_compiles(shader::Language lang, std::string_view exported_source,
                    shader::Precision precision) {
  // An export defines functions only; it is checked inside the compute
  // shader that calls its scalar entry point.
  const std::string type = precision == shader::Precision::float16
                               ? (lang == shader::Language::glsl ? "float16_t " : "half ")
                               : "float ";
  const auto pos = exported_source.find(type + "sglab_irradiance_");
  if (pos == std::string_view::npos)
    throw CompileError("no sglab_irradiance_ entry point in the source");
  const auto end = exported_source.find('(', pos);
  const std::string entry(exported_source.substr(pos + type.size(), end - pos - type.size()));
  compile_compute(lang, shader::compute_shader(lang, exported_source, entry, precision), precision);
}

// ---------------------------------------------------------------------------

namespace {

// A zero-initialized Vulkan create-info structure of type t.
template <class T>
T make(VkStructureType t) {
  T x{};
  x.sType = t;
  return x;
}

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS)
    throw std::runtime_error(
        fmt::format("Vulkan: {} failed (VkResult {})", what, static_cast<int>(r)));
}

// A host-visible, host-coherent storage buffer with its memory.
struct Buffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer() {
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
  }
};

// The compute pipeline of the sweep wrapper: one shader module, storage
// buffers at bindings 0 … bindings − 1 of set 0, entry point `main`. `flags` asks the
// driver to keep its statistics (VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR).
struct ComputePipeline {
  VkDevice dev;
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;

  ComputePipeline(VkDevice device, const std::vector<std::uint32_t>& spirv,
                  VkPipelineCreateFlags flags = 0, std::uint32_t binding_count = 2)
      : dev(device) {
    auto smci = make<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    smci.codeSize = spirv.size() * sizeof(std::uint32_t);
    smci.pCode = spirv.data();
    check(vkCreateShaderModule(dev, &smci, nullptr, &module), "vkCreateShaderModule");
    std::vector<VkDescriptorSetLayoutBinding> bindings(binding_count);
    for (std::uint32_t i = 0; i < binding_count; ++i) {
      bindings[i].binding = i;
      bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      bindings[i].descriptorCount = 1;
      bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    auto dslci =
        make<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    dslci.bindingCount = binding_count;
    dslci.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(dev, &dslci, nullptr, &set_layout),
          "vkCreateDescriptorSetLayout");
    auto plci = make<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &set_layout;
    check(vkCreatePipelineLayout(dev, &plci, nullptr, &pipeline_layout), "vkCreatePipelineLayout");
    auto cpci = make<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    cpci.flags = flags;
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.layout = pipeline_layout;
    check(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline),
          "vkCreateComputePipelines");
  }
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  ~ComputePipeline() {
    if (pipeline) vkDestroyPipeline(dev, pipeline, nullptr);
    if (pipeline_layout) vkDestroyPipelineLayout(dev, pipeline_layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(dev, set_layout, nullptr);
    if (module) vkDestroyShaderModule(dev, module, nullptr);
  }
};

}  // namespace

struct Device::Impl {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  std::string name;
  std::string driver_name, driver_info;
  bool statistics = false;  // VK_KHR_pipeline_executable_properties enabled
  bool float16 = false;     // shaderFloat16 (VK_KHR_shader_float16_int8) enabled
  PFN_vkGetPipelineExecutablePropertiesKHR get_executable_properties = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR get_executable_statistics = nullptr;
  PFN_vkGetPipelineExecutableInternalRepresentationsKHR get_executable_representations = nullptr;
  VkPhysicalDeviceMemoryProperties memory_properties{};

  // The steps of Device::Device, in order.
  void create_instance();
  void pick_compute_device();
  void read_properties();
  void create_device();
  void load_statistics_functions();

  ~Impl() {
    if (device) vkDestroyDevice(device, nullptr);
    if (instance) vkDestroyInstance(instance, nullptr);
  }

  void make_buffer(Buffer& b, VkDeviceSize size) {
    b.device = device;
    b.size = size;
    auto info = make<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    info.size = size;
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(device, &info, nullptr, &b.buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b.buffer, &req);
    const VkMemoryPropertyFlags want =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::optional<std::uint32_t> type;
    for (std::uint32_t i = 0; i < memory_properties.memoryTypeCount; ++i)
      if ((req.memoryTypeBits & (1u << i)) &&
          (memory_properties.memoryTypes[i].propertyFlags & want) == want) {
        type = i;
        break;
      }
    if (!type)
      throw std::runtime_error("Vulkan: no host-visible coherent memory type for a storage buffer");
    auto alloc = make<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = *type;
    check(vkAllocateMemory(device, &alloc, nullptr, &b.memory), "vkAllocateMemory");
    check(vkBindBufferMemory(device, b.buffer, b.memory, 0), "vkBindBufferMemory");
  }

  // A storage buffer holding `data`.
  void upload(Buffer& b, const std::vector<float>& data) {
    make_buffer(b, data.size() * sizeof(float));
    void* mapped = nullptr;
    check(vkMapMemory(device, b.memory, 0, b.size, 0, &mapped), "vkMapMemory");
    std::memcpy(mapped, data.data(), b.size);
    vkUnmapMemory(device, b.memory);
  }
};

namespace {

// A descriptor set of `layout` from a new pool (left in `pool` for the caller
// to destroy) whose binding i is buffers[i], whole.
VkDescriptorSet descriptor_set(VkDevice dev, VkDescriptorSetLayout layout,
                               const std::vector<Buffer>& buffers, VkDescriptorPool& pool) {
  const auto n = static_cast<std::uint32_t>(buffers.size());
  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, n};
  auto dpci = make<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  dpci.maxSets = 1;
  dpci.poolSizeCount = 1;
  dpci.pPoolSizes = &pool_size;
  check(vkCreateDescriptorPool(dev, &dpci, nullptr, &pool), "vkCreateDescriptorPool");
  auto dsai = make<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  dsai.descriptorPool = pool;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &layout;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(dev, &dsai, &set), "vkAllocateDescriptorSets");
  std::vector<VkDescriptorBufferInfo> infos(n);
  std::vector<VkWriteDescriptorSet> writes(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    infos[i] = {buffers[i].buffer, 0, VK_WHOLE_SIZE};
    writes[i] = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(dev, n, writes.data(), 0, nullptr);
  return set;
}

}  // namespace

// Device::Device in its steps (Impl's members below): the instance, the first
// device with a compute queue, its properties, the logical device with the
// optional features it offers, and the statistics entry points.
void Device::Impl::create_instance() {
  auto app = make<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "sglab";
  // 1.1 for vkGetPhysicalDeviceProperties2 (the driver's name and version).
  app.apiVersion = VK_API_VERSION_1_1;
  auto ici = make<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  ici.pApplicationInfo = &app;
  if (VkResult r = vkCreateInstance(&ici, nullptr, &instance); r != VK_SUCCESS)
    throw Unavailable(fmt::format(
        "no Vulkan instance (vkCreateInstance returned {}): is a Vulkan driver installed (e.g. "
        "mesa-vulkan-drivers for lavapipe)?",
        static_cast<int>(r)));
}

void Device::Impl::pick_compute_device() {
  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  if (count) vkEnumeratePhysicalDevices(instance, &count, devices.data());
  for (VkPhysicalDevice pd : devices) {
    std::uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> families(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, families.data());
    for (std::uint32_t i = 0; i < nq; ++i)
      if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        physical = pd;
        queue_family = i;
        break;
      }
    if (physical) break;
  }
  if (!physical)
    throw Unavailable(fmt::format("no Vulkan device with a compute queue ({} devices)", count));
}

void Device::Impl::read_properties() {
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(physical, &props);
  name = props.deviceName;
  if (props.apiVersion >= VK_API_VERSION_1_2) {
    auto driver =
        make<VkPhysicalDeviceDriverProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    auto props2 = make<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    props2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical, &props2);
    driver_name = driver.driverName;
    driver_info = driver.driverInfo;
  }
  vkGetPhysicalDeviceMemoryProperties(physical, &memory_properties);
}

// The logical device and its queue, with pipeline statistics and half
// arithmetic enabled where the device offers them.
void Device::Impl::create_device() {
  std::uint32_t extension_count = 0;
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &extension_count, nullptr);
  std::vector<VkExtensionProperties> extensions(extension_count);
  if (extension_count)
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &extension_count, extensions.data());
  constexpr const char* kStatistics = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
  const auto has_extension = [&](const char* extension) {
    return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
      return std::strcmp(e.extensionName, extension) == 0;
    });
  };
  statistics = has_extension(kStatistics);
  // Half arithmetic in shaders, where offered (lavapipe and RADV do).
  auto float16_feature = make<VkPhysicalDeviceShaderFloat16Int8FeaturesKHR>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES_KHR);
  constexpr const char* kFloat16 = VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME;
  if (has_extension(kFloat16)) {
    auto features2 = make<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    features2.pNext = &float16_feature;
    vkGetPhysicalDeviceFeatures2(physical, &features2);
    float16 = float16_feature.shaderFloat16 == VK_TRUE;
    float16_feature = make<VkPhysicalDeviceShaderFloat16Int8FeaturesKHR>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES_KHR);
    float16_feature.shaderFloat16 = VK_TRUE;
  }
  const float priority = 1.0f;
  auto qci = make<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  qci.queueFamilyIndex = queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  auto statistics_feature = make<VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR>(
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR);
  statistics_feature.pipelineExecutableInfo = VK_TRUE;
  auto dci = make<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  std::vector<const char*> enabled;
  if (statistics) {
    statistics_feature.pNext = const_cast<void*>(dci.pNext);
    dci.pNext = &statistics_feature;
    enabled.push_back(kStatistics);
  }
  if (float16) {
    float16_feature.pNext = const_cast<void*>(dci.pNext);
    dci.pNext = &float16_feature;
    enabled.push_back(kFloat16);
  }
  dci.enabledExtensionCount = static_cast<std::uint32_t>(enabled.size());
  dci.ppEnabledExtensionNames = enabled.empty() ? nullptr : enabled.data();
  if (VkResult r = vkCreateDevice(physical, &dci, nullptr, &device); r != VK_SUCCESS)
    throw Unavailable(fmt::format("vkCreateDevice on {} returned {}", name, static_cast<int>(r)));
  vkGetDeviceQueue(device, queue_family, 0, &queue);
}

void Device::Impl::load_statistics_functions() {
  if (statistics) {
    get_executable_properties = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(device, "vkGetPipelineExecutablePropertiesKHR"));
    get_executable_statistics = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(device, "vkGetPipelineExecutableStatisticsKHR"));
    get_executable_representations =
        reinterpret_cast<PFN_vkGetPipelineExecutableInternalRepresentationsKHR>(
            vkGetDeviceProcAddr(device, "vkGetPipelineExecutableInternalRepresentationsKHR"));
    statistics =
        get_executable_properties && get_executable_statistics && get_executable_representations;
  }
}

Device::Device() : impl_(std::make_unique<Impl>()) {
  impl_->create_instance();
  impl_->pick_compute_device();
  impl_->read_properties();
  impl_->create_device();
  impl_->load_statistics_functions();
}

Device::~Device() = default;

std::string Device::name() const { return impl_->name; }
std::string Device::driver_name() const { return impl_->driver_name; }
std::string Device::driver_info() const { return impl_->driver_info; }
bool Device::has_pipeline_statistics() const { return impl_->statistics; }
bool Device::has_float16() const { return impl_->float16; }

std::vector<float> Device::run(const std::vector<std::uint32_t>& spirv,
                               const std::vector<float>& pairs) {
  if (pairs.empty() || pairs.size() % 2)
    throw std::invalid_argument("Device::run: need a non-empty list of pairs");
  const std::size_t n = pairs.size() / 2;
  return dispatch(spirv, {pairs}, n, static_cast<std::uint32_t>((n + 63) / 64));
}

std::vector<float> Device::dispatch(const std::vector<std::uint32_t>& spirv,
                                    const std::vector<std::vector<float>>& inputs,
                                    std::size_t out_floats, std::uint32_t groups_x,
                                    std::uint32_t groups_y) {
  Impl& d = *impl_;
  if (inputs.empty() || out_floats == 0 ||
      std::any_of(inputs.begin(), inputs.end(), [](const auto& in) { return in.empty(); }))
    throw std::invalid_argument("Device::dispatch: need non-empty inputs and output");
  VkDevice dev = d.device;
  const auto binding_count = static_cast<std::uint32_t>(inputs.size() + 1);

  // buffers[b] is binding b: the output at 1, the inputs at 0, 2, 3, …
  std::vector<Buffer> buffers(binding_count);
  for (std::uint32_t b = 0; b < binding_count; ++b) {
    if (b == 1) {
      d.make_buffer(buffers[b], out_floats * sizeof(float));
      continue;
    }
    d.upload(buffers[b], inputs[b == 0 ? 0 : b - 1]);
  }
  const Buffer& out = buffers[1];

  ComputePipeline p(dev, spirv, 0, binding_count);
  // Every object below is destroyed by one guard, in reverse order.
  struct Objects {
    VkDevice dev;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkCommandPool command_pool = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    ~Objects() {
      if (fence) vkDestroyFence(dev, fence, nullptr);
      if (command_pool) vkDestroyCommandPool(dev, command_pool, nullptr);
      if (pool) vkDestroyDescriptorPool(dev, pool, nullptr);
    }
  } o{dev};

  const VkDescriptorSet set = descriptor_set(dev, p.set_layout, buffers, o.pool);

  auto cpoolci = make<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  cpoolci.queueFamilyIndex = d.queue_family;
  check(vkCreateCommandPool(dev, &cpoolci, nullptr, &o.command_pool), "vkCreateCommandPool");
  auto cbai = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cbai.commandPool = o.command_pool;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 1;
  VkCommandBuffer cb;
  check(vkAllocateCommandBuffers(dev, &cbai, &cb), "vkAllocateCommandBuffers");
  auto begin = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline_layout, 0, 1, &set, 0,
                          nullptr);
  vkCmdDispatch(cb, groups_x, groups_y, 1);
  auto barrier = make<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &barrier, 0, nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
  auto fci = make<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  check(vkCreateFence(dev, &fci, nullptr, &o.fence), "vkCreateFence");
  auto submit = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cb;
  check(vkQueueSubmit(d.queue, 1, &submit, o.fence), "vkQueueSubmit");
  check(vkWaitForFences(dev, 1, &o.fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");

  std::vector<float> result(out_floats);
  void* mapped = nullptr;
  check(vkMapMemory(dev, out.memory, 0, out.size, 0, &mapped), "vkMapMemory");
  std::memcpy(result.data(), mapped, out.size);
  vkUnmapMemory(dev, out.memory);
  return result;
}

namespace {

// The one compute executable of a pipeline built with `flags`.
VkPipelineExecutableInfoKHR compute_executable(
    VkDevice device, VkPipeline pipeline, PFN_vkGetPipelineExecutablePropertiesKHR get_properties) {
  auto info = make<VkPipelineInfoKHR>(VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR);
  info.pipeline = pipeline;
  std::uint32_t executables = 0;
  check(get_properties(device, &info, &executables, nullptr),
        "vkGetPipelineExecutablePropertiesKHR");
  if (executables != 1)
    throw std::runtime_error(
        fmt::format("Vulkan: expected one compute executable, the driver reports {}", executables));
  auto executable =
      make<VkPipelineExecutableInfoKHR>(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR);
  executable.pipeline = pipeline;
  executable.executableIndex = 0;
  return executable;
}

}  // namespace

std::vector<PipelineStatistic> Device::pipeline_statistics(const std::vector<std::uint32_t>& spirv,
                                                           std::uint32_t bindings) {
  Impl& d = *impl_;
  if (!d.statistics)
    throw Unavailable(
        fmt::format("{} does not offer VK_KHR_pipeline_executable_properties", d.name));
  ComputePipeline p(d.device, spirv, VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR, bindings);
  const auto executable = compute_executable(d.device, p.pipeline, d.get_executable_properties);
  std::uint32_t count = 0;
  check(d.get_executable_statistics(d.device, &executable, &count, nullptr),
        "vkGetPipelineExecutableStatisticsKHR");
  std::vector<VkPipelineExecutableStatisticKHR> raw(
      count,
      make<VkPipelineExecutableStatisticKHR>(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR));
  check(d.get_executable_statistics(d.device, &executable, &count, raw.data()),
        "vkGetPipelineExecutableStatisticsKHR");
  std::vector<PipelineStatistic> out;
  for (const auto& st : raw) {
    if (st.format == VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR)
      out.push_back({st.name, st.value.u64});
    else if (st.format == VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR && st.value.i64 >= 0)
      out.push_back({st.name, static_cast<std::uint64_t>(st.value.i64)});
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> Device::pipeline_representations(
    const std::vector<std::uint32_t>& spirv, std::uint32_t bindings) {
  Impl& d = *impl_;
  if (!d.statistics)
    throw Unavailable(
        fmt::format("{} does not offer VK_KHR_pipeline_executable_properties", d.name));
  ComputePipeline p(d.device, spirv, VK_PIPELINE_CREATE_CAPTURE_INTERNAL_REPRESENTATIONS_BIT_KHR,
                    bindings);
  const auto executable = compute_executable(d.device, p.pipeline, d.get_executable_properties);
  std::uint32_t count = 0;
  check(d.get_executable_representations(d.device, &executable, &count, nullptr),
        "vkGetPipelineExecutableInternalRepresentationsKHR");
  std::vector<VkPipelineExecutableInternalRepresentationKHR> raw(
      count, make<VkPipelineExecutableInternalRepresentationKHR>(
                 VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INTERNAL_REPRESENTATION_KHR));
  // First the sizes, then the text into buffers of those sizes.
  check(d.get_executable_representations(d.device, &executable, &count, raw.data()),
        "vkGetPipelineExecutableInternalRepresentationsKHR");
  std::vector<std::string> text(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    text[i].resize(raw[i].dataSize);
    raw[i].pData = text[i].data();
  }
  check(d.get_executable_representations(d.device, &executable, &count, raw.data()),
        "vkGetPipelineExecutableInternalRepresentationsKHR");
  std::vector<std::pair<std::string, std::string>> out;
  for (std::uint32_t i = 0; i < count; ++i) {
    if (!raw[i].isText) continue;
    text[i].resize(std::strlen(text[i].c_str()));  // the driver's text ends with a NUL
    out.emplace_back(raw[i].name, std::move(text[i]));
  }
  return out;
}

std::vector<std::string> add_device_entries(validate::SweepResult& r,
                                            std::span<const validate::SweepMethod> methods,
                                            shader::Language lang, Device& device, bool keep_points,
                                            shader::Precision precision) {
  const bool half = precision == shader::Precision::float16;
  if (half && !device.has_float16())
    throw Unavailable(
        fmt::format("{} offers no half arithmetic in shaders (shaderFloat16)", device.name()));
  const auto exportable = shader::exportable_methods();
  std::vector<float> pairs;
  pairs.reserve(2 * r.kappas.size() * r.cosines.size());
  for (std::size_t k = 0; k < r.kappas.size(); ++k)
    for (std::size_t j = 0; j < r.cosines.size(); ++j) {
      pairs.push_back(static_cast<float>(r.cosines[j]));
      pairs.push_back(static_cast<float>(r.kappas[k]));
    }
  std::vector<std::string> skipped;
  for (const validate::SweepMethod& sm : methods) {
    const std::string id(sm.method.id);
    if (sm.quantity != validate::Quantity::irradiance ||
        std::find(exportable.begin(), exportable.end(), id) == exportable.end()) {
      skipped.push_back(fmt::format("{} ({})", id, to_string(sm.quantity)));
      continue;
    }
    const shader::ExportResult ex =
        shader::export_source(shader::standard_request(lang, id, precision));
    const auto spirv = compile_compute(
        lang, shader::compute_shader(lang, ex.source, ex.entry_point, precision), precision);
    const std::vector<float> out = device.run(spirv, pairs);
    const std::vector<double> values(out.begin(), out.end());
    r.entries.push_back(sweep_entry(r, sm, io::on_vulkan(lang, precision), values, keep_points));
  }
  return skipped;
}

std::vector<float> device_lights(const shader::ExportResult& ex, shader::Language lang,
                                 const std::vector<float>& kappas, Device& device) {
  const auto spirv = compile_compute(lang, shader::light_compute_shader(lang, ex.source, ex));
  return device.dispatch(spirv, {kappas}, kappas.size() * ex.light_floats,
                         static_cast<std::uint32_t>((kappas.size() + 63) / 64));
}

std::vector<float> split_lights(const sglab::Method& method, const shader::ExportResult& ex,
                                shader::Language lang, const std::vector<float>& kappas,
                                Device& device) {
  const std::size_t n = ex.light_floats;
  if (n == 0 || n > kLightStateFloats)
    throw std::invalid_argument(
        fmt::format("split_lights: {} is not a split export of at most {} floats", ex.entry_point,
                    kLightStateFloats));
  if (!method.light_setup32) return device_lights(ex, lang, kappas, device);
  std::vector<float> lights;
  lights.reserve(kappas.size() * n);
  for (float kappa : kappas) {
    float state[kLightStateFloats] = {};
    method.light_setup32(kappa, state);
    lights.insert(lights.end(), state, state + n);
  }
  return lights;
}

std::vector<float> run_split(const shader::ExportResult& ex, shader::Language lang,
                             const std::vector<float>& lights, const std::vector<float>& cosines,
                             Device& device) {
  if (ex.light_floats == 0 || lights.size() % ex.light_floats)
    throw std::invalid_argument(fmt::format("run_split: {} lights of {} floats expected",
                                            ex.light_struct, ex.light_floats));
  const std::size_t count = lights.size() / ex.light_floats;
  const auto spirv = compile_compute(lang, shader::split_compute_shader(lang, ex.source, ex));
  // One row of workgroups per light: the sweep has at most SweepGrid::kMaxPoints / 2 = 50,000
  // kappas, within the 65,535 workgroups every Vulkan device offers in y.
  return device.dispatch(spirv, {cosines, lights}, count * cosines.size(),
                         static_cast<std::uint32_t>((cosines.size() + 63) / 64),
                         static_cast<std::uint32_t>(count));
}

std::vector<std::string> add_split_device_entries(validate::SweepResult& r,
                                                  std::span<const validate::SweepMethod> methods,
                                                  shader::Language lang, Device& device,
                                                  bool keep_points) {
  const auto split = shader::split_methods();
  const std::vector<float> kappas(r.kappas.begin(), r.kappas.end()),
      cosines(r.cosines.begin(), r.cosines.end());
  std::vector<std::string> skipped;
  for (const validate::SweepMethod& sm : methods) {
    const std::string id(sm.method.id);
    if (sm.quantity != validate::Quantity::irradiance ||
        std::find(split.begin(), split.end(), id) == split.end()) {
      skipped.push_back(fmt::format("{} ({})", id, to_string(sm.quantity)));
      continue;
    }
    shader::ExportRequest request = shader::standard_request(lang, id);
    request.split = true;
    const shader::ExportResult ex = shader::export_source(request);
    const std::vector<float> out =
        run_split(ex, lang, split_lights(sm.method, ex, lang, kappas, device), cosines, device);
    const std::vector<double> values(out.begin(), out.end());
    r.entries.push_back(sweep_entry(
        r, sm, io::on_vulkan(lang, io::Precision::float32, io::Form::split), values, keep_points));
  }
  return skipped;
}

}  // namespace sglab::shader::vulkan
