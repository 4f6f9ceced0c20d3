// app/probe_source.hpp — a fitted probe (envmap::Probe) as the export's terms
// (shader::ProbeTerms), and the probe file `sglab export --probe` reads.
#pragma once

#include <string>

#include "envmap/probe.hpp"
#include "export/probe_export.hpp"

namespace sglab::app {

// Largest probe file read (a probe of 256 lobes is about 60 kB of JSON).
inline constexpr std::size_t kMaxProbeFileBytes = std::size_t{1} << 22;

// One probe object as envmap::Probe::to_json writes it (and `envmap recommend
// --write-probe`). Throws io::InputError naming the file and the key.
envmap::Probe read_probe_file(const std::string& path);

// The probe's terms: SH coefficients, ZH3's zonal term along its derived
// axis, the lobes with the probe's method; `command` for the header comment.
shader::ProbeTerms probe_terms(const envmap::Probe& probe, const std::string& command);

}  // namespace sglab::app
