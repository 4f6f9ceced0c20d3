#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/closed_forms.hpp>
#include <sglab/constants.hpp>
#include <sglab/erf.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/irradiance.hpp>
#include <sglab/registry.hpp>
#include <sglab/sg.hpp>

#include "validate/stability.hpp"
#include "validate/stability_exact.hpp"
#include "validate/stability_probe.hpp"

// The catalogue of the stability table: every probed function with its
// documented range and, where there is one, its exact value, in a fixed order.

namespace sglab::validate {
namespace {

using namespace stability_detail;

constexpr Origin own = Origin::sglab, pub = Origin::published;

// SG primitives (sg.hpp).
template <class T>
void probe_sg_primitives(Runner<T>& r) {
  r.cosine_kappa(
      "sg_evaluate(c, κ)", own, kUnit, [](T c, T k) { return sg_evaluate(c, k); },
      [](T c, T k) { return std::exp(L(k) * (L(c) - 1)); });
  r.axes_kappa("sg_evaluate(ω, v, κ)", own, kUnit,
               [](const Vec3<T>& w, const Vec3<T>& v, T k) { return sg_evaluate(w, v, k); });
  r.kappa_only(
      "sphere_integral", own, kFourPi, [](T k) { return sphere_integral(k); },
      [](T k) { return exact_sphere_integral(k); });
  r.kappa_only("sphere_integral_approx", pub, kFourPi,
               [](T k) { return sphere_integral_approx(k); });
  r.approximation();
  r.kappa_only(
      "expm1_over_x(-κ)", own, kUnit, [](T k) { return expm1_over_x(-k); },
      [](T k) { return exact_expm1_over_minus(k); });
  r.axes_two_kappas(
      "sg_product.sharpness", own, kNonNegative,
      [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
        return sg_product(a, k1, b, k2).sharpness;
      },
      exact_product_sharpness<T>);
  r.axes_two_kappas(
      "sg_product.log_amplitude", own, kNonPositive,
      [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
        return sg_product(a, k1, b, k2).log_amplitude;
      },
      exact_product_log_amplitude<T>);
  r.axes_two_kappas("sg_product.axis_length", own, kUnitLength,
                    [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
                      return length(sg_product(a, k1, b, k2).axis);
                    });
  r.cosine_two_kappas(
      "sg_product_with_normal.sharpness", own, kNonNegative,
      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).sharpness; },
      exact_normal_product_sharpness<T>);
  r.cosine_two_kappas(
      "sg_product_with_normal.log_amplitude", own, kNonPositive,
      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).log_amplitude; },
      exact_normal_product_log_amplitude<T>);
  r.cosine_two_kappas("sg_product_with_normal.cosine", own, kSigned,
                      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).cosine; });
  r.cosine_two_kappas(
      "sg_inner_product", own, kFourPi, [](T c, T k1, T k2) { return sg_inner_product(c, k1, k2); },
      [](T c, T k1, T k2) {
        return std::exp(exact_normal_product_log_amplitude(c, k1, k2)) *
               exact_sphere_integral(exact_normal_product_sharpness(c, k1, k2));
      });
  r.cosine_two_kappas("sg_inner_product_iwasaki", pub, kFourPi,
                      [](T c, T k1, T k2) { return sg_inner_product_iwasaki(c, k1, k2); });
  r.approximation();
}

// Closed forms (closed_forms.hpp).
template <class T>
void probe_closed_forms(Runner<T>& r) {
  r.kappa_only(
      "irradiance_upper", own, kPi, [](T k) { return irradiance_upper(k); },
      [](T k) { return 2 * kPiL * exact_upper_over_two_pi(k); });
  r.kappa_only(
      "irradiance_lower", own, kPi, [](T k) { return irradiance_lower(k); },
      [](T k) { return 2 * kPiL * exact_lower_over_two_pi(k); });
  r.kappa_only(
      "irradiance_upper_over_two_pi", own, kHalf,
      [](T k) { return irradiance_upper_over_two_pi(k); },
      [](T k) { return exact_upper_over_two_pi(k); });
  r.kappa_only(
      "irradiance_lower_over_two_pi", own, kHalf,
      [](T k) { return irradiance_lower_over_two_pi(k); },
      [](T k) { return exact_lower_over_two_pi(k); });
  r.kappa_only(
      "hemispherical_upper", own, kTwoPi, [](T k) { return hemispherical_upper(k); },
      [](T k) { return 2 * kPiL * exact_expm1_over_minus(k); });
  r.kappa_only(
      "hemispherical_lower", own, kTwoPi, [](T k) { return hemispherical_lower(k); },
      [](T k) { return std::exp(-L(k)) * 2 * kPiL * exact_expm1_over_minus(k); });
  r.kappa_only(
      "hemispherical_equator", own, kTwoPi, [](T k) { return hemispherical_equator(k); },
      [](T k) { return exact_sphere_integral(k) / 2; });
}

// The reference engine, exact at the poles and (H, s) on the horizon.
template <class T>
void probe_reference(Runner<T>& r) {
  const auto nan_l = std::numeric_limits<L>::quiet_NaN();
  r.reference(
      "reference/hemispherical", kTwoPi,
      [](const reference::ReferencePoint& q) { return q.hemispherical; },
      [nan_l](T c, T k) {
        if (c == T(1)) return 2 * kPiL * exact_expm1_over_minus(k);
        if (c == T(-1)) return std::exp(-L(k)) * 2 * kPiL * exact_expm1_over_minus(k);
        if (c == T(0)) return exact_sphere_integral(k) / 2;
        return nan_l;
      });
  r.reference(
      "reference/irradiance", kPi, [](const reference::ReferencePoint& q) { return q.irradiance; },
      [nan_l](T c, T k) {
        if (c == T(1)) return 2 * kPiL * exact_upper_over_two_pi(k);
        if (c == T(-1)) return 2 * kPiL * exact_lower_over_two_pi(k);
        return nan_l;
      });
  r.reference(
      "reference/normalized", kUnit,
      [](const reference::ReferencePoint& q) { return q.normalized; },
      [nan_l](T c, T k) {
        if (c == T(1)) return L(1);
        if (c == T(-1)) return L(0);
        if (c != T(0)) return nan_l;
        // s(0, κ) = (S/2 − H(−1))/(H(1) − H(−1)) = ½ + O(κ); the difference
        // form loses ~ε_L/κ in long double, so below κ = 1e−6 take ½.
        if (L(k) < L(1e-6)) return L(0.5);
        const L h1 = exact_expm1_over_minus(k), hm1 = std::exp(-L(k)) * h1;
        return (exact_sphere_integral(k) / (4 * kPiL) - hm1) / (h1 - hm1);
      });
}

// Steepness functions and erf-based pieces (hemispherical.hpp, irradiance.hpp),
// and the erf variants.
template <class T>
void probe_steepness_and_erf(Runner<T>& r) {
  r.kappa_only(
      "steepness2022", own, kNonNegative, [](T k) { return steepness2022(k); },
      [](T k) { return exact_steepness2022(k, constants::steepness2022_published); });
  r.approximation();
  r.kappa_only(
      "steepness2024", own, kNonNegative, [](T k) { return steepness2024(k); },
      [](T k) { return exact_steepness2024(k, constants::steepness2024_published); });
  r.approximation();
  r.kappa_only("steepness_meder2018", pub, kNonNegative,
               [](T k) { return steepness_meder2018(k); });
  r.approximation();
  r.cosine_kappa("erf_ratio(t, c)", own, kSigned, [](T c, T t) { return erf_ratio(t, c); });
  r.cosine_kappa("lerp_factor_tokuyoshi2024", own, kUnit,
                 [](T c, T k) { return lerp_factor_tokuyoshi2024(c, k); });
  r.approximation();

  // erf variants.
  for (const ErfVariant& v : erf_variants) {
    const auto f = v;
    r.real_line(fmt::format("erf/{}", v.id), pub, kSigned, [f](T x) {
      if constexpr (sizeof(T) == sizeof(float))
        return f.f32(x);
      else
        return f.f64(x);
    });
    r.approximation();
  }
}

// Every registered method, each labelled with the registry's origin (Method::origin).
template <class T>
void probe_methods(Runner<T>& r) {
  const auto call = [](const Method& m) {
    return [m](T c, T k) {
      if constexpr (sizeof(T) == sizeof(float))
        return m.f32(c, k);
      else
        return m.f64(c, k);
    };
  };
  for (const Method& m : normalized_methods) {
    r.cosine_kappa(fmt::format("normalized/{}", m.id), m.origin, kUnit, call(m));
    r.approximation();
  }
  for (const Method& m : hemispherical_methods) {
    r.cosine_kappa(fmt::format("hemispherical/{}", m.id), m.origin, kTwoPi, call(m));
    r.approximation();
  }
  for (const Method& m : irradiance_methods) {
    r.cosine_kappa(fmt::format("irradiance/{}", m.id), m.origin, kPi, call(m));
    r.approximation();
  }
}

// Every probe, in a fixed order, for precision T.
template <class T>
std::vector<StabilityRow> run_all(std::vector<double>& kappas, std::vector<double>& cosines) {
  Runner<T> r;
  for (T k : r.kappas()) kappas.push_back(static_cast<double>(k));
  for (T c : r.cosines()) cosines.push_back(static_cast<double>(c));
  probe_sg_primitives(r);
  probe_closed_forms(r);
  probe_reference(r);
  probe_steepness_and_erf(r);
  probe_methods(r);
  return std::move(r.rows);
}

}  // namespace

StabilityReport stability() {
  StabilityReport report;
  auto f = run_all<float>(report.kappas_float, report.cosines_float);
  auto d = run_all<double>(report.kappas_double, report.cosines_double);
  // Interleave: per function, float (valid, invalid) then double (valid, invalid).
  for (std::size_t i = 0; i + 1 < f.size() && i + 1 < d.size(); i += 2) {
    report.rows.push_back(std::move(f[i]));
    report.rows.push_back(std::move(f[i + 1]));
    report.rows.push_back(std::move(d[i]));
    report.rows.push_back(std::move(d[i + 1]));
  }
  return report;
}

}  // namespace sglab::validate
