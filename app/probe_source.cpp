#include "app/probe_source.hpp"

#include <fmt/format.h>

#include "common/io.hpp"
#include "common/json_input.hpp"

namespace sglab::app {

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

}  // namespace sglab::app
