// Edge cases of the runtime primitives, the transcribed methods and the
// reference engine, in float and double: the largest finite κ, cosines a
// rounding error outside [−1, 1], the 0/0 points of published formulas, and
// relative accuracy of the reference where its values are tiny. Each truth is
// independent of the code under test: the formula in long double or in
// 50-digit arithmetic, an analytic limit, or a first-order expansion.
#include <cmath>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/expm1.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <sglab/sglab.hpp>

#include "reference/reference.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::test::hex;
using L = long double;
using mp = boost::multiprecision::cpp_bin_float_50;
constexpr L kPiL = 3.141592653589793238462643383279502884L;

// |got − want| within `ulps` units of the precision's epsilon relative to
// want where want is a normal number of T; within `ulps` denormal steps below.
template <class T>
::testing::AssertionResult close(T got, L want, double ulps) {
  if (!std::isfinite(static_cast<double>(got)))
    return ::testing::AssertionFailure()
           << "got " << hex(got) << ", want " << hex(static_cast<double>(want));
  const L err = std::abs(static_cast<L>(got) - want);
  const L min_normal = std::numeric_limits<T>::min();
  const L tol = std::abs(want) >= min_normal
                    ? ulps * std::numeric_limits<T>::epsilon() * std::abs(want)
                    : ulps * static_cast<L>(std::numeric_limits<T>::denorm_min());
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "got " << hex(got) << ", want " << hex(static_cast<double>(want)) << " (error "
         << static_cast<double>(err /
                                std::max(std::abs(want), L(std::numeric_limits<T>::denorm_min())))
         << " relative)";
}

template <class T>
class RuntimeEdge : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RuntimeEdge, Precisions);

// κ from a quarter of the largest finite value to the value itself: −2κ
// overflows above max/2, yet S(κ) ≈ 2π/κ, H(0, κ) = S/2, H(1, κ) ≈ 2π/κ and
// E(1, κ) ≈ 2π/κ are normal numbers (H(0) only down to min_normal).
template <class T>
std::vector<T> huge_kappas() {
  const T m = std::numeric_limits<T>::max();
  return {m / T(4), std::nextafter(m / T(2), T(0)), std::nextafter(m / T(2), m), m / T(1.5), m};
}

TYPED_TEST(RuntimeEdge, ClosedFormsAccurateUpToLargestFiniteKappa) {
  using T = TypeParam;
  for (T k : huge_kappas<T>()) {
    SCOPED_TRACE(fmt::format("κ = {}", hex(k)));
    const L K = k;
    // e^{−κ} and e^{−2κ} are 0 in long double at these κ.
    EXPECT_TRUE(close(sglab::sphere_integral(k), 2 * kPiL / K, 4));
    EXPECT_TRUE(close(sglab::hemispherical_equator(k), kPiL / K, 4));
    EXPECT_TRUE(close(sglab::hemispherical_upper(k), 2 * kPiL / K, 4));
    EXPECT_TRUE(close(sglab::irradiance_upper(k), 2 * kPiL * (K - 1) / K / K, 4));
  }
}

TYPED_TEST(RuntimeEdge, InnerProductAccurateUpToLargestFiniteKappa) {
  using T = TypeParam;
  for (T k : huge_kappas<T>()) {
    SCOPED_TRACE(fmt::format("κ = {}", hex(k)));
    const L K = k;
    // Equal axes: the product has κ3 = 2κ (beyond max for κ > max/2) and no
    // amplitude loss, ∫G² dω = S(2κ) = π/κ.
    EXPECT_TRUE(close(sglab::sg_inner_product(T(1), k, k), kPiL / K, 8));
    // With the Wang lobe λ = 2.133 at c = 1: κ3 = κ + λ, amplitude 1, S(κ3) = 2π/κ3.
    const T lambda = T(2.133);
    EXPECT_TRUE(close(sglab::sg_inner_product(T(1), k, lambda), 2 * kPiL / (K + L(lambda)), 8));
    // Orthogonal axes, κ2 = 1: κ3 = √(κ² + 1), log-amplitude κ3 − κ − 1 → −1.
    const L k3 = std::sqrt(K * K + 1);
    EXPECT_TRUE(close(sglab::sg_inner_product(T(0), k, T(1)),
                      std::exp(-2 * K / (k3 + K + 1)) * 2 * kPiL / k3, 8));
  }
}

TYPED_TEST(RuntimeEdge, InnerProductClampsCosineJustBelowMinusOne) {
  using T = TypeParam;
  const T below = std::nextafter(T(-1), T(-2));
  for (T k : {T(0.5), T(2), T(2.133), T(40)}) {
    // Opposite axes, equal κ: G1·G2 = e^{−2κ} everywhere, ∫ = 4π e^{−2κ}.
    const T v = sglab::sg_inner_product(below, k, k);
    EXPECT_TRUE(close(v, 4 * kPiL * std::exp(-2 * L(k)), 8))
        << "c = " << hex(below) << ", κ = " << hex(k);
    EXPECT_EQ(v, sglab::sg_inner_product(T(-1), k, k));
  }
}

// [Wang2009] as in [Pettineo2016], written naively in 50 digits:
// 2π a e^{d − κ − λ}(1 − e^{−2d})/d with d = |κv + λn| (no 0/0 unless d = 0).
template <class T>
L wang_naive(T cosine, T kappa) {
  const auto& p = sglab::constants::cosine_lobe_published;
  const mp k = kappa, c = cosine, lambda = static_cast<T>(p.lambda),
           a = static_cast<T>(p.amplitude);
  const mp d = sqrt(k * k + lambda * lambda + 2 * k * lambda * c);
  const mp two_pi = 2 * boost::math::constants::pi<mp>();
  return static_cast<L>(two_pi * a * exp(d - k - lambda) * (1 - exp(-2 * d)) / d);
}

TYPED_TEST(RuntimeEdge, Wang2009FiniteAtKappaEqualsLambdaOpposite) {
  using T = TypeParam;
  const auto& p = sglab::constants::cosine_lobe_published;
  const T lambda = static_cast<T>(p.lambda), a = static_cast<T>(p.amplitude);
  // d = 0: (1 − e^{−2d})/d → 2, Ê = 2π a e^{−2λ}·2 = 4π a e^{−2λ}.
  const T v = sglab::irradiance_wang2009(T(-1), lambda);
  EXPECT_TRUE(close(v, 4 * kPiL * L(a) * std::exp(-2 * L(lambda)), 8)) << "κ = λ = " << hex(lambda);
  // Next to it the function is continuous (the naive form in 50 digits is fine
  // once d > 0).
  for (T k : {std::nextafter(lambda, T(0)), std::nextafter(lambda, T(4))})
    for (T c : {T(-1), std::nextafter(T(-1), T(0))}) {
      EXPECT_TRUE(close(sglab::irradiance_wang2009(c, k), wang_naive(c, k), 64))
          << "c = " << hex(c) << ", κ = " << hex(k);
    }
}

TYPED_TEST(RuntimeEdge, Wang2009IsThePublishedFunctionAndStableAtLargeKappa) {
  using T = TypeParam;
  // Up to 1e12 the 50-digit naive form keeps ≥ 30 digits of d − κ − λ.
  for (T k : {T(1e-3), T(0.5), T(4), T(100), T(1e4), T(1e8), T(1e12)})
    for (T c : {T(-1), T(-0.5), T(0), T(0.7), T(1)}) {
      const L want = wang_naive(c, k);
      if (want < L(std::numeric_limits<T>::min())) continue;  // e^{−2κ}-small: below the normals
      EXPECT_TRUE(close(sglab::irradiance_wang2009(c, k), want, 32))
          << "c = " << hex(c) << ", κ = " << hex(k);
    }
  // Beyond, the naive exponent is gone even in 50 digits; the result must stay
  // finite and at c = 1 equal a·S(κ + λ) (no cancellation there).
  const auto& p = sglab::constants::cosine_lobe_published;
  for (T k : {T(1e20), T(1e30), std::numeric_limits<T>::max()}) {
    const L K = k, lambda = static_cast<T>(p.lambda), a = static_cast<T>(p.amplitude);
    EXPECT_TRUE(close(sglab::irradiance_wang2009(T(1), k), a * 2 * kPiL / (K + lambda), 8))
        << "κ = " << hex(k);
    for (T c : {T(-1), T(0), T(0.5)})
      EXPECT_TRUE(std::isfinite(sglab::irradiance_wang2009(c, k))) << hex(c);
  }
}

TYPED_TEST(RuntimeEdge, HillFiniteAtHorizonForLargeKappa) {
  using T = TypeParam;
  // At c = 0 Hill's curve is y = c1²x with x = √(1 − scale) = √(1/κ − 2e^{−2κ}),
  // scale = 1 − x², bias = (e^{−κ} − e^{−2κ})/κ − e^{−2κ}; for κ ≥ 1e8 the
  // exponentials vanish: Ê = (1 − 1/κ)c1²κ^{−1/2}·2π/κ (hill) or ·S(κ) (hill_exact).
  const T c0 = static_cast<T>(sglab::constants::hill_published.c0);
  const L c1 = 1 / (4 * L(c0));
  const std::vector<T> kappas = sizeof(T) == sizeof(float)
                                    ? std::vector<T>{T(1e8), T(1e12), T(1e16), T(1e20)}
                                    : std::vector<T>{T(1e17), T(1e50), T(1e100), T(1e150)};
  for (T k : kappas) {
    const L K = k;
    const L y = (1 - 1 / K) * c1 * c1 / std::sqrt(K);
    EXPECT_TRUE(close(sglab::irradiance_hill(T(0), k), y * 2 * kPiL / K, 16)) << "κ = " << hex(k);
    EXPECT_TRUE(close(sglab::irradiance_hill_exact(T(0), k), y * 2 * kPiL / K, 16))
        << "κ = " << hex(k);
    for (T c : {T(-0.0), std::numeric_limits<T>::denorm_min(), T(1e-30), T(-1e-30)})
      EXPECT_TRUE(std::isfinite(sglab::irradiance_hill(c, k)))
          << "c = " << hex(c) << ", κ = " << hex(k);
  }
}

// [Meder2018] normalized logistic (e^t e^{tc} − 1)/((e^t − 1)(e^{tc} + 1)) in
// 50 digits, with e^x − 1 as expm1 so that tiny t keeps its digits.
template <class T>
L meder_s_naive(T cosine, T kappa) {
  const mp t = sglab::steepness_meder2018(kappa), c = cosine;
  if (t == 0) return (1 + L(cosine)) / 2;
  return static_cast<L>(boost::math::expm1(t * (1 + c)) /
                        (boost::math::expm1(t) * (exp(t * c) + 1)));
}

TYPED_TEST(RuntimeEdge, Meder2018IsTheNormalizedLogistic) {
  using T = TypeParam;
  for (T k : {T(0), T(1e-30), T(1e-6), T(1e-3), T(0.1), T(1), T(10), T(1e3), T(1e6), T(1e12)}) {
    SCOPED_TRACE(fmt::format("κ = {}", hex(k)));
    EXPECT_TRUE(close(sglab::normalized_meder2018(T(1), k), 1, 4));
    EXPECT_EQ(sglab::normalized_meder2018(T(-1), k), T(0));
    for (T c : {T(-1) + std::numeric_limits<T>::epsilon(), T(-0.9), T(-0.3), T(0), T(0.2), T(0.75),
                T(0.999)}) {
      const L want = meder_s_naive(c, k);
      if (want < L(std::numeric_limits<T>::min())) {
        EXPECT_LE(sglab::normalized_meder2018(c, k), T(4) * std::numeric_limits<T>::min())
            << hex(c);
        continue;
      }
      // s depends on t through e^{−t|c|} and e^{−t(1+c)}: rounding t·c and
      // t(1 + c) to T costs up to ~t ulps (the exponential's condition number).
      const double t = sglab::steepness_meder2018(k);
      EXPECT_TRUE(close(sglab::normalized_meder2018(c, k), want, 16 * (1 + 2 * t)))
          << "c = " << hex(c);
    }
  }
  // κ → 0: s → (1 + c)/2 and H̃ → 2π, so Ê → π (E(c, 0) = π for every c).
  for (T k : {T(0), T(1e-6)})
    for (T c : {T(-1), T(0), T(1)}) {
      EXPECT_NEAR(sglab::normalized_meder2018(c, k), (1 + c) / 2, 1e-5) << hex(c);
      EXPECT_NEAR(sglab::irradiance_meder2018(c, k) / T(kPiL), 1.0, 1e-2)
          << "c = " << hex(c) << ", κ = " << hex(k);
    }
}

// ---------------------------------------------------------------------------
// Every registered irradiance method across the subnormal κ range.
//
// For κ → 0 the SG is constant and E(c, κ) → π at every cosine; at a subnormal
// κ the exact E (the reference engine) is π to within O(κ), far below
// rounding. Each method's allowed distance from it is one row of this table:
// the κ → 0 limit of its formula, or rounding (0 = 4ε of the precision), or
// "diverges" for published formulas that fail at κ → 0 by construction (the
// stability table reports those).
constexpr double kRounding = 0, kDiverges = -1;
struct SubnormalLimit {
  std::string_view id;
  double bound;  // max |Ê − E| / E(1, κ), E(1, κ) → π
  const char* reason;
};
constexpr SubnormalLimit kSubnormalLimits[] = {
    {"wang2009", 0.085, "[Wang2009] cosine lobe: Ê → a·2π(1 − e^{−2λ})/λ = 1.0816π"},
    {"punctual", kDiverges, "2π/κ [Pettineo2016]: infinite at κ = 0 by construction"},
    {"hill", kDiverges,
     "Hill's curve [Pettineo2016]: 1/κ and √(1 − scale) of a number > 1 at small κ"},
    {"hill_exact", kDiverges, "Hill's curve [Pettineo2016]: as hill"},
    {"vsgl2015", kRounding, "2π e^{λ'(c − 1)}/(κ + λd) → 2π/λd = π (λd = 2)"},
    {"meder2018", 0.005, "[Meder2018] cosine fit a·G(λm) − b: 0.42% at κ → 0"},
    {"tokuyoshi2022", 2e-4,
     "α(p − q) with α ≈ 1182 [Tokuyoshi2022]: float cancellation (1e−13 in double)"},
    {"tokuyoshi2024", kRounding, "exact poles Ē(±1) → ½: Ê → 2π·½ for any lerp factor"},
    {"tokuyoshi2022_listing5", 2e-4, "as tokuyoshi2022"},
    {"tokuyoshi2022_refit", 2e-4, "as tokuyoshi2022"},
    {"tokuyoshi2024_refit", kRounding, "as tokuyoshi2024"},
    {"vsgl2015_refit", 0.037, "2π/λd with the refitted λd: 3.6% above π"},
    {"wang2009_refit", 0.085, "as wang2009 with the refitted (λ, a): 8.3% above π"},
    {"sglab_fast", 2.6e-3,
     "exact E(1, κ) × fitted shape: its max peak_rel 2.52e−3 (sglab_fast.hpp)"},
    {"sglab_mid", 4.6e-4, "exact E(1, κ) × fitted shape: its max peak_rel 4.2e−4 (sglab_mid.hpp)"},
    {"sglab_lite", 3.7e-3, "fitted rationals at κ̃ = 0: its card's bound (sglab_lite.hpp)"},
    {"sglab_min", 0.043, "fitted polynomials at y = 1/s: its card's bound (sglab_min.hpp)"},
    {"sglab_tab", 1.2e-6, "exact E(1, κ) × the first cell's cubics at t = −1: its card's bound"},
    {"sglab_acc1", kRounding, "exact poles, as tokuyoshi2024"},
    {"sglab_acc2", kRounding, "exact poles, as tokuyoshi2024"},
    {"sglab_acc3", kRounding, "exact poles, as tokuyoshi2024"},
    {"sglab_acc4", kRounding, "exact poles, as tokuyoshi2024"},
};

// κ in every subnormal binade of T: 2^e, 1.5·2^e and the binade's largest
// value, from the smallest subnormal through the smallest normal.
template <class T>
std::vector<T> subnormal_kappas() {
  std::vector<T> out;
  for (T k = std::numeric_limits<T>::denorm_min(); k < std::numeric_limits<T>::min(); k *= T(2)) {
    out.push_back(k);
    if (k > std::numeric_limits<T>::denorm_min()) out.push_back(k + k / T(2));
    out.push_back(T(2) * k - std::numeric_limits<T>::denorm_min());
  }
  out.push_back(std::numeric_limits<T>::min());
  return out;
}

// One method's value at (c, κ) by every path the registry offers in T: scalar,
// batch, and (float) the per-light split.
template <class T>
std::vector<std::pair<const char*, T>> method_paths(const sglab::Method& m, T c, T k) {
  std::vector<std::pair<const char*, T>> v;
  T batch;
  if constexpr (sizeof(T) == sizeof(float)) {
    v.push_back({"scalar", m.f32(c, k)});
    m.batch32(&c, &k, &batch, 1);
    v.push_back({"batch", batch});
    if (m.light_setup32) {
      float state[sglab::kLightStateFloats];
      m.light_setup32(k, state);
      v.push_back({"light split", m.light_eval32(state, c)});
    }
  } else {
    v.push_back({"scalar", m.f64(c, k)});
    m.batch64(&c, &k, &batch, 1);
    v.push_back({"batch", batch});
  }
  return v;
}

TYPED_TEST(RuntimeEdge, EveryMethodAtSubnormalKappaMeetsTheReferenceLimit) {
  using T = TypeParam;
  const T one(1);
  const T cosines[] = {T(-1),  std::nextafter(-one, T(0)), T(-0.5), T(0),
                       T(0.5), std::nextafter(one, T(0)),  one};
  const auto kappas = subnormal_kappas<T>();
  // The reference limit: E(c, κ) at these κ, exactly π up to double rounding.
  for (T k : {kappas.front(), kappas.back()})
    for (T c : cosines)
      EXPECT_NEAR(sglab::reference::reference_engine().evaluate(double(k), double(c)).irradiance,
                  double(kPiL), 1e-15 * double(kPiL))
          << "c = " << hex(c) << ", κ = " << hex(k);
  for (const sglab::Method& m : sglab::irradiance_methods) {
    const SubnormalLimit* row = nullptr;
    for (const SubnormalLimit& r : kSubnormalLimits)
      if (r.id == m.id) row = &r;
    ASSERT_NE(row, nullptr) << m.id << ": no row in kSubnormalLimits";
    SCOPED_TRACE(fmt::format("{} ({})", m.id, row->reason));
    const double bound =
        row->bound == kRounding ? 4 * double(std::numeric_limits<T>::epsilon()) : row->bound;
    std::size_t failures = 0;
    for (T k : kappas)
      for (T c : cosines)
        for (const auto& [path, v] : method_paths(m, c, k)) {
          const bool fails = !std::isfinite(v) || v < T(0);
          failures += fails;
          if (row->bound == kDiverges) continue;
          ASSERT_FALSE(fails) << path << ": c = " << hex(c) << ", κ = " << hex(k) << " -> "
                              << hex(v);
          EXPECT_LE(std::abs(double(v) - double(kPiL)) / double(kPiL), bound)
              << path << ": c = " << hex(c) << ", κ = " << hex(k) << " -> " << hex(v);
        }
    // A published formula listed as diverging does fail here (else its row is stale).
    if (row->bound == kDiverges) {
      EXPECT_GT(failures, 0u);
    }
  }
}

// ---------------------------------------------------------------------------
// Reference engine.
namespace sr = sglab::reference;

double rel(double got, double want) { return std::abs(got / want - 1); }

TEST(ReferenceEdge, AccurateUpToLargestFiniteKappa) {
  const auto& engine = sr::reference_engine();
  for (double k : {1e300, 3e307, 1e308, std::numeric_limits<double>::max()}) {
    SCOPED_TRACE(fmt::format("κ = {}", hex(k)));
    const L K = k;
    const sr::ReferencePoint up = engine.evaluate(k, 1.0), mid = engine.evaluate(k, 0.0);
    const sr::ReferencePoint half = engine.evaluate(k, 0.5);
    // H(1) = 2π(1 − e^{−κ})/κ, E(1) = 2π(κ − 1 + e^{−κ})/κ², H(0) = S/2, and
    // at c = 0.5 the whole lobe is inside the hemisphere: H = S, E ≈ cH.
    EXPECT_LE(rel(up.hemispherical, static_cast<double>(2 * kPiL / K)), 1e-13)
        << hex(up.hemispherical);
    EXPECT_LE(rel(up.irradiance, static_cast<double>(2 * kPiL * (K - 1) / K / K)), 1e-13)
        << hex(up.irradiance);
    EXPECT_LE(rel(half.hemispherical, static_cast<double>(2 * kPiL / K)), 1e-13)
        << hex(half.hemispherical);
    const double h0 = static_cast<double>(kPiL / K);
    if (h0 >= std::numeric_limits<double>::min()) {
      EXPECT_LE(rel(mid.hemispherical, h0), 1e-13) << hex(mid.hemispherical);
    } else {
      EXPECT_NEAR(mid.hemispherical, h0, 1e-13 * std::numeric_limits<double>::min());
    }
    EXPECT_NEAR(up.normalized, 1.0, 1e-13);
    EXPECT_NEAR(mid.normalized, 0.5, 1e-13);
    EXPECT_NEAR(half.normalized, 1.0, 1e-13);
  }
}

// s near c = −1 is O(δ), δ = 1 + c. To first order (e^{κδu} ≈ 1 + κδu,
// I0(κrρ) ≈ 1 + κ²δρ²/2 with r² ≈ 2δ):
//   H(−1 + δ) − H(−1) = 2πδ ∫₀¹ e^{−κ(1+u)} (κu + κ²(1 − u²)/2) du + O(δ²),
// and s = (H(c) − H(−1))/(H(1) − H(−1)), H(1) − H(−1) = 2π(1 − e^{−κ})²/κ.
double s_first_order(double kappa, double delta) {
  auto f = [&](double u) {
    return std::exp(-kappa * (1 + u)) * (kappa * u + kappa * kappa * (1 - u * u) / 2);
  };
  const double integral =
      boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, 0.0, 1.0, 10, 1e-15);
  const double m = -std::expm1(-kappa);
  return delta * integral * kappa / (m * m);
}

TEST(ReferenceEdge, NormalizedRelativelyAccurateNearMinusOne) {
  const auto& engine = sr::reference_engine();
  // δ = 2^−50 (c = −1 + δ is a double): the O(δ²) term is ~δκ² relative.
  const double delta = std::ldexp(1.0, -50);
  for (double k : {1e-3, 0.5, 2.0, 10.0}) {
    const sr::ReferencePoint p = engine.evaluate(k, -1 + delta);
    EXPECT_LE(rel(p.normalized, s_first_order(k, delta)), 1e-12)
        << "κ = " << hex(k) << ": s = " << hex(p.normalized) << ", first order "
        << hex(s_first_order(k, delta));
  }
  // Against the engine's 50-digit mode (Quadrature::high) at a few δ.
  for (double k : {1e-3, 0.5, 1.0, 1.5, 2.0, 10.0, 100.0, 600.0})
    for (double d : {1e-10, 1e-6, 1e-3, 0.1}) {
      const double c = -1 + d;
      const sr::ReferencePoint a = engine.evaluate(k, c),
                               b = engine.evaluate(k, c, sr::Quadrature::high);
      if (b.normalized < 1e-290) continue;
      EXPECT_LE(rel(a.normalized, b.normalized), 1e-13)
          << "κ = " << hex(k) << ", c = " << hex(c) << ": " << hex(a.normalized) << " vs high "
          << hex(b.normalized);
      EXPECT_LE(rel(a.hemispherical, b.hemispherical), 1e-13)
          << "H at κ = " << hex(k) << ", c = " << hex(c);
      if (b.irradiance >= 1e-290) {
        EXPECT_LE(rel(a.irradiance, b.irradiance), 1e-13)
            << "E at κ = " << hex(k) << ", c = " << hex(c);
      }
    }
}

}  // namespace
