// Reference engine (reference/reference.hpp): H, E, s of docs/quantities.md against
// independent truth — the closed forms evaluated here in 50-digit arithmetic,
// the κ → 0 limits, the engine's own 50-digit mode on random points, and a
// brute-force 2-D quadrature over the sphere that does not use the 1-D
// reduction at all — plus the cache, argument checks and the
// `sglab reference` command.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/special_functions/bessel.hpp>
#include <boost/math/special_functions/erf.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "common/io.hpp"
#include "reference/reference.hpp"
#include "reference/reference_detail.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::reference::Quadrature;
using sglab::reference::Query;
using sglab::reference::reference_engine;
using sglab::reference::ReferenceEngine;
using sglab::reference::ReferencePoint;
using sglab::test::hex;
using mp = boost::multiprecision::cpp_bin_float_50;

using sglab::test::kPi;
constexpr double kRelTol = 1e-13;     // required relative accuracy of H, E
constexpr double kAbsTolS = 1e-13;    // required absolute accuracy of s
constexpr double kSmallest = 1e-290;  // relative accuracy required above this

using sglab::test::rel_err;

// ---------------------------------------------------------------------------
// closed forms of docs/quantities.md in 50-digit arithmetic, written naively on purpose:
// with 50 digits the cancellations in 1 − e^{−κ} and 1 − e^{−κ} − κe^{−κ}
// (≈ κ²/2 at κ = 1e−6) still leave ~38 correct digits. Nothing here comes
// from the engine or from the runtime headers.
struct ClosedForms {
  mp h_plus, h_minus, h_zero, e_plus, e_minus;
  double s_zero;  // s(0, κ) = (S/2 − H(−1)) / (H(1) − H(−1))
};
ClosedForms closed_forms(double kappa_in) {
  const mp k = kappa_in, two_pi = 2 * boost::math::constants::pi<mp>();
  const mp em = exp(-k);
  ClosedForms f;
  f.h_plus = two_pi * (1 - em) / k;                       // H(1, κ)
  f.h_minus = em * f.h_plus;                              // H(−1, κ)
  f.h_zero = (two_pi * (1 - exp(-2 * k)) / k) / 2;        // S(κ)/2
  f.e_plus = two_pi * (k - 1 + em) / (k * k);             // E(1, κ)
  f.e_minus = two_pi * em * (1 - em - k * em) / (k * k);  // E(−1, κ)
  f.s_zero = static_cast<double>((f.h_zero - f.h_minus) / (f.h_plus - f.h_minus));
  return f;
}

const std::vector<double>& closed_form_kappas() {
  static const std::vector<double> k = {1e-6, 1e-5, 3e-4, 0.01, 0.2, 0.5, 0.999, 1.0,   1.001, 2.5,
                                        10,   37.5, 100,  710,  1e3, 1e4, 1e5,   3.3e5, 1e6};
  return k;
}

// Asserts value ≈ exact (relative) where exact ≥ 1e−290, else finite and tiny.
void expect_rel(double value, const mp& exact, const char* what, double kappa, double cosine) {
  const double x = static_cast<double>(exact);
  ASSERT_FALSE(std::isnan(value)) << what << " NaN at κ=" << hex(kappa) << " c=" << hex(cosine);
  if (x >= kSmallest) {
    EXPECT_LE(rel_err(value, x), kRelTol) << what << " at κ=" << hex(kappa) << " c=" << hex(cosine)
                                          << ": got " << hex(value) << ", exact " << hex(x);
  } else {
    EXPECT_GE(value, 0) << what << " at κ=" << hex(kappa);
    EXPECT_LE(value, 1e-285) << what << " at κ=" << hex(kappa);
  }
}

TEST(ReferenceClosedForms, PolesAndEquator) {
  ReferenceEngine engine;
  for (double kappa : closed_form_kappas()) {
    const ClosedForms f = closed_forms(kappa);
    const ReferencePoint up = engine.evaluate(kappa, 1.0);
    const ReferencePoint down = engine.evaluate(kappa, -1.0);
    const ReferencePoint mid = engine.evaluate(kappa, 0.0);
    expect_rel(up.hemispherical, f.h_plus, "H(1,κ)", kappa, 1.0);
    expect_rel(down.hemispherical, f.h_minus, "H(-1,κ)", kappa, -1.0);
    expect_rel(mid.hemispherical, f.h_zero, "H(0,κ) = S/2", kappa, 0.0);
    expect_rel(up.irradiance, f.e_plus, "E(1,κ)", kappa, 1.0);
    expect_rel(down.irradiance, f.e_minus, "E(-1,κ)", kappa, -1.0);
    EXPECT_NEAR(up.normalized, 1.0, kAbsTolS) << "s(1,κ) at κ=" << hex(kappa);
    EXPECT_NEAR(down.normalized, 0.0, kAbsTolS) << "s(-1,κ) at κ=" << hex(kappa);
    EXPECT_NEAR(mid.normalized, f.s_zero, kAbsTolS) << "s(0,κ) at κ=" << hex(kappa);
  }
}

// The quadrature's error estimate must bound the actual error (it is the
// pessimistic |Kronrod − Gauss| sum), and the L1 norms are ≥ |value|.
TEST(ReferenceClosedForms, ErrorEstimateBoundsActualError) {
  ReferenceEngine engine;
  for (double kappa : closed_form_kappas()) {
    const ClosedForms f = closed_forms(kappa);
    const std::vector<std::tuple<double, mp, mp>> ends = {{1.0, f.h_plus, f.e_plus},
                                                          {-1.0, f.h_minus, f.e_minus}};
    for (const auto& [c, h, e] : ends) {
      const ReferencePoint p = engine.evaluate(kappa, c);
      if (static_cast<double>(h) < kSmallest) continue;
      const double slack = 4 * std::numeric_limits<double>::epsilon();
      EXPECT_LE(std::abs(p.hemispherical - static_cast<double>(h)),
                p.hemispherical_error + slack * p.hemispherical)
          << "κ=" << hex(kappa) << " c=" << c;
      EXPECT_LE(std::abs(p.irradiance - static_cast<double>(e)),
                p.irradiance_error + slack * p.irradiance)
          << "κ=" << hex(kappa) << " c=" << c;
      EXPECT_GE(p.hemispherical_error, 0);
      EXPECT_GE(p.irradiance_error, 0);
      EXPECT_GE(p.hemispherical_l1, std::abs(p.hemispherical));
      EXPECT_GE(p.irradiance_l1, std::abs(p.irradiance));
    }
  }
}

// κ → 0: H → 2π, E → π, s → (1+c)/2 (docs/quantities.md); κ = 0 itself exactly.
TEST(ReferenceLimits, KappaToZero) {
  ReferenceEngine engine;
  for (double c : {-1.0, -0.75, -1e-9, 0.0, 0.3, 0.999, 1.0}) {
    for (Quadrature mode : {Quadrature::standard, Quadrature::high}) {
      const ReferencePoint zero = engine.evaluate(0.0, c, mode);
      EXPECT_NEAR(zero.hemispherical, 2 * kPi, 1e-15) << "c=" << c;
      EXPECT_NEAR(zero.irradiance, kPi, 1e-15) << "c=" << c;
      EXPECT_NEAR(zero.normalized, (1 + c) / 2, 1e-16) << "c=" << c;
    }
    // H = 2π + O(κ), E = π + O(κ), s = (1+c)/2 + O(κ): |dH/dκ| ≤ ∫_hemi |ω·v − 1| dω
    // ≤ 4π, |dE/dκ| ≤ 2π, and |s − (1+c)/2| is far below κ (measured
    // ~1e−2·κ at κ = 1e−4). Plus a few ulps.
    for (double kappa : {1e-300, 1e-30, 1e-12, 1e-8}) {
      const ReferencePoint p = engine.evaluate(kappa, c);
      EXPECT_NEAR(p.hemispherical, 2 * kPi, 4 * kPi * kappa + 1e-14) << "κ=" << kappa << " c=" << c;
      EXPECT_NEAR(p.irradiance, kPi, 2 * kPi * kappa + 1e-14) << "κ=" << kappa << " c=" << c;
      EXPECT_NEAR(p.normalized, (1 + c) / 2, kappa + 4e-16) << "κ=" << kappa << " c=" << c;
    }
  }
}

// ---------------------------------------------------------------------------
// Large κ, to the largest float and beyond, against closed forms written here.
//
// E(0, κ) = 2π e^{−κ} I₁(κ)/κ exactly: with v ⊥ n and ω in polar angles θ from v,
// φ around it, ω·v = cos θ and ω·n = sin θ cos φ, so E = ∫₀^π e^{κ(cos θ − 1)} sin²θ dθ
// ∫_{−π/2}^{π/2} cos φ dφ = 2 e^{−κ} π I₁(κ)/κ ([AS1964] 9.6.18). e^{−x}I₁(x) in 50 digits:
// Boost's I₁ below x = 50, above it the Hankel series ([AS1964] 9.7.1,
// a_k = a_{k−1}(4 − (2k − 1)²)/(8k), alternating), summed while its terms shrink (the
// smallest is ~e^{−2x}, below 1e−43 at x = 50).
mp scaled_bessel_i1(const mp& x) {
  if (x < 50) return boost::math::cyl_bessel_i(1, x) * exp(-x);
  mp term = 1, sum = 1;
  for (int k = 1; k < 400; ++k) {
    const mp next = -term * mp(4 - (2 * k - 1) * (2 * k - 1)) / (8 * k * x);
    if (abs(next) >= abs(term)) break;
    term = next;
    sum += term;
  }
  return sum / sqrt(2 * boost::math::constants::pi<mp>() * x);
}

TEST(ReferenceLargeKappa, EquatorIsTheBesselClosedForm) {
  ReferenceEngine engine;
  const double flt_max = std::numeric_limits<float>::max();
  for (double kappa :
       {0.5, 3.0, 49.9, 50.0, 700.0, 1e4, 1e6, 1e9, 1e12, 1e20, 1e30, flt_max, 1e200, 1e300}) {
    const mp k = kappa;
    const mp exact = 2 * boost::math::constants::pi<mp>() * scaled_bessel_i1(k) / k;
    expect_rel(engine.evaluate(kappa, 0.0).irradiance, exact, "E(0,κ) = 2π e^{-κ}I1(κ)/κ", kappa,
               0.0);
  }
}

// For a sharp light the lobe is a Gaussian of width 1/√κ on the tangent plane at v, and
// ω·n = c + √(1 − c²)·x₁ to first order, so
//   E(c, κ) = (2π/κ)[c Φ(z) + (r/√κ) φ(z)] (1 + O(1/κ)),  z = c√κ/r, r = √(1 − c²),
// with Φ, φ the standard normal distribution and density: the expectation of
// max(c + r x₁, 0) under that Gaussian. Checked across the layer |c| ≤ 6/√κ where the
// irradiance turns on, and at c = ±1/2 where it is c·2π/κ or 0, to κ = FLT_MAX.
TEST(ReferenceLargeKappa, FollowsTheGaussianLimitAcrossTheHorizon) {
  ReferenceEngine engine;
  for (double kappa : {1e12, 1e16, 1e20, 1e30, double(std::numeric_limits<float>::max())}) {
    // the O(1/κ) term: 5.5e-10 measured at κ = 1e12 (t = −6)
    const double tol = kRelTol + 1e3 / kappa;
    std::vector<double> cosines;
    for (int i = -48; i <= 48; ++i) cosines.push_back(i / 8.0 / std::sqrt(kappa));
    for (double c : {-0.5, 0.5}) cosines.push_back(c);
    for (double c : cosines) {
      const mp km = kappa, cm = c, r = sqrt((1 - cm) * (1 + cm)), z = cm * sqrt(km) / r;
      const mp two_pi = 2 * boost::math::constants::pi<mp>();
      const mp big_phi = boost::math::erfc(-z / sqrt(mp(2))) / 2;
      const mp small_phi = exp(-z * z / 2) / sqrt(two_pi);
      const mp limit = two_pi / km * (cm * big_phi + r / sqrt(km) * small_phi);
      const double value = engine.evaluate(kappa, c).irradiance;
      if (static_cast<double>(limit) < kSmallest) {
        EXPECT_LE(value, 1e-285) << "κ=" << hex(kappa) << " c=" << hex(c);
        continue;
      }
      EXPECT_LE(rel_err(value, static_cast<double>(limit)), tol)
          << "κ=" << hex(kappa) << " c=" << hex(c) << " (t = c√κ = " << c * std::sqrt(kappa) << ")";
    }
  }
}

// ---------------------------------------------------------------------------
// The high-precision mode (50-digit arithmetic, its own truncation points and
// tolerances) against the standard mode.
TEST(ReferenceHighPrecision, AgreesWithStandardOnRandomPoints) {
  std::vector<Query> queries;
  // Corners and the awkward places: both poles, the horizon from both sides,
  // near-pole c, and the underflow edge of H at large κ and c < 0.
  for (double kappa : {1e-6, 0.7, 1.0, 1.5, 50.0, 1e6})
    for (double c : {-1.0, -0.0365, -1e-12, 0.0, 1e-12, 0.5, 1 - 1e-12, 1.0})
      queries.push_back({kappa, c});
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 220; ++i)
    queries.push_back({std::pow(10.0, -6 + 12 * unit(rng)), -1 + 2 * unit(rng)});

  ReferenceEngine engine;
  const auto standard = engine.evaluate(queries, Quadrature::standard);
  const auto high = engine.evaluate(queries, Quadrature::high);
  double max_h = 0, max_e = 0, max_s = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const double k = queries[i].kappa, c = queries[i].cosine;
    const ReferencePoint& a = standard[i];
    const ReferencePoint& b = high[i];
    for (double v :
         {a.hemispherical, a.irradiance, a.normalized, b.hemispherical, b.irradiance, b.normalized})
      ASSERT_TRUE(std::isfinite(v)) << "non-finite at κ=" << hex(k) << " c=" << hex(c);
    if (b.hemispherical >= kSmallest)
      max_h = std::max(max_h, rel_err(a.hemispherical, b.hemispherical));
    if (b.irradiance >= kSmallest) max_e = std::max(max_e, rel_err(a.irradiance, b.irradiance));
    max_s = std::max(max_s, std::abs(a.normalized - b.normalized));
    if (b.hemispherical >= kSmallest) {
      EXPECT_LE(rel_err(a.hemispherical, b.hemispherical), kRelTol)
          << "H at κ=" << hex(k) << " c=" << hex(c);
    }
    if (b.irradiance >= kSmallest) {
      EXPECT_LE(rel_err(a.irradiance, b.irradiance), kRelTol)
          << "E at κ=" << hex(k) << " c=" << hex(c);
    }
    EXPECT_LE(std::abs(a.normalized - b.normalized), kAbsTolS)
        << "s at κ=" << hex(k) << " c=" << hex(c);
    EXPECT_GE(a.normalized, 0);
    EXPECT_LE(a.normalized, 1);
    EXPECT_LE(a.irradiance, a.hemispherical);  // u ≤ 1 under the integral
  }
  const std::string summary =
      fmt::format("{} points: max rel H {:.3e}, max rel E {:.3e}, max abs s {:.3e}", queries.size(),
                  max_h, max_e, max_s);
  std::printf("high vs standard: %s\n", summary.c_str());
  RecordProperty("high_vs_standard", summary);
}

TEST(ReferenceHighPrecision, NeverNaNAtTheExtremes) {
  ReferenceEngine engine;
  for (Quadrature mode : {Quadrature::standard, Quadrature::high}) {
    for (double kappa : {0.0, 5e-324, 1e-300, 1e-6, 1e6})
      for (double c : {-1.0, -0.5, -0.0, 0.0, 1.0}) {
        const ReferencePoint p = engine.evaluate(kappa, c, mode);
        EXPECT_TRUE(std::isfinite(p.hemispherical) && std::isfinite(p.irradiance) &&
                    std::isfinite(p.normalized))
            << "κ=" << hex(kappa) << " c=" << hex(c);
      }
  }
  // Deep in the tail: H(−1, 1e6) = 2π e^{−1e6}/κ underflows to 0.
  const ReferencePoint tail = engine.evaluate(1e6, -1.0);
  EXPECT_EQ(tail.hemispherical, 0.0);
  EXPECT_EQ(tail.irradiance, 0.0);
  EXPECT_EQ(tail.normalized, 0.0);
}

// ---------------------------------------------------------------------------
// The engine's contract (reference/reference_detail.hpp, Settings::tolerance):
// the error bound it reports for H and for E is at most 1e−14 of the value,
// and the value agrees with the 50-digit mode within that bound, on the
// points where the quadrature is hardest: c at and next to ±1 (the peak
// against the pole, the boundary layer collapsing onto u = 0), κ at the
// switch of the scaled Bessel I0e from series to the Hankel asymptotic
// expansion (x = κrρ = 50 in double, about 69 for 50 digits; at c = 0 the
// peak has ρ = 1, at c = 0.6 it has ρ = r = 0.8), at the κ = 1 switch of s,
// κ near 0 and κ huge. Values that underflow below 1e−290 are only required
// to have a bound no larger than themselves.
std::vector<Query> contract_points() {
  const double below_one = std::nextafter(1.0, 0.0);
  const std::vector<double> cosines = {-1.0,  -below_one, -(1 - 1e-12), -(1 - 1e-6), -0.999,
                                       -0.5,  -1e-9,      0.0,          1e-9,        0.6,
                                       0.999, 1 - 1e-6,   1 - 1e-12,    below_one,   1.0};
  // The switch of the 50-digit mode: 0.6 ln(1/ε) of its type (mp has the same digits).
  const double high_switch = static_cast<double>(-0.6 * log(std::numeric_limits<mp>::epsilon()));
  const std::vector<double> kappas = {1e-300,
                                      1e-12,
                                      1e-4,
                                      std::nextafter(1.0, 0.0),
                                      1.0,
                                      1.5,
                                      2.0,
                                      10.0,
                                      50 * (1 - 1e-12),
                                      50.0,
                                      50 * (1 + 1e-12),
                                      78.125,
                                      high_switch * (1 - 1e-12),
                                      high_switch * (1 + 1e-12),
                                      1e4,
                                      1e6,
                                      1e10,
                                      1e100,
                                      1e300};
  std::vector<Query> q;
  for (double k : kappas)
    for (double c : cosines) q.push_back({k, c});
  return q;
}

TEST(ReferenceContract, ReportedBoundWithin1e14AndHighPrecisionAgrees) {
  constexpr double kContract = 1e-14;  // relative, per quantity (H, E)
  // rounding of the result to double
  const double slack = 4 * std::numeric_limits<double>::epsilon();
  const std::vector<Query> queries = contract_points();
  ReferenceEngine engine;
  const auto standard = engine.evaluate(queries, Quadrature::standard);
  const auto high = engine.evaluate(queries, Quadrature::high);
  double worst_bound = 0, worst_agreement = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const double k = queries[i].kappa, c = queries[i].cosine;
    const ReferencePoint& a = standard[i];
    const ReferencePoint& b = high[i];
    const struct {
      const char* name;
      double value, bound, high;
    } quantities[] = {{"H", a.hemispherical, a.hemispherical_error, b.hemispherical},
                      {"E", a.irradiance, a.irradiance_error, b.irradiance}};
    for (const auto& x : quantities) {
      ASSERT_TRUE(std::isfinite(x.value) && std::isfinite(x.bound))
          << x.name << " at κ=" << hex(k) << " c=" << hex(c);
      EXPECT_GE(x.bound, 0) << x.name << " at κ=" << hex(k) << " c=" << hex(c);
      if (b.hemispherical < kSmallest || x.high < kSmallest) {
        EXPECT_LE(x.bound, std::abs(x.value)) << x.name << " at κ=" << hex(k) << " c=" << hex(c);
        continue;
      }
      worst_bound = std::max(worst_bound, x.bound / x.value);
      EXPECT_LE(x.bound, kContract * x.value)
          << x.name << " at κ=" << hex(k) << " c=" << hex(c) << ": reported bound "
          << x.bound / x.value << " of the value, contract " << kContract;
      const double diff = std::abs(x.value - x.high);
      worst_agreement = std::max(worst_agreement, diff / x.high);
      EXPECT_LE(diff, x.bound + slack * x.high)
          << x.name << " at κ=" << hex(k) << " c=" << hex(c) << ": standard " << hex(x.value)
          << ", high " << hex(x.high) << ", reported bound " << x.bound;
    }
  }
  std::printf(
      "contract points: %zu, worst reported bound %.3e, worst standard/high difference %.3e "
      "(relative)\n",
      queries.size(), worst_bound, worst_agreement);
}

// The tolerance itself. On every point of the engine (the contract points
// above, and 20000 random ones with κ in [1e−4, 1e8]) the first Kronrod
// segments of the geometric split already meet it, so H and E do not change
// when it is loosened; what enforces it is the adaptive bisection, exercised
// here with the engine's own settings (order and tolerance) on an integrand
// that needs it: a Gaussian of width σ = 1e−3 at 0.3 on one segment [0, 1],
// exactly σ√(2π)·½(erf(0.7/(σ√2)) + erf(0.3/(σ√2))).
TEST(ReferenceContract, AdaptiveQuadratureMeetsTheToleranceWhereBisectionIsNeeded) {
  using sglab::reference::detail::AdaptiveQuadrature;
  using Settings = sglab::reference::detail::Settings<double>;
  const double sigma = 1e-3, mu = 0.3;
  auto f = [&](int, double x) {
    const double z = (x - mu) / sigma;
    return std::exp(-0.5 * z * z);
  };
  const mp s = sigma, root2 = boost::math::constants::root_two<mp>();
  const double exact = static_cast<double>(
      s * sqrt(2 * boost::math::constants::pi<mp>()) *
      (boost::math::erf((1 - mp(mu)) / (s * root2)) + boost::math::erf(mp(mu) / (s * root2))) / 2);
  AdaptiveQuadrature<double, double> quad;
  quad.add(f, 0, 0.0, 1.0);
  EXPECT_GT(quad.error(), 1e-6 * exact)
      << "one segment must not resolve the peak (the loop would not be tested)";
  quad.run(f, Settings::tolerance());
  EXPECT_LE(quad.error(), 1e-14 * quad.value())
      << "reported bound after " << quad.size() << " segments";
  EXPECT_LE(std::abs(quad.value() - exact),
            quad.error() + 4 * std::numeric_limits<double>::epsilon() * exact)
      << "value " << hex(quad.value()) << ", exact " << hex(exact);
  EXPECT_LE(rel_err(quad.value(), exact), 1e-14);
}

// ---------------------------------------------------------------------------
// Brute force: ∫_{S²} G(ω; v, κ)·w(ω·n) dω in (θ, φ) about n by composite
// Gauss–Legendre (Boost's 20-point rule on 24 equal panels in each angle),
// with v at polar angle acos(c). No 1-D reduction, no Bessel function, no
// adaptivity: catches a wrong formula that both engine modes would share.
template <class F>
double composite_gauss(const F& f, double a, double b) {
  constexpr int panels = 24;
  const double h = (b - a) / panels;
  double sum = 0;
  for (int i = 0; i < panels; ++i)
    sum += boost::math::quadrature::gauss<double, 20>::integrate(f, a + i * h, a + (i + 1) * h);
  return sum;
}
double sphere_quadrature(double kappa, double c, bool cosine_weighted) {
  const double r = std::sqrt((1 - c) * (1 + c));
  auto over_phi = [&](double theta) {
    const double ct = std::cos(theta), st = std::sin(theta);
    auto g = [&](double phi) { return std::exp(kappa * (st * r * std::cos(phi) + ct * c - 1)); };
    // φ ∈ [0, 2π], symmetric
    return 2 * composite_gauss(g, 0.0, kPi) * st * (cosine_weighted ? ct : 1.0);
  };
  return composite_gauss(over_phi, 0.0, kPi / 2);
}

TEST(ReferenceBruteForce, MatchesSphereQuadrature) {
  ReferenceEngine engine;
  for (double kappa : {0.05, 0.9, 4.0, 25.0})
    for (double c : {-0.8, -0.3, 0.0, 0.35, 0.9}) {
      const ReferencePoint p = engine.evaluate(kappa, c);
      const double h = sphere_quadrature(kappa, c, false);
      const double e = sphere_quadrature(kappa, c, true);
      EXPECT_LE(rel_err(p.hemispherical, h), 1e-12) << "H at κ=" << kappa << " c=" << c;
      EXPECT_LE(rel_err(p.irradiance, e), 1e-12) << "E at κ=" << kappa << " c=" << c;
      // s from the brute-force H and the closed-form ends.
      const ClosedForms f = closed_forms(kappa);
      const double s =
          (h - static_cast<double>(f.h_minus)) / static_cast<double>(f.h_plus - f.h_minus);
      EXPECT_NEAR(p.normalized, s, 1e-11) << "s at κ=" << kappa << " c=" << c;
    }
}

// ---------------------------------------------------------------------------
TEST(ReferenceEngineApi, RejectsBadArguments) {
  ReferenceEngine engine;
  const double nan = std::numeric_limits<double>::quiet_NaN(),
               inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<double, double>> bad = {
      {-1.0, 0.0}, {-1e-300, 0.0}, {nan, 0.0}, {inf, 0.0}, {1.0, 1.0000000000000002},
      {1.0, -1.5}, {1.0, nan},     {1.0, inf}};
  for (auto [k, c] : bad)
    EXPECT_THROW(engine.evaluate(k, c), std::invalid_argument) << "κ=" << k << " c=" << c;
  const std::vector<Query> batch = {{1.0, 0.5}, {2.0, 2.0}};
  EXPECT_THROW(engine.evaluate(batch), std::invalid_argument);
  EXPECT_EQ(engine.cache_size(), 0u);  // nothing computed for a rejected batch
}

TEST(ReferenceEngineApi, CacheKeyedByBitsAndPrecision) {
  ReferenceEngine engine;
  EXPECT_EQ(engine.cache_size(), 0u);
  const ReferencePoint a = engine.evaluate(3.0, 0.25);
  EXPECT_EQ(engine.cache_size(), 1u);
  const ReferencePoint b = engine.evaluate(3.0, 0.25);
  EXPECT_EQ(engine.cache_size(), 1u);
  EXPECT_EQ(a.hemispherical, b.hemispherical);
  engine.evaluate(3.0, 0.0);
  engine.evaluate(3.0, -0.0);  // a different bit pattern, a different entry
  EXPECT_EQ(engine.cache_size(), 3u);
  engine.evaluate(3.0, 0.25, Quadrature::high);
  EXPECT_EQ(engine.cache_size(), 4u);
  engine.clear_cache();
  EXPECT_EQ(engine.cache_size(), 0u);
  EXPECT_EQ(&reference_engine(), &reference_engine());
}

TEST(ReferenceEngineApi, BatchIsInQueryOrderAndMatchesSingleCalls) {
  std::vector<Query> queries;
  // 300 distinct points (i mod 37, i mod 23 are unique for i < 851), then a repeat.
  for (int i = 0; i < 300; ++i)
    queries.push_back({std::pow(10.0, -3 + 7 * (i % 37) / 36.0), -1 + 2 * (i % 23) / 22.0});
  queries.push_back(queries[17]);
  ReferenceEngine batch_engine, single_engine;
  const auto batch = batch_engine.evaluate(queries);
  ASSERT_EQ(batch.size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    EXPECT_EQ(batch[i].kappa, queries[i].kappa);
    EXPECT_EQ(batch[i].cosine, queries[i].cosine);
    const ReferencePoint p = single_engine.evaluate(queries[i].kappa, queries[i].cosine);
    EXPECT_EQ(batch[i].hemispherical, p.hemispherical);
    EXPECT_EQ(batch[i].irradiance, p.irradiance);
    EXPECT_EQ(batch[i].normalized, p.normalized);
  }
  EXPECT_EQ(batch_engine.cache_size(), 300u);  // the repeat shares an entry
}

TEST(ReferenceEngineApi, ConcurrentCallersAgree) {
  ReferenceEngine engine;
  std::vector<double> first(64);
  for (int i = 0; i < 64; ++i) first[i] = engine.evaluate(1.0 + i, 0.5 - i / 64.0).irradiance;
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 64; ++i) {
        if (engine.evaluate(1.0 + i, 0.5 - i / 64.0).irradiance != first[i]) ++mismatches;
        engine.evaluate(100.0 + t, -0.5 + i / 64.0);  // concurrent inserts
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(mismatches.load(), 0);
}

// ---------------------------------------------------------------------------
// `sglab reference`.
// Writes `content` to dir/name and returns the path.
std::string write(const sglab::test::TempDir& dir, const std::string& name,
                  const std::string& content) {
  const auto file = dir.path / name;
  sglab::io::write_file_atomic(file, content);
  return file.string();
}

// `sglab reference --points FILE` with extra options before --points.
sglab::test::CommandResult sglab_reference(const std::string& file,
                                           std::vector<std::string> options = {}) {
  options.insert(options.begin(), "reference");
  options.insert(options.end(), {"--points", file});
  return sglab::test::run_sglab(options);
}

TEST(ReferenceCommand, PrintsCsvWith17Digits) {
  const sglab::test::TempDir dir("reference");
  const std::string file = write(
      dir, "points.csv", "kappa,cosine\n0,0.5\n1e-6,-1\n2.5,0.1\r\n 1000 , -0.25 \n1e6,1\n\n");
  const auto r = sglab_reference(file);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string expected = "kappa,cosine,hemispherical,irradiance,normalized\n";
  const std::vector<std::pair<double, double>> points = {
      {0.0, 0.5}, {1e-6, -1.0}, {2.5, 0.1}, {1000.0, -0.25}, {1e6, 1.0}};
  for (auto [k, c] : points) {
    const ReferencePoint p = reference_engine().evaluate(k, c);
    expected += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", k, c, p.hemispherical,
                            p.irradiance, p.normalized);
  }
  EXPECT_EQ(r.output, expected);

  const auto high = sglab_reference(file, {"--precision", "high"});
  ASSERT_EQ(high.exit_code, 0) << high.output;
  EXPECT_EQ(std::count(high.output.begin(), high.output.end(), '\n'), 6);
}

TEST(ReferenceCommand, BadInputIsExitCode2NamingTheLine) {
  const sglab::test::TempDir dir("reference-bad");
  struct Case {
    const char* name;
    const char* content;
    const char* where;  // must appear in the message
  };
  const Case cases[] = {
      {"negative.csv", "kappa,cosine\n1,0.5\n-2,0.5\n", "negative.csv:3"},
      {"cosine.csv", "kappa,cosine\n1,1.5\n", "cosine.csv:2"},
      {"text.csv", "kappa,cosine\n1,0\n2,0\nabc,0.5\n", "text.csv:4"},
      {"trailing.csv", "kappa,cosine\n1,0.5x\n", "trailing.csv:2"},
      {"missing.csv", "kappa,cosine\n1,0\n3\n", "missing.csv:3"},
      {"empty_field.csv", "kappa,cosine\n1,\n", "empty_field.csv:2"},
      {"extra.csv", "kappa,cosine\n1,0,7\n", "extra.csv:2"},
      {"nan.csv", "kappa,cosine\nnan,0\n", "nan.csv:2"},
      {"inf.csv", "kappa,cosine\ninf,0\n", "inf.csv:2"},
      {"header.csv", "k,c\n1,0\n", "header.csv:1"},
  };
  for (const Case& c : cases) {
    const std::string file = write(dir, c.name, c.content);
    const auto r = sglab_reference(file);
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.output;
    EXPECT_NE(r.output.find(c.where), std::string::npos) << c.name << ": " << r.output;
  }
  const std::string missing = (dir.path / "does-not-exist.csv").string();
  const auto r = sglab_reference(missing);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("does-not-exist.csv"), std::string::npos) << r.output;
}

}  // namespace
