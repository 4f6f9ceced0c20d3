// export/gpu_cost.cpp — see gpu_cost.hpp.
#include "export/gpu_cost.hpp"

#include <stdlib.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <system_error>
#include <tuple>

#include <fmt/format.h>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include "common/io.hpp"
#include "export/probe_export.hpp"
#include "export/vulkan_runner.hpp"

namespace sglab::shader::gpu {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
// The rows, statistics and harness names of the report (cost/gpu_report.hpp).
using namespace cost::gpu;

namespace {

constexpr std::string_view kBaselineEntry = "sglab_gpucost_baseline";
constexpr std::string_view kBaselineLight = "SglabGpucostBaseline";

// A private folder under the system's temporary directory, removed with
// everything in it when this goes out of scope.
class ScratchDir {
 public:
  ScratchDir() {
    std::string templ = (fs::temp_directory_path() / "sglab-gpucost-XXXXXX").string();
    if (!::mkdtemp(templ.data()))
      throw std::runtime_error(fmt::format("gpucost: cannot create a temporary folder {}: {}",
                                           templ, std::strerror(errno)));
    path_ = templ;
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string shader_file(std::size_t i) { return fmt::format("{}.spv", i); }

void write_spirv(const fs::path& path, const std::vector<std::uint32_t>& words) {
  io::write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(words.data()),
                                               words.size() * sizeof(std::uint32_t)));
}

std::vector<std::uint32_t> read_spirv(const fs::path& path) {
  const std::string bytes = io::read_file(path);
  if (bytes.size() % sizeof(std::uint32_t))
    throw std::runtime_error(
        fmt::format("{}: not SPIR-V (size not a multiple of 4)", path.string()));
  std::vector<std::uint32_t> words(bytes.size() / sizeof(std::uint32_t));
  std::memcpy(words.data(), bytes.data(), bytes.size());
  return words;
}

// The last lines of a child's log, for an error message.
std::string log_tail(const fs::path& log) {
  std::ifstream in(log);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line.find("not a conformant Vulkan implementation") != std::string::npos)
      continue;
    lines.push_back(line.substr(0, 300));
    if (lines.size() > 6) lines.erase(lines.begin());
  }
  std::string out;
  for (const auto& l : lines) out += "\n  " + l;
  return out;
}

Statistics from_driver(const std::vector<vulkan::PipelineStatistic>& raw) {
  Statistics s;
  for (const StatisticField& f : kStatisticFields) {
    const auto it =
        std::find_if(raw.begin(), raw.end(), [&](const auto& r) { return r.name == f.aco; });
    if (it == raw.end())
      throw Unavailable(
          fmt::format("the driver reports no \"{}\" statistic: not RADV's ACO compiler?", f.aco));
    s.*f.member = static_cast<std::int64_t>(it->value);
  }
  return s;
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return u;
}

}  // namespace

std::vector<std::uint32_t> apply_compile_path(shader::Language lang, CompilePath compile,
                                              std::vector<std::uint32_t> spirv) {
  if (compile == CompilePath::none) return spirv;
  const bool hlsl = lang == shader::Language::hlsl;
  if (compile == CompilePath::legalized && !hlsl)
    throw std::invalid_argument("gpucost: the legalized compile path is HLSL's (GLSL needs none)");
  std::string messages;
  const auto consumer = [&](spv_message_level_t level, const char*, const spv_position_t& at,
                            const char* message) {
    if (level <= SPV_MSG_WARNING) messages += fmt::format("\n  word {}: {}", at.index, message);
  };
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_0);
  optimizer.SetMessageConsumer(consumer);
  if (hlsl) optimizer.RegisterLegalizationPasses();
  if (compile == CompilePath::optimized) optimizer.RegisterPerformancePasses();
  std::vector<std::uint32_t> out;
  if (!optimizer.Run(spirv.data(), spirv.size(), &out))
    throw std::runtime_error(fmt::format("gpucost: SPIRV-Tools' optimizer ({}) failed:{}",
                                         to_string(compile), messages));
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_0);
  tools.SetMessageConsumer(consumer);
  if (!tools.Validate(out))
    throw std::runtime_error(fmt::format("gpucost: the SPIR-V after the {} passes is not valid:{}",
                                         to_string(compile), messages));
  return out;
}

std::uint32_t binding_count(const Shader& s) {
  switch (s.harness) {
    case Harness::single:
      return s.split ? 3 : 2;
    case Harness::loop:
      return 4;
    case Harness::setup:
      return 2;
  }
  return 2;
}

namespace {

Shader compiled(std::string_view method, shader::Language lang, const std::string& source,
                shader::Precision precision, bool split, Harness harness, int lights,
                CompilePath compile) {
  return {std::string(method),
          lang,
          apply_compile_path(lang, compile, vulkan::compile_compute(lang, source, precision)),
          split,
          precision,
          harness,
          lights,
          compile};
}

shader::ExportResult split_export(std::string_view method, shader::Language lang) {
  shader::ExportRequest request = shader::standard_request(lang, method);
  request.split = true;
  return shader::export_source(request);
}

void require_lights(int lights) {
  if (lights < 1 || lights > kMaxLights)
    throw std::invalid_argument(
        fmt::format("gpucost: {} lights (the loop harness takes 1 to {})", lights, kMaxLights));
}

}  // namespace

Shader baseline_shader(shader::Language lang, shader::Precision precision, Harness harness,
                       int lights, CompilePath compile) {
  const bool half = precision == shader::Precision::float16;
  if (half && harness != Harness::single)
    throw std::invalid_argument("gpu::baseline_shader: the half exports are costed one call each");
  const std::string type = half ? (lang == shader::Language::glsl ? "float16_t" : "half") : "float";
  const std::string body =
      fmt::format("{}{} {}({} cosine, {} kappa) {{ return cosine + kappa; }}\n",
                  half && lang == shader::Language::glsl
                      ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n"
                      : "",
                  type, kBaselineEntry, type, type);
  std::string source;
  switch (harness) {
    case Harness::single:
      source = shader::compute_shader(lang, body, kBaselineEntry, precision,
                                      shader::Dispatch::whole_groups);
      break;
    case Harness::loop:
      require_lights(lights);
      source = shader::loop_compute_shader(lang, body, kBaselineEntry, {}, lights);
      break;
    case Harness::setup: {
      shader::ExportResult ex;
      ex.light_struct = kBaselineLight;
      ex.light_function = kBaselineEntry;
      ex.entry_point = kBaselineEntry;
      ex.light_floats = 1;
      ex.source = fmt::format(
          "struct {0} {{\n  float kappa;\n}};\n{0} {1}(float kappa) {{\n  {0} light;\n  "
          "light.kappa = kappa;\n  return light;\n}}\n",
          kBaselineLight, kBaselineEntry);
      source = shader::light_compute_shader(lang, ex.source, ex, shader::Dispatch::whole_groups);
      break;
    }
  }
  return compiled(kBaseline, lang, source, precision, false, harness,
                  harness == Harness::loop ? lights : 1, compile);
}

Shader method_shader(std::string_view method, shader::Language lang, shader::Precision precision,
                     CompilePath compile) {
  const shader::ExportResult ex =
      shader::export_source(shader::standard_request(lang, method, precision));
  return compiled(method, lang,
                  shader::compute_shader(lang, ex.source, ex.entry_point, precision,
                                         shader::Dispatch::whole_groups),
                  precision, false, Harness::single, 1, compile);
}

Shader split_method_shader(std::string_view method, shader::Language lang, CompilePath compile) {
  const shader::ExportResult ex = split_export(method, lang);
  return compiled(method, lang,
                  shader::split_compute_shader(lang, ex.source, ex, shader::Dispatch::whole_groups),
                  shader::Precision::float32, true, Harness::single, 1, compile);
}

Shader loop_shader(std::string_view method, shader::Language lang, bool split, int lights,
                   CompilePath compile) {
  require_lights(lights);
  const shader::ExportResult ex =
      split ? split_export(method, lang)
            : shader::export_source(shader::standard_request(lang, method));
  return compiled(
      method, lang,
      shader::loop_compute_shader(lang, ex.source, ex.entry_point, ex.light_struct, lights),
      shader::Precision::float32, split, Harness::loop, lights, compile);
}

Shader setup_shader(std::string_view method, shader::Language lang, CompilePath compile) {
  const shader::ExportResult ex = split_export(method, lang);
  return compiled(method, lang,
                  shader::light_compute_shader(lang, ex.source, ex, shader::Dispatch::whole_groups),
                  shader::Precision::float32, true, Harness::setup, 1, compile);
}

Shader export_shader(std::string_view method, shader::Language lang,
                     const shader::ExportResult& exported, shader::Precision precision) {
  const bool split = !exported.light_struct.empty();
  if (split && precision != shader::Precision::float32)
    throw std::invalid_argument("gpu::export_shader: the split export is float only");
  const std::string source =
      split ? shader::split_compute_shader(lang, exported.source, exported,
                                           shader::Dispatch::whole_groups)
            : shader::compute_shader(lang, exported.source, exported.entry_point, precision,
                                     shader::Dispatch::whole_groups);
  return compiled(method, lang, source, precision, split, Harness::single, 1, CompilePath::none);
}

Shader probe_shader(std::string_view label, shader::Language lang,
                    std::string_view exported_probe_source) {
  return compiled(
      label, lang,
      shader::probe_compute_shader(lang, exported_probe_source, shader::Dispatch::whole_groups),
      shader::Precision::float32, false, Harness::single, 1, CompilePath::none);
}

Shader probe_baseline_shader(shader::Language lang) {
  const std::string body = lang == shader::Language::glsl
                               ? "vec3 probe_irradiance(vec3 n) { return n; }\n"
                               : "float3 probe_irradiance(float3 n) { return n; }\n";
  return probe_shader(kBaseline, lang, body);
}

std::string spirv_hash(const std::vector<std::uint32_t>& spirv) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bits
  for (std::uint32_t w : spirv)
    for (int b = 0; b < 4; ++b) {
      h ^= (w >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  return fmt::format("{:016x}", h);
}

std::optional<fs::path> find_radv_manifest() {
  struct utsname u {};
  const std::string arch = ::uname(&u) == 0 ? u.machine : "x86_64";
  std::vector<fs::path> dirs;
  const char* xdg = std::getenv("XDG_DATA_DIRS");
  std::string_view rest = xdg && *xdg ? xdg : "";
  while (!rest.empty()) {
    const auto colon = rest.find(':');
    const std::string_view dir = rest.substr(0, colon);
    if (!dir.empty()) dirs.push_back(fs::path(dir) / "vulkan" / "icd.d");
    rest = colon == std::string_view::npos ? std::string_view{} : rest.substr(colon + 1);
  }
  for (const char* d :
       {"/usr/local/share/vulkan/icd.d", "/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"})
    dirs.emplace_back(d);
  std::error_code ec;
  for (const fs::path& dir : dirs)
    if (const fs::path p = dir / fmt::format("radeon_icd.{}.json", arch);
        fs::is_regular_file(p, ec))
      return p;
  return std::nullopt;
}

WorkerSetup worker_setup(std::string_view who) {
  const auto manifest = find_radv_manifest();
  if (!manifest)
    throw Unavailable(
        "no radeon Vulkan driver (radeon_icd.*.json) in the Vulkan loader's folders: install "
        "mesa-vulkan-drivers");
  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec)
    throw std::runtime_error(fmt::format("{}: cannot find this executable: {}", who, ec.message()));
  return {std::move(self), *manifest};
}

std::vector<std::string> family_environment(const fs::path& manifest, std::string_view family) {
  return {
      // The radeon driver only: the loader's driver-file variable (and its
      // older name), so nothing else that is installed is enumerated.
      "VK_DRIVER_FILES=" + manifest.string(),
      "VK_ICD_FILENAMES=" + manifest.string(),
      // No implicit layers (overlays, capture tools) between sglab and the driver.
      "VK_LOADER_LAYERS_DISABLE=~implicit~",
      fmt::format("RADV_FORCE_FAMILY={}", family),
      // Compile every pipeline afresh; write nothing into the user's cache.
      "MESA_SHADER_CACHE_DISABLE=true",
      "MESA_GLSL_CACHE_DISABLE=true",
  };
}

Measured measure_here(std::string_view family, const std::vector<Shader>& shaders) {
  std::unique_ptr<vulkan::Device> device;
  try {
    device = std::make_unique<vulkan::Device>();
  } catch (const vulkan::Unavailable& e) {
    throw Unavailable(fmt::format("RADV created no device for family '{}': {}", family, e.what()));
  }
  // "Null hardware (RADV NAVI21)": the driver honoured the family.
  if (device->driver_name() != "radv" || device->name().find(upper(family)) == std::string::npos)
    throw Unavailable(fmt::format(
        "expected RADV's null device for family '{}', the loader gave '{}' (driver '{}')", family,
        device->name(), device->driver_name()));
  if (!device->has_pipeline_statistics())
    throw Unavailable(
        fmt::format("{} does not offer VK_KHR_pipeline_executable_properties", device->name()));
  Measured m;
  m.driver = fmt::format("{} {}", device->driver_name(), device->driver_info());
  for (const Shader& s : shaders)
    m.stats.push_back(from_driver(device->pipeline_statistics(s.spirv, binding_count(s))));
  return m;
}

void run_worker(std::string_view family, const fs::path& dir) {
  const json manifest = json::parse(io::read_file(dir / "shaders.json"));
  const bool disassemble = manifest.at("disassemble").get<bool>();
  std::vector<Shader> shaders;
  for (std::size_t i = 0; i < manifest.at("shaders").size(); ++i) {
    const json& entry = manifest.at("shaders")[i];
    Shader s;
    s.method = entry.at("method").get<std::string>();
    s.spirv = read_spirv(dir / shader_file(i));
    s.split = entry.at("split").get<bool>();
    s.harness = io::parse_enum<Harness>(entry.at("harness").get<std::string>()).value();
    shaders.push_back(std::move(s));
  }
  json out;
  try {
    const Measured m = measure_here(family, shaders);
    out["driver"] = m.driver;
    out["stats"] = json::array();
    for (const Statistics& s : m.stats) out["stats"].push_back(to_json(s));
    if (disassemble) {
      vulkan::Device device;  // the one measure_here checked is RADV's for this family
      out["assembly"] = json::array();
      for (const Shader& s : shaders) {
        std::string text;
        for (auto& [name, representation] :
             device.pipeline_representations(s.spirv, binding_count(s)))
          if (name == "Assembly") text = std::move(representation);
        out["assembly"].push_back(text);
      }
    }
  } catch (const Unavailable& e) {
    out["unavailable"] = e.what();
  }
  io::write_file_atomic(dir / fmt::format("result-{}.json", family), out.dump() + "\n");
}

namespace {

// Runs the worker for one family over `shaders` in a scratch folder and
// returns its result (driver, stats, and with `disassemble` the assembly).
json run_family(const fs::path& self, const fs::path& manifest, const std::string& family,
                const std::vector<Shader>& shaders, bool disassemble) {
  ScratchDir scratch;
  json list = json::array();
  for (std::size_t i = 0; i < shaders.size(); ++i) {
    write_spirv(scratch.path() / shader_file(i), shaders[i].spirv);
    list.push_back({{"method", shaders[i].method},
                    {"split", shaders[i].split},
                    {"harness", std::string(to_string(shaders[i].harness))}});
  }
  io::write_file_atomic(scratch.path() / "shaders.json",
                        json{{"shaders", list}, {"disassemble", disassemble}}.dump() + "\n");
  const fs::path log = scratch.path() / fmt::format("log-{}.txt", family);
  const fs::path result = scratch.path() / fmt::format("result-{}.json", family);
  const int rc = io::run_program({self.string(), "gpucost", "--worker-family", family,
                                  "--worker-dir", scratch.path().string()},
                                 {}, log, family_environment(manifest, family));
  std::error_code ec;
  if (rc != 0 || !fs::is_regular_file(result, ec))
    throw std::runtime_error(
        fmt::format("gpucost: the process measuring family '{}' failed (exit {}){}", family, rc,
                    log_tail(log)));
  json r = json::parse(io::read_file(result));
  if (r.contains("unavailable")) throw Unavailable(r.at("unavailable").get<std::string>());
  if (!r.contains("stats") || r.at("stats").size() != shaders.size() ||
      (disassemble && (!r.contains("assembly") || r.at("assembly").size() != shaders.size())))
    throw std::runtime_error(
        fmt::format("gpucost worker for '{}': wrong number of results", family));
  return r;
}

}  // namespace

Report measure(const fs::path& self, const fs::path& manifest,
               const std::vector<std::string>& families, const std::vector<Shader>& shaders,
               const std::function<void(std::string_view)>& progress) {
  Report report;
  for (const std::string& family : families) {
    if (progress) progress(family);
    const json r = run_family(self, manifest, family, shaders, false);
    if (report.driver.empty()) report.driver = r.at("driver").get<std::string>();
    const std::string where = fmt::format("gpucost worker for '{}'", family);
    std::map<std::tuple<shader::Language, shader::Precision, Harness, int, CompilePath>, Statistics>
        baseline;
    for (std::size_t i = 0; i < shaders.size(); ++i) {
      const Shader& sh = shaders[i];
      const Statistics s =
          statistics_from_json(r.at("stats")[i], fmt::format("{}: stats[{}]", where, i));
      const auto key = std::make_tuple(sh.lang, sh.precision, sh.harness, sh.lights, sh.compile);
      if (sh.method == kBaseline) {
        baseline[key] = s;
        continue;
      }
      if (!baseline.count(key))
        throw std::logic_error(fmt::format(
            "gpu::measure: the baseline of {} {} {} ({} lights, {}) must come before its methods",
            shader::to_string(sh.lang), shader::to_string(sh.precision), to_string(sh.harness),
            sh.lights, to_string(sh.compile)));
      report.rows.push_back(
          {sh.method, family, sh.lang, sh.split, std::string(shader::to_string(sh.precision)),
           subtract(s, baseline[key]), spirv_hash(sh.spirv), sh.harness, sh.lights, sh.compile});
    }
  }
  return report;
}

std::string disassemble(const fs::path& self, const fs::path& manifest, std::string_view family,
                        const Shader& shader) {
  const json r = run_family(self, manifest, std::string(family), {shader}, true);
  const std::string text = r.at("assembly")[0].get<std::string>();
  if (text.empty()) throw Unavailable("the driver returned no \"Assembly\" representation");
  return text;
}

}  // namespace sglab::shader::gpu
