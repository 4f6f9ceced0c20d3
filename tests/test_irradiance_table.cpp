// The irradiance table (reference/irradiance_table.hpp) against its truth, the
// reference quadrature, at points no interpolant used: the grid between the
// nodes of every piece with its edges, random points over κ ∈ [1e−8, 1e14],
// the narrow horizon at large κ, the piece boundaries, κ → 0 and the largest
// doubles. Then the closed forms at c = ±1 and 0 in 50-digit arithmetic, the
// two facts the construction rests on (the odd part c·M(κ) and the tail
// beyond a_max, both checked on the quadrature), the argument checks, and
// concurrent first use.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/bessel.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "reference/irradiance_table.hpp"
#include "reference/reference.hpp"
#include "sglab/closed_forms.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::reference::check_irradiance_table;
using sglab::reference::irradiance_odd_slope;
using sglab::reference::irradiance_table;
using sglab::reference::irradiance_table_check_points;
using sglab::reference::irradiance_table_cosine_range;
using sglab::reference::IrradianceTable;
using sglab::reference::IrradianceTableCheck;
using sglab::reference::kIrradianceTableBound;
using sglab::reference::Query;
using sglab::reference::ReferenceEngine;
using sglab::test::hex;
using mp = boost::multiprecision::cpp_bin_float_50;

// What the layout achieves (the dense check, `sglab reference --check-table`,
// finds ~5e−15): a thousandth of the stated bound, so that a degraded piece
// fails here long before it reaches kIrradianceTableBound.
constexpr double kAchieved = 1e-13;
constexpr double kDoubleMax = std::numeric_limits<double>::max();

void expect_within(const IrradianceTableCheck& r, const char* what) {
  EXPECT_GT(r.points, 0u) << what;
  EXPECT_LE(r.max_error, kAchieved)
      << what << ": worst at κ=" << hex(r.worst_kappa) << " c=" << hex(r.worst_cosine);
  EXPECT_LE(r.max_error, kIrradianceTableBound) << what;
}

// The second-kind grid of every piece (its edges, c = 0 and c = ±a_max, and
// the midpoints between nodes), both signs of c.
TEST(IrradianceTable, BetweenTheNodesOfEveryPiece) {
  const auto points = irradiance_table_check_points(1);
  for (const IrradianceTable::Piece& p : irradiance_table().pieces()) {
    std::vector<Query> mine;
    for (const Query& q : points)
      if (&irradiance_table().piece_of(q.kappa) == &p) mine.push_back(q);
    const IrradianceTableCheck r = check_irradiance_table(mine);
    expect_within(r, fmt::format("piece [{}, {}]", p.kappa_lo, p.kappa_hi).c_str());
  }
}

// Random points over the whole κ range, log-uniform, with c uniform.
TEST(IrradianceTable, RandomPointsOverEveryKappa) {
  std::mt19937_64 rng(36);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Query> q;
  for (int i = 0; i < 1500; ++i)
    q.push_back({std::pow(10.0, -8 + 22 * unit(rng)), -1 + 2 * unit(rng)});
  expect_within(check_irradiance_table(q), "random");
}

// The narrow transition near c = 0 at large κ, c = ±t/√κ over t ∈ [0, 10]
// (beyond a_max = 8/√κ the shadow side is dropped).
TEST(IrradianceTable, HorizonAtLargeKappa) {
  std::vector<Query> q;
  for (double kappa : {70.0, 300.0, 1000.0, 1024.0, 5e3, 1e5, 3.3e7, 1e12, 1e20, 3.4e38})
    for (int i = 0; i <= 100; ++i) {
      const double c = std::min(1.0, (i / 10.0 + 0.0123) / std::sqrt(kappa));
      q.push_back({kappa, c});
      q.push_back({kappa, -c});
    }
  expect_within(check_irradiance_table(q), "horizon");
}

// κ at and next to every piece boundary, κ → 0, and the largest κ.
TEST(IrradianceTable, PieceBoundariesAndTheEndsOfTheKappaRange) {
  std::vector<double> kappas = {0,
                                5e-324,
                                1e-300,
                                1e-30,
                                1e-10,
                                1e-4,
                                1e30,
                                1e100,
                                1e200,
                                1e300,
                                3.4028234663852886e38,
                                kDoubleMax};
  for (const IrradianceTable::Piece& p : irradiance_table().pieces())
    for (double k : {p.kappa_lo, p.kappa_hi})
      if (std::isfinite(k) && k > 0)
        for (double x : {std::nextafter(k, 0.0), k, std::nextafter(k, kDoubleMax)})
          kappas.push_back(x);
  std::vector<Query> q;
  for (double k : kappas)
    for (int i = 0; i <= 40; ++i) {
      const double a = irradiance_table_cosine_range(k) * i / 40;
      q.push_back({k, a});
      q.push_back({k, -a});
    }
  expect_within(check_irradiance_table(q), "boundaries and ends");
}

// The closed forms of docs/quantities.md at c = ±1, and at c = 0
// E(0, κ) = 2π e^{−κ} I1(κ)/κ (with r = 1, u du = −ρ dρ and ∫ x I0(x) dx = x I1(x)),
// in 50-digit arithmetic.
TEST(IrradianceTable, ClosedFormsAtThePolesAndTheEquator) {
  const mp two_pi = 2 * boost::math::constants::pi<mp>();
  for (double kappa :
       {1e-9, 1e-3, 0.3, 0.999, 1.0, 2.0, 7.7, 40.0, 64.0, 150.0, 700.0, 1e3, 5e3, 1e5, 1e9}) {
    const mp k = kappa, em = exp(-k);
    const mp e_plus = two_pi * (k - 1 + em) / (k * k);
    const mp e_minus = two_pi * em * (1 - em - k * em) / (k * k);
    const double peak = static_cast<double>(e_plus);
    const double tolerance = kAchieved * peak;
    const auto& table = irradiance_table();
    EXPECT_NEAR(table.irradiance(kappa, 1.0), peak, tolerance) << "E(1, κ) at κ=" << kappa;
    EXPECT_NEAR(table.irradiance(kappa, -1.0), static_cast<double>(e_minus), tolerance)
        << "E(−1, κ) at κ=" << kappa;
    if (kappa <= 1e5) {
      const mp e_zero = two_pi * em * boost::math::cyl_bessel_i(1, k) / k;
      EXPECT_NEAR(table.irradiance(kappa, 0.0), static_cast<double>(e_zero), tolerance)
          << "E(0, κ) at κ=" << kappa;
    }
    // The closed forms the table itself uses, relative to themselves.
    EXPECT_NEAR(sglab::irradiance_upper(kappa) / peak, 1.0, 1e-15) << "E(1, κ) at κ=" << kappa;
    const double slope = static_cast<double>(e_plus - e_minus);
    EXPECT_NEAR(irradiance_odd_slope(kappa) / slope, 1.0, 1e-15) << "M(κ) at κ=" << kappa;
  }
  // κ = 0: E ≡ π.
  for (double c : {-1.0, -0.3, 0.0, 0.5, 1.0})
    EXPECT_NEAR(irradiance_table().irradiance(0, c), std::numbers::pi, kAchieved * 4) << c;
}

// The odd part (irradiance_table.hpp, step 1) on the quadrature:
// E(c, κ) − E(−c, κ) = c·M(κ).
TEST(IrradianceTable, OddPartIsLinearInTheCosine) {
  const ReferenceEngine engine;
  for (double kappa : {1e-4, 0.5, 3.0, 30.0, 500.0, 1e5})
    for (double c : {0.05, 0.3, 0.7, 0.99}) {
      const double odd =
          engine.evaluate(kappa, c).irradiance - engine.evaluate(kappa, -c).irradiance;
      EXPECT_NEAR(odd, c * irradiance_odd_slope(kappa), 2e-15 * sglab::irradiance_upper(kappa))
          << "κ=" << kappa << " c=" << c;
    }
}

// The tail (step 2) on the quadrature: E(·, κ) is nondecreasing in c, and at
// c = −a_max(κ) it is below 1e−16 of the peak, for κ from a_max < 1 on.
TEST(IrradianceTable, ShadowBeyondTheRangeIsBelowTheBound) {
  const ReferenceEngine engine;
  for (double kappa : {64.0, 64.5, 100.0, 1e3, 1e4, 1e6, 1e10, 1e15, 1e30, 1e300}) {
    const double a_max = irradiance_table_cosine_range(kappa);
    ASSERT_LE(a_max, 1.0);
    const double peak = sglab::irradiance_upper(kappa);
    EXPECT_LE(engine.evaluate(kappa, -a_max).irradiance, 1e-16 * peak) << "κ=" << kappa;
    double previous = 0;
    for (int i = 0; i <= 64; ++i) {
      const double c = -std::min(1.0, a_max * (1 + i / 8.0));
      const double e = engine.evaluate(kappa, c).irradiance;
      EXPECT_LE(e, engine.evaluate(kappa, -a_max).irradiance) << "κ=" << kappa << " c=" << c;
      if (i > 0) {
        EXPECT_LE(e, previous) << "κ=" << kappa << " c=" << c;
      }
      previous = e;
    }
  }
}

TEST(IrradianceTable, RefusesInvalidArguments) {
  const auto& table = irradiance_table();
  for (double k : {-1.0, -1e-300, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(table.slice(k), std::invalid_argument) << k;
  for (double c :
       {-1.0000000000000002, 1.0000000000000002, std::numeric_limits<double>::quiet_NaN(), 2.0})
    EXPECT_THROW(table.irradiance(1.0, c), std::invalid_argument) << c;
  EXPECT_THROW(irradiance_table_check_points(2), std::invalid_argument);
  EXPECT_THROW(irradiance_table_check_points(0), std::invalid_argument);
}

// No check point is a node (the check measures the interpolant where it
// interpolates, never where it was forced to agree): the nodes (κ, ±a) are
// rebuilt from the pieces as the table places them.
TEST(IrradianceTable, CheckPointsAreNotNodes) {
  std::vector<std::pair<double, double>> nodes;
  for (const IrradianceTable::Piece& p : irradiance_table().pieces())
    for (int i = 0; i < p.kappa_nodes; ++i) {
      const double k = p.kappa_at(std::cos(std::numbers::pi * (i + 0.5) / p.kappa_nodes));
      for (int j = 0; j < p.cosine_nodes; ++j)
        nodes.emplace_back(k, IrradianceTable::Piece::cosine_at(
                                  k, std::cos(std::numbers::pi * (j + 0.5) / p.cosine_nodes)));
    }
  std::sort(nodes.begin(), nodes.end());
  for (int oversample : {1, 3, 5})
    for (const Query& q : irradiance_table_check_points(oversample))
      EXPECT_FALSE(std::binary_search(nodes.begin(), nodes.end(),
                                      std::pair<double, double>(q.kappa, std::abs(q.cosine))))
          << "oversample " << oversample << ": κ=" << hex(q.kappa) << " c=" << hex(q.cosine);
}

// Built once, from many threads at once (plain threads and TBB tasks); every
// build gives the same coefficients (the quadrature is deterministic).
TEST(IrradianceTable, ConcurrentFirstUse) {
  std::vector<double> seen(8, 0.0);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < 4; ++i)
    threads.emplace_back([&seen, i] { seen[i] = irradiance_table().irradiance(100.0, 0.01); });
  tbb::parallel_for(std::size_t{4}, std::size_t{8},
                    [&](std::size_t i) { seen[i] = irradiance_table().irradiance(100.0, 0.01); });
  for (auto& t : threads) t.join();
  for (double x : seen) EXPECT_EQ(x, seen[0]);
  const IrradianceTable again;
  ASSERT_EQ(again.pieces().size(), irradiance_table().pieces().size());
  for (std::size_t p = 0; p < again.pieces().size(); ++p)
    EXPECT_EQ(again.pieces()[p].coefficients, irradiance_table().pieces()[p].coefficients) << p;
}

}  // namespace
