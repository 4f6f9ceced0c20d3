// sglab_lite (include/sglab/sglab_lite.hpp) and sglab_min (include/sglab/sglab_min.hpp),
// the cheap end of sglab's models: their behaviour outside the fitted range and
// the certificates of their committed coefficients. Their error against the
// reference engine on random points, their per-light splits and float batches
// are checked with every method by tests/test_methods.cpp, their cards to
// κ = FLT_MAX by tests/test_kappa_range.cpp.
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "tests/lp_certificate.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;

double card_bound(const char* id) {
  return sglab::find_method(sglab::irradiance_methods, id)->valid.max_peak_rel;
}

// Finite and ≥ 0 for every κ ≥ 0 a float holds, and E = π for every normal as κ → 0.
template <class F>
void expect_finite_non_negative(const F& f, double bound) {
  const float fk[] = {0.0f,  std::numeric_limits<float>::denorm_min(), 1e-30f, 1e-4f, 2e4f, 1e8f,
                      1e30f, std::numeric_limits<float>::max()};
  for (float k : fk)
    for (float c : {-1.0f, -0.3f, 0.0f, 1e-6f, 0.5f, 1.0f}) {
      const float v = f(c, k);
      const double d = f(double(c), double(k));
      EXPECT_TRUE(std::isfinite(v) && v >= 0)
          << "float kappa " << hex(k) << " c " << hex(c) << " -> " << v;
      EXPECT_TRUE(std::isfinite(d) && d >= 0)
          << "double kappa " << hex(k) << " c " << hex(c) << " -> " << d;
    }
  for (float c : {-1.0f, 0.0f, 1.0f}) EXPECT_NEAR(f(c, 0.0f), M_PI, bound * M_PI) << c;
}

TEST(SglabLite, FiniteAndNonNegativeOutsideTheFittedRange) {
  expect_finite_non_negative([](auto c, auto k) { return sglab::irradiance_sglab_lite(c, k); },
                             card_bound("sglab_lite"));
}

TEST(SglabMin, FiniteAndNonNegativeOutsideTheFittedRange) {
  expect_finite_non_negative([](auto c, auto k) { return sglab::irradiance_sglab_min(c, k); },
                             card_bound("sglab_min"));
}

// As κ → ∞ the form tends to y·max(0, a0 + b0 c + g0 c²), y = 1/(κ + s): at
// κ = FLT_MAX (y a subnormal float) the float runtime agrees with that limit.
TEST(SglabMin, ReachesItsLimitAtTheLargestFloat) {
  const auto& p = sglab::constants::sglab_min_float;
  const float k = std::numeric_limits<float>::max();
  for (float c : {-1.0f, 0.0f, 0.5f, 1.0f}) {
    const double shape = p.a[0] + c * (p.b[0] + c * p.g[0]);
    const double limit = std::max(shape, 0.0) / double(k);
    EXPECT_NEAR(sglab::irradiance_sglab_min(c, k), limit, 1e-5 * sglab::irradiance_upper(double(k)))
        << c;
  }
}

// The fits' residuals (fit/fit_sglab_fast.cpp's sglab-lite, fit/fit_sglab_min.cpp):
// peak_rel of the runtime function with every coefficient a parameter.
template <class T>
sglab::SglabLiteParams<T> lite_params(const std::vector<T>& v, T kappa_max) {
  sglab::SglabLiteParams<T> p{};
  std::size_t i = 0;
  for (auto* poly : {p.a, p.b, p.c, p.v})
    for (std::size_t j = 0; j < 5; ++j) poly[j] = v[i++];
  for (std::size_t j = 0; j < 4; ++j) p.q[j] = v[i++];
  p.kappa_max = kappa_max;
  return p;
}
template <class T>
sglab::SglabMinParams<T> min_params(const std::vector<T>& v) {
  sglab::SglabMinParams<T> p{};
  std::size_t i = 0;
  for (std::size_t j = 0; j < 3; ++j) p.a[j] = v[i++];
  for (std::size_t j = 0; j < 2; ++j) p.b[j] = v[i++];
  for (std::size_t j = 0; j < 2; ++j) p.g[j] = v[i++];
  p.s = v[i];
  return p;
}
struct LiteResidual {
  double kappa, cosine, reference, peak, kappa_max;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    std::vector<T> v(24);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = p[i][0];
    r[0] = (sglab::irradiance_sglab_lite(T(cosine), T(kappa), lite_params(v, T(kappa_max))) -
            T(reference)) /
           T(peak);
    return true;
  }
};
struct MinResidual {
  double kappa, cosine, reference, peak;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    std::vector<T> v(8);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = p[i][0];
    r[0] =
        (sglab::irradiance_sglab_min(T(cosine), T(kappa), min_params(v)) - T(reference)) / T(peak);
    return true;
  }
};

nlohmann::json recorded_certificate(const char* file) {
  std::ifstream in(std::string(SGLAB_TEST_SOURCE_DIR "/../data/constants/") + file);
  return nlohmann::json::parse(in)["provenance"]["certificate"];
}

// The certificates (clamped_lp_certificate in fit/model_family.hpp) of the committed
// coefficients: the check of tests/lp_certificate.hpp, and the numbers each committed set's
// provenance records (made at these coefficients).
TEST(SglabLite, CertificateBoundsTheBestNumeratorsAtTheCommittedNonlinearPart) {
  const auto& k = sglab::constants::sglab_lite_float;
  std::vector<double> values;
  for (const auto* poly : {k.a, k.b, k.c, k.v}) values.insert(values.end(), poly, poly + 5);
  values.insert(values.end(), k.q, k.q + 4);
  const auto c = sglab::test::check_clamped_lp_certificate(
      values, 15,
      [&](const sglab::reference::ReferencePoint& r) {
        return sglab::fit::make_residual(
            LiteResidual{r.kappa, r.cosine, r.irradiance, sglab::irradiance_upper(r.kappa),
                         k.kappa_max},
            24);
      },
      [&](const std::vector<double>& v, const sglab::reference::ReferencePoint& r) {
        return std::abs(
                   sglab::irradiance_sglab_lite(r.cosine, r.kappa, lite_params(v, k.kappa_max)) -
                   r.irradiance) /
               sglab::irradiance_upper(r.kappa);
      });
  const auto recorded = recorded_certificate("sglab-lite-float.json");
  EXPECT_EQ(c["grid"], recorded["grid"]);
  EXPECT_NEAR(c["achieved"].get<double>(), recorded["achieved"].get<double>(),
              1e-12 * recorded["achieved"].get<double>());
  EXPECT_NEAR(c["lower_bound"].get<double>(), recorded["lower_bound"].get<double>(),
              1e-9 * recorded["lower_bound"].get<double>());
}

TEST(SglabMin, CertificateBoundsTheBestCoefficientsAtTheCommittedS) {
  const auto& k = sglab::constants::sglab_min_float;
  std::vector<double> values;
  values.insert(values.end(), k.a, k.a + 3);
  values.insert(values.end(), k.b, k.b + 2);
  values.insert(values.end(), k.g, k.g + 2);
  values.push_back(k.s);
  const auto c = sglab::test::check_clamped_lp_certificate(
      values, 7,
      [&](const sglab::reference::ReferencePoint& r) {
        return sglab::fit::make_residual(
            MinResidual{r.kappa, r.cosine, r.irradiance, sglab::irradiance_upper(r.kappa)}, 8);
      },
      [&](const std::vector<double>& v, const sglab::reference::ReferencePoint& r) {
        return std::abs(sglab::irradiance_sglab_min(r.cosine, r.kappa, min_params(v)) -
                        r.irradiance) /
               sglab::irradiance_upper(r.kappa);
      },
      {1e5, 1e6, 1e8, 1e20});
  const auto recorded = recorded_certificate("sglab-min-float.json");
  EXPECT_EQ(c["grid"], recorded["grid"]);
  EXPECT_NEAR(c["achieved"].get<double>(), recorded["achieved"].get<double>(),
              1e-12 * recorded["achieved"].get<double>());
  EXPECT_NEAR(c["lower_bound"].get<double>(), recorded["lower_bound"].get<double>(),
              1e-9 * recorded["lower_bound"].get<double>());
}

}  // namespace
