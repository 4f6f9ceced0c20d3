// sglab_mid `sglab_mid` (include/sglab/sglab_mid.hpp): its error against the
// reference engine on points no fit used, never NaN at the edges, its per-light
// split against the fused function, its float batch against the scalar path.
// tests/test_methods.cpp checks it with every method as well.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "reference/reference.hpp"
#include "tests/lp_certificate.hpp"
#include "tests/random_points.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;

// The bound on the model's registry card (max peak_rel; its κ range is checked in
// tests/test_kappa_range.cpp).
const double kMidBound =
    sglab::find_method(sglab::irradiance_methods, "sglab_mid")->valid.max_peak_rel;

TEST(SglabMid, WithinBoundOnPointsNoFitUsed) {
  // Random points (another seed than test_methods.cpp's) and the poles.
  auto q = sglab::test::random_points(4000, 17004);
  for (double k : {1e-3, 0.25, 1.0, 30.0, 1e4})
    for (double c : {-1.0, 0.0, 1.0}) q.push_back({k, c});
  const auto ref = sglab::reference::reference_engine().evaluate(q);
  double worst_f = 0, worst_d = 0;
  for (const auto& r : ref) {
    const double peak = sglab::irradiance_upper(r.kappa);
    const double ef =
        std::abs(double(sglab::irradiance_sglab_mid(float(r.cosine), float(r.kappa))) -
                 r.irradiance) /
        peak;
    const double ed =
        std::abs(sglab::irradiance_sglab_mid(r.cosine, r.kappa) - r.irradiance) / peak;
    worst_f = std::max(worst_f, ef), worst_d = std::max(worst_d, ed);
    EXPECT_LE(ef, kMidBound) << "float kappa " << r.kappa << " c " << r.cosine;
    EXPECT_LE(ed, kMidBound) << "double kappa " << r.kappa << " c " << r.cosine;
  }
  RecordProperty("max_peak_rel_float", std::to_string(worst_f));
  RecordProperty("max_peak_rel_double", std::to_string(worst_d));
}

TEST(SglabMid, SplitEqualsFusedAndBatchMatchesScalar) {
  const auto q = sglab::test::random_points(2000, 17005);
  std::vector<float> cs, ks, out(q.size());
  for (const auto& p : q) cs.push_back(float(p.cosine)), ks.push_back(float(p.kappa));
  sglab::irradiance_sglab_mid_batch(cs.data(), ks.data(), out.data(), q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    const float fused = sglab::irradiance_sglab_mid(cs[i], ks[i]);
    // The same operations in the same order: bit for bit.
    EXPECT_EQ(sglab::sglab_mid_eval(sglab::sglab_mid_light(ks[i]), cs[i]), fused)
        << "kappa " << hex(ks[i]) << " c " << hex(cs[i]);
    // branch_free.hpp's exp and square root: float rounding of the peak.
    EXPECT_NEAR(out[i], fused, 2e-6 * sglab::irradiance_upper(double(ks[i])))
        << "kappa " << hex(ks[i]) << " c " << hex(cs[i]);
  }
}

TEST(SglabMid, FiniteAndNonNegativeOutsideTheFittedRange) {
  const float fk[] = {0.0f,  std::numeric_limits<float>::denorm_min(), 1e-30f, 1e-4f, 2e4f, 1e8f,
                      1e30f, std::numeric_limits<float>::max()};
  for (float k : fk)
    for (float c : {-1.0f, -0.3f, -1e-20f, 0.0f, 1e-20f, 1e-6f, 0.5f, 1.0f}) {
      const float v = sglab::irradiance_sglab_mid(c, k);
      const double d = sglab::irradiance_sglab_mid(double(c), double(k));
      float b = 0;
      sglab::irradiance_sglab_mid_batch(&c, &k, &b, 1);
      EXPECT_TRUE(std::isfinite(v) && v >= 0)
          << "float kappa " << hex(k) << " c " << hex(c) << " -> " << v;
      EXPECT_TRUE(std::isfinite(d) && d >= 0)
          << "double kappa " << hex(k) << " c " << hex(c) << " -> " << d;
      EXPECT_TRUE(std::isfinite(b) && b >= 0)
          << "batch kappa " << hex(k) << " c " << hex(c) << " -> " << b;
    }
  // κ → 0: the light is uniform, E = π for every normal.
  for (float c : {-1.0f, 0.0f, 1.0f})
    EXPECT_NEAR(sglab::irradiance_sglab_mid(c, 0.0f), M_PI, kMidBound * M_PI) << c;
}

TEST(SglabMid, SoftMaxStaysFiniteAtTheExponentBounds) {
  using sglab::detail::sglab_mid_soft_max2;
  // The exponent is clamped to [−80, 80]: e^{−80} > 0 keeps the square root's
  // argument positive at c = 0, e^{80} stays finite in float.
  for (float s : {-1e30f, -200.0f, 0.0f, 200.0f, 1e30f})
    for (float c : {-1.0f, 0.0f, 1.0f}) {
      const float y = sglab_mid_soft_max2(c, s, 0.0f);
      EXPECT_TRUE(std::isfinite(y) && y >= 0) << "s " << s << " c " << c << " -> " << y;
      if (c == 0.0f) {
        EXPECT_GT(y, 0.0f) << "s " << s;
      }
    }
  // Far below the bound it is 2 max(c, 0) to rounding.
  EXPECT_EQ(sglab_mid_soft_max2(0.5, -70.0, 0.0), 1.0);
  EXPECT_EQ(sglab_mid_soft_max2(-0.5, -70.0, 0.0), 0.0);
}

// The fit's residual (fit/fit_sglab_mid.cpp's ModelResidual): peak_rel of the
// runtime function, parameters a, b, d, s, v (5 each) and q (4).
template <class T>
sglab::SglabMidParams<T> mid_params(const std::vector<T>& v, T kappa_max) {
  sglab::SglabMidParams<T> p{};
  std::size_t i = 0;
  for (auto* poly : {p.a, p.b, p.d, p.s, p.v})
    for (std::size_t j = 0; j < 5; ++j) poly[j] = v[i++];
  for (std::size_t j = 0; j < 4; ++j) p.q[j] = v[i++];
  p.kappa_max = kappa_max;
  return p;
}
struct MidResidual {
  double kappa, cosine, reference, peak, kappa_max;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    std::vector<T> v(29);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = p[i][0];
    r[0] = (sglab::irradiance_sglab_mid(T(cosine), T(kappa), mid_params(v, T(kappa_max))) -
            T(reference)) /
           T(peak);
    return true;
  }
};

// The certificate (clamped_lp_certificate in fit/model_family.hpp)
// at the committed coefficients: the numerators of A, B and D free, Q, S and V
// as committed; the check of tests/lp_certificate.hpp.
TEST(SglabMid, CertificateBoundsTheBestNumeratorsAtTheCommittedNonlinearPart) {
  const auto& k = sglab::constants::sglab_mid_float;
  std::vector<double> values;
  for (const auto* poly : {k.a, k.b, k.d, k.s, k.v}) values.insert(values.end(), poly, poly + 5);
  values.insert(values.end(), k.q, k.q + 4);
  const auto c = sglab::test::check_clamped_lp_certificate(
      values, 15,
      [&](const sglab::reference::ReferencePoint& r) {
        return sglab::fit::make_residual(MidResidual{r.kappa, r.cosine, r.irradiance,
                                                     sglab::irradiance_upper(r.kappa), k.kappa_max},
                                         29);
      },
      [&](const std::vector<double>& v, const sglab::reference::ReferencePoint& r) {
        return std::abs(sglab::irradiance_sglab_mid(r.cosine, r.kappa, mid_params(v, k.kappa_max)) -
                        r.irradiance) /
               sglab::irradiance_upper(r.kappa);
      });
  RecordProperty("lower_bound", std::to_string(c["lower_bound"].get<double>()));
}

}  // namespace
