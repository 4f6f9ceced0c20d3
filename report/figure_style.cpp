#include "report/figure_style.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace sglab::report::figures_detail {

std::string line_style(std::size_t i, Origin origin) {
  switch (origin) {
    case Origin::published:
      return fmt::format("lw 1.6 dt 1 lc rgb '{}'", kPalette[i % kPaletteSize]);
    case Origin::refit:
      return fmt::format("lw 1.8 dt (8,4) lc rgb '{}'", kPalette[i % kPaletteSize]);
    case Origin::sglab:
      return fmt::format("lw 3.0 dt (12,4,3,4) lc rgb '{}'", kPalette[i % kPaletteSize]);
  }
  return "";
}

std::string origin_suffix(Origin o) {
  switch (o) {
    case Origin::published:
      return "";
    case Origin::refit:
      return " (refit)";
    case Origin::sglab:
      return " [sglab]";
  }
  return "";
}

// A method's family: its id without a trailing "_refit", so that a refit
// shares the colour (or marker shape) of the published method it refits.
std::string family_of(std::string_view id) {
  constexpr std::string_view suffix = "_refit";
  if (id.size() > suffix.size() && id.substr(id.size() - suffix.size()) == suffix)
    id.remove_suffix(suffix.size());
  return std::string(id);
}

// Index of each method's family, numbered in order of first appearance.
std::vector<std::size_t> family_indices(const std::vector<std::string_view>& ids) {
  std::vector<std::string> families;
  std::vector<std::size_t> out;
  for (std::string_view id : ids) {
    const std::string f = family_of(id);
    auto it = std::find(families.begin(), families.end(), f);
    if (it == families.end()) it = families.insert(families.end(), f);
    out.push_back(static_cast<std::size_t>(it - families.begin()));
  }
  return out;
}

// "1e-3" for a power of ten, else "%g".
std::string short_number(double x) {
  if (x > 0 && std::isfinite(x)) {
    const double e = std::round(std::log10(x));
    if (std::abs(x / std::pow(10.0, e) - 1) < 1e-9) return fmt::format("1e{}", static_cast<int>(e));
  }
  return fmt::format("{:g}", x);
}

// κ tic labels "1e-3" … "1e4" on an axis that carries log10 κ.
std::string log10_kappa_tics(int lo, int hi) {
  std::string s = "(";
  for (int e = lo; e <= hi; ++e) s += fmt::format("{}'1e{}' {}", e == lo ? "" : ", ", e, e);
  return s + ")";
}

}  // namespace sglab::report::figures_detail
