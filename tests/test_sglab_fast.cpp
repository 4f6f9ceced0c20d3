// sglab_fast `sglab_fast` (include/sglab/sglab_fast.hpp): its upper pole and
// pole series, its ramp, and its behaviour outside the fitted range. Its error
// against the reference engine on random points, its per-light split and its
// float batch are checked with every method by tests/test_methods.cpp.
#include <cmath>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "tests/lp_certificate.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;

// The bound on the model's registry card (max peak_rel; its κ range is checked in
// tests/test_kappa_range.cpp).
const double kFastBound =
    sglab::find_method(sglab::irradiance_methods, "sglab_fast")->valid.max_peak_rel;

TEST(SglabFast, UpperPoleWithinBoundAndSeriesMatchesClosedForm) {
  // At c = 1 the model is E(1, κ)·s(1) with s(1) fitted, not forced.
  for (double kappa : {1e-3, 0.1, 0.24, 0.25, 0.26, 2.0, 80.0, 1e4}) {
    const auto light = sglab::sglab_fast_light(kappa);
    const double s = sglab::sglab_fast_eval(light, 1.0);
    const double e1 = sglab::irradiance_upper(kappa);
    EXPECT_NEAR(s / e1, 1.0, kFastBound) << "kappa " << kappa;
  }
  // The series and the closed form of E(1, κ)/2π agree with closed_forms.hpp
  // on both sides of the switch κ = ¼.
  for (double kappa : {1e-3, 0.2499999, 0.25, 0.5, 3.0}) {
    EXPECT_NEAR(sglab::detail::upper_over_two_pi_fast(kappa),
                sglab::irradiance_upper_over_two_pi(kappa), 1e-15);
    EXPECT_NEAR(sglab::detail::upper_over_two_pi_fast(float(kappa)),
                sglab::irradiance_upper_over_two_pi(kappa), 2e-7);
  }
}

TEST(SglabFast, RampIsC1AndLinearAboveOne) {
  using sglab::detail::sglab_ramp;
  EXPECT_EQ(sglab_ramp(-0.5), 0.0);
  EXPECT_EQ(sglab_ramp(0.0), 0.0);
  EXPECT_DOUBLE_EQ(sglab_ramp(1.0), 1.0);
  EXPECT_DOUBLE_EQ(sglab_ramp(3.0), 5.0);
  const double h = 1e-6;
  for (double u : {0.0, 1.0}) {  // one-sided slopes agree at the joints
    const double left = (sglab_ramp(u) - sglab_ramp(u - h)) / h,
                 right = (sglab_ramp(u + h) - sglab_ramp(u)) / h;
    EXPECT_NEAR(left, right, 1e-5) << u;
  }
}

TEST(SglabFast, FiniteAndNonNegativeOutsideTheFittedRange) {
  const float fk[] = {0.0f,  std::numeric_limits<float>::denorm_min(), 1e-30f, 1e-4f, 2e4f, 1e8f,
                      1e30f, std::numeric_limits<float>::max()};
  for (float k : fk)
    for (float c : {-1.0f, -0.3f, 0.0f, 1e-6f, 0.5f, 1.0f}) {
      const float v = sglab::irradiance_sglab_fast(c, k);
      const double d = sglab::irradiance_sglab_fast(double(c), double(k));
      EXPECT_TRUE(std::isfinite(v) && v >= 0)
          << "float kappa " << hex(k) << " c " << hex(c) << " -> " << v;
      EXPECT_TRUE(std::isfinite(d) && d >= 0)
          << "double kappa " << hex(k) << " c " << hex(c) << " -> " << d;
    }
  // κ → 0: the light is uniform, E = π for every normal.
  for (float c : {-1.0f, 0.0f, 1.0f})
    EXPECT_NEAR(sglab::irradiance_sglab_fast(c, 0.0f), M_PI, kFastBound * M_PI) << c;
}

// The fit's residual (fit/fit_sglab_fast.cpp's ModelResidual): peak_rel of the
// runtime function, parameters a, b, c, v (5 each) and q (4).
template <class T>
sglab::SglabFastParams<T> fast_params(const std::vector<T>& v, T kappa_max) {
  sglab::SglabFastParams<T> p{};
  std::size_t i = 0;
  for (auto* poly : {p.a, p.b, p.c, p.v})
    for (std::size_t j = 0; j < 5; ++j) poly[j] = v[i++];
  for (std::size_t j = 0; j < 4; ++j) p.q[j] = v[i++];
  p.kappa_max = kappa_max;
  return p;
}
struct FastResidual {
  double kappa, cosine, reference, peak, kappa_max;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    std::vector<T> v(24);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = p[i][0];
    r[0] = (sglab::irradiance_sglab_fast(T(cosine), T(kappa), fast_params(v, T(kappa_max))) -
            T(reference)) /
           T(peak);
    return true;
  }
};

// The certificate (clamped_lp_certificate in fit/model_family.hpp) of the committed
// coefficients: the check of tests/lp_certificate.hpp, and the numbers the committed set's
// provenance records (its certificate was made at these coefficients).
TEST(SglabFast, CertificateBoundsTheBestNumeratorsAtTheCommittedNonlinearPart) {
  const auto& k = sglab::constants::sglab_fast_float;
  std::vector<double> values;
  for (const auto* poly : {k.a, k.b, k.c, k.v}) values.insert(values.end(), poly, poly + 5);
  values.insert(values.end(), k.q, k.q + 4);
  const auto c = sglab::test::check_clamped_lp_certificate(
      values, 15,
      [&](const sglab::reference::ReferencePoint& r) {
        return sglab::fit::make_residual(
            FastResidual{r.kappa, r.cosine, r.irradiance, sglab::irradiance_upper(r.kappa),
                         k.kappa_max},
            24);
      },
      [&](const std::vector<double>& v, const sglab::reference::ReferencePoint& r) {
        return std::abs(
                   sglab::irradiance_sglab_fast(r.cosine, r.kappa, fast_params(v, k.kappa_max)) -
                   r.irradiance) /
               sglab::irradiance_upper(r.kappa);
      });
  std::ifstream in(SGLAB_TEST_SOURCE_DIR "/../data/constants/sglab-fast-float.json");
  const auto recorded = nlohmann::json::parse(in)["provenance"]["certificate"];
  EXPECT_EQ(c["grid"], recorded["grid"]);
  EXPECT_NEAR(c["achieved"].get<double>(), recorded["achieved"].get<double>(),
              1e-12 * recorded["achieved"].get<double>());
  EXPECT_NEAR(c["lower_bound"].get<double>(), recorded["lower_bound"].get<double>(),
              1e-9 * recorded["lower_bound"].get<double>());
}

}  // namespace
