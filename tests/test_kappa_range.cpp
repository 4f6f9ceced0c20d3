// tests/test_kappa_range.cpp — every irradiance method's registry card (sglab::ValidRange: a
// bound on the max peak_rel over c and the κ range it holds on) against the reference engine
// over every κ a float holds, from κ = 0 and the smallest positive float to FLT_MAX, in float
// and double; the card's bound is the method's worst error on the fitted range [1e−3, 1e4] and
// its range ends no earlier than the bound allows. Then the scanner behind `sglab range`
// (validate/kappa_range.hpp) and the command. The reference engine's own large-κ limits are
// checked in tests/test_reference.cpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "reference/reference.hpp"
#include "tests/test_support.hpp"
#include "validate/kappa_range.hpp"

namespace {

using sglab::test::hex;
constexpr float kMax = std::numeric_limits<float>::max();
constexpr float kTiny = std::numeric_limits<float>::denorm_min();

// The cosines at κ: 61 uniform over [−1, 1] and 33 at c = t/√κ, t ∈ [−8, 8] (the layer where
// a sharp light's irradiance turns on, 1/√κ wide), float-exact, sorted, distinct. Written here
// independently of the scanner under test.
std::vector<double> cosines_at(double kappa) {
  std::vector<double> c;
  for (int i = 0; i <= 60; ++i) c.push_back(static_cast<float>(-1.0 + i / 30.0));
  if (kappa > 0)
    for (int i = 0; i <= 32; ++i) {
      const double x = (-8.0 + i * 0.5) / std::sqrt(kappa);
      if (std::abs(x) < 1) c.push_back(static_cast<float>(x));
    }
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  return c;
}

// The worst peak_rel over cosines_at(κ) of every irradiance method, float and double alike
// (+inf on a non-finite output), and where.
struct Worst {
  double peak_rel = 0, cosine = 0;
  bool in_float = false;
};
std::vector<std::vector<Worst>> worst_of_every_method(const std::vector<double>& kappas) {
  std::vector<sglab::reference::Query> q;
  for (double k : kappas)
    for (double c : cosines_at(k)) q.push_back({k, c});
  const auto ref = sglab::reference::reference_engine().evaluate(q);
  std::vector<std::vector<Worst>> out(std::size(sglab::irradiance_methods),
                                      std::vector<Worst>(kappas.size()));
  std::size_t at = 0;
  for (std::size_t i = 0; i < kappas.size(); ++i) {
    const double k = kappas[i],
                 peak = sglab::reference::reference_engine().evaluate(k, 1.0).irradiance;
    const std::size_t n = cosines_at(k).size();
    for (std::size_t m = 0; m < std::size(sglab::irradiance_methods); ++m) {
      const sglab::Method& method = sglab::irradiance_methods[m];
      Worst& w = out[m][i];
      for (std::size_t j = at; j < at + n; ++j) {
        const double c = ref[j].cosine, e = ref[j].irradiance;
        const double vf = method.f32(static_cast<float>(c), static_cast<float>(k));
        const double vd = method.f64(c, k);
        const double ef = std::isfinite(vf) ? std::abs(vf - e) / peak : INFINITY;
        const double ed = std::isfinite(vd) ? std::abs(vd - e) / peak : INFINITY;
        if (!(ef <= w.peak_rel)) w = {ef, c, true};
        if (!(ed <= w.peak_rel)) w = {ed, c, false};
      }
    }
    at += n;
  }
  return out;
}

// The registry index of a method (test parameters are copies: found by id).
std::size_t index_of(const sglab::Method& m) {
  const sglab::Method* it = sglab::find_method(sglab::irradiance_methods, m.id);
  if (!it) throw std::runtime_error("not registered: " + std::string(m.id));
  return static_cast<std::size_t>(it - sglab::irradiance_methods.data());
}

// κ from 0 and the smallest positive float to FLT_MAX, 2 per decade, with 1e−3, 1e4 and every
// card's ends.
const std::vector<double>& every_kappa() {
  static const std::vector<double> k = [] {
    std::vector<double> extra;
    for (const sglab::Method& m : sglab::irradiance_methods)
      extra.insert(extra.end(), {m.valid.kappa_lo, m.valid.kappa_hi});
    return sglab::validate::scan_kappas(2, extra);
  }();
  return k;
}
const std::vector<std::vector<Worst>>& every_worst() {
  static const auto w = worst_of_every_method(every_kappa());
  return w;
}

class Card : public ::testing::TestWithParam<sglab::Method> {};

TEST_P(Card, BoundHoldsOnItsRangeFromZeroToFloatMax) {
  const sglab::Method& m = GetParam();
  const sglab::ValidRange& v = m.valid;
  ASSERT_GT(v.max_peak_rel, 0) << "every irradiance method states its bound";
  ASSERT_LE(v.kappa_lo, v.kappa_hi);
  const auto& kappas = every_kappa();
  ASSERT_EQ(kappas.front(), 0.0);
  ASSERT_NE(std::find(kappas.begin(), kappas.end(), double(kTiny)), kappas.end());
  ASSERT_EQ(kappas.back(), double(kMax));
  const auto& worst = every_worst()[index_of(m)];
  std::size_t checked = 0;
  for (std::size_t i = 0; i < kappas.size(); ++i) {
    if (!v.covers(kappas[i])) continue;
    ++checked;
    EXPECT_LE(worst[i].peak_rel, v.max_peak_rel)
        << m.id << " at kappa " << hex(kappas[i]) << " c " << hex(worst[i].cosine) << " ("
        << (worst[i].in_float ? "float" : "double") << "), its card: max peak_rel "
        << v.max_peak_rel << " on [" << v.kappa_lo << ", " << v.kappa_hi << "]";
  }
  EXPECT_GE(checked, 30u);  // at the very least [1e-3, 1e4] at 2 per decade
}

// Where a card's range stops short of 0 or of FLT_MAX, the bound fails within a factor 1.25
// beyond the end: the stated range is the measured one rounded inward to two digits, not less.
TEST(CardRange, EndsWhereTheBoundFails) {
  std::size_t ends = 0;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    const sglab::ValidRange& v = m.valid;
    for (const bool upper : {true, false}) {
      if (upper ? v.kappa_hi == kMax : v.kappa_lo == 0) continue;
      ++ends;
      std::vector<double> beyond;
      for (int i = 1; i <= 16; ++i)
        beyond.push_back(static_cast<float>(upper ? v.kappa_hi * std::pow(1.25, i / 16.0)
                                                  : v.kappa_lo / std::pow(1.25, i / 16.0)));
      const auto worst = worst_of_every_method(beyond)[index_of(m)];
      EXPECT_TRUE(std::any_of(worst.begin(), worst.end(),
                              [&](const Worst& w) { return !(w.peak_rel <= v.max_peak_rel); }))
          << m.id << ": the bound " << v.max_peak_rel << " still holds "
          << (upper ? "to " : "from ") << (upper ? v.kappa_hi * 1.25 : v.kappa_lo / 1.25)
          << ": the range stated " << (upper ? "ends too early" : "starts too late");
    }
  }
  EXPECT_GE(ends, 5u);  // punctual, hill, hill_exact below; meder2018, sglab_fast above
}

// The bound is the method's worst error over the fitted range: it holds on a grid finer than
// the sweep's (24 κ per decade, 201 + 33 cosines), and the worst there is within 25 % of it (a
// bound far above the error would let a worse model through: a changed coefficient, say).
TEST(CardBound, IsTheWorstErrorOnTheFittedRange) {
  std::vector<double> kappas;
  for (int i = 0; i <= 168; ++i)
    kappas.push_back(static_cast<float>(std::pow(10.0, -3 + i / 24.0)));
  const auto worst = worst_of_every_method(kappas);
  for (const sglab::Method& m : sglab::irradiance_methods) {
    const auto& w = worst[index_of(m)];
    const auto it = std::max_element(
        w.begin(), w.end(), [](const Worst& a, const Worst& b) { return a.peak_rel < b.peak_rel; });
    const double kappa = kappas[static_cast<std::size_t>(it - w.begin())];
    EXPECT_LE(it->peak_rel, m.valid.max_peak_rel)
        << m.id << " at kappa " << hex(kappa) << " c " << hex(it->cosine);
    EXPECT_GE(it->peak_rel, m.valid.max_peak_rel / 1.25)
        << m.id << ": its card's bound " << m.valid.max_peak_rel
        << " is far above its worst error on [1e-3, 1e4]";
  }
}

using sglab::test::method_name;
INSTANTIATE_TEST_SUITE_P(Registry, Card, ::testing::ValuesIn(sglab::irradiance_methods),
                         method_name);

// ---- the scanner -------------------------------------------------------------

TEST(KappaScan, KappasSpanEveryFloatWithTheFittedEnds) {
  const std::vector<double> extra = {5.5, 5.5, -1.0, 1e39};
  const auto k = sglab::validate::scan_kappas(3, extra);
  EXPECT_EQ(k.front(), 0.0);
  EXPECT_EQ(k[1], double(kTiny));
  EXPECT_EQ(k.back(), double(kMax));
  for (double x : {double(float(1e-3)), double(float(1e4)), 5.5})
    EXPECT_EQ(std::count(k.begin(), k.end(), x), 1) << x;
  EXPECT_TRUE(std::is_sorted(k.begin(), k.end()));
  EXPECT_EQ(std::adjacent_find(k.begin(), k.end()), k.end()) << "duplicates";
  for (double x : k) EXPECT_EQ(x, double(float(x))) << "not float-exact: " << x;
  // 3 per decade over the 83.4 decades of the positive floats, the three extra values
  // (0, 1e-3, 1e4; 5.5) and nothing for the out-of-range extras.
  EXPECT_NEAR(double(k.size()), 3 * 83.4 + 5, 2.0);
}

// A method that is the reference plus a bump of known height at a known cosine: the exact
// worst is known, so the scan's search is checked by what it finds.
constexpr double kBump = 1e-3;
double reference_plus_bump(double c, double kappa, double t0) {
  const auto& engine = sglab::reference::reference_engine();
  const double peak = engine.evaluate(kappa, 1.0).irradiance;
  // bump at c = t0/√κ for κ ≥ 1, at c = t0/8 below; width 0.1 in t (or in c/8)
  const double t = kappa >= 1 ? c * std::sqrt(kappa) : 8 * c;
  return engine.evaluate(kappa, c).irradiance +
         kBump * peak * std::exp(-(t - t0) * (t - t0) / 0.02);
}
sglab::Method bump_method(double (*f64)(double, double), float (*f32)(float, float)) {
  return sglab::Method{{.id = "bump",
                        .origin = sglab::Origin::sglab,
                        .source = "test",
                        .valid = {.max_peak_rel = 2e-3}},
                       f32,
                       f64,
                       nullptr,
                       nullptr};
}

// At κ = 1e10 the bump sits at c = 2.5/√κ = 2.5e-5, between the uniform cosines: only the
// layer c = t/√κ finds it.
TEST(KappaScan, TheLayerFindsASharpLightsError) {
  const sglab::Method m =
      bump_method([](double c, double k) { return reference_plus_bump(c, k, 2.5); },
                  [](float c, float k) { return float(reference_plus_bump(c, k, 2.5)); });
  sglab::validate::KappaScanOptions o;
  o.per_decade = 1;
  o.cosines = 41;
  o.refine = false;
  o.progress = false;
  o.extra_kappas = {1e10};
  const auto at = [](const sglab::validate::KappaScan& s, double kappa) {
    const auto it = std::find(s.kappas.begin(), s.kappas.end(), double(float(kappa)));
    return s.methods[0].worst(static_cast<std::size_t>(it - s.kappas.begin()));
  };
  o.layer = 129;  // t steps of 1/8: 2.5 is on it
  EXPECT_NEAR(at(scan_kappa_range(std::span(&m, 1), o), 1e10), kBump, 1e-5);
  o.layer = 0;
  EXPECT_LT(at(scan_kappa_range(std::span(&m, 1), o), 1e10), kBump / 100);
}

// At κ = 1 (the bump at c = 0.37) three cosines −1, 0, 1 see only its tail; Brent's method
// between the neighbours of the worst of them finds its top.
TEST(KappaScan, RefinementFindsTheWorstCosineBetweenGridCosines) {
  const sglab::Method m =
      bump_method([](double c, double k) { return reference_plus_bump(c, k, 0.37); },
                  [](float c, float k) { return float(reference_plus_bump(c, k, 0.37)); });
  sglab::validate::KappaScanOptions o;
  o.per_decade = 1;
  o.cosines = 3;
  o.layer = 0;
  o.progress = false;
  o.extra_kappas = {1.0};
  const auto worst_at_one = [&](const sglab::validate::KappaScan& s) {
    const auto it = std::find(s.kappas.begin(), s.kappas.end(), 1.0);
    return s.methods[0].f64[static_cast<std::size_t>(it - s.kappas.begin())];
  };
  o.refine = false;
  EXPECT_LT(worst_at_one(scan_kappa_range(std::span(&m, 1), o)).peak_rel, kBump / 100);
  o.refine = true;
  const auto w = worst_at_one(scan_kappa_range(std::span(&m, 1), o));
  EXPECT_NEAR(w.peak_rel, kBump, 2e-5);
  EXPECT_NEAR(w.cosine, 0.37, 1e-3);
}

// holds_on and worst_over on a scan made by hand.
TEST(KappaScan, HoldsOnIsTheLargestRunAroundTheRangeAndWorstOverItsMax) {
  sglab::validate::KappaScan s;
  s.kappas = {0, 1, 2, 3, 4, 5, 6};
  sglab::validate::MethodScan m;
  m.id = "hand";
  const double f[] = {0.5, 3.0, 1.0, 1.0, 2.0, 1.0, 0.5};
  const double d[] = {0.5, 0.5, 1.0, 1.5, 1.0, 1.0, 3.0};
  for (int i = 0; i < 7; ++i) {
    m.f32.push_back({f[i], 0.1 * i});
    m.f64.push_back({d[i], -0.1 * i});
  }
  EXPECT_EQ(m.worst(1), 3.0);
  EXPECT_EQ(m.worst(6), 3.0);
  const auto h = holds_on(s, m, 2.0, 2, 3);
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->lo, 2);  // κ = 1 fails in float
  EXPECT_EQ(h->hi, 5);  // κ = 6 fails in double; κ = 4 holds at the bound itself
  EXPECT_FALSE(holds_on(s, m, 1.2, 2, 4).has_value());  // fails at κ = 3, 4 inside
  EXPECT_FALSE(holds_on(s, m, 9.0, 7, 8).has_value());  // no scanned κ in [7, 8]
  const auto everywhere = holds_on(s, m, 3.0, 2, 3);
  ASSERT_TRUE(everywhere.has_value());
  EXPECT_EQ(everywhere->lo, 0);
  EXPECT_EQ(everywhere->hi, 6);
  const auto w = worst_over(s, m, 2, 5);
  EXPECT_EQ(w.peak_rel, 2.0);
  EXPECT_EQ(w.kappa, 4);
  EXPECT_DOUBLE_EQ(w.cosine, 0.4);  // the float one
  const auto w2 = worst_over(s, m, 2, 3);
  EXPECT_EQ(w2.peak_rel, 1.5);
  EXPECT_DOUBLE_EQ(w2.cosine, -0.3);  // the double one
}

// The table says "NO" where a card's bound fails on its range, and the extent where it holds.
TEST(KappaScan, TableJudgesEachCard) {
  sglab::Method ok =
      bump_method([](double c, double k) { return reference_plus_bump(c, k, 0.37); },
                  [](float c, float k) { return float(reference_plus_bump(c, k, 0.37)); });
  ok.id = "ok";
  sglab::Method tight = ok;
  tight.id = "tight";
  tight.valid.max_peak_rel = 5e-4;  // below the bump's 1e-3
  const sglab::Method both[] = {ok, tight};
  sglab::validate::KappaScanOptions o;
  o.per_decade = 1;
  o.cosines = 41;
  o.layer = 9;
  o.progress = false;
  const auto scan = scan_kappa_range(both, o);
  const auto t = kappa_range_table(scan, both, o);
  ASSERT_EQ(t.rows().size(), 2u);
  const std::size_t holds = t.column_index("holds"), max = t.column_index("max_peak_rel");
  EXPECT_EQ(std::get<std::string>(t.rows()[0][holds]), "yes");
  EXPECT_EQ(std::get<std::string>(t.rows()[1][holds]), "NO");
  EXPECT_NEAR(std::get<double>(t.rows()[0][max]), kBump, 1e-4);
  EXPECT_TRUE(std::isnan(std::get<double>(t.rows()[1][t.column_index("holds_from")])));
  const sglab::Method other[] = {sglab::irradiance_methods[0]};
  EXPECT_THROW(kappa_range_table(scan, other, o), std::invalid_argument);
  o.per_decade = 0;
  EXPECT_THROW(scan_kappa_range(both, o), std::invalid_argument);
}

// `sglab range`: the table written and printed, exit 0 when every card holds; bad options
// exit 2 before any work.
TEST(RangeCommand, WritesTheTableAndChecksItsOptions) {
  sglab::test::TempDir dir("range");
  const std::string out = (dir.path / "out").string();
  const auto r = sglab::test::run_program({SGLAB_BINARY, "range", "--per-decade", "1", "--cosines",
                                           "21", "--layer", "9", "--no-refine", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| sglab_mid | sglab |"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.path / "out" / "kappa_range.csv"));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.path / "out" / "kappa_range.md"));
  for (const char* bad : {"0", "1001", "x"}) {
    const auto b =
        sglab::test::run_program({SGLAB_BINARY, "range", "--per-decade", bad, "--out", out});
    EXPECT_EQ(b.exit_code, 2) << bad << ": " << b.output;
  }
  std::ofstream(dir.path / "file") << "x";
  const auto f =
      sglab::test::run_program({SGLAB_BINARY, "range", "--out", (dir.path / "file").string()});
  EXPECT_EQ(f.exit_code, 2) << f.output;
  EXPECT_NE(f.output.find("file"), std::string::npos) << f.output;
}

}  // namespace
