// tests/tolerances.hpp — the committed tolerance table of the runtime
// properties that tests/test_methods.cpp checks for every irradiance method of
// the registry (include/sglab/registry.hpp), kept as Boost.Math keeps its
// tests: one row per (method, quantity, precision) with the bound and the
// reason for it. Every method of the registry needs a row for every quantity:
// a method without one fails that quantity's suite, so a new method cannot
// slip through; a row naming no registered method fails ToleranceTable.
#pragma once

#include <array>
#include <limits>
#include <string_view>

#include "common/vocabulary.hpp"

namespace sglab::test {

// What is measured, each relative to the peak E(1, κ) (docs/quantities.md).
enum class Quantity {
  // |f32 − f64| / max(E(1, κ), |f64|) over the standard sweep from κ ≥ kappa_from.
  float_vs_double,
  // |batch32 − f64| / E(1, κ), and the scalar f32 alike, on 2^20 random points,
  // the standard sweep and edge κ. kNone: no dedicated kernel, batch32 is f32
  // element by element, equal to it bit for bit.
  batch_vs_double,
  // |light_eval32(light_setup32(κ), c) − f32(c, κ)| / E(1, κ) over the standard
  // sweep and random points. kNone: the method has no per-light split. (The
  // error against the reference engine is bounded by each method's registry
  // card, sglab::ValidRange, not here.)
  split_vs_plain,
  // max |Ê − E| / E(1, κ) of the method's half export (`sweep --backend vulkan
  // --precision half`, GLSL and HLSL, tests/test_half_precision.cpp) against the
  // reference engine over κ ∈ [1e-2, 1e3]. kNone: no claim in half.
  half_peak_rel,
  // max |half − float| / E(1, κ) of the method's exports over κ ∈ [1e-2, 1e3]
  // (`stability --half`, which also requires the half export to survive that
  // whole range). kNone: no claim in half (stability_half.md says where it fails).
  half_vs_float,
};
constexpr std::array<io::EnumName<Quantity>, 5> names_of(Quantity) {
  return {{{Quantity::float_vs_double, "float_vs_double"},
           {Quantity::batch_vs_double, "batch_vs_double"},
           {Quantity::split_vs_plain, "split_vs_plain"},
           {Quantity::half_peak_rel, "half_peak_rel"},
           {Quantity::half_vs_float, "half_vs_float"}}};
}
using io::Precision;
using io::to_string;

// A bound that is not a number: the property is absent (see Quantity).
inline constexpr double kNone = -1;
// Float rounding of the peak: the same operations in the same order.
inline constexpr double kFourFloatUlps =
    4 * static_cast<double>(std::numeric_limits<float>::epsilon());

struct Tolerance {
  std::string_view method;
  Quantity quantity;
  Precision precision;
  double bound;
  std::string_view reason;
  double kappa_from = 0;  // float_vs_double: checked for κ ≥ kappa_from only
};

using enum Quantity;
inline constexpr Precision f16 = Precision::float16, f32 = Precision::float32,
                           f64 = Precision::float64;

// Reasons said once.
inline constexpr std::string_view kWellConditioned = "float rounding of a well-conditioned formula";
inline constexpr std::string_view kTokuyoshi2022Alpha =
    "the difference of two integrals scaled by α ≈ 1182 ([Tokuyoshi2022] supplementary §1.1) "
    "amplifies float rounding ~1e3";
inline constexpr std::string_view kNoKernel =
    "no dedicated float batch kernel (registry.hpp make_method)";
inline constexpr std::string_view kNoSplit = "no per-light split in the runtime";
inline constexpr std::string_view kKernel =
    "the vectorizing kernel (branch_free.hpp exp/expm1/erfc; erfc_bf within 6e-7 absolute moves "
    "the lerp factor by at most that)";
inline constexpr std::string_view kKernelScalar =
    "both float paths at float noise (kernel: branch_free.hpp exp/expm1/erfc; erfc_bf within 6e-7 "
    "absolute)";
inline constexpr std::string_view kNoHalfClaim =
    "no claim in half: stability_half.md (`stability --half`) says where its half export fails";
inline constexpr std::string_view kHillBelowOne =
    "Hill's curve is ill-conditioned below κ = 1 (1 − scale ≈ 1/κ, [Pettineo2016]): checked from κ "
    "= 1";

inline constexpr Tolerance kTolerances[] = {
    // ---- float_vs_double: the scalar float path against the scalar double one
    {"wang2009", float_vs_double, f32, 2e-6, kWellConditioned},
    {"punctual", float_vs_double, f32, 2e-6, kWellConditioned},
    {"hill", float_vs_double, f32, 2e-6, kHillBelowOne, 1.0},
    {"hill_exact", float_vs_double, f32, 2e-6, kHillBelowOne, 1.0},
    {"vsgl2015", float_vs_double, f32, 2e-6, kWellConditioned},
    {"meder2018", float_vs_double, f32, 1e-4,
     "32.7 H̃(product) − 31.7 H̃(c, κ) ([Meder2018]) cancels ~30×"},
    {"tokuyoshi2022", float_vs_double, f32, 2e-3, kTokuyoshi2022Alpha},
    {"tokuyoshi2024", float_vs_double, f32, 2e-6, kWellConditioned},
    {"tokuyoshi2022_listing5", float_vs_double, f32, 2e-3, kTokuyoshi2022Alpha},
    {"tokuyoshi2022_refit", float_vs_double, f32, 2e-3, kTokuyoshi2022Alpha},
    {"tokuyoshi2024_refit", float_vs_double, f32, 2e-6, kWellConditioned},
    {"vsgl2015_refit", float_vs_double, f32, 2e-6, kWellConditioned},
    {"wang2009_refit", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_fast", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_mid", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_lite", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_min", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_tab", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_acc1", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_acc2", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_acc3", float_vs_double, f32, 2e-6, kWellConditioned},
    {"sglab_acc4", float_vs_double, f32, 2e-6, kWellConditioned},

    // ---- batch_vs_double: the float batch (and the scalar float) against the scalar double
    {"wang2009", batch_vs_double, f32, kNone, kNoKernel},
    {"punctual", batch_vs_double, f32, kNone, kNoKernel},
    {"hill", batch_vs_double, f32, kNone, kNoKernel},
    {"hill_exact", batch_vs_double, f32, kNone, kNoKernel},
    {"vsgl2015", batch_vs_double, f32, kNone, kNoKernel},
    {"meder2018", batch_vs_double, f32, kNone, kNoKernel},
    {"tokuyoshi2022", batch_vs_double, f32, kNone, kNoKernel},
    {"tokuyoshi2024", batch_vs_double, f32, 1e-6, kKernelScalar},
    {"tokuyoshi2022_listing5", batch_vs_double, f32, kNone, kNoKernel},
    {"tokuyoshi2022_refit", batch_vs_double, f32, kNone, kNoKernel},
    {"tokuyoshi2024_refit", batch_vs_double, f32, 1e-6, kKernelScalar},
    {"vsgl2015_refit", batch_vs_double, f32, kNone, kNoKernel},
    {"wang2009_refit", batch_vs_double, f32, kNone, kNoKernel},
    {"sglab_fast", batch_vs_double, f32, 2e-6,
     "the same algebra with branch_free.hpp's exp and selects: float rounding of the peak, far "
     "below the model's "
     "own 3e-3"},
    {"sglab_mid", batch_vs_double, f32, 2e-6,
     "the same algebra with branch_free.hpp's exp, square root and selects: float rounding of the "
     "peak, far below the model's own error"},
    {"sglab_lite", batch_vs_double, f32, kNone, kNoKernel},
    {"sglab_min", batch_vs_double, f32, 2e-6,
     "the scalar algebra (no library call), vectorized: float rounding of the peak, far below "
     "the model's own error"},
    {"sglab_tab", batch_vs_double, f32, 2e-6,
     "a loop of the scalar float call (the table read is a gather): float rounding of the peak"},
    {"sglab_acc1", batch_vs_double, f32, 1e-6, kKernel},
    {"sglab_acc2", batch_vs_double, f32, 1e-6, kKernel},
    {"sglab_acc3", batch_vs_double, f32, 1e-6, kKernel},
    {"sglab_acc4", batch_vs_double, f32, 1e-6, kKernel},

    // ---- split_vs_plain: the per-light split against the plain float function
    {"wang2009", split_vs_plain, f32, kNone, kNoSplit},
    {"punctual", split_vs_plain, f32, kNone, kNoSplit},
    {"hill", split_vs_plain, f32, kNone, kNoSplit},
    {"hill_exact", split_vs_plain, f32, kNone, kNoSplit},
    {"vsgl2015", split_vs_plain, f32, kNone, kNoSplit},
    {"meder2018", split_vs_plain, f32, kNone, kNoSplit},
    {"tokuyoshi2022", split_vs_plain, f32, kNone, kNoSplit},
    {"tokuyoshi2024", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (tokuyoshi2024_light)"},
    {"tokuyoshi2022_listing5", split_vs_plain, f32, kNone, kNoSplit},
    {"tokuyoshi2022_refit", split_vs_plain, f32, kNone, kNoSplit},
    {"tokuyoshi2024_refit", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (tokuyoshi2024_light)"},
    {"vsgl2015_refit", split_vs_plain, f32, kNone, kNoSplit},
    {"wang2009_refit", split_vs_plain, f32, kNone, kNoSplit},
    {"sglab_fast", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_fast_light)"},
    {"sglab_mid", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_mid_light)"},
    {"sglab_lite", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_lite_light)"},
    {"sglab_min", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_min_light)"},
    {"sglab_tab", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_tab_light)"},
    {"sglab_acc1", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_acc_light)"},
    {"sglab_acc2", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_acc_light)"},
    {"sglab_acc3", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_acc_light)"},
    {"sglab_acc4", split_vs_plain, f32, kFourFloatUlps,
     "same operations in the same order (sglab_acc_light)"},

    // ---- half_peak_rel: the half export against the reference engine, κ ∈ [1e-2, 1e3]
    {"wang2009", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"punctual", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"hill", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"hill_exact", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"vsgl2015", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"meder2018", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2022", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2024", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2022_listing5", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2022_refit", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2024_refit", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"vsgl2015_refit", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"wang2009_refit", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_fast", half_peak_rel, f16, 5e-3,
     "its own half form (the κ-only part in float: κ⁴ overflows half)"},
    {"sglab_mid", half_peak_rel, f16, 2.5e-3,
     "its own half form (the κ-only part in float: κ⁴ overflows half); half rounding (~1e-3 of "
     "each "
     "term) dominates the model's 4.2e-4"},
    {"sglab_lite", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_min", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_tab", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_acc1", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_acc2", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_acc4", half_peak_rel, f16, kNone, kNoHalfClaim},
    {"sglab_acc3", half_peak_rel, f16, 5e-3,
     "half rounding (~1e-3 of each term) dominates the model's 2e-5"},

    // ---- half_vs_float: the half export against the float export, κ ∈ [1e-2, 1e3]
    {"wang2009", half_vs_float, f16, kNone, kNoHalfClaim},
    {"punctual", half_vs_float, f16, kNone, kNoHalfClaim},
    {"hill", half_vs_float, f16, kNone, kNoHalfClaim},
    {"hill_exact", half_vs_float, f16, kNone, kNoHalfClaim},
    {"vsgl2015", half_vs_float, f16, kNone, kNoHalfClaim},
    {"meder2018", half_vs_float, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2022", half_vs_float, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2024", half_vs_float, f16, 1e-2,
     "half rounding of the float form; survives [1e-2, 1e3]"},
    {"tokuyoshi2022_listing5", half_vs_float, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2022_refit", half_vs_float, f16, kNone, kNoHalfClaim},
    {"tokuyoshi2024_refit", half_vs_float, f16, kNone, kNoHalfClaim},
    {"vsgl2015_refit", half_vs_float, f16, kNone, kNoHalfClaim},
    {"wang2009_refit", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_fast", half_vs_float, f16, 1e-2,
     "half rounding of its own half form; survives [1e-2, 1e3]"},
    {"sglab_mid", half_vs_float, f16, 1e-2,
     "half rounding of its own half form; survives [1e-2, 1e3]"},
    {"sglab_lite", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_min", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_tab", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_acc1", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_acc2", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_acc4", half_vs_float, f16, kNone, kNoHalfClaim},
    {"sglab_acc3", half_vs_float, f16, 1e-2,
     "half rounding of the float form; survives [1e-2, 1e3]"},
};

// The exports (tests/test_shader_export.cpp): each exported method's max
// peak_rel on the sweep grid is at most twice its runtime float error plus
// this much of the peak, for every method alike: the erf/erfc tiers of the
// export err by at most 1.5e-7 and its expm1 by 2e-7 relative, and 2e-5
// leaves room for their propagation through the formulas (a method that
// amplifies rounding, as tokuyoshi2022's α does, has a float error to match,
// which the 2× term carries).
inline constexpr double kExportAllowance = 2e-5;

// The row of (method, quantity, precision), or nullptr.
constexpr const Tolerance* find_tolerance(std::string_view method, Quantity q, Precision p) {
  for (const Tolerance& t : kTolerances)
    if (t.method == method && t.quantity == q && t.precision == p) return &t;
  return nullptr;
}

}  // namespace sglab::test
