// validate/sweep.hpp — the accuracy sweep of docs/quantities.md (standard grid): every method
// against the reference engine over a (κ, c) grid, in float and in double, with the metrics of
// docs/quantities.md.
//
// Inputs are rounded to float first and the reference is evaluated at those
// float-exact inputs, so the float and the double evaluation of a method see
// identical (κ, c) and differ only by the arithmetic they run in.
//
// Used by `sglab sweep`, and by the Pareto/recommend work and the fitters.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <sglab/registry.hpp>

#include "common/vocabulary.hpp"
#include "reference/reference.hpp"
#include "validate/metrics.hpp"
#include "validate/table.hpp"

namespace sglab::validate {

// What a method approximates, and therefore which reference it is held to:
// E(c, κ), H(c, κ) or s(c, κ) (docs/quantities.md).
enum class Quantity { irradiance, hemispherical, normalized };
constexpr std::array<io::EnumName<Quantity>, 3> names_of(Quantity) {
  return {{{Quantity::irradiance, "irradiance"},
           {Quantity::hemispherical, "hemispherical"},
           {Quantity::normalized, "normalized"}}};
}
using io::to_string;

// Where and in what arithmetic an entry was evaluated (io::Evaluation): the
// runtime on the CPU in float or double, or the method's export on a Vulkan
// device, values supplied through sweep_entry: the GLSL or HLSL export
// (`sglab export`) in float, in half (`--precision half`, float buffers
// converted to half and back in the wrapper) or in the float per-light split
// form (`sglab export --split`; split is not combined with half).

// κ: kappa_count values log-spaced over [kappa_lo, kappa_hi] inclusive;
// c: cosine_count values evenly spaced over [−1, 1] inclusive. The default is
// The standard grid of docs/quantities.md: κ = 10^(i/4), i = −12…16, and c = −1 + 2i/40.
struct SweepGrid {
  double kappa_lo = 1e-3;
  double kappa_hi = 1e4;
  int kappa_count = 29;
  int cosine_count = 41;

  // The largest grid a sweep accepts: κ count × cosine count ≤ this many
  // points (the standard grid has 1,189). A sweep keeps, per point and per
  // method and precision, the value and its error and a row of points.csv:
  // about kSweepBytesPerPointEntry bytes per point and entry, so the full
  // registry in float and double needs about 2.4 GB of memory at the limit
  // (and writes a 500 MB points.csv). The limit admits the held-out grid
  // of 217 κ × 401 cosines (87,017 points).
  static constexpr std::uint64_t kMaxPoints = 100'000;

  // κ count × cosine count (0 when either is not positive).
  std::uint64_t point_count() const;

  // Throws std::invalid_argument unless 0 < lo ≤ hi are finite and
  // representable as positive finite floats, count ≥ 1 (count = 1 needs
  // lo = hi), cosine_count ≥ 2 and point_count() ≤ kMaxPoints (the message
  // then says how much memory the grid would need). Allocates nothing.
  void validate() const;

  // Nominal values in double. κ_j = 10^(e_lo + (e_hi − e_lo)·j/(N − 1)) with
  // e = log10 (the exponent step is exact for the standard grid, so each κ is
  // the correctly rounded 10^(i/4) and the end points are lo and hi exactly;
  // io::log_spaced, which also keeps them sorted within [lo, hi]);
  // c_i = −1 + 2i/(M − 1) evaluated as written (so c_0 = −1 and c_{M−1} = 1 exactly).
  std::vector<double> kappas() const;
  std::vector<double> cosines() const;
};

// Estimated bytes a sweep holds per grid point and per entry (one method in
// one precision) with keep_points: value and peak_rel, and its row of the
// points table and of points.csv. Measured: `sglab sweep --kappa
// 1e-3:1e4:1000` (41,000 points, 38 entries) peaks at 886 MB resident.
inline constexpr std::uint64_t kSweepBytesPerPointEntry = 560;

// Estimated peak memory of sweep() plus the points table of `grid` over
// `entries` entries (methods × precisions) with keep_points.
std::uint64_t sweep_memory_estimate(const SweepGrid& grid, std::size_t entries);

// The nominal values rounded to float (and back to double, exactly).
std::vector<double> float_exact(std::span<const double> values);

// A method together with the quantity it approximates.
struct SweepMethod {
  Quantity quantity;
  Method method;
};

// Every registered method: irradiance_methods against E, hemispherical_methods
// against H, normalized_methods against s.
std::vector<SweepMethod> registered_sweep_methods();

struct SweepOptions {
  std::vector<io::Precision> precisions{io::Precision::float32, io::Precision::float64};
  reference::Quadrature reference = reference::Quadrature::standard;
  bool keep_points = true;  // keep every value and peak_rel (for plots and fitters)
  bool progress = true;     // terminal progress on stderr (quiet when piped)
};

// One method, quantity and precision over the whole grid.
struct SweepEntry {
  std::string method;
  Quantity quantity = Quantity::irradiance;
  io::Evaluation precision = io::kCpuDouble;
  MetricSummary summary;                 // over every (κ, c)
  std::vector<MetricSummary> per_kappa;  // over c, one per κ
  // Point data, index k·cosine_count + j (empty unless keep_points).
  std::vector<double> values;    // the method's output, widened to double
  std::vector<double> peak_rel;  // NaN where the output is non-finite
};

struct SweepResult {
  SweepGrid grid;
  std::vector<double> kappas;                        // evaluated, float-exact
  std::vector<double> cosines;                       // evaluated, float-exact
  std::vector<reference::ReferencePoint> reference;  // index k·cosine_count + j
  std::vector<reference::ReferencePoint> peak;       // per κ, at c = 1: the peak values x(1, κ)
  std::vector<SweepEntry> entries;                   // method-major, then precision

  std::size_t index(std::size_t k, std::size_t j) const { return k * cosines.size() + j; }
  // The reference value of quantity q at grid point (k, j), and its peak at κ_k.
  double reference_value(Quantity q, std::size_t k, std::size_t j) const;
  double peak_value(Quantity q, std::size_t k) const;
  const SweepEntry* find(std::string_view method, Quantity q, const io::Evaluation& f) const;
};

// The reference value of quantity q in a reference point.
double reference_value(const reference::ReferencePoint& point, Quantity q);

// The entry of method `m` in precision `f` from its values at every grid point
// (index k·cosine_count + j), measured against r's reference.
SweepEntry sweep_entry(const SweepResult& r, const SweepMethod& m, const io::Evaluation& f,
                       std::span<const double> values, bool keep_points = true);

// Runs the sweep (the `vulkan` precision is skipped here: its values come from
// a device). Throws std::invalid_argument on an invalid grid.
SweepResult sweep(const SweepGrid& grid, std::span<const SweepMethod> methods,
                  const SweepOptions& options = {});

// The tables `sglab sweep` writes.
// summary: method, quantity, precision, max_peak_rel, worst_kappa, worst_cosine,
//          rms_peak_rel, max_rel, nonfinite
Table summary_table(const SweepResult& result);
// per κ: method, quantity, precision, kappa, max_peak_rel, worst_cosine,
//        rms_peak_rel, max_rel, nonfinite (max and RMS over c at each κ)
Table per_kappa_table(const SweepResult& result);
// points: kappa, cosine, method, quantity, precision, value, reference, peak_rel
Table points_table(const SweepResult& result);

}  // namespace sglab::validate
