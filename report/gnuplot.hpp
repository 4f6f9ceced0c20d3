// report/gnuplot.hpp — the small gnuplot driver of `sglab figures`: a
// figure's data as CSV, and its gnuplot script written next to it and run
// (no shell) to render a PNG and an SVG.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "report/figures.hpp"

namespace sglab::report::figures_detail {

// gnuplot single-quoted string: only ' needs doubling.
std::string gp_quote(const std::string& s);

// A CSV from a header and rows of numbers (full precision; NaN → "nan").
// `block` > 0 inserts a blank line every `block` rows (gnuplot scan lines).
std::string numeric_csv(const std::vector<std::string>& header,
                        const std::vector<std::vector<double>>& rows, std::size_t block = 0);

// Writes <stem>.gp next to the data and runs gnuplot in `dir`; the body is
// rendered once to PNG and once to SVG. Returns the script, PNG and SVG paths.
std::vector<std::filesystem::path> render(const FiguresOptions& opt, const std::string& stem,
                                          const std::string& body, int width, int height);

}  // namespace sglab::report::figures_detail
