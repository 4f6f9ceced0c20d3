// sglab/sglab_lite.hpp — sglab's model `sglab_lite`:
//   Ê(c, κ) = max(0, A + B c + C ρ(V c + ½)),
//   A, B, C = Pa, Pb, Pc / ((1 + κ̃) Q),  V = Pv/Q,  κ̃ = min(κ, kappa_max),
// the shape of sglab_fast (a line plus the C² ramp ρ, sglab_fast.hpp) with
// E(1, κ) folded into A, B, C, so that no exp is formed: 1/(1 + κ̃) carries the
// 1/κ fall of E(1, κ) (π at κ = 0, ≈ 2π/κ beyond), the numerators, of degree 4
// over one shared monic quartic Q, the rest (SglabLiteParams); form, fit,
// error and cost: docs/models.md#sglab_lite.
//
// Never NaN for finite κ ≥ 0 and c ∈ [−1, 1]: (1 + κ̃) Q(κ̃) ≥ q[0] > 0 is
// finite, so is every rational. Beyond kappa_max every value stays that of kappa_max
// while the exact E(1, κ) keeps falling like 2π/κ: the registry card's valid
// range ends at kappa_max.
#pragma once

#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"
#include "sglab_fast.hpp"

namespace sglab {

// Everything of `sglab_lite` that depends on κ alone:
// Ê = max(0, a + b c + c_ramp ρ(v c + ½)).
template <class T>
struct SglabLiteLight {
  T a, b, c_ramp, v;
};

// Per-light setup: one division, four quartic numerators and (1 + κ̃) Q.
template <class T, class S = double>
SglabLiteLight<T> sglab_lite_light(const T& kappa,
                                   const SglabLiteParams<S>& p = constants::sglab_lite_float) {
  const T k = detail::min_of(kappa, T(p.kappa_max));
  // Q = (((κ̃ + q3)κ̃ + q2)κ̃ + q1)κ̃ + q0: monic Horner, four operations.
  const T one_k = T(1) + k;
  const T inv =
      T(1) / (((((k + T(p.q[3])) * k + T(p.q[2])) * k + T(p.q[1])) * k + T(p.q[0])) * one_k);
  return {horner(k, p.a) * inv, horner(k, p.b) * inv, horner(k, p.c) * inv,
          horner(k, p.v) * inv * one_k};
}

// Per-shading-point evaluation (that of sglab_fast).
template <class T>
T sglab_lite_eval(const SglabLiteLight<T>& light, const T& cosine) {
  return detail::max0_branchless(light.a + light.b * cosine +
                                 light.c_ramp * detail::sglab_ramp(light.v * cosine + T(0.5)));
}

// `sglab_lite`: Ê(c, κ), the two steps above in one call.
template <class T, class S = double>
T irradiance_sglab_lite(const T& cosine, const T& kappa,
                        const SglabLiteParams<S>& p = constants::sglab_lite_float) {
  return sglab_lite_eval(sglab_lite_light(kappa, p), cosine);
}

}  // namespace sglab
