// export/gpu_cost.cpp — see gpu_cost.hpp.
#include "export/gpu_cost.hpp"

#include <stdlib.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <system_error>

#include <fmt/format.h>

#include "common/io.hpp"
#include "export/vulkan_runner.hpp"

namespace sglab::shader::gpu {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

constexpr std::string_view kBaselineEntry = "sglab_gpucost_baseline";

// ACO's names for the statistics sglab keeps (radv_pipeline.c, Mesa 22.3).
struct StatisticName {
  const char* aco;
  std::int64_t Statistics::*member;
  bool additive;  // subtract the wrapper's (registers are a peak: not subtracted)
};
constexpr StatisticName kStatistics[] = {
    {"Instructions", &Statistics::instructions, true},
    {"Inverse Throughput", &Statistics::inverse_throughput, true},
    {"Latency", &Statistics::latency, true},
    {"VGPRs", &Statistics::vgprs, false},
    {"SGPRs", &Statistics::sgprs, false},
    {"Code size", &Statistics::code_size, true},
    {"Branches", &Statistics::branches, true},
};
constexpr const char* kJsonKeys[] = {"instructions", "inverse_throughput", "latency", "vgprs",
                                     "sgprs",        "code_size",          "branches"};
static_assert(std::size(kJsonKeys) == std::size(kStatistics));

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
  for (const StatisticName& n : kStatistics) {
    const auto it =
        std::find_if(raw.begin(), raw.end(), [&](const auto& r) { return r.name == n.aco; });
    if (it == raw.end())
      throw Unavailable(
          fmt::format("the driver reports no \"{}\" statistic: not RADV's ACO compiler?", n.aco));
    s.*n.member = static_cast<std::int64_t>(it->value);
  }
  return s;
}

json stats_json(const Statistics& s) {
  json j;
  for (std::size_t i = 0; i < std::size(kStatistics); ++i)
    j[kJsonKeys[i]] = s.*kStatistics[i].member;
  return j;
}

Statistics stats_from_json(const json& j, const std::string& where) {
  Statistics s;
  for (std::size_t i = 0; i < std::size(kStatistics); ++i) {
    if (!j.is_object() || !j.contains(kJsonKeys[i]) || !j.at(kJsonKeys[i]).is_number_integer())
      throw std::runtime_error(fmt::format("{}.{}: must be an integer", where, kJsonKeys[i]));
    s.*kStatistics[i].member = j.at(kJsonKeys[i]).get<std::int64_t>();
  }
  return s;
}

Statistics subtract(const Statistics& measured, const Statistics& baseline) {
  Statistics s = measured;
  for (const StatisticName& n : kStatistics)
    if (n.additive) s.*n.member -= baseline.*n.member;
  return s;
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return u;
}

}  // namespace

Shader baseline_shader(shader::Language lang, shader::Precision precision) {
  const bool half = precision == shader::Precision::float16;
  const std::string type = half ? (lang == shader::Language::glsl ? "float16_t" : "half") : "float";
  const std::string body =
      fmt::format("{}{} {}({} cosine, {} kappa) {{ return cosine + kappa; }}\n",
                  half && lang == shader::Language::glsl
                      ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n"
                      : "",
                  type, kBaselineEntry, type, type);
  return {std::string(kBaseline), lang,
          vulkan::compile_compute(
              lang, shader::compute_shader(lang, body, kBaselineEntry, precision), precision),
          false, precision};
}

Shader method_shader(std::string_view method, shader::Language lang, shader::Precision precision) {
  return export_shader(method, lang,
                       shader::export_source(shader::standard_request(lang, method, precision)),
                       precision);
}

Shader split_method_shader(std::string_view method, shader::Language lang) {
  shader::ExportRequest request = shader::standard_request(lang, method);
  request.split = true;
  return export_shader(method, lang, shader::export_source(request));
}

Shader export_shader(std::string_view method, shader::Language lang,
                     const shader::ExportResult& exported, shader::Precision precision) {
  const bool split = !exported.light_struct.empty();
  if (split && precision != shader::Precision::float32)
    throw std::invalid_argument("gpu::export_shader: the split export is float only");
  const std::string source =
      split ? shader::split_compute_shader(lang, exported.source, exported)
            : shader::compute_shader(lang, exported.source, exported.entry_point, precision);
  return {std::string(method), lang, vulkan::compile_compute(lang, source, precision), split,
          precision};
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
    m.stats.push_back(from_driver(device->pipeline_statistics(s.spirv, s.split ? 3 : 2)));
  return m;
}

void run_worker(std::string_view family, const fs::path& dir) {
  const json manifest = json::parse(io::read_file(dir / "shaders.json"));
  const bool disassemble = manifest.at("disassemble").get<bool>();
  std::vector<Shader> shaders;
  for (std::size_t i = 0; i < manifest.at("shaders").size(); ++i)
    shaders.push_back({manifest.at("shaders")[i].at("method").get<std::string>(),
                       shader::Language::glsl, read_spirv(dir / shader_file(i)),
                       manifest.at("shaders")[i].value("split", false)});
  json out;
  try {
    const Measured m = measure_here(family, shaders);
    out["driver"] = m.driver;
    out["stats"] = json::array();
    for (const Statistics& s : m.stats) out["stats"].push_back(stats_json(s));
    if (disassemble) {
      vulkan::Device device;  // the one measure_here checked is RADV's for this family
      out["assembly"] = json::array();
      for (const Shader& s : shaders) {
        std::string text;
        for (auto& [name, representation] :
             device.pipeline_representations(s.spirv, s.split ? 3 : 2))
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
                    {"lang", std::string(shader::to_string(shaders[i].lang))},
                    {"split", shaders[i].split}});
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
    std::map<std::pair<shader::Language, shader::Precision>, Statistics> baseline;
    for (std::size_t i = 0; i < shaders.size(); ++i) {
      const Statistics s =
          stats_from_json(r.at("stats")[i], fmt::format("{}: stats[{}]", where, i));
      const auto key = std::make_pair(shaders[i].lang, shaders[i].precision);
      if (shaders[i].method == kBaseline) {
        baseline[key] = s;
        continue;
      }
      if (!baseline.count(key))
        throw std::logic_error(
            "gpu::measure: a language and precision's baseline must come before its methods");
      report.rows.push_back({shaders[i].method, family, shaders[i].lang, shaders[i].split,
                             std::string(shader::to_string(shaders[i].precision)),
                             subtract(s, baseline[key]), spirv_hash(shaders[i].spirv)});
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

json to_json(const Report& report) {
  json j;
  j["driver"] = report.driver;
  j["command"] = report.command;
  j["wrapper"] =
      "the sweep's compute wrapper (one float2 load, one float store, 64 threads), minus the same "
      "wrapper around `return cosine + kappa;`; vgprs and sgprs are the whole pipeline's. Rows "
      "with split = true: the per-pixel function of the split export in the split wrapper (one "
      "float load, the light struct loaded at the workgroup's index, one float store), minus the "
      "same baseline: the struct's loads count as the function's";
  j["rows"] = json::array();
  for (const Row& r : report.rows) {
    json row = {{"method", r.method},
                {"family", r.family},
                {"lang", std::string(shader::to_string(r.lang))},
                {"split", r.split},
                {"precision", r.precision}};
    row.update(stats_json(r.stats));
    row["spirv_hash"] = r.spirv_hash;
    j["rows"].push_back(std::move(row));
  }
  return j;
}

Report report_from_json(const json& j, std::string_view where) {
  const auto text = [&](const json& obj, const char* key, const std::string& at) {
    if (!obj.is_object() || !obj.contains(key) || !obj.at(key).is_string())
      throw std::runtime_error(fmt::format("{}: {}{} must be a string", where, at, key));
    return obj.at(key).get<std::string>();
  };
  Report r;
  r.driver = text(j, "driver", "");
  r.command = text(j, "command", "");
  if (!j.contains("rows") || !j.at("rows").is_array())
    throw std::runtime_error(fmt::format("{}: rows must be an array", where));
  std::size_t i = 0;
  for (const json& row : j.at("rows")) {
    const std::string at = fmt::format("rows[{}].", i++);
    Row x;
    x.method = text(row, "method", at);
    x.family = text(row, "family", at);
    const auto lang = shader::parse_language(text(row, "lang", at));
    if (!lang || *lang == shader::Language::cpp)
      throw std::runtime_error(fmt::format("{}: {}lang must be glsl or hlsl", where, at));
    x.lang = *lang;
    if (!row.contains("split") || !row.at("split").is_boolean())
      throw std::runtime_error(fmt::format("{}: {}split must be true or false", where, at));
    x.split = row.at("split").get<bool>();
    x.precision = text(row, "precision", at);
    if (x.precision != "float" && x.precision != "half")
      throw std::runtime_error(fmt::format("{}: {}precision must be float or half", where, at));
    x.stats = stats_from_json(row, fmt::format("{}: {}", where, at.substr(0, at.size() - 1)));
    x.spirv_hash = text(row, "spirv_hash", at);
    r.rows.push_back(std::move(x));
  }
  return r;
}

std::string to_markdown(const Report& report) {
  std::string out;
  std::string family;
  for (const Row& r : report.rows) {
    if (r.family != family) {
      family = r.family;
      std::string generation;
      for (const Family& f : kDefaultFamilies)
        if (family == f.name) generation = fmt::format(" ({})", f.generation);
      out += fmt::format("{}## {}{}\n\n", out.empty() ? "" : "\n", family, generation);
      out +=
          "| method | lang | instructions | inverse throughput | latency | VGPRs | SGPRs | code "
          "size | branches |\n";
      out += "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    }
    out += fmt::format("| {}{} | {}{} | {} | {} | {} | {} | {} | {} | {} |\n", r.method,
                       r.split ? " (split)" : "", shader::to_string(r.lang),
                       r.precision == "half" ? " half" : "", r.stats.instructions,
                       r.stats.inverse_throughput, r.stats.latency, r.stats.vgprs, r.stats.sgprs,
                       r.stats.code_size, r.stats.branches);
  }
  return out;
}

}  // namespace sglab::shader::gpu
