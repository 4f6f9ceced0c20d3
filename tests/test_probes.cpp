// Probes (envmap/probe.hpp): the dense error, spherical harmonics, ZH3 and
// SG lobes against closed forms on small synthetic maps.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "envmap/probe.hpp"
#include "reference/scene.hpp"
#include "tests/map_of.hpp"

namespace {

using namespace sglab;
using envmap::Map;
using envmap::Probe;
using envmap::Vec3;

using sglab::test::map_of;

std::vector<Vec3> random_normals(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> out;
  for (std::size_t k = 0; k < n; ++k) {
    Vec3 v{g(rng), g(rng), g(rng)};
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    out.push_back({v[0] / len, v[1] / len, v[2] / len});
  }
  return out;
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

TEST(Probes, TiledIrradianceOfAConstantMapIsPiL) {
  const Vec3 radiance{1.5, 0.25, 3.0};
  const Map m = map_of(128, [&](const Vec3&) { return radiance; });
  const envmap::MapIrradiance field(m);
  // Exact but for the sub-pixels n's horizon cuts (as envmap::irradiance: 8.4e−7 at this size).
  for (const Vec3& n : random_normals(200, 1))
    for (std::size_t ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(field.at(n)[ch], M_PI * radiance[ch], 2e-6 * M_PI * radiance[ch]);
  // At the poles the horizon runs along pixel edges: exact to rounding.
  for (std::size_t ch = 0; ch < 3; ++ch)
    EXPECT_NEAR(field.at(Vec3{0, 0, -1})[ch], M_PI * radiance[ch], 1e-12 * M_PI * radiance[ch]);
}

TEST(Probes, TiledIrradianceMatchesThePixelSum) {
  // A map with detail at every scale: the tiles' shortcut and the per-pixel sum agree.
  const Map m = map_of(96, [](const Vec3& w) {
    const double s = 1 + std::sin(9 * w[0]) * std::cos(7 * w[1]) + 2 * std::exp(30 * (w[2] - 1));
    return Vec3{s, 0.5 * s + w[0] * w[0], 1.0};
  });
  const envmap::MapIrradiance field(m);
  const auto normals = random_normals(100, 2);
  const auto tiled = field.at(normals);
  // The per-pixel sum: every pixel's exact weight, by sub-pixel moments.
  for (std::size_t k = 0; k < normals.size(); ++k) {
    Vec3 ref{0, 0, 0};
    for (std::size_t j = 0; j < m.height; ++j)
      for (std::size_t i = 0; i < m.width; ++i) {
        // 16 × 16 sub-pixels with their own centre direction and solid angle.
        double w = 0;
        const double t0 = M_PI * static_cast<double>(j) / static_cast<double>(m.height);
        const double p0 = 2 * M_PI * static_cast<double>(i) / static_cast<double>(m.width);
        const double dt = M_PI / static_cast<double>(m.height) / 16;
        const double dp = 2 * M_PI / static_cast<double>(m.width) / 16;
        for (int a = 0; a < 16; ++a)
          for (int b = 0; b < 16; ++b) {
            const double th = t0 + (a + 0.5) * dt, ph = p0 + (b + 0.5) * dp;
            const Vec3 om{std::sin(th) * std::cos(ph), -std::sin(th) * std::sin(ph), std::cos(th)};
            const double solid = (std::cos(th - dt / 2) - std::cos(th + dt / 2)) * dp;
            w += std::max(0.0, dot(om, normals[k])) * solid;
          }
        for (std::size_t ch = 0; ch < 3; ++ch) ref[ch] += w * m.at(i, j, ch);
      }
    // Midpoint sub-pixels: O(Δ²) of the sub-pixel, ~1e−5 of E here.
    for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(tiled[k][ch], ref[ch], 1e-4 * ref[ch]);
  }
}

TEST(Probes, DenseErrorOfAConstantMap) {
  const Vec3 radiance{2.0, 1.0, 0.5};
  const Map m = map_of(32, [&](const Vec3&) { return radiance; });
  const envmap::MapIrradiance field(m);
  const envmap::DenseTruth truth = envmap::dense_truth(field, 2000);
  EXPECT_NEAR(truth.peak, 2 * M_PI, 3e-5 * 2 * M_PI);  // the horizon sub-pixels at 32 × 16
  const auto e = envmap::dense_error(truth, [&](const Vec3&) {
    return Vec3{M_PI * radiance[0], M_PI * radiance[1], M_PI * radiance[2]};
  });
  EXPECT_LT(e.max_rel, 3e-5);
  // A probe off by 1 % of the peak everywhere in one channel: exactly that.
  const auto off = envmap::dense_error(truth, [&](const Vec3& n) {
    Vec3 v = field.at(n);
    v[0] += 0.01 * truth.peak;
    return v;
  });
  EXPECT_NEAR(off.max_rel, 0.01, 1e-12);
  EXPECT_NEAR(off.rms_rel, 0.01 / std::sqrt(3.0), 1e-12);
}

TEST(Probes, LocalSearchFindsTheWorstNormalACoarseSetMisses) {
  const Map m = map_of(32, [](const Vec3& w) { return Vec3{1 + w[2], 1.0, 1.0}; });
  const envmap::MapIrradiance field(m);
  const envmap::DenseTruth truth = envmap::dense_truth(field, 300);  // spacing ≈ 0.2 rad
  // A narrow bump (width 0.03 rad) of 10 % of the peak midway between set normals.
  const Vec3 a = truth.normals[100];
  Vec3 nearest = truth.normals[0];
  for (const Vec3& v : truth.normals)
    if (&v != &truth.normals[100] && dot(v, a) > dot(nearest, a) && dot(v, a) < 1) nearest = v;
  Vec3 b{a[0] + nearest[0], a[1] + nearest[1], a[2] + nearest[2]};
  const double len = std::sqrt(dot(b, b));
  for (double& x : b) x /= len;
  const double height = 0.1 * truth.peak, width = 0.03;
  const auto approx = [&](const Vec3& n) {
    Vec3 e = field.at(n);
    const double ang = std::acos(std::clamp(dot(n, b), -1.0, 1.0));
    e[1] += height * std::exp(-(ang * ang) / (width * width));
    return e;
  };
  const auto e = envmap::dense_error(truth, approx);
  EXPECT_LT(e.dense_max_rel, 0.02);
  EXPECT_NEAR(e.max_rel, 0.1, 1e-6);
  EXPECT_GT(dot(e.worst, b), std::cos(1e-3));
}

TEST(Probes, ShBasisClosedForms) {
  for (const Vec3& n : random_normals(20, 3)) {
    std::array<double, 25> y{};
    envmap::sh_basis(4, n[0], n[1], n[2], y.data());
    const double x = n[0], yy = n[1], z = n[2];
    EXPECT_NEAR(y[0], 0.5 / std::sqrt(M_PI), 1e-15);
    EXPECT_NEAR(y[1], std::sqrt(3 / (4 * M_PI)) * yy, 1e-15);
    EXPECT_NEAR(y[2], std::sqrt(3 / (4 * M_PI)) * z, 1e-15);
    EXPECT_NEAR(y[3], std::sqrt(3 / (4 * M_PI)) * x, 1e-15);
    EXPECT_NEAR(y[4], std::sqrt(15 / (4 * M_PI)) * x * yy, 1e-14);
    EXPECT_NEAR(y[6], std::sqrt(5 / (16 * M_PI)) * (3 * z * z - 1), 1e-14);
    EXPECT_NEAR(y[8], std::sqrt(15 / (16 * M_PI)) * (x * x - yy * yy), 1e-14);
    EXPECT_NEAR(y[20], 3 / (16 * std::sqrt(M_PI)) * (35 * z * z * z * z - 30 * z * z + 3), 1e-14);
  }
  // Published Funk–Hecke factors of the clamped cosine [Ramamoorthi2001].
  EXPECT_NEAR(envmap::clamped_cosine_factor(0), M_PI, 1e-15);
  EXPECT_NEAR(envmap::clamped_cosine_factor(1), 2 * M_PI / 3, 1e-15);
  EXPECT_NEAR(envmap::clamped_cosine_factor(2), M_PI / 4, 1e-15);
  EXPECT_EQ(envmap::clamped_cosine_factor(3), 0);
  EXPECT_NEAR(envmap::clamped_cosine_factor(4), -M_PI / 24, 1e-15);
}

TEST(Probes, RadianceProjectionIsOrthonormal) {
  // The map Y_k at pixel centres: its projection is the unit vector e_k but for
  // the pixelization, O(l(l + 1)Δ²/24) ≈ 5e−4 at l = 4, 256 × 128.
  for (std::size_t k : {0, 2, 4, 7, 13, 21}) {
    const Map m = map_of(256, [&](const Vec3& w) {
      std::array<double, 25> y{};
      envmap::sh_basis(4, w[0], w[1], w[2], y.data());
      return Vec3{y[k], 0, 0};
    });
    const auto c = envmap::radiance_sh(m, 4);
    for (std::size_t q = 0; q < 25; ++q)
      EXPECT_NEAR(c[q][0], q == k ? 1 : 0, 1e-3) << k << " " << q;
  }
}

TEST(Probes, ShOfAConstantMapAndOfABandLimitedMap) {
  const Map flat = map_of(32, [](const Vec3&) { return Vec3{1, 2, 3}; });
  const Probe p = envmap::project_sh(envmap::radiance_sh(flat, 4), 4);
  const auto f = envmap::probe_irradiance(p);
  for (const Vec3& n : random_normals(50, 4))
    for (std::size_t ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(f(n)[ch], M_PI * static_cast<double>(ch + 1), 1e-6);
  // Radiance of bands 0–2: E in closed form, E = Σ_l Â_l × band l.
  const auto radiance = [](const Vec3& w) {
    const double v = 1 + 0.5 * w[0] - 0.3 * w[2] + 0.1 * (3 * w[2] * w[2] - 1) + 0.2 * w[0] * w[1];
    return Vec3{v, v, v};
  };
  const auto closed = [](const Vec3& n) {
    return M_PI + 2 * M_PI / 3 * (0.5 * n[0] - 0.3 * n[2]) +
           M_PI / 4 * (0.1 * (3 * n[2] * n[2] - 1) + 0.2 * n[0] * n[1]);
  };
  const Map m = map_of(256, radiance);
  const auto e2 = envmap::probe_irradiance(envmap::project_sh(envmap::radiance_sh(m, 2), 2));
  const envmap::MapIrradiance field(m);
  for (const Vec3& n : random_normals(50, 5)) {
    EXPECT_NEAR(e2(n)[0], closed(n), 1e-4 * M_PI);
    // The pixel sum of the pixel-constant map: O(Δ²) from the smooth radiance.
    EXPECT_NEAR(field.at(n)[0], closed(n), 1e-3 * M_PI);
  }
}

TEST(Probes, ZonalHarmonicRotatedEqualsItsShExpansion) {
  const auto normals = random_normals(30, 6);
  for (const Vec3& d : random_normals(5, 7))
    for (const Vec3& n : normals) {
      std::array<double, 25> yd{}, yn{};
      envmap::sh_basis(2, d[0], d[1], d[2], yd.data());
      envmap::sh_basis(2, n[0], n[1], n[2], yn.data());
      double sum = 0;
      for (std::size_t k = 4; k < 9; ++k) sum += std::sqrt(4 * M_PI / 5) * yd[k] * yn[k];
      const double t = dot(d, n);
      EXPECT_NEAR(sum, std::sqrt(5 / (16 * M_PI)) * (3 * t * t - 1), 1e-14);
    }
}

TEST(Probes, Zh3OfAnAxiallySymmetricMapIsItsL2Sh) {
  const Vec3 d{0.48, -0.6, 0.64};  // unit
  const Map m = map_of(256, [&](const Vec3& w) {
    const double t = dot(w, d);
    return Vec3{1 + 0.5 * t + 0.8 * t * t, 2 + 0.4 * t + 0.3 * t * t, 1 + 0.2 * t};
  });
  const auto radiance = envmap::radiance_sh(m, 2);
  const Probe zh3 = envmap::project_zh3(radiance);
  const Vec3 axis = zh3.zonal_axis();
  EXPECT_GT(dot(axis, d), 1 - 1e-6);
  const auto a = envmap::probe_irradiance(zh3);
  const auto b = envmap::probe_irradiance(envmap::project_sh(radiance, 2));
  for (const Vec3& n : random_normals(50, 8))
    for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(a(n)[ch], b(n)[ch], 2e-5 * b(n)[ch]);
  EXPECT_EQ(zh3.floats(), 15u);
  // The non-negative L1 reconstruction never goes below zero.
  const Map sun = map_of(64, [](const Vec3& w) {
    const double s = std::exp(200 * (w[2] - 1)) * 1e3;
    return Vec3{s, s, s};
  });
  const auto nn = envmap::probe_irradiance(envmap::project_sh_nonneg(envmap::radiance_sh(sun, 1)));
  const auto raw = envmap::probe_irradiance(envmap::project_sh(envmap::radiance_sh(sun, 1), 1));
  EXPECT_LT(raw(Vec3{0, 0, -1})[0], 0);
  for (const Vec3& n : random_normals(200, 9)) EXPECT_GE(nn(n)[0], -1e-9);
}

TEST(Probes, OneLobeIsTheExactSgIrradiance) {
  const envmap::Lobe lobe{{0.0, 0.6, 0.8}, 12.0, {2.0, 1.0, 0.5}};
  Probe p;
  p.kind = envmap::ProbeKind::lobes;
  p.lobes = {lobe};
  const auto normals = random_normals(100, 10);
  const auto reference = envmap::lobes_irradiance_exact(p.lobes, normals);
  const auto f = envmap::probe_irradiance(p);
  for (std::size_t k = 0; k < normals.size(); ++k)
    for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(f(normals[k])[ch], reference[k][ch], 1e-9);
  // A map that is this lobe: its dense error against the probe is the map's
  // own pixelization (pixel centres of a κ = 12 lobe at 256 × 128: ~1e−4).
  const Map m = map_of(256, [&](const Vec3& w) {
    const double g = std::exp(lobe.sharpness * (dot(w, lobe.axis) - 1));
    return Vec3{2 * g, g, 0.5 * g};
  });
  const envmap::MapIrradiance field(m);
  const auto truth = envmap::dense_truth(field, 2000);
  const auto e = envmap::dense_error(truth, f);
  EXPECT_LT(e.max_rel, 1e-3);
  // Round trip through the probe file.
  const Probe q = Probe::from_json(p.to_json());
  EXPECT_EQ(q.floats(), 7u);
  EXPECT_NEAR(envmap::probe_irradiance(q)(normals[0])[0], f(normals[0])[0], 1e-12);
}

}  // namespace

namespace {

// A 32 × 16 map of SG lights over a constant sky.
Map lobes_map(const std::vector<envmap::Lobe>& lights, const Vec3& sky) {
  return map_of(32, [&](const Vec3& w) {
    Vec3 v = sky;
    for (const auto& l : lights) {
      const double g = std::exp(l.sharpness * (dot(w, l.axis) - 1));
      for (std::size_t ch = 0; ch < 3; ++ch) v[ch] += l.amplitude[ch] * g;
    }
    return v;
  });
}

TEST(Probes, LobeLadderIsMonotoneAndRecoversKnownLobes) {
  // A 32 × 16 map made of three lobes; fits on its irradiance, judged densely.
  const std::vector<envmap::Lobe> known = {
      {{0.0, 0.0, 1.0}, 6.0, {2.0, 1.5, 1.0}},
      {{0.8, 0.0, -0.6}, 3.0, {0.4, 0.6, 0.9}},
      {{0.0, -0.6, 0.8}, 20.0, {3.0, 2.0, 1.0}},
  };
  const Map m = lobes_map(known, {0, 0, 0});
  const envmap::MapIrradiance field(m);
  const auto truth = envmap::dense_truth(field, 1000);
  const auto normals = sglab::reference::fibonacci_normals(256);
  const auto exact = field.at(normals);
  const auto judge = [&](const Probe& p) {
    return envmap::dense_error(truth, envmap::probe_irradiance(p), 2).max_rel;
  };
  const auto ladder = envmap::fit_lobe_ladder(m, normals, exact, 4, judge, 50);
  ASSERT_EQ(ladder.size(), 4u);
  for (std::size_t k = 1; k < ladder.size(); ++k)
    EXPECT_LE(ladder[k].judged, ladder[k - 1].judged) << k;
  // Three lobes fit the irradiance of three lobes (the map's pixelization aside).
  EXPECT_LT(ladder[2].judged, 5e-3);
  EXPECT_GT(ladder[0].judged, 10 * ladder[2].judged);
  const auto hybrid = envmap::fit_hybrid_ladder(m, normals, exact, ladder, 2, judge, 50);
  ASSERT_EQ(hybrid.size(), 2u);
  EXPECT_LE(hybrid[1].judged, hybrid[0].judged);
  EXPECT_EQ(hybrid[1].probe.floats(), 27u + 14u);
}

}  // namespace

namespace {

// Max over normals and RGB of |E_probe − exact| (the fit normals' own error).
double max_residual(const Probe& p, const std::vector<Vec3>& normals,
                    const std::vector<Vec3>& exact) {
  const auto f = envmap::probe_irradiance(p);
  double m = 0;
  for (std::size_t k = 0; k < normals.size(); ++k) {
    const Vec3 e = f(normals[k]);
    for (std::size_t ch = 0; ch < 3; ++ch) m = std::max(m, std::abs(e[ch] - exact[k][ch]));
  }
  return m;
}

TEST(Probes, MinimaxShL0IsTheMidrange) {
  // The best constant in the max norm is (max + min)/2 (least squares: the
  // mean, far from it for these skewed values).
  const auto normals = sglab::reference::fibonacci_normals(512);
  std::vector<Vec3> exact;
  for (const Vec3& n : normals)
    exact.push_back({std::exp(3 * n[2]), 1 + n[0] * n[0], 2 + std::sin(5 * n[1])});
  const Probe p = envmap::fit_sh(normals, exact, 0, envmap::LinearFit::minimax);
  const Probe ls = envmap::fit_sh(normals, exact, 0);
  EXPECT_EQ(p.fit, "minimax");
  for (std::size_t ch = 0; ch < 3; ++ch) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const Vec3& e : exact) {
      lo = std::min(lo, e[ch]);
      hi = std::max(hi, e[ch]);
    }
    // Lawson's iteration converges linearly: its max residual within 0.5 % of
    // the minimax (hi − lo)/2 (least squares: 33 % above it on channel 1).
    const double at = envmap::probe_irradiance(p)(Vec3{0, 0, 1})[ch];
    EXPECT_LE(std::max(at - lo, hi - at), 1.005 * (hi - lo) / 2) << ch;
  }
  EXPECT_LT(max_residual(p, normals, exact), 0.9 * max_residual(ls, normals, exact));
}

TEST(Probes, MinimaxRefinementLowersTheLobesMaxError) {
  // Two lobes cannot fit three: the least-squares fit leaves a max residual
  // the minimax refinement (judged at the fit normals) lowers.
  const std::vector<envmap::Lobe> known = {
      {{0.0, 0.0, 1.0}, 6.0, {2.0, 1.5, 1.0}},
      {{0.8, 0.0, -0.6}, 3.0, {0.4, 0.6, 0.9}},
      {{0.0, -0.6, 0.8}, 20.0, {3.0, 2.0, 1.0}},
  };
  const Map m = lobes_map(known, {0, 0, 0});
  const envmap::MapIrradiance field(m);
  const auto normals = sglab::reference::fibonacci_normals(256);
  const auto exact = field.at(normals);
  const auto judge = [&](const Probe& p) { return max_residual(p, normals, exact); };
  const std::vector<std::size_t> counts{1, 2};
  const auto ls = envmap::fit_lobe_ladder(m, normals, exact, counts, judge, 50, 0);
  const auto mm = envmap::fit_lobe_ladder(m, normals, exact, counts, judge, 50);
  ASSERT_EQ(ls.size(), 2u);
  ASSERT_EQ(mm.size(), 2u);
  EXPECT_EQ(mm[1].probe.lobes.size(), 2u);
  EXPECT_LT(mm[1].judged, 0.9 * ls[1].judged);
  EXPECT_LE(mm[1].judged, mm[0].judged);
}

TEST(Probes, LadderAtGivenCountsGrowsBySeveralLobes) {
  const Map m = map_of(32, [](const Vec3& w) {
    const double s = 1 + 4 * std::exp(10 * (w[2] - 1)) + 2 * std::exp(5 * (w[0] - 1));
    return Vec3{s, s, 0.5 * s};
  });
  const envmap::MapIrradiance field(m);
  const auto normals = sglab::reference::fibonacci_normals(256);
  const auto exact = field.at(normals);
  const auto judge = [&](const Probe& p) { return max_residual(p, normals, exact); };
  const auto ladder =
      envmap::fit_lobe_ladder(m, normals, exact, std::vector<std::size_t>{1, 4}, judge, 50);
  ASSERT_EQ(ladder.size(), 2u);
  EXPECT_EQ(ladder[1].probe.lobes.size(), 4u);
  EXPECT_LE(ladder[1].judged, ladder[0].judged);
  EXPECT_THROW(envmap::fit_lobe_ladder(m, normals, exact, std::vector<std::size_t>{2, 2}, judge),
               std::logic_error);
}

TEST(Probes, RestartLobesAreDrawnFromTheMapsLight) {
  // Light only in two caps of equal solid angle, the one about +z three times
  // as bright: every starting axis lies in a cap, about 3 in 4 in the bright
  // one, and each restart's lobes carry the map's light between them.
  const Vec3 za{0, 0, 1}, xa{1, 0, 0};
  const Map m = map_of(64, [&](const Vec3& w) {
    if (dot(w, za) > 0.95) return Vec3{3, 3, 3};
    if (dot(w, xa) > 0.95) return Vec3{1, 1, 1};
    return Vec3{0, 0, 0};
  });
  double light = 0;
  for (std::size_t j = 0; j < m.height; ++j)
    for (std::size_t i = 0; i < m.width; ++i)
      light += envmap::pixel_solid_angle(m, j) * m.at(i, j, 0);
  const double kmax = std::pow(static_cast<double>(m.height) / M_PI, 2);
  std::size_t bright = 0, total = 0;
  double kappa_lo = HUGE_VAL, kappa_hi = 0;
  for (std::size_t r = 0; r < 16; ++r) {
    const auto lobes = envmap::restart_lobes(m, 4, r);
    ASSERT_EQ(lobes.size(), 4u);
    double carried = 0;
    for (const auto& l : lobes) {
      const Vec3 a{l.axis[0], l.axis[1], l.axis[2]};
      EXPECT_TRUE(dot(a, za) > 0.95 || dot(a, xa) > 0.95) << a[0] << " " << a[1] << " " << a[2];
      bright += dot(a, za) > 0.95;
      ++total;
      EXPECT_GE(l.sharpness, 1.0);
      EXPECT_LE(l.sharpness, std::min(kmax, 256.0) * (1 + 1e-12));
      kappa_lo = std::min(kappa_lo, l.sharpness);
      kappa_hi = std::max(kappa_hi, l.sharpness);
      carried += 2 * M_PI * l.amplitude[0] / l.sharpness;
    }
    EXPECT_NEAR(carried, light, 1e-9 * light);
  }
  EXPECT_NEAR(static_cast<double>(bright) / static_cast<double>(total), 0.75, 0.08);
  EXPECT_LT(kappa_lo, 2.0);
  EXPECT_GT(kappa_hi, 0.5 * std::min(kmax, 256.0));
}

TEST(Probes, RestartsNeverRaiseTheLaddersError) {
  const std::vector<envmap::Lobe> known = {
      {{0.0, 0.0, 1.0}, 40.0, {2.0, 2.0, 2.0}},
      {{0.8, 0.0, -0.6}, 3.0, {0.4, 0.6, 0.9}},
      {{0.0, -0.6, 0.8}, 20.0, {3.0, 2.0, 1.0}},
      {{-0.6, 0.8, 0.0}, 60.0, {1.0, 3.0, 1.0}},
  };
  const Map m = lobes_map(known, {0.2, 0.3, 0.4});
  const envmap::MapIrradiance field(m);
  const auto normals = sglab::reference::fibonacci_normals(256);
  const auto exact = field.at(normals);
  const auto judge = [&](const Probe& p) { return max_residual(p, normals, exact); };
  const auto plain = envmap::fit_lobe_ladder(m, normals, exact, 4, judge, 50);
  const auto restarted =
      envmap::fit_lobe_ladder(m, normals, exact, 4, judge, 50, envmap::kMinimaxRounds, 4);
  ASSERT_EQ(plain.size(), 4u);
  ASSERT_EQ(restarted.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_LE(restarted[k].judged, plain[k].judged) << k + 1 << " lobes";
    if (k > 0) {
      EXPECT_LE(restarted[k].judged, restarted[k - 1].judged) << k + 1 << " lobes";
    }
  }
}

// Grown to 2 lobes and then to 4, a LobeLadder is fit_lobe_ladder to 4, lobe
// for lobe, and judges no more probes than it (its first steps are not refitted).
TEST(Probes, LobeLadderGrownInTwoStepsIsTheLadder) {
  const Map m = lobes_map({{{0.0, 0.0, 1.0}, 30.0, {2.0, 2.0, 2.0}},
                           {{0.8, 0.0, -0.6}, 3.0, {0.4, 0.6, 0.9}},
                           {{0.0, -0.6, 0.8}, 12.0, {3.0, 2.0, 1.0}}},
                          {0.2, 0.3, 0.4});
  const envmap::MapIrradiance field(m);
  const auto normals = sglab::reference::fibonacci_normals(256);
  const auto exact = field.at(normals);
  for (int restarts : {0, 2}) {
    std::size_t judged_whole = 0, judged_grown = 0;
    const auto whole = envmap::fit_lobe_ladder(
        m, normals, exact, 4,
        [&](const Probe& p) {
          ++judged_whole;
          return max_residual(p, normals, exact);
        },
        50, envmap::kMinimaxRounds, restarts);
    envmap::LobeLadder ladder(
        m, normals, exact,
        [&](const Probe& p) {
          ++judged_grown;
          return max_residual(p, normals, exact);
        },
        50, envmap::kMinimaxRounds, restarts);
    EXPECT_EQ(ladder.grow_to(2).size(), 2u);
    const auto grown = ladder.grow_to(4);
    EXPECT_EQ(ladder.grow_to(3).size(), 4u);  // never shrinks, fits nothing
    ASSERT_EQ(grown.size(), whole.size());
    for (std::size_t k = 0; k < whole.size(); ++k) {
      EXPECT_EQ(grown[k].judged, whole[k].judged) << restarts << " restarts, " << k + 1;
      EXPECT_EQ(grown[k].start, whole[k].start) << restarts << " restarts, " << k + 1;
      ASSERT_EQ(grown[k].probe.lobes.size(), whole[k].probe.lobes.size());
      for (std::size_t l = 0; l < whole[k].probe.lobes.size(); ++l) {
        EXPECT_EQ(grown[k].probe.lobes[l].axis, whole[k].probe.lobes[l].axis);
        EXPECT_EQ(grown[k].probe.lobes[l].sharpness, whole[k].probe.lobes[l].sharpness);
        EXPECT_EQ(grown[k].probe.lobes[l].amplitude, whole[k].probe.lobes[l].amplitude);
      }
    }
    EXPECT_EQ(judged_grown, judged_whole) << restarts << " restarts";
  }
}

}  // namespace
