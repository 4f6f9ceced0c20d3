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
#include "sglab_mid.hpp"

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

// A scalar quantity f(cosine, κ) in float and in double, scalar and batch.
struct Method {
  std::string_view id;
  std::string_view source;     // paper / document and equation or listing
  std::string_view constants;  // constant sets from sglab/constants.hpp it uses
  float (*f32)(float cosine, float kappa);
  double (*f64)(double cosine, double kappa);
  void (*batch32)(const float* cosine, const float* kappa, float* out, std::size_t n);
  void (*batch64)(const double* cosine, const double* kappa, double* out, std::size_t n);
  Origin origin = Origin::published;
  ValidRange valid = kNoStatedBound;
  // Optional per-light split in float (both nullptr when the method has none):
  // light_setup32(κ, state) fills state[0 .. kLightStateFloats), and
  // light_eval32(state, c) equals f32(c, κ) up to float rounding.
  void (*light_setup32)(float kappa, float* state) = nullptr;
  float (*light_eval32)(const float* state, float cosine) = nullptr;
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
constexpr MethodOf<F> make_method(std::string_view id, std::string_view source,
                                  std::string_view constants, ValidRange valid, F,
                                  Origin origin = Origin::published) {
  return {Method{
      id,
      source,
      constants,
      [](float c, float k) { return F{}(c, k); },
      [](double c, double k) { return F{}(c, k); },
      [](const float* c, const float* k, float* o, std::size_t n) {
        evaluate_batch(F{}, c, k, o, n);
      },
      [](const double* c, const double* k, double* o, std::size_t n) {
        evaluate_batch(F{}, c, k, o, n);
      },
      origin,
      valid,
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
constexpr auto make_sglab_acc(std::string_view id, std::string_view source,
                              std::string_view constants, ValidRange valid) {
  auto m = make_method(
      id, source, constants, valid, [](auto c, auto k) { return irradiance_sglab_acc(c, k, P); },
      Origin::sglab);
  m.light_setup32 = &SglabAccSplit<P>::setup;
  m.light_eval32 = &SglabAccSplit<P>::eval;
  // Float batch that vectorizes (sglab_acc.hpp irradiance_sglab_acc_batch).
  m.batch32 = [](const float* c, const float* k, float* o, std::size_t n) {
    irradiance_sglab_acc_batch(c, k, o, n, P);
  };
  return m;
}
}  // namespace detail

// Irradiance approximations Ê(c, κ) (docs/references.md), with published
// constants: the one list, passed to `visit` as MethodOf<F> arguments in order
// (irradiance_methods below is visit = collect into an array of Method).
template <class Visitor>
constexpr decltype(auto) with_irradiance_methods(Visitor&& visit) {
  return visit(
      detail::make_method(
          "wang2009",
          "[Wang2009] cosine-lobe SG (λ=2.133, a=1.17) inner product, via [Pettineo2016]",
          "cosine_lobe_published", ValidRange{.max_peak_rel = 0.18},
          [](auto c, auto k) { return irradiance_wang2009(c, k); }),
      detail::make_method("punctual", "cosine pulled out, approximate integral 2π/κ [Pettineo2016]",
                          "", ValidRange{.max_peak_rel = 2.1e3, .kappa_lo = 9.8e-4f},
                          [](auto c, auto k) { return irradiance_punctual(c, k); }),
      detail::make_method("hill", "Stephen Hill's fitted curve × 2π/κ [Pettineo2016]",
                          "hill_published", ValidRange{.max_peak_rel = 3.2e7, .kappa_lo = 1e-3f},
                          [](auto c, auto k) { return irradiance_hill(c, k); }),
      detail::make_method("hill_exact", "Hill's fitted curve × exact S(κ) (as Probulator)",
                          "hill_published", ValidRange{.max_peak_rel = 6.4e4, .kappa_lo = 1e-3f},
                          [](auto c, auto k) { return irradiance_hill_exact(c, k); }),
      detail::make_method("vsgl2015",
                          "[Tokuyoshi2015] diffuse SG λd=2, [Iwasaki2012] product integral",
                          "diffuse_lobe_published", ValidRange{.max_peak_rel = 0.16},
                          [](auto c, auto k) { return irradiance_vsgl2015(c, k); }),
      detail::make_method(
          "meder2018", "Meder & Brüderlin 2018 logistic hemispherical integral + SG cosine fit",
          "meder2018_published", ValidRange{.max_peak_rel = 0.013, .kappa_hi = 2e15f},
          [](auto c, auto k) { return irradiance_meder2018(c, k); }),
      detail::make_method(
          "tokuyoshi2022", "[Tokuyoshi2022] Eq. 3-6, supplementary Listings 1-4, std::erf",
          "clamped_cosine_published, steepness2022_published", ValidRange{.max_peak_rel = 5.1e-3},
          [](auto c, auto k) { return irradiance_tokuyoshi2022(c, k); }),
      detail::with_light_split<Tokuyoshi2024Light<float>>(
          detail::with_batch32(
              detail::make_method("tokuyoshi2024",
                                  "[Tokuyoshi2024] supplementary Listings 6-7 (author's VSGL code)",
                                  "steepness2024_published", ValidRange{.max_peak_rel = 1.6e-3},
                                  [](auto c, auto k) { return irradiance_tokuyoshi2024(c, k); }),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_tokuyoshi2024_batch(c, k, o, n);
              }),
          [](float k) { return tokuyoshi2024_light(k); },
          [](const Tokuyoshi2024Light<float>& l, float c) { return tokuyoshi2024_eval(l, c); }),
      // The published formulas with sglab's refitted constants (`sglab fit all`)
      // and the shader path of the 2022 method (Listing 5 erf).
      detail::make_method(
          "tokuyoshi2022_listing5",
          "tokuyoshi2022 with the [Tokuyoshi2022] Listing 5 erf, as a shader runs it",
          "clamped_cosine_published, steepness2022_published, erf_listing5_published",
          ValidRange{.max_peak_rel = 5e-3},
          [](auto c, auto k) {
            return irradiance_tokuyoshi2022(c, k, constants::clamped_cosine_published,
                                            constants::steepness2022_published, ErfListing5{});
          }),
      detail::make_method(
          "tokuyoshi2022_refit", "tokuyoshi2022 refitted: float clamped cosine, t(κ) on irradiance",
          "clamped_cosine_float, steepness2022_irradiance", ValidRange{.max_peak_rel = 4e-3},
          [](auto c, auto k) {
            return irradiance_tokuyoshi2022(c, k, constants::clamped_cosine_float,
                                            constants::steepness2022_irradiance);
          },
          Origin::refit),
      detail::with_light_split<Tokuyoshi2024Light<float>>(
          detail::with_batch32(
              detail::make_method(
                  "tokuyoshi2024_refit", "tokuyoshi2024 refitted: t(κ) on irradiance",
                  "steepness2024_irradiance", ValidRange{.max_peak_rel = 1.5e-3},
                  [](auto c, auto k) {
                    return irradiance_tokuyoshi2024(c, k, constants::steepness2024_irradiance);
                  },
                  Origin::refit),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_tokuyoshi2024_batch(c, k, o, n, constants::steepness2024_irradiance);
              }),
          [](float k) { return tokuyoshi2024_light(k, constants::steepness2024_irradiance); },
          [](const Tokuyoshi2024Light<float>& l, float c) { return tokuyoshi2024_eval(l, c); }),
      detail::make_method(
          "vsgl2015_refit", "vsgl2015 refitted: λd minimizing the irradiance error",
          "lambda_d_diffuse_lobe_irradiance", ValidRange{.max_peak_rel = 0.15},
          [](auto c, auto k) {
            return irradiance_vsgl2015(c, k, constants::lambda_d_diffuse_lobe_irradiance);
          },
          Origin::refit),
      detail::make_method(
          "wang2009_refit",
          "wang2009 refitted: cosine lobe (λ, a) by least squares over the sphere",
          "lambda_d_cosine_lobe_free_amplitude", ValidRange{.max_peak_rel = 0.18},
          [](auto c, auto k) {
            return irradiance_wang2009(c, k, constants::lambda_d_cosine_lobe_free_amplitude);
          },
          Origin::refit),
      // sglab's own models (fitted by `sglab fit`), with their per-light split.
      detail::with_light_split<SglabFastLight<float>>(
          detail::with_batch32(
              detail::make_method(
                  "sglab_fast",
                  "sglab: exact E(1, κ) × fitted shape A + Bc + Cρ(Vc + ½), rational "
                  "A, B, C, V in κ (sglab_fast.hpp)",
                  "sglab_fast_float", ValidRange{.max_peak_rel = 2.6e-3, .kappa_hi = 1.1e4f},
                  [](auto c, auto k) { return irradiance_sglab_fast(c, k); }, Origin::sglab),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_fast_batch(c, k, o, n);
              }),
          [](float k) { return sglab_fast_light(k); },
          [](const SglabFastLight<float>& l, float c) { return sglab_fast_eval(l, c); }),
      detail::with_light_split<SglabMidLight<float>>(
          detail::with_batch32(
              detail::make_method(
                  "sglab_mid",
                  "sglab: exact E(1, κ) × fitted shape A + B(c + √(c² + e^{S − Vc²})) + Dc², "
                  "rational A, B, D, S, V/κ in κ (sglab_mid.hpp)",
                  "sglab_mid_float", ValidRange{.max_peak_rel = 4.3e-4},
                  [](auto c, auto k) { return irradiance_sglab_mid(c, k); }, Origin::sglab),
              [](const float* c, const float* k, float* o, std::size_t n) {
                irradiance_sglab_mid_batch(c, k, o, n);
              }),
          [](float k) { return sglab_mid_light(k); },
          [](const SglabMidLight<float>& l, float c) { return sglab_mid_eval(l, c); }),
      // sglab's own models (sglab_acc.hpp, `sglab fit sglab-acc`): the
      // tokuyoshi2024 form with a fitted correction of its lerp factor; a ladder
      // of 1, 2, 3, 4 correction terms.
      detail::make_sglab_acc<constants::sglab_acc_acc1>(
          "sglab_acc1",
          "sglab: tokuyoshi2024 lerp factor + (1-c^2)e^{-z^2}b0(kappa), b0 = u(1-u)^3 P(u), u = "
          "t/(t+s), P of degree 3",
          "sglab_acc_acc1", ValidRange{.max_peak_rel = 2e-4}),
      detail::make_sglab_acc<constants::sglab_acc_acc2>(
          "sglab_acc2",
          "sglab: tokuyoshi2024 lerp factor + (1-c^2)e^{-z^2}(b0 + b1 z^2), b_j = u(1-u)^3 P_j(u), "
          "P_j of degree 5",
          "sglab_acc_acc2", ValidRange{.max_peak_rel = 3e-5}),
      detail::make_sglab_acc<constants::sglab_acc_acc3>(
          "sglab_acc3",
          "sglab: tokuyoshi2024 lerp factor + (1-c^2)e^{-z^2}(b0 + b1 z^2 + b2 z^4), b_j = "
          "u(1-u)^3 P_j(u), P_j of degree 6, t(kappa) rational of order 3",
          "sglab_acc_acc3", ValidRange{.max_peak_rel = 7.8e-6}),
      detail::make_sglab_acc<constants::sglab_acc_acc4>(
          "sglab_acc4",
          "sglab: tokuyoshi2024 lerp factor + (1-c^2)e^{-z^2}(b0 + b1 z^2 + b2 z^4 + b3 z^6), b_j "
          "= u(1-u)^3 P_j(u), P_j of degree 6, t(kappa) rational of order 3",
          "sglab_acc_acc4", ValidRange{.max_peak_rel = 4.8e-6}));
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
    detail::make_method("erf2022", "[Tokuyoshi2022] Eq. 5/6, Listing 3, std::erf",
                        "steepness2022_published", kNoStatedBound,
                        [](auto c, auto k) { return hemispherical_erf2022(c, k); }),
    detail::make_method("erf2022_listing5", "[Tokuyoshi2022] Eq. 5/6 with the Listing 5 erf",
                        "steepness2022_published, erf_listing5_published", kNoStatedBound,
                        [](auto c, auto k) {
                          return hemispherical_erf2022(c, k, constants::steepness2022_published,
                                                       ErfListing5{});
                        }),
    detail::make_method("meder2018", "[Meder2018] logistic normalized hemispherical integral",
                        "meder2018_published", kNoStatedBound,
                        [](auto c, auto k) { return hemispherical_meder2018(c, k); }),
};

// Normalized hemispherical integrals s̃(c, κ) matching hemispherical_methods.
inline constexpr Method normalized_methods[] = {
    detail::make_method("erf2022", "[Tokuyoshi2022] Eq. 5/6, std::erf", "steepness2022_published",
                        kNoStatedBound, [](auto c, auto k) { return normalized_erf2022(c, k); }),
    detail::make_method("erf2022_listing5", "[Tokuyoshi2022] Eq. 5/6 with the Listing 5 erf",
                        "steepness2022_published, erf_listing5_published", kNoStatedBound,
                        [](auto c, auto k) {
                          return normalized_erf2022(c, k, constants::steepness2022_published,
                                                    ErfListing5{});
                        }),
    detail::make_method("meder2018", "[Meder2018] logistic normalized hemispherical integral",
                        "meder2018_published", kNoStatedBound,
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
