// report/probes_report.hpp — `sglab envmap probes`: every representation of
// envmap/probe.hpp on every map at the storage budgets, measured with the
// dense error on the full map (data/results/probes.md and its figure).
#pragma once

#include <string>

namespace sglab::report {

// The maps of `maps` (default: Blender's full-resolution studio-light worlds
// when blender-data is installed, else the project's data/envmaps copies) →
// probes.md, probes.csv, probes.png and one probe file per map and
// representation (probes/<map>_<label>.json) in `out` (default
// data/results). quick: every third map, 27 floats only (the envmap step of
// `sglab run`).
void run_probe_table(const std::string& maps, const std::string& out, bool quick);

}  // namespace sglab::report
