#include "probe/probe_source.hpp"

#include <filesystem>
#include <map>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "common/io.hpp"
#include "common/json_input.hpp"
#include "export/gpu_cost.hpp"

namespace sglab::probe {

envmap::Probe read_probe_file(const std::string& path) {
  const auto j = io::read_json_file(path, kMaxProbeFileBytes, "a probe file");
  if (j.is_object() && j.contains("probes") && !j.contains("kind"))
    throw io::InputError(fmt::format(
        "{}: holds a 'probes' array (a per-map file of `envmap baselines --probes`); pass one "
        "probe object, as `envmap recommend --write-probe` writes",
        path));
  try {
    return envmap::Probe::from_json(j);
  } catch (const io::InputError& e) {
    throw io::InputError(fmt::format("{}: {}", path, e.what()));
  }
}

shader::ProbeTerms probe_terms(const envmap::Probe& probe, const std::string& command) {
  shader::ProbeTerms t;
  t.label = probe.label() + (probe.fit.empty() ? "" : " (" + probe.fit + ")");
  t.command = command;
  for (const envmap::Vec3& c : probe.sh) t.sh.push_back({c[0], c[1], c[2]});
  if (probe.kind == envmap::ProbeKind::zh3) {
    t.has_zonal = true;
    t.zonal = {probe.zonal[0], probe.zonal[1], probe.zonal[2]};
    const envmap::Vec3 d = probe.zonal_axis();
    t.zonal_axis = {d[0], d[1], d[2]};
  }
  for (const envmap::Lobe& l : probe.lobes)
    t.lobes.push_back({{l.axis[0], l.axis[1], l.axis[2]},
                       l.sharpness,
                       {l.amplitude[0], l.amplitude[1], l.amplitude[2]}});
  t.method = probe.method;
  return t;
}

std::vector<double> probe_gpu_costs(const std::string& family, shader::Language lang,
                                    const std::vector<const envmap::Probe*>& probes,
                                    std::string& driver) {
  namespace gpu = shader::gpu;
  if (lang == shader::Language::cpp)
    throw std::logic_error("probe_gpu_costs: a GPU costs GLSL or HLSL, not C++");
  const auto [self, manifest] = gpu::worker_setup("envmap recommend");
  std::vector<gpu::Shader> shaders{gpu::probe_baseline_shader(lang)};
  std::map<std::string, std::size_t> row_of;  // distinct source -> its row in the report
  std::vector<std::size_t> rows;
  for (const envmap::Probe* p : probes) {
    const std::string source = shader::export_probe(lang, probe_terms(*p, "")).source;
    const auto [it, fresh] = row_of.emplace(source, shaders.size() - 1);
    if (fresh) shaders.push_back(gpu::probe_shader(p->label(), lang, source));
    rows.push_back(it->second);
  }
  const cost::gpu::Report report = gpu::measure(self, manifest, {family}, shaders);
  if (report.rows.size() != shaders.size() - 1)
    throw std::logic_error("probe_gpu_costs: one row per distinct probe expected");
  driver = report.driver;
  std::vector<double> costs;
  for (std::size_t r : rows)
    costs.push_back(static_cast<double>(report.rows[r].stats.inverse_throughput));
  return costs;
}

}  // namespace sglab::probe
