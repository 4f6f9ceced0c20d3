#include <cmath>
#include <limits>
#include <vector>

#include <sglab/constants.hpp>

#include "validate/stability_probe.hpp"

namespace sglab::validate {

std::vector<double> method_sharpness_constants() {
  // The sharpness of the SG each method multiplies the light by (κ = λ is
  // where the product with it has κ3 = 0 at c = −1), read from the constant
  // sets the methods use: the cosine lobe of wang2009 and its refit, the
  // diffuse lobe λd of vsgl2015 and its refits, Meder's cosine-fit λm, and the
  // clamped-cosine λ of tokuyoshi2022 and its refits.
  return {constants::cosine_lobe_published.lambda,
          constants::lambda_d_cosine_lobe_free_amplitude.lambda,
          constants::diffuse_lobe_published.lambda_d,
          constants::lambda_d_diffuse_lobe_irradiance.lambda_d,
          constants::lambda_d_diffuse_lobe_hemisphere_ls.lambda_d,
          constants::lambda_d_diffuse_lobe_sphere_ls.lambda_d,
          constants::meder2018_published.sharpness,
          constants::clamped_cosine_published.lambda,
          constants::clamped_cosine_float.lambda,
          constants::clamped_cosine_float_alpha_free.lambda,
          constants::clamped_cosine_double.lambda,
          constants::clamped_cosine_half.lambda};
}

namespace stability_detail {

template <class T>
std::vector<T> probe_kappas() {
  const double list[] = {-1,   0,    1e-30, 1e-6, 1e-3,  1e-2,  0.1,  0.2, 0.3, 0.4,
                         0.5,  0.6,  0.7,   0.8,  1,     2,     5,    10,  20,  50,
                         88,   89,   100,   700,  710,   1e3,   1e4,  1e5, 1e6, 1e10,
                         1e15, 1e20, 1e30,  1e38, 1e100, 1e200, 1e300};
  std::vector<T> out;
  // Every binade of the subnormals, 2^e from the smallest subnormal up to the
  // smallest normal, and the largest subnormal.
  for (int e = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits;
       e < std::numeric_limits<T>::min_exponent; ++e)
    out.push_back(std::ldexp(T(1), e));
  out.push_back(std::numeric_limits<T>::min() - std::numeric_limits<T>::denorm_min());
  for (double v : list) {
    const T t = static_cast<T>(v);
    if (std::isfinite(t)) out.push_back(t);
  }
  for (double v : method_sharpness_constants()) out.push_back(static_cast<T>(v));
  out.push_back(std::numeric_limits<float>::max());
  if constexpr (sizeof(T) > sizeof(float)) out.push_back(std::numeric_limits<double>::max());
  out.push_back(std::numeric_limits<T>::infinity());
  out.push_back(std::numeric_limits<T>::quiet_NaN());
  return out;
}

template <class T>
std::vector<T> probe_cosines() {
  const T one(1);
  return {T(-1) - T(0x1p-10),
          std::nextafter(-one, T(-2)),
          T(-1),
          std::nextafter(-one, T(0)),
          T(-0.5),
          T(-0.0),
          T(0),
          T(0.5),
          std::nextafter(one, T(0)),
          T(1),
          std::nextafter(one, T(2)),
          T(1) + T(0x1p-10),
          std::numeric_limits<T>::quiet_NaN()};
}

template <class T>
std::vector<AxisPair<T>> probe_axes() {
  using std::sqrt;
  const T z0(0), o(1);
  const Vec3<T> z{z0, z0, o}, x{o, z0, z0};
  const T d = sizeof(T) == sizeof(float) ? T(0x1p-12) : T(0x1p-26);
  const T s = T(0.70710678118654752440L);
  const T nan = std::numeric_limits<T>::quiet_NaN();
  return {
      {"same", z, z, true},
      {"orthogonal", z, x, true},
      {"opposite", z, Vec3<T>{z0, z0, -o}, true},
      {"nearly opposite", z, Vec3<T>{d, z0, -sqrt(o - d * d)}, true},
      {"45 degrees", z, Vec3<T>{s, z0, s}, true},
      {"generic", Vec3<T>{T(0.36), T(0.48), T(0.8)}, Vec3<T>{T(0.6), z0, T(-0.8)}, true},
      {"non-unit (2x)", z, Vec3<T>{z0, z0, T(2)}, false},
      {"non-unit opposite (2x)", z, Vec3<T>{z0, z0, T(-2)}, false},
      {"non-unit (0.5x) orthogonal", z, Vec3<T>{T(0.5), z0, z0}, false},
      {"zero axis", z, Vec3<T>{z0, z0, z0}, false},
      {"NaN axis", z, Vec3<T>{nan, z0, z0}, false},
  };
}

template std::vector<float> probe_kappas<float>();
template std::vector<double> probe_kappas<double>();
template std::vector<float> probe_cosines<float>();
template std::vector<double> probe_cosines<double>();
template std::vector<AxisPair<float>> probe_axes<float>();
template std::vector<AxisPair<double>> probe_axes<double>();

}  // namespace stability_detail
}  // namespace sglab::validate
