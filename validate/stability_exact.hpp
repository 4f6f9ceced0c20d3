// validate/stability_exact.hpp — the exact values the stability probes are
// judged against (`inaccurate`, and overflow of the exact result), in long
// double: the SG product quantities and the closed forms of docs/quantities.md.
#pragma once

#include <cmath>

#include <sglab/math.hpp>
#include <sglab/params.hpp>

namespace sglab::validate::stability_detail {

// Exact product quantities in long double (docs/quantities.md; [Tokuyoshi2022] Eq. 1-2):
// κ3 = |κ1 v1 + κ2 v2|, log-amplitude κ3 − κ1 − κ2 = −κ1κ2|v1 − v2|²/(κ3 + κ1 + κ2).
// |κ1v1 + κ2v2|² = (κ1 − κ2)(κ1|v1|² − κ2|v2|²) + κ1κ2|v1 + v2|², an identity
// that does not cancel for nearly opposite axes and nearly equal κ.
template <class T>
long double exact_product_sharpness(const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
  using L = long double;
  const L a2 = L(a.x) * a.x + L(a.y) * a.y + L(a.z) * a.z,
          b2 = L(b.x) * b.x + L(b.y) * b.y + L(b.z) * b.z;
  const L sx = L(a.x) + b.x, sy = L(a.y) + b.y, sz = L(a.z) + b.z;
  const L s = (L(k1) - k2) * (L(k1) * a2 - L(k2) * b2) + L(k1) * k2 * (sx * sx + sy * sy + sz * sz);
  return std::sqrt(s > 0 ? s : L(0));
}
template <class T>
long double exact_product_log_amplitude(const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
  using L = long double;
  const L dx = L(a.x) - b.x, dy = L(a.y) - b.y, dz = L(a.z) - b.z;
  const L den = exact_product_sharpness(a, k1, b, k2) + L(k1) + L(k2);
  return den > 0 ? -L(k1) * L(k2) * (dx * dx + dy * dy + dz * dz) / den : L(0);
}
template <class T>
long double exact_normal_product_sharpness(T c, T k, T l) {
  using L = long double;
  const L s = (L(k) - l) * (L(k) - l) + 2 * L(k) * l * (1 + L(c));  // (κ − λ)² + 2κλ(1 + c)
  return std::sqrt(s > 0 ? s : L(0));
}
template <class T>
long double exact_normal_product_log_amplitude(T c, T k, T l) {
  using L = long double;
  const L den = exact_normal_product_sharpness(c, k, l) + L(k) + L(l);
  return den > 0 ? -2 * (1 - L(c)) * L(k) * L(l) / den : L(0);
}

// Exact closed forms of docs/quantities.md in long double, for κ ≥ 0 (series near 0,
// where long double would cancel too).
using L = long double;
inline constexpr L kPiL = 3.141592653589793238462643383279502884L;
inline L exact_expm1_over_minus(L k) {
  return k == 0 ? L(1) : -std::expm1(-k) / k;
}  // (1 − e^{−κ})/κ
inline L exact_sphere_integral(L k) { return 4 * kPiL * exact_expm1_over_minus(2 * k); }
inline L exact_upper_over_two_pi(L k) {  // (κ − 1 + e^{−κ})/κ²
  if (k < L(1e-2)) return L(1) / 2 - k / 6 + k * k / 24 - k * k * k / 120 + k * k * k * k / 720;
  return (k - 1 + std::exp(-k)) / (k * k);
}
inline L exact_lower_over_two_pi(L k) {  // e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ²
  if (k < L(1e-2))
    return std::exp(-k) *
           (L(1) / 2 - 2 * k / 6 + 3 * k * k / 24 - 4 * k * k * k / 120 + 5 * k * k * k * k / 720);
  const L e = std::exp(-k);
  return e * (1 - e - k * e) / (k * k);
}
template <class S>
L exact_steepness2022(L k, const Steepness2022Params<S>& p) {
  return k * std::sqrt((L(0.5) * k + L(p.A)) / ((k + L(p.B)) * k + L(p.C)));
}
template <class S>
L exact_steepness2024(L k, const Steepness2024Params<S>& p) {
  return k * std::sqrt(L(0.5) * ((k + L(p.A)) * k + L(p.B)) /
                       (((k + L(p.C)) * k + L(p.D)) * k + L(p.E)));
}

}  // namespace sglab::validate::stability_detail
