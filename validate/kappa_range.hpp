// validate/kappa_range.hpp — every irradiance method against the reference engine over all the
// κ a float can hold: for each κ of a dense log grid from the smallest positive float to
// FLT_MAX (and κ = 0), the worst peak_rel over the cosines, in float and in double; and from it
// the κ range on which a method's stated bound (its registry card, sglab::ValidRange) holds.
// `sglab range` prints it (data/results/kappa_range.md).
//
// The cosines at each κ: `cosines` uniform over [−1, 1], and `layer` values c = t/√κ,
// t ∈ [−8, 8], where the irradiance of a sharp light turns on (its width in c is 1/√κ, far
// finer than a uniform grid at large κ: docs/quantities.md); with `refine`, Brent's method
// (Boost.Math) then seeks the worst cosine between the neighbours of the worst one found.
// Inputs are rounded to float and the reference is evaluated there, as in the sweep.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <sglab/registry.hpp>

#include "validate/table.hpp"

namespace sglab::validate {

// A card's κ range as text, the ends to two digits and the largest float named:
// "[0, 1.1e+04]", "[0.00098, FLT_MAX]", "[0, FLT_MAX]".
std::string kappa_range_text(const ValidRange& v);

struct KappaScanOptions {
  int per_decade = 16;  // κ per decade (log-spaced) from the smallest positive float to FLT_MAX
  int cosines = 401;    // uniform over [−1, 1], both ends included
  int layer = 129;      // c = t/√κ, t evenly spaced over [−8, 8] (where |c| < 1)
  bool refine = true;   // Brent's local maximum around each worst cosine
  bool progress = true;
  // Further κ to scan besides the grid (each method's card ends and their
  // neighbours, for instance); rounded to float, sorted in with the grid.
  std::vector<double> extra_kappas;
};

// The worst point over the cosines at one κ.
struct KappaWorst {
  double peak_rel = 0;  // max over c of |Ê − E|/E(1, κ); +inf where Ê is not finite
  double cosine = 0;    // where
};

struct MethodScan {
  std::string id;
  std::vector<KappaWorst> f32, f64;  // one per κ of KappaScan::kappas
  // max(float, double) at κ index i.
  double worst(std::size_t i) const;
};

struct KappaScan {
  std::vector<double> kappas;  // 0, then increasing float-exact values up to FLT_MAX
  std::vector<MethodScan> methods;
};

// The κ of a scan: 0, `per_decade` log-spaced values per decade from the
// smallest positive float (denormal) to FLT_MAX, the ends of the fitted range
// 1e−3 and 1e4, plus `extra`; float-exact, sorted, without duplicates.
std::vector<double> scan_kappas(int per_decade, std::span<const double> extra = {});

// Throws std::invalid_argument on options out of range (per_decade in [1, 1000],
// cosines in [2, 100001], layer in [0, 100001]).
KappaScan scan_kappa_range(std::span<const Method> methods, const KappaScanOptions& options);

// The largest run of consecutive scanned κ around [from, to] where the worst
// peak_rel (float and double) is ≤ bound: its first and last κ; nullopt when the
// bound fails somewhere in [from, to] itself.
struct KappaInterval {
  double lo = 0, hi = 0;
};
std::optional<KappaInterval> holds_on(const KappaScan& scan, const MethodScan& m, double bound,
                                      double from, double to);

// The worst point of `m` over the scanned κ in [lo, hi]: peak_rel, κ and c (float or double,
// whichever is worse).
struct WorstPoint {
  double peak_rel = 0, kappa = 0, cosine = 0;
};
WorstPoint worst_over(const KappaScan& scan, const MethodScan& m, double lo, double hi);

// One row per method of `methods` (each must be in the scan): its card (bound, κ range), the
// worst peak_rel measured on that range and where, whether the bound holds there, the largest
// range around [1e−3, 1e4] where it holds, and the worst over every scanned κ.
Table kappa_range_table(const KappaScan& scan, std::span<const Method> methods,
                        const KappaScanOptions& options);

}  // namespace sglab::validate
