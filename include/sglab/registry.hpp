// sglab/registry.hpp — the single list of methods that every validator,
// benchmark and document iterates (no static self-registration).
#pragma once

#include <array>
#include <cstddef>
#include <cstring>
#include <limits>
#include <span>
#include <string_view>

#include "batch.hpp"
#include "erf.hpp"
#include "hemispherical.hpp"
#include "irradiance.hpp"
#include "sglab_acc.hpp"
#include "sglab_fast.hpp"
#include "sglab_lite.hpp"
#include "sglab_mid.hpp"
#include "sglab_min.hpp"
#include "sglab_tab.hpp"

namespace sglab {

// Where a method's formula and constants come from.
enum class Origin {
  published,  // a published formula with its published constants
  refit,      // a published formula with sglab's refitted constants (`sglab fit`)
  sglab,      // a model of sglab's own, fitted by `sglab fit`
};

constexpr std::string_view to_string(Origin o) {
  switch (o) {
    case Origin::published:
      return "published";
    case Origin::refit:
      return "refit";
    case Origin::sglab:
      return "sglab";
  }
  return "?";
}

// Where a method's stated error bound holds, on its card in the tables below:
// the max over c ∈ [−1, 1] of peak_rel = |Ê − E|/E(1, κ) (docs/quantities.md)
// is at most `max_peak_rel` for every κ ∈ [kappa_lo, kappa_hi], with Ê in float
// and in double. kappa_lo = 0 and kappa_hi = FLT_MAX: every κ a float holds.
// The bound is the method's worst error over the fitted range [1e−3, 1e4],
// with 1 % to spare for float rounding, rounded up to two digits; the range is
// the largest around [1e−3, 1e4] on which that bound still holds, its ends
// rounded inward to two digits. `sglab range` measures
// it over every κ a float holds (data/results/kappa_range.md) and
// tests/test_kappa_range.cpp holds each method to its card; `recommend`,
// `pareto`, the scene ranking and the exports flag a κ outside the range.
struct ValidRange {
  double max_peak_rel = 0;  // 0: no stated bound (the lists other than irradiance)
  float kappa_lo = 0;
  float kappa_hi = std::numeric_limits<float>::max();
  // Whether every κ of [lo, hi] lies in the range, compared as the floats κ is used in (1e-3
  // as a double is below 1e-3f).
  constexpr bool covers(double lo, double hi) const {
    return lo <= hi && hi <= static_cast<double>(std::numeric_limits<float>::max()) &&
           kappa_lo <= static_cast<float>(lo) && static_cast<float>(hi) <= kappa_hi;
  }
  constexpr bool covers(double kappa) const { return covers(kappa, kappa); }
};
inline constexpr float kFloatMax = std::numeric_limits<float>::max();
// The hemispherical and normalized lists, whose bounds are not stated here.
inline constexpr ValidRange kNoStatedBound{};

// Per-light split of a method (optional): everything that depends on κ alone
// is computed once per light into an opaque state of at most
// kLightStateFloats floats; each shading point then pays only `eval`.
inline constexpr std::size_t kLightStateFloats = 16;

// A method's card: what it is, in the one place every table, export and document reads it
// (`sglab methods --json` / `--format md`, the shader exports' header comments, the results
// tables of scripts/results_tables.sh, docs/references.md).
struct Card {
  std::string_view id;
  Origin origin = Origin::published;
  // docs/references.md key and the equation or listing; sglab's own models: docs/models.md.
  std::string_view source = {};
  std::string_view summary = {};    // what it is, in one line
  std::string_view form = {};       // its formula, in one line (empty: that of `source`)
  std::string_view constants = {};  // constant sets from sglab/constants.hpp it uses
  ValidRange valid = kNoStatedBound;
  // The half-precision export's own form, what stays in float ("" : the float code in half).
  std::string_view half = {};
};

// A scalar quantity f(cosine, κ) in float and in double, scalar and batch, with its card.
struct Method : Card {
  float (*f32)(float cosine, float kappa);
  double (*f64)(double cosine, double kappa);
  void (*batch32)(const float* cosine, const float* kappa, float* out, std::size_t n);
  void (*batch64)(const double* cosine, const double* kappa, double* out, std::size_t n);
  // Optional per-light split in float (both nullptr when the method has none):
  // light_setup32(κ, state) fills state[0 .. kLightStateFloats), and
  // light_eval32(state, c) equals f32(c, κ) up to float rounding.
  void (*light_setup32)(float kappa, float* state) = nullptr;
  float (*light_eval32)(const float* state, float cosine) = nullptr;
  constexpr bool has_split() const { return light_setup32 != nullptr && light_eval32 != nullptr; }
};

// A Method together with the type of the generic functor F(cosine, κ) it
// was made from, so that code outside the runtime can instantiate the same
// template with another scalar type (the Python module differentiates it with
// Ceres Jets: python/gradient.hpp). Converts to Method by slicing.
template <class F>
struct MethodOf : Method {
  using Functor = F;
};

namespace detail {
template <class F>
constexpr MethodOf<F> make_method(const Card& card, F) {
  return {Method{
      card,
      [](float c, float k) { return F{}(c, k); },
      [](double c, double k) { return F{}(c, k); },
      [](const float* c, const float* k, float* o, std::size_t n) {
        evaluate_batch(F{}, c, k, o, n);
      },
      [](const double* c, const double* k, double* o, std::size_t n) {
        evaluate_batch(F{}, c, k, o, n);
      },
  }};
}

// A method whose float batch is a dedicated kernel (e.g. one that vectorizes).
template <class M>
constexpr M with_batch32(M m, void (*batch32)(const float*, const float*, float*, std::size_t)) {
  m.batch32 = batch32;
  return m;
}

// A method with the per-light split: Setup(κ) returns a Light (a struct of at
// most kLightStateFloats floats), Eval(light, c) the value.
template <class Light, class M, class Setup, class Eval>
constexpr M with_light_split(M m, Setup, Eval) {
  static_assert(sizeof(Light) <= kLightStateFloats * sizeof(float) &&
                alignof(Light) <= alignof(float));
  m.light_setup32 = [](float kappa, float* state) {
    const Light light = Setup{}(kappa);
    std::memcpy(state, &light, sizeof light);
  };
  m.light_eval32 = [](const float* state, float cosine) {
    Light light;
    std::memcpy(&light, state, sizeof light);
    return Eval{}(light, cosine);
  };
  return m;
}

// The per-light split of a method whose setup returns a trivially copyable
// struct of floats (sglab_acc.hpp): the struct is the state.
template <const auto& P>
struct SglabAccSplit {
  using Light = decltype(sglab_acc_light(0.0f, P));
  static_assert(sizeof(Light) <= kLightStateFloats * sizeof(float));
  static void setup(float kappa, float* state) {
    const Light l = sglab_acc_light(kappa, P);
    std::memcpy(state, &l, sizeof l);
  }
  static float eval(const float* state, float cosine) {
    Light l;
    std::memcpy(&l, state, sizeof l);
    return sglab_acc_eval(l, cosine);
  }
};

template <const auto& P>
constexpr auto make_sglab_acc(const Card& card) {
  auto m = make_method(card, [](auto c, auto k) { return irradiance_sglab_acc(c, k, P); });
  m.light_setup32 = &SglabAccSplit<P>::setup;
  m.light_eval32 = &SglabAccSplit<P>::eval;
  // Float batch that vectorizes (sglab_acc.hpp irradiance_sglab_acc_batch).
  m.batch32 = [](const float* c, const float* k, float* o, std::size_t n) {
    irradiance_sglab_acc_batch(c, k, o, n, P);
  };
  return m;
}
}  // namespace detail

// Irradiance approximations Ê(c, κ) (docs/references.md, docs/models.md): the one list,
// passed to `visit` as MethodOf<F> arguments in order (irradiance_methods below is visit =
// collect into an array of Method).
template <class Visitor>
constexpr decltype(auto) with_irradiance_methods(Visitor&& visit) {
  using detail::make_method;
  using detail::with_batch32;
  using detail::with_light_split;
  return visit(
      make_method({.id = "wang2009",
                   .source = "[Wang2009] via [Pettineo2016]",
                   .summary = "cosine-lobe SG (λ = 2.133, a = 1.17) inner product",
                   .form = "a e^{d − κ − λ} 2π(1 − e^{−2d})/d, d = |κv + λn|",
                   .constants = "cosine_lobe_published",
                   .valid = {.max_peak_rel = 0.18}},
                  [](auto c, auto k) { return irradiance_wang2009(c, k); }),
      make_method({.id = "punctual",
                   .source = "[Pettineo2016] \"A Cheaper Approximation\"",
                   .summary = "cosine pulled out of the integral, approximate SG integral 2π/κ",
                   .form = "max(c, 0) 2π/κ",
                   .valid = {.max_peak_rel = 2.1e3, .kappa_lo = 9.8e-4f}},
                  [](auto c, auto k) { return irradiance_punctual(c, k); }),
      make_method({.id = "hill",
                   .source = "[Pettineo2016] \"A More Accurate Approximation\"",
                   .summary = "Stephen Hill's fitted curve × 2π/κ",
                   .form = "hill(c, κ) 2π/κ",
                   .constants = "hill_published",
                   .valid = {.max_peak_rel = 3.2e7, .kappa_lo = 1e-3f}},
                  [](auto c, auto k) { return irradiance_hill(c, k); }),
      make_method({.id = "hill_exact",
                   .source = "[Pettineo2016], as in [Probulator]",
                   .summary = "Hill's fitted curve × the exact SG integral S(κ)",
                   .form = "hill(c, κ) S(κ)",
                   .constants = "hill_published",
                   .valid = {.max_peak_rel = 6.4e4, .kappa_lo = 1e-3f}},
                  [](auto c, auto k) { return irradiance_hill_exact(c, k); }),
      make_method({.id = "vsgl2015",
                   .source = "[Tokuyoshi2015] supplemental §3.2, after [Iwasaki2012]",
                   .summary = "diffuse SG λd = 2, approximate product integral, one exp",
                   .form = "2π e^{λ'(c − 1)}/(κ + λd), λ' = κλd/(κ + λd)",
                   .constants = "diffuse_lobe_published",
                   .valid = {.max_peak_rel = 0.16}},
                  [](auto c, auto k) { return irradiance_vsgl2015(c, k); }),
      make_method({.id = "meder2018",
                   .source = "[Meder2018]",
                   .summary = "logistic hemispherical integral with an SG cosine fit",
                   .form = "a e^{…} H̃(c₃, κ₃) − o H̃(c, κ), H̃ logistic",
                   .constants = "meder2018_published",
                   .valid = {.max_peak_rel = 0.013, .kappa_hi = 2e15f}},
                  [](auto c, auto k) { return irradiance_meder2018(c, k); }),
      make_method({.id = "tokuyoshi2022",
                   .source = "[Tokuyoshi2022] Eq. 3-6, supplementary Listings 1-4",
                   .summary = "clamped cosine α(e^{λ(c − 1)} − …) and erf-based H̃, std::erf",
                   .form = "α (H̃(c₃, κ₃) e^{λ + …} − H̃(c, κ)), H̃ = 2π lerp(e^{−κ}, 1, s̃)(1 − "
                           "e^{−κ})/κ, s̃ erf-based",
                   .constants = "clamped_cosine_published, steepness2022_published",
                   .valid = {.max_peak_rel = 5.1e-3}},
                  [](auto c, auto k) { return irradiance_tokuyoshi2022(c, k); }),
      with_light_split<Tokuyoshi2024Light<float>>(
          with_batch32(
              make_method({.id = "tokuyoshi2024",
                           .source = "[Tokuyoshi2024] supplementary Listings 6-7 (author's "
                                     "VSGL code)",
                           .summary = "lerp of the exact poles by an erfc-based factor",
                           .form = "2π lerp(Ē(−1, κ), Ē(1, κ), f₂₀₂₄(c, t(κ)))",
                           .constants = "steepness2024_published",
                           .valid = {.max_peak_rel = 1.6e-3}},
                          [](auto c, auto k) { return irradiance_tokuyoshi2024(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_tokuyoshi2024_batch(c, k, o, n);
              }),
          [](float k) { return tokuyoshi2024_light(k); },
          [](const Tokuyoshi2024Light<float>& l, float c) { return tokuyoshi2024_eval(l, c); }),
      // The shader path of the 2022 method (its Listing 5 erf), and the published formulas
      // with sglab's refitted constants (`sglab fit all`).
      make_method(
          {.id = "tokuyoshi2022_listing5",
           .source = "[Tokuyoshi2022] Eq. 3-6, supplementary Listings 1-5",
           .summary = "tokuyoshi2022 with the Listing 5 erf, as a shader runs it",
           .form = "that of tokuyoshi2022",
           .constants = "clamped_cosine_published, steepness2022_published, erf_listing5_published",
           .valid = {.max_peak_rel = 5e-3}},
          [](auto c, auto k) {
            return irradiance_tokuyoshi2022(c, k, constants::clamped_cosine_published,
                                            constants::steepness2022_published, ErfListing5{});
          }),
      make_method({.id = "tokuyoshi2022_refit",
                   .origin = Origin::refit,
                   .source = "[Tokuyoshi2022] Eq. 3-6, sglab's constants",
                   .summary = "tokuyoshi2022 refitted: float clamped cosine, t(κ) on irradiance",
                   .form = "that of tokuyoshi2022",
                   .constants = "clamped_cosine_float, steepness2022_irradiance",
                   .valid = {.max_peak_rel = 4e-3}},
                  [](auto c, auto k) {
                    return irradiance_tokuyoshi2022(c, k, constants::clamped_cosine_float,
                                                    constants::steepness2022_irradiance);
                  }),
      with_light_split<Tokuyoshi2024Light<float>>(
          with_batch32(
              make_method(
                  {.id = "tokuyoshi2024_refit",
                   .origin = Origin::refit,
                   .source = "[Tokuyoshi2024] supplementary Listings 6-7, sglab's constants",
                   .summary = "tokuyoshi2024 refitted: t(κ) on irradiance",
                   .form = "that of tokuyoshi2024",
                   .constants = "steepness2024_irradiance",
                   .valid = {.max_peak_rel = 1.5e-3}},
                  [](auto c, auto k) {
                    return irradiance_tokuyoshi2024(c, k, constants::steepness2024_irradiance);
                  }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_tokuyoshi2024_batch(c, k, o, n, constants::steepness2024_irradiance);
              }),
          [](float k) { return tokuyoshi2024_light(k, constants::steepness2024_irradiance); },
          [](const Tokuyoshi2024Light<float>& l, float c) { return tokuyoshi2024_eval(l, c); }),
      make_method({.id = "vsgl2015_refit",
                   .origin = Origin::refit,
                   .source = "[Tokuyoshi2015], sglab's constants",
                   .summary = "vsgl2015 refitted: λd minimizing the irradiance error",
                   .form = "that of vsgl2015",
                   .constants = "lambda_d_diffuse_lobe_irradiance",
                   .valid = {.max_peak_rel = 0.15}},
                  [](auto c, auto k) {
                    return irradiance_vsgl2015(c, k, constants::lambda_d_diffuse_lobe_irradiance);
                  }),
      make_method(
          {.id = "wang2009_refit",
           .origin = Origin::refit,
           .source = "[Wang2009], sglab's constants",
           .summary = "wang2009 refitted: cosine lobe (λ, a) by least squares over the sphere",
           .form = "that of wang2009",
           .constants = "lambda_d_cosine_lobe_free_amplitude",
           .valid = {.max_peak_rel = 0.18}},
          [](auto c, auto k) {
            return irradiance_wang2009(c, k, constants::lambda_d_cosine_lobe_free_amplitude);
          }),
      // sglab's own models (fitted by `sglab fit`, docs/models.md), with their per-light split.
      with_light_split<SglabFastLight<float>>(
          with_batch32(
              make_method(
                  {.id = "sglab_fast",
                   .origin = Origin::sglab,
                   .source = "docs/models.md#sglab_fast",
                   .summary = "exact E(1, κ) times a line plus a C² ramp, one exp, no erf",
                   .form = "exact E(1, κ) × A + Bc + Cρ(Vc + ½), rational A, B, C, V",
                   .constants = "sglab_fast_float",
                   .valid = {.max_peak_rel = 2.6e-3, .kappa_hi = 1.1e4f},
                   .half = "kappa-only part (E(1, kappa), the rational A, B, C, V) in float, "
                           "per-pixel shape in half"},
                  [](auto c, auto k) { return irradiance_sglab_fast(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_fast_batch(c, k, o, n);
              }),
          [](float k) { return sglab_fast_light(k); },
          [](const SglabFastLight<float>& l, float c) { return sglab_fast_eval(l, c); }),
      with_light_split<SglabLiteLight<float>>(
          make_method({.id = "sglab_lite",
                       .origin = Origin::sglab,
                       .source = "docs/models.md#sglab_lite",
                       .summary = "sglab_fast's line plus C² ramp with E(1, κ) folded into the "
                                  "rationals: one division, no exp",
                       .form = "A + Bc + Cρ(Vc + ½), rational A, B, C, V (E(1, κ) in A, B, C)",
                       .constants = "sglab_lite_float",
                       .valid = {.max_peak_rel = 3.7e-3, .kappa_hi = 1e4f}},
                      [](auto c, auto k) { return irradiance_sglab_lite(c, k); }),
          [](float k) { return sglab_lite_light(k); },
          [](const SglabLiteLight<float>& l, float c) { return sglab_lite_eval(l, c); }),
      with_light_split<SglabMinLight<float>>(
          with_batch32(
              make_method(
                  {.id = "sglab_min",
                   .origin = Origin::sglab,
                   .source = "docs/models.md#sglab_min",
                   .summary = "a clamped quadratic in c over κ + s, quadratics in x = κ/(κ + s): "
                              "one division",
                   .form = "max(0, A(x) + B(x)c + G(x)c²)/(κ + s), x = κ/(κ + s)",
                   .constants = "sglab_min_float",
                   .valid = {.max_peak_rel = 0.043}},
                  [](auto c, auto k) { return irradiance_sglab_min(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_min_batch(c, k, o, n);
              }),
          [](float k) { return sglab_min_light(k); },
          [](const SglabMinLight<float>& l, float c) { return sglab_min_eval(l, c); }),
      with_light_split<SglabMidLight<float>>(
          with_batch32(
              make_method(
                  {.id = "sglab_mid",
                   .origin = Origin::sglab,
                   .source = "docs/models.md#sglab_mid",
                   .summary = "exact E(1, κ) times a line, a smoothed max(c, 0) of varying width "
                              "and c²",
                   .form = "exact E(1, κ) × A + B(c + √(c² + e^{S − Vc²})) + Dc², rational A, "
                           "B, D, S, V",
                   .constants = "sglab_mid_float",
                   .valid = {.max_peak_rel = 4.3e-4},
                   .half = "kappa-only part (E(1, kappa), the rational A, B, D, S, V) in float, "
                           "per-pixel shape in half"},
                  [](auto c, auto k) { return irradiance_sglab_mid(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_mid_batch(c, k, o, n);
              }),
          [](float k) { return sglab_mid_light(k); },
          [](const SglabMidLight<float>& l, float c) { return sglab_mid_eval(l, c); }),
      with_light_split<SglabTabLight<float>>(
          with_batch32(
              make_method({.id = "sglab_tab",
                           .origin = Origin::sglab,
                           .source = "docs/models.md#sglab_tab",
                           .summary = "sglab_mid's shape with two more terms, its seven values "
                                      "read from a table of cubics over 32 cells of κ",
                           .form = "exact E(1, κ) × A + B(c + √(c² + g)) + Dc² + (G + Hc²)g, "
                                   "g = e^{S − Vc²}, cubics per cell of √κ/(1 + √κ)",
                           .constants = "sglab_tab_float",
                           .valid = {.max_peak_rel = 1.2e-6}},
                          [](auto c, auto k) { return irradiance_sglab_tab(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_tab_batch(c, k, o, n);
              }),
          [](float k) { return sglab_tab_light(k); },
          [](const SglabTabLight<float>& l, float c) { return sglab_tab_eval(l, c); }),
      // The sglab_acc ladder (sglab_acc.hpp): the tokuyoshi2024 form with a fitted correction
      // of its lerp factor of 1, 2, 3, 4 terms.
      detail::make_sglab_acc<constants::sglab_acc1>(
          {.id = "sglab_acc1",
           .origin = Origin::sglab,
           .source = "docs/models.md#sglab_acc1--sglab_acc4",
           .summary = "[Tokuyoshi2024] lerp factor + a fitted even correction fading at both "
                      "ends, N = 1, D = 3",
           .form = "2024 factor + (1 − c²)e^{−z²}b0(κ), z = tc, b0 = u(1 − u)³P0(u), u = t/(t + "
                   "s)",
           .constants = "sglab_acc1",
           .valid = {.max_peak_rel = 2e-4}}),
      detail::make_sglab_acc<constants::sglab_acc2>(
          {.id = "sglab_acc2",
           .origin = Origin::sglab,
           .source = "docs/models.md#sglab_acc1--sglab_acc4",
           .summary = "[Tokuyoshi2024] lerp factor + a fitted even correction fading at both "
                      "ends, N = 2, D = 5",
           .form = "sglab_acc1 + b1(κ)z², P_j of degree 5",
           .constants = "sglab_acc2",
           .valid = {.max_peak_rel = 3e-5}}),
      detail::make_sglab_acc<constants::sglab_acc3>(
          {.id = "sglab_acc3",
           .origin = Origin::sglab,
           .source = "docs/models.md#sglab_acc1--sglab_acc4",
           .summary = "[Tokuyoshi2024] lerp factor + a fitted even correction fading at both "
                      "ends, N = 3, D = 6, steepness of order M = 3",
           .form = "sglab_acc2 + b2(κ)z⁴, P_j of degree 6, t(κ) rational of order 3",
           .constants = "sglab_acc3",
           .valid = {.max_peak_rel = 7.8e-6}}),
      detail::make_sglab_acc<constants::sglab_acc4>(
          {.id = "sglab_acc4",
           .origin = Origin::sglab,
           .source = "docs/models.md#sglab_acc1--sglab_acc4",
           .summary = "[Tokuyoshi2024] lerp factor + a fitted even correction fading at both "
                      "ends, N = 4, D = 6, steepness of order M = 3",
           .form = "sglab_acc3 + b3(κ)z⁶, P_j of degree 6, t(κ) rational of order 3",
           .constants = "sglab_acc4",
           .valid = {.max_peak_rel = 4.8e-6}}));
}

namespace detail {
struct CollectMethods {
  template <class... M>
  constexpr std::array<Method, sizeof...(M)> operator()(const M&... m) const {
    return {static_cast<const Method&>(m)...};
  }
};
}  // namespace detail

inline constexpr auto irradiance_methods = with_irradiance_methods(detail::CollectMethods{});

// Approximate hemispherical integrals H̃(c, κ) (`erf2022` [Tokuyoshi2022], `meder2018` [Meder2018]).
inline constexpr Method hemispherical_methods[] = {
    detail::make_method({.id = "erf2022",
                         .source = "[Tokuyoshi2022] Eq. 5-6, Listing 3",
                         .summary = "erf-based hemispherical integral, std::erf",
                         .constants = "steepness2022_published"},
                        [](auto c, auto k) { return hemispherical_erf2022(c, k); }),
    detail::make_method({.id = "erf2022_listing5",
                         .source = "[Tokuyoshi2022] Eq. 5-6, Listings 3 and 5",
                         .summary = "erf2022 with the Listing 5 erf",
                         .constants = "steepness2022_published, erf_listing5_published"},
                        [](auto c, auto k) {
                          return hemispherical_erf2022(c, k, constants::steepness2022_published,
                                                       ErfListing5{});
                        }),
    detail::make_method({.id = "meder2018",
                         .source = "[Meder2018]",
                         .summary = "logistic normalized hemispherical integral",
                         .constants = "meder2018_published"},
                        [](auto c, auto k) { return hemispherical_meder2018(c, k); }),
};

// Normalized hemispherical integrals s̃(c, κ) matching hemispherical_methods.
inline constexpr Method normalized_methods[] = {
    detail::make_method({.id = "erf2022",
                         .source = "[Tokuyoshi2022] Eq. 5-6, Listing 3",
                         .summary = "erf-based normalized hemispherical integral, std::erf",
                         .constants = "steepness2022_published"},
                        [](auto c, auto k) { return normalized_erf2022(c, k); }),
    detail::make_method({.id = "erf2022_listing5",
                         .source = "[Tokuyoshi2022] Eq. 5-6, Listings 3 and 5",
                         .summary = "erf2022 with the Listing 5 erf",
                         .constants = "steepness2022_published, erf_listing5_published"},
                        [](auto c, auto k) {
                          return normalized_erf2022(c, k, constants::steepness2022_published,
                                                    ErfListing5{});
                        }),
    detail::make_method({.id = "meder2018",
                         .source = "[Meder2018]",
                         .summary = "logistic normalized hemispherical integral",
                         .constants = "meder2018_published"},
                        [](auto c, auto k) { return normalized_meder2018(c, k); }),
};

// erf variants (docs/references.md).
struct ErfVariant {
  std::string_view id;
  std::string_view source;
  float (*f32)(float x);
  double (*f64)(double x);
};
inline constexpr ErfVariant erf_variants[] = {
    {"listing5", "[Tokuyoshi2022] supplementary Listing 5", [](float x) { return erf_listing5(x); },
     [](double x) { return erf_listing5(x); }},
    {"as7125", "[AS1964] 7.1.25, claimed |error| <= 2.5e-5",
     [](float x) { return erf_abramowitz_stegun(x); },
     [](double x) { return erf_abramowitz_stegun(x); }},
    {"std", "platform std::erf", [](float x) { return std::erf(x); },
     [](double x) { return std::erf(x); }},
};

// Look-ups by id; nullptr when absent.
inline const Method* find_method(std::span<const Method> list, std::string_view id) {
  for (const Method& m : list)
    if (m.id == id) return &m;
  return nullptr;
}
inline const ErfVariant* find_erf_variant(std::string_view id) {
  for (const ErfVariant& v : erf_variants)
    if (v.id == id) return &v;
  return nullptr;
}

}  // namespace sglab
