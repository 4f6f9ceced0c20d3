// reference/irradiance_table.hpp — the reference irradiance E(c, κ) of
// docs/quantities.md at the cost of a polynomial: piecewise Chebyshev
// interpolants of the reference engine's quadrature (reference/reference.hpp),
// built from it once, at first use. The quadrature stays the truth: the table
// is checked against it at points no interpolant used (check_irradiance_table,
// `sglab reference --check-table`, tests/test_irradiance_table.cpp).
//
// The bound. For every finite κ ≥ 0 and c ∈ [−1, 1],
//   |E_table(c, κ) − E(c, κ)| ≤ kIrradianceTableBound · E(1, κ),
// E the quadrature (itself ~1e−15 relative), i.e. 1e−10 of the lobe's peak,
// the scale of peak_rel (docs/quantities.md). Checked, not proven: the dense
// check `sglab reference --check-table` (every piece on a grid 9× finer than
// its nodes in each direction, between the nodes, on the piece edges and
// beyond a_max below; about 460,000 points) finds at most ~5e−15, the
// quadrature's own level (docs/quantities.md, "The irradiance table").
//
// The construction (docs/quantities.md, "The irradiance table"):
//
// 1. The odd part is closed. max(x, 0) − max(−x, 0) = x, so with the normal
//    flipped, E(c, κ) − E(−c, κ) = ∫ G (ω·n) dω = c·M(κ), where
//      M(κ) = ∫ G (ω·v) dω = 2π((κ − 1) + (κ + 1)e^{−2κ})/κ² = E(1, κ) − E(−1, κ).
//    Only the shadow side T(a, κ) = E(−a, κ), a ∈ [0, 1], is tabulated:
//      E(c, κ) = T(−c, κ) for c ≤ 0,  c·M(κ) + T(c, κ) for c > 0.
// 2. The width of the horizon. At large κ the lobe is a Gaussian of angular
//    width 1/√κ, and T(a, κ) lives on a ∈ [0, ~8/√κ]: it is
//    ≈ (2π/κ^{3/2})(φ(t) − tΦ(−t)), t = a√κ. The table covers
//    a ∈ [0, a_max(κ)], a_max = min(1, 8/√κ), on its own Chebyshev variable
//    2a/a_max − 1, so the narrow transition is resolved at every κ. Beyond
//    a_max, T is set to 0: E(·, κ) is nondecreasing in c (two-point
//    symmetrization: reflect across the plane that bisects two normals; the
//    SG and the clamped cosine are both nonincreasing in angle, so the closer
//    normal gains pointwise), so 0 ≤ T(a) ≤ T(a_max) for a ≥ a_max, and
//    T(a_max, κ) < 1e−16·E(1, κ) for κ ≥ 64 (tests/test_irradiance_table.cpp;
//    the dense check also measures points beyond a_max).
// 3. The pieces in κ. Linear in κ on [0, 1] (E is entire in κ: κ = 0 and the
//    denormals are inside the piece, no limit needed), in ln κ on [1, 4],
//    [4, 16], [16, 64], [64, 256], [256, 1024], and in w = 1024/κ on
//    [1024, ∞): at large κ, √κ·T/E(1, κ) at fixed t is a series in 1/κ that
//    tends to the Gaussian form above, so one piece of 6 nodes in w covers
//    every κ up to the largest double (w = 0 is never a node; the check
//    includes κ = DBL_MAX). Stored: v = √max(κ, 1)·T(a, κ)/E(1, κ), O(1)
//    everywhere. 2,803 nodes in all, at most 37 in a; built in ~0.1 s.
//
// Thread-safe: the table is immutable once built; irradiance_table() builds it
// once (a function-local static) in isolation from any enclosing TBB work.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "reference/reference.hpp"

namespace sglab::reference {

// The stated bound, relative to the peak E(1, κ) (see above).
inline constexpr double kIrradianceTableBound = 1e-10;

// M(κ) = E(1, κ) − E(−1, κ) = 2π((κ − 1) + (κ + 1)e^{−2κ})/κ², the slope of
// the odd part E(c) − E(−c) = c·M (see above), likewise.
double irradiance_odd_slope(double kappa);
// a_max(κ) = min(1, 8/√κ): the shadow side beyond it is below 1e−16 of the peak.
double irradiance_table_cosine_range(double kappa);

class IrradianceTable {
 public:
  static constexpr int kMaxCosineNodes = 40;
  enum class Axis { linear, log, inverse };  // the Chebyshev variable in κ (see above)

  // One piece: κ in [kappa_lo, kappa_hi] (kappa_hi = +inf for `inverse`),
  // a ∈ [0, a_max(κ)]; Chebyshev interpolant through kappa_nodes ×
  // cosine_nodes first-kind points y = cos(π(i + ½)/n).
  struct Piece {
    Axis axis;
    double kappa_lo, kappa_hi;
    int kappa_nodes, cosine_nodes;
    std::vector<double> coefficients;  // [m·cosine_nodes + n]: T_m(y_κ)·T_n(y_a)

    // The κ and the a = |c| of the Chebyshev variables y_κ, y_a ∈ [−1, 1], and back.
    double kappa_at(double y) const;
    double y_of_kappa(double kappa) const;
    static double cosine_at(double kappa, double y);
  };

  // E(·, κ) at one κ: the κ direction summed once, then one Chebyshev sum of
  // at most kMaxCosineNodes terms per cosine. Cheap to copy, no allocation.
  class Slice {
   public:
    // E(c, κ); throws std::invalid_argument unless c ∈ [−1, 1].
    double operator()(double cosine) const;
    double kappa() const { return kappa_; }

   private:
    friend class IrradianceTable;
    std::array<double, kMaxCosineNodes> b_{};
    int n_ = 0;
    double kappa_ = 0;
    double a_max_ = 1, two_over_a_max_ = 2;
    double scale_ = 0;  // E(1, κ)/√max(κ, 1)
    double slope_ = 0;  // M(κ)
  };

  // Builds the table: one quadrature per node (2,803), in parallel.
  IrradianceTable();

  // Requires finite κ ≥ 0; throws std::invalid_argument otherwise.
  Slice slice(double kappa) const;
  double irradiance(double kappa, double cosine) const { return slice(kappa)(cosine); }

  std::span<const Piece> pieces() const { return pieces_; }
  // The piece that serves κ.
  const Piece& piece_of(double kappa) const;

 private:
  std::vector<Piece> pieces_;
};

// The process-wide table, built at first use (thread-safe).
const IrradianceTable& irradiance_table();

// The check of the table against the quadrature.
struct IrradianceTableCheck {
  std::size_t points = 0;
  double max_error = 0;  // max |E_table − E| / E(1, κ)
  double worst_kappa = 0, worst_cosine = 0;
};
// Points between the nodes of every piece: in each direction, the angles
// π·j/(k·n), j = 0 … k·n, of a piece with n nodes (k = `oversample`, odd): for
// k = 1 the second-kind points (the piece's edges and the midpoints between
// its nodes in angle), for larger k a grid k times finer that contains them.
// No point is a node: a node's angle π(i + ½)/n would need j = k(i + ½),
// not an integer for odd k. Also, on each κ row with a_max < 1, a few a
// beyond a_max (1.001 … 4 times it). Each a is returned as c = a and c = −a. Throws
// std::invalid_argument unless k is odd and ≥ 1.
std::vector<Query> irradiance_table_check_points(int oversample);
// The table against the quadrature (a fresh engine, so nothing is cached
// between calls) at `points`, in parallel; `progress` on a terminal.
IrradianceTableCheck check_irradiance_table(std::span<const Query> points, bool progress = false);

}  // namespace sglab::reference
