// validate/stability.hpp — the stability table: every runtime function and
// every registered method over special inputs (κ from 0 through the denormals
// to the largest finite value, +inf and NaN; cosines at and just outside ±1,
// NaN; unit, non-unit and opposite axes), in float and in double, counting
// NaN / Inf / negative / out-of-range outputs.
//
// Published methods are faithful transcriptions: their failures are findings
// this table reports. sglab's own primitives, and every registered method whose
// origin (sglab/registry.hpp) is sglab or refit, must be finite, non-negative
// and in range for every valid input (docs/quantities.md);
// `own_failures_on_valid_inputs` lists the rows where they are not.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <sglab/registry.hpp>

#include "validate/sweep.hpp"
#include "validate/table.hpp"

namespace sglab::validate {

// A row's origin is the registry's (sglab::Origin): a registered method's own
// Method::origin; a runtime primitive is `sglab` (sglab's own code) or
// `published` (a transcription of a published formula).
using sglab::Origin;

// What an output can be besides fine:
//   nan          NaN
//   inf          ±inf where the exact result is finite (or not known)
//   overflow     ±inf where the exact result itself lies beyond the largest
//                finite value (recorded, but not a failure)
//   negative     < 0 where the documented range is non-negative
//   out_of_range outside the documented range otherwise (bounds that are not
//                representable, such as π, get 4 ulp of slack)
//   inaccurate   finite and in range, but off the exact value (computed in
//                long double, where the probe has one) by more than 1e−4
//                relative wherever the exact value is a normal number of the
//                evaluated precision (below it, 1e−4 of the smallest normal):
//                a lost term, not rounding
enum class FailureKind : std::size_t {
  nan = 0,
  inf = 1,
  overflow = 2,
  negative = 3,
  out_of_range = 4,
  inaccurate = 5
};
inline constexpr std::size_t kFailureKinds = 6;
constexpr std::array<io::EnumName<FailureKind>, kFailureKinds> names_of(FailureKind) {
  return {{{FailureKind::nan, "nan"},
           {FailureKind::inf, "inf"},
           {FailureKind::overflow, "overflow"},
           {FailureKind::negative, "negative"},
           {FailureKind::out_of_range, "out_of_range"},
           {FailureKind::inaccurate, "inaccurate"}}};
}

// One kind of failure over a set of inputs: how often, and between which κ
// it happens (κ is the probe's main argument: the light's κ, the first κ of a
// pair, or x for erf). κ = NaN inputs do not enter the min/max; they set
// `at_nan_kappa`.
struct FailureStats {
  std::size_t count = 0;
  double kappa_min = std::numeric_limits<double>::quiet_NaN();
  double kappa_max = std::numeric_limits<double>::quiet_NaN();
  bool at_nan_kappa = false;
  // The first failing input and its output, exact (hex floats); for
  // `inaccurate`, the input with the largest error instead.
  std::string example;
  double example_error = -1;  // `inaccurate` only: inaccuracy(y, exact)
};

// One function or method, in one precision, over valid or over invalid inputs.
struct StabilityRow {
  std::string function;
  Origin origin = Origin::sglab;
  io::Precision precision = io::Precision::float64;
  bool valid_inputs = true;  // finite κ ≥ 0, c ∈ [−1, 1], unit axes, finite x
  std::string range;         // the documented output range, e.g. "[0, π]"
  bool sign_checked = true;  // false where negative outputs are in range (erf, log-amplitudes)
  // An approximation (a method, or a published approximate formula): its
  // output exceeding the exact quantity's range by its approximation error is
  // an accuracy matter (`sglab sweep`), so out_of_range does not make it fail.
  bool approximation = false;
  std::size_t evaluations = 0;
  std::array<FailureStats, kFailureKinds> failures{};

  const FailureStats& operator[](FailureKind k) const {
    return failures[static_cast<std::size_t>(k)];
  }
  // Failures: nan, inf, negative, inaccurate, and out_of_range unless an
  // approximation (overflow is never a failure).
  bool is_failure(FailureKind k) const;
  std::size_t failure_count() const;
};

struct StabilityReport {
  std::vector<StabilityRow> rows;  // function-major, then precision, then valid before invalid
  // The κ, cosine and x values probed, per precision (for the report header).
  std::vector<double> kappas_float, kappas_double, cosines_float, cosines_double;

  const StabilityRow* find(std::string_view function, io::Precision f, bool valid_inputs) const;
};

StabilityReport stability();

// The sharpness constants of the methods' own lobes (λ of wang2009 and its
// refit, λd of vsgl2015 and its refits, Meder's λm, the clamped-cosine λ of
// tokuyoshi2022 and its refits), read from sglab/constants.hpp: each is among
// the κ probes, rounded to the evaluated precision.
std::vector<double> method_sharpness_constants();

// The `inaccurate` judgement: |y − exact| / max(|exact|, smallest normal of T),
// and whether it exceeds 1e−4 (T = float or double).
template <class T>
long double inaccuracy(T y, long double exact);
template <class T>
bool is_inaccurate(T y, long double exact);

// Rows of origin sglab or refit (sglab's own primitives and models, and the
// published formulas with sglab's refitted constants) with any failure on
// valid inputs (docs/quantities.md: finite, non-negative and in range for
// finite κ ≥ 0, c ∈ [−1, 1]).
std::vector<const StabilityRow*> own_failures_on_valid_inputs(const StabilityReport& report);

// Full table: function, origin, precision, inputs, evaluations, then for each
// kind (nan, inf, overflow, negative, out_of_range, inaccurate) its count, kappa_min and
// kappa_max, then range, approximation, findings, first_failure.
Table stability_table(const StabilityReport& report);
// Only the rows with failures, with a one-line summary of each.
Table stability_findings_table(const StabilityReport& report);

// Where half precision fails, per method: from a sweep holding each method's
// float export and its half export run on a device (`vulkan` and
// `vulkan_half` entries; `sglab stability --half`), a κ is survived when every
// cosine's half value is finite, non-negative and within `tolerance` of the
// float export's, relative to the peak E(1, κ). Columns: method, the largest
// run of survived κ of the grid (lo, hi), the nearest failing κ below and above
// it with what failed there (nan, inf, negative, off), the largest
// |E_half − E_float|/E(1, κ) inside the run and over the whole grid.
inline constexpr double kHalfTolerance = 1e-2;
Table half_ranges_table(const SweepResult& r, double tolerance = kHalfTolerance);

}  // namespace sglab::validate
