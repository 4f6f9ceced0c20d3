// tests/test_methods.cpp — the runtime properties of every irradiance method of
// the registry (include/sglab/registry.hpp), one suite per property
// parameterized over the registry, each bound read from the committed table
// tests/tolerances.hpp (a method without a row fails): float against double,
// the float batch against the double, the per-light split against the plain
// function, and the error against the reference engine on random points (the
// bound of the method's registry card).
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "reference/reference.hpp"
#include "tests/random_points.hpp"
#include "tests/test_support.hpp"
#include "tests/tolerances.hpp"

namespace {

using sglab::test::find_tolerance;
using sglab::test::hex;
using sglab::test::kNone;
using sglab::test::Precision;
using sglab::test::Quantity;
using sglab::test::random_points;
using sglab::test::Tolerance;

// The row of (method, quantity, precision); fails the test when there is none.
const Tolerance& row(const sglab::Method& m, Quantity q, Precision p = Precision::float32) {
  const Tolerance* t = find_tolerance(m.id, q, p);
  if (!t)
    throw std::runtime_error(
        fmt::format("tests/tolerances.hpp has no row for {} {} {}: add one with its reason", m.id,
                    to_string(q), to_string(p)));
  return *t;
}

class Registry : public ::testing::TestWithParam<sglab::Method> {};

// ---- float_vs_double --------------------------------------------------------

class FloatVsDouble : public Registry {};

TEST_P(FloatVsDouble, WithinTheTable) {
  const sglab::Method& m = GetParam();
  const Tolerance& t = row(m, Quantity::float_vs_double);
  ASSERT_GT(t.bound, 0) << "every method has a float path";
  for (double kappa : sglab::test::standard_kappas()) {
    if (kappa < t.kappa_from) continue;
    const float kf = static_cast<float>(kappa);
    const double peak = sglab::irradiance_upper(double(kf));
    for (double c : sglab::test::standard_cosines()) {
      const float cf = static_cast<float>(c);
      const double v64 = m.f64(cf, kf);
      EXPECT_LE(std::abs(double(m.f32(cf, kf)) - v64), t.bound * std::max(peak, std::abs(v64)))
          << t.reason << "; kappa " << hex(kf) << " c " << hex(cf);
    }
  }
}

// ---- batch_vs_double --------------------------------------------------------

// 2^20 random inputs (κ log-uniform in [1e-3, 1e4], c uniform), the standard
// sweep, and edge κ from 0 to FLT_MAX.
struct FloatPoints {
  std::vector<float> cosine, kappa;
};
const FloatPoints& batch_points() {
  static const FloatPoints points = [] {
    FloatPoints p;
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < (1 << 20); ++i) {
      p.kappa.push_back(static_cast<float>(std::pow(10.0, -3 + 7 * u(rng))));
      p.cosine.push_back(static_cast<float>(-1 + 2 * u(rng)));
    }
    for (double kappa : sglab::test::standard_kappas())
      for (double cosine : sglab::test::standard_cosines()) {
        p.kappa.push_back(static_cast<float>(kappa));
        p.cosine.push_back(static_cast<float>(cosine));
      }
    for (float kappa : {0.0f, 1e-30f, 0.25f, std::nextafter(0.25f, 0.0f), 0.99999994f, 1.0f, 80.0f,
                        1e4f, 1e20f, 1e30f, std::numeric_limits<float>::max()})
      for (float cosine : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f}) {
        p.kappa.push_back(kappa);
        p.cosine.push_back(cosine);
      }
    return p;
  }();
  return points;
}

class BatchVsDouble : public Registry {};

TEST_P(BatchVsDouble, WithinTheTable) {
  const sglab::Method& m = GetParam();
  const Tolerance& t = row(m, Quantity::batch_vs_double);
  const FloatPoints& p = batch_points();
  std::vector<float> out(p.kappa.size());
  m.batch32(p.cosine.data(), p.kappa.data(), out.data(), out.size());
  double worst_batch = 0, worst_scalar = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float c = p.cosine[i], k = p.kappa[i], scalar = m.f32(c, k);
    if (t.bound == kNone) {  // batch32 is f32 element by element
      ASSERT_TRUE(out[i] == scalar || (std::isnan(out[i]) && std::isnan(scalar)))
          << t.reason << "; kappa " << hex(k) << " c " << hex(c) << " batch " << hex(out[i])
          << " scalar " << hex(scalar);
      continue;
    }
    const double want = m.f64(c, k), peak = sglab::irradiance_upper(double(k));
    ASSERT_TRUE(std::isfinite(out[i])) << hex(k) << " " << hex(c);
    const double e = std::abs(out[i] - want) / peak;
    ASSERT_LE(e, t.bound) << t.reason << "; kappa " << hex(k) << " c " << hex(c) << " batch "
                          << out[i] << " double " << want;
    worst_batch = std::max(worst_batch, e);
    worst_scalar = std::max(worst_scalar, std::abs(scalar - want) / peak);
  }
  EXPECT_LE(worst_scalar, std::max(t.bound, 0.0)) << t.reason;
  RecordProperty("max_batch_error_over_peak", std::to_string(worst_batch));
}

// ---- split_vs_plain ---------------------------------------------------------

class LightSplit : public Registry {};

TEST_P(LightSplit, EqualsThePlainFloatFunction) {
  const sglab::Method& m = GetParam();
  const Tolerance& t = row(m, Quantity::split_vs_plain);
  if (t.bound == kNone) {
    EXPECT_EQ(m.light_setup32, nullptr)
        << "the registry has a split the table says is absent: " << t.reason;
    EXPECT_EQ(m.light_eval32, nullptr)
        << "the registry has a split the table says is absent: " << t.reason;
    return;
  }
  ASSERT_NE(m.light_setup32, nullptr) << "the table bounds a split the registry does not have";
  ASSERT_NE(m.light_eval32, nullptr) << "setup and eval come together";
  std::vector<sglab::reference::Query> points = random_points(4000, 5);
  for (double kappa : sglab::test::standard_kappas())
    for (double cosine : sglab::test::standard_cosines()) points.push_back({kappa, cosine});
  for (const auto& q : points) {
    const float k = static_cast<float>(q.kappa), c = static_cast<float>(q.cosine);
    float state[sglab::kLightStateFloats];
    m.light_setup32(k, state);
    const float split = m.light_eval32(state, c), plain = m.f32(c, k);
    ASSERT_LE(std::abs(split - plain), t.bound * sglab::irradiance_upper(q.kappa))
        << t.reason << "; kappa " << hex(k) << " c " << hex(c) << " split " << hex(split)
        << " plain " << hex(plain);
  }
}

// ---- peak_rel ---------------------------------------------------------------

class PeakRel : public Registry {};

TEST_P(PeakRel, AgainstTheReferenceOnPointsNoFitSaw) {
  const sglab::Method& m = GetParam();
  // The stated bound on the method's registry card (its κ range is held from 0 to FLT_MAX by
  // tests/test_kappa_range.cpp; every card covers [1e-3, 1e4]).
  const double bound = m.valid.max_peak_rel;
  ASSERT_GT(bound, 0) << m.id << " states no bound";
  ASSERT_TRUE(m.valid.covers(1e-3, 1e4)) << m.id;
  const auto ref = sglab::reference::reference_engine().evaluate(random_points(6000, 20261201));
  double worst_f = 0, worst_d = 0;
  std::size_t at_f = 0, at_d = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const double peak = sglab::irradiance_upper(ref[i].kappa);
    const double ef =
        std::abs(double(m.f32(float(ref[i].cosine), float(ref[i].kappa))) - ref[i].irradiance) /
        peak;
    const double ed = std::abs(m.f64(ref[i].cosine, ref[i].kappa) - ref[i].irradiance) / peak;
    if (!(ef <= worst_f)) worst_f = ef, at_f = i;
    if (!(ed <= worst_d)) worst_d = ed, at_d = i;
  }
  RecordProperty("max_peak_rel_float", std::to_string(worst_f));
  RecordProperty("max_peak_rel_double", std::to_string(worst_d));
  EXPECT_LE(worst_f, bound) << m.id << "; float worst at kappa=" << hex(ref[at_f].kappa)
                            << " c=" << hex(ref[at_f].cosine);
  EXPECT_LE(worst_d, bound) << m.id << "; double worst at kappa=" << hex(ref[at_d].kappa)
                            << " c=" << hex(ref[at_d].cosine);
  // Not trivially exact either: an error far below the bound would mean the
  // model and the reference are the same code, or a stale bound.
  EXPECT_GT(worst_d, 1e-3 * bound);
}

using sglab::test::method_name;

INSTANTIATE_TEST_SUITE_P(Registry, FloatVsDouble, ::testing::ValuesIn(sglab::irradiance_methods),
                         method_name);
INSTANTIATE_TEST_SUITE_P(Registry, BatchVsDouble, ::testing::ValuesIn(sglab::irradiance_methods),
                         method_name);
INSTANTIATE_TEST_SUITE_P(Registry, LightSplit, ::testing::ValuesIn(sglab::irradiance_methods),
                         method_name);
INSTANTIATE_TEST_SUITE_P(Registry, PeakRel, ::testing::ValuesIn(sglab::irradiance_methods),
                         method_name);

// ---- the table itself ---------------------------------------------------------

TEST(ToleranceTable, EveryRowNamesARegisteredMethodOnceWithAReason) {
  std::set<std::string> seen;
  for (const Tolerance& t : sglab::test::kTolerances) {
    const std::string key =
        fmt::format("{} {} {}", t.method, to_string(t.quantity), to_string(t.precision));
    EXPECT_NE(sglab::find_method(sglab::irradiance_methods, t.method), nullptr)
        << "stale row: " << key;
    EXPECT_TRUE(seen.insert(key).second) << "duplicate row: " << key;
    EXPECT_FALSE(t.reason.empty()) << key;
    EXPECT_TRUE(t.bound == kNone || t.bound > 0) << key;
  }
}

// Every registered method has a row for every quantity (the half ones are
// checked by tests/test_half_precision.cpp on a Vulkan device, so their rows
// are required here, where no device is needed).
TEST(ToleranceTable, EveryMethodHasARowForEveryQuantity) {
  const std::pair<Quantity, Precision> quantities[] = {
      {Quantity::float_vs_double, Precision::float32},
      {Quantity::batch_vs_double, Precision::float32},
      {Quantity::split_vs_plain, Precision::float32},
      {Quantity::half_peak_rel, Precision::float16},
      {Quantity::half_vs_float, Precision::float16}};
  for (const sglab::Method& m : sglab::irradiance_methods)
    for (const auto& [q, p] : quantities)
      EXPECT_NE(find_tolerance(m.id, q, p), nullptr)
          << "tests/tolerances.hpp has no row for " << m.id << " " << to_string(q) << " "
          << to_string(p) << ": add one with its reason";
}

}  // namespace
