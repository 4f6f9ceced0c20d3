// sglab/sglab_min.hpp — sglab's model `sglab_min`, the cheapest of sglab's models:
//   Ê(c, κ) = y · max(0, A(y) + B(y) c + G(y) c²),  y = 1/(κ + s),
// a clamped quadratic in the cosine whose coefficients are polynomials in
// y ∈ (0, 1/s] (A quadratic, B and G linear; SglabMinParams). y carries the
// 2π/κ fall of E(1, κ) and maps every κ ≥ 0 into (0, 1/s], so one division is
// the whole κ-dependent cost and the form has a limit as κ → ∞ (y → 0: the
// clamped quadratic (a0 + b0 c + g0 c²)/κ against the exact 2π max(c, 0)/κ),
// which the fit holds to its bound; form, fit, error and cost:
// docs/models.md#sglab_min.
//
// Never NaN for finite κ ≥ 0 and c ∈ [−1, 1]: κ + s ≥ s > 0 and y ∈ (0, 1/s].
#pragma once

#include <cstddef>

#include "constants.hpp"
#include "math.hpp"
#include "params.hpp"
#include "sglab_fast.hpp"

namespace sglab {

// Everything of `sglab_min` that depends on κ alone, y folded in:
// Ê = max(0, a + b c + g c²).
template <class T>
struct SglabMinLight {
  T a, b, g;
};

// Per-light setup: one division and three polynomials in y.
template <class T, class S = double>
SglabMinLight<T> sglab_min_light(const T& kappa,
                                 const SglabMinParams<S>& p = constants::sglab_min_float) {
  const T y = T(1) / (kappa + T(p.s));
  return {horner(y, p.a) * y, horner(y, p.b) * y, horner(y, p.g) * y};
}

// Per-shading-point evaluation: two multiply-adds and the clamp.
template <class T>
T sglab_min_eval(const SglabMinLight<T>& light, const T& cosine) {
  return detail::max0_branchless(light.a + cosine * (light.b + cosine * light.g));
}

// `sglab_min`: Ê(c, κ), the two steps above in one call.
template <class T, class S = double>
T irradiance_sglab_min(const T& cosine, const T& kappa,
                       const SglabMinParams<S>& p = constants::sglab_min_float) {
  return sglab_min_eval(sglab_min_light(kappa, p), cosine);
}

// Float batch of `sglab_min`: no library call and no branch, so the loop
// vectorizes as written.
template <class S = double>
SGLAB_FLATTEN void irradiance_sglab_min_batch(
    const float* __restrict cosine, const float* __restrict kappa, float* __restrict out,
    std::size_t n, const SglabMinParams<S>& p = constants::sglab_min_float) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] = sglab_min_eval(sglab_min_light(kappa[i], p), cosine[i]);
}

}  // namespace sglab
