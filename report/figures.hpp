// report/figures.hpp — the figures of `sglab figures`: for each figure the
// data CSV is written first (io::write_file_atomic), then a gnuplot script
// next to it, then gnuplot renders a PNG and an SVG. An index.md lists them.
//
// validate/ does not link fit/, so the per-κ optimal steepness t*(κ)
// (figure b) is passed in.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <sglab/registry.hpp>

#include "cost/gpu_report.hpp"
#include "report/pareto.hpp"  // ParetoRow, read_pareto_csv (figure e reads the CSV)

namespace sglab::report {

// gnuplot is not installed (or not runnable).
struct GnuplotMissing : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct FiguresOptions {
  std::filesystem::path out = "out/figures";
  // Figure (e): `sglab pareto` CSVs, one panel per cost source in them (absent files are skipped;
  // the figure is skipped when none exists).
  std::vector<std::filesystem::path> pareto = {"out/pareto/pareto.csv"};
  // The "gpu" section of the cost table (cost/gpu_report.hpp): figure (e)
  // tables the other families' inverse throughput beside a GPU panel.
  std::optional<cost::gpu::Report> gpu;
  std::string gnuplot = "gnuplot";
  // t*(κ) of the 2022 normalized hemispherical integral (fit::optimal_steepness).
  std::function<std::vector<double>(const std::vector<double>&)> optimal_steepness;
};

struct Figure {
  std::string id;  // "a_clamped_cosine", …
  std::string title;
  std::string description;
  std::vector<std::filesystem::path> files;  // data CSV(s), script, PNG, SVG (relative to out)
  bool skipped = false;
  std::string note;  // why skipped, or remarks
};

// True when `gnuplot --version` runs.
bool gnuplot_available(const std::string& gnuplot = "gnuplot");

// Writes every figure and out/index.md; returns the figures in order.
// Throws GnuplotMissing when gnuplot is absent, std::runtime_error when
// gnuplot fails (the message names the script and its log), and
// std::invalid_argument for a malformed Pareto CSV.
std::vector<Figure> make_figures(const FiguresOptions& options);

}  // namespace sglab::report
