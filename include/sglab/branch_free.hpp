// sglab/branch_free.hpp — branch-free float elementary functions for batch
// kernels that the compiler can vectorize.
//
// A loop over the standard library's expf/erfcf/expm1f does not vectorize:
// each is an opaque call (that may set errno), and with the default
// -ftrapping-math GCC will not if-convert `a < b ? x : y` on floats either.
// Everything here is straight-line arithmetic on float (FMAs, one division,
// integer bit operations for 2^n and for selects), so a loop of inlined calls
// vectorizes under the default flags (-O3, no -ffast-math, no -fno-math-errno)
// at whatever vector width the target has (4 floats with the x86-64 baseline
// SSE2). Standard library only (std::bit_cast), like the rest of the runtime.
//
// Accuracy (float, measured against double in tests/test_branch_free.cpp):
//   exp_bf(x), x ≤ 88        relative ≤ 2 ulp; 0 below −87.3 (no subnormals)
//   expm1_bf(x), x ≤ 0       relative ≤ 3 ulp
//   erfc_bf(x), any x        absolute ≤ 6e−7 ([AS1964] 7.1.26 is within 1.5e−7;
//                            evaluated in float it loses up to 4e−7 more near
//                            x = 0, where its polynomial cancels; ≤ 3e−7 for |x| ≥ 0.75)
//   sqrt_bf(y), y ≥ 0        relative ≤ 1 ulp
// erfc_bf is accurate in the absolute sense only (as a weight in [0, 2]): it
// is meant for sums such as the clamped-cosine interpolation of
// [Tokuyoshi2024], where an absolute error of e becomes at most e of the peak.
#pragma once

#include <bit>
#include <cstdint>

#include "math.hpp"  // SGLAB_FORCE_INLINE, SGLAB_FLATTEN

namespace sglab::branch_free {

// m ? a : b without a branch (bitwise select on the IEEE representation).
SGLAB_FORCE_INLINE float select(bool m, float a, float b) {
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(m);
  return std::bit_cast<float>((std::bit_cast<std::uint32_t>(a) & mask) |
                              (std::bit_cast<std::uint32_t>(b) & ~mask));
}
SGLAB_FORCE_INLINE float min(float a, float b) { return select(b < a, b, a); }
SGLAB_FORCE_INLINE float max(float a, float b) { return select(a < b, b, a); }
SGLAB_FORCE_INLINE float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }

// Round to the nearest integer (ties to even), |x| < 2^22.
SGLAB_FORCE_INLINE float round_nearest(float x) {
  const float shifter = 12582912.0f;  // 1.5 · 2^23
  return (x + shifter) - shifter;
}

// √y for y ≥ 0: 1/√y from the bit-level initial guess, two Newton steps, then
// one Newton step on √y itself (error below 1 ulp). √0 = 0.
SGLAB_FORCE_INLINE float sqrt_bf(float y) {
  float r = std::bit_cast<float>(0x5f3759dfu - (std::bit_cast<std::uint32_t>(y) >> 1));
  const float h = 0.5f * y;
  r = r * (1.5f - h * r * r);
  r = r * (1.5f - h * r * r);
  const float s = y * r;
  return s + 0.5f * r * (y - s * s);
}

// The Taylor polynomials of e^r (degree 7: 1/k!, k = 0 … 7) and of
// (e^x − 1)/x (degree 7: 1/(k + 1)!), coefficients lowest order first (horner).
inline constexpr float kExpTaylor[] = {1.0f,         1.0f,          0.5f,          1.0f / 6.0f,
                                       1.0f / 24.0f, 1.0f / 120.0f, 1.0f / 720.0f, 1.0f / 5040.0f};
inline constexpr float kExpm1Taylor[] = {1.0f,           0.5f,           1.0f / 6.0f,
                                         1.0f / 24.0f,   1.0f / 120.0f,  1.0f / 720.0f,
                                         1.0f / 5040.0f, 1.0f / 40320.0f};

// e^x for x ≤ 88: x = n ln2 + r with |r| ≤ ln2/2 (Cody–Waite, two-part ln2),
// e^r by its Taylor polynomial of degree 7 (truncation < 6e−9), times 2^n
// built in the exponent bits. Below −87.3 the result is 0.
SGLAB_FORCE_INLINE float exp_bf(float x) {
  const float xc = clamp(x, -87.0f, 88.0f);
  const float n = round_nearest(xc * 1.44269504088896341f);
  const float r = (xc - n * 0.693145751953125f) - n * 1.428606765330187e-6f;
  const float p = horner(r, kExpTaylor);
  const std::int32_t e = static_cast<std::int32_t>(n) + 127;
  const float scale = std::bit_cast<float>(static_cast<std::uint32_t>(e) << 23);
  return select(x < -87.0f, 0.0f, p * scale);
}

// e^x − 1 for x ≤ 0 with a relative error of a few ulp: the Taylor series
// x(1 + x/2 + … + x^7/8!) for x > −ln2/2 (truncation < 2e−8), e^x − 1
// below (where e^x − 1 ≤ −0.29, so the subtraction costs at most 2 bits).
SGLAB_FORCE_INLINE float expm1_bf(float x) {
  return select(x > -0.34657359f, horner(x, kExpm1Taylor) * x, exp_bf(x) - 1.0f);
}

// erfc(x) from |x| and e^{−x²} (passed in so that a caller that needs e^{−x²}
// anyway pays for it once): [AS1964] 7.1.26,
// erfc(|x|) ≈ (a1 u + a2 u² + … + a5 u⁵) e^{−x²}, u = 1/(1 + p|x|), |ε| ≤ 1.5e−7;
// erfc(−|x|) = 2 − erfc(|x|).
SGLAB_FORCE_INLINE float erfc_bf(float x, float exp_minus_x2) {
  const float a = select(x < 0.0f, -x, x);
  const float u = 1.0f / (1.0f + 0.3275911f * a);
  float p = 1.061405429f;
  p = p * u - 1.453152027f;
  p = p * u + 1.421413741f;
  p = p * u - 0.284496736f;
  p = p * u + 0.254829592f;
  const float y = p * u * exp_minus_x2;
  return select(x < 0.0f, 2.0f - y, y);
}
SGLAB_FORCE_INLINE float erfc_bf(float x) { return erfc_bf(x, exp_bf(-x * x)); }

}  // namespace sglab::branch_free
