// report/figure_style.hpp — the styles the figures share: log-axis tick
// labels, one colour per method family, a dash per origin.
#pragma once

#include <cstddef>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include <sglab/registry.hpp>

namespace sglab::report::figures_detail {

// Tick labels: "1e-2" style on every log axis.
inline constexpr const char* kLogFormat = "1e%T";

// 20 colours that stay apart on white (one per method in the line charts).
inline constexpr const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                           "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
                                           "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173",
                                           "#3182bd", "#e6550d", "#31a354", "#756bb1", "#000080"};
inline constexpr std::size_t kPaletteSize = std::size(kPalette);

// Line style of a method of family `i`: the family's colour; solid for
// published constants, dashed for sglab's refits, thick dash-dot for sglab's
// own models (so they stand out). Colour and dash together tell every curve apart.
std::string line_style(std::size_t i, Origin origin);
// The legend suffix of an origin: "", " (refit)", " [sglab]".
std::string origin_suffix(Origin o);
// A method's family: its id without a trailing "_refit", so that a refit
// shares the colour (or marker shape) of the published method it refits.
std::string family_of(std::string_view id);
// Index of each method's family, numbered in order of first appearance.
std::vector<std::size_t> family_indices(const std::vector<std::string_view>& ids);
// "1e-3" for a power of ten, else "%g".
std::string short_number(double x);
// κ tic labels "1e-3" … "1e4" on an axis that carries log10 κ.
std::string log10_kappa_tics(int lo, int hi);

}  // namespace sglab::report::figures_detail
