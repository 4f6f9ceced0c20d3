// Environment maps (envmap/envmap.hpp, `sglab envmap`): the exact irradiance
// of a map, the fit of a map made from known lobes, bad files, and the
// selector's choice checked against the exact irradiance.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "envmap/envmap.hpp"
#include "report/envmap_report.hpp"
#include "tests/test_support.hpp"
#include "validate/scene_errors.hpp"

namespace {

using namespace sglab;
using envmap::Lobe;
using envmap::Map;
using envmap::Vec3;
using test::run_sglab;
using test::TempDir;

Map constant_map(std::size_t w, Vec3 value) {
  Map m;
  m.width = w;
  m.height = w / 2;
  m.rgb.resize(m.width * m.height * 3);
  for (std::size_t p = 0; p < m.width * m.height; ++p)
    for (std::size_t ch = 0; ch < 3; ++ch) m.rgb[3 * p + ch] = static_cast<float>(value[ch]);
  return m;
}

const std::vector<Lobe> kKnown = {
    {{0.3, 0.4, std::sqrt(1 - 0.25)}, 40.0, {4.0, 3.5, 3.0}},
    {{-0.8, 0.0, -0.6}, 6.0, {0.5, 0.8, 1.2}},
    {{0.0, -1.0, 0.0}, 15.0, {1.5, 1.0, 0.5}},
};

TEST(Envmap, SolidAnglesCoverTheSphereAndMomentsCancel) {
  const Map m = constant_map(64, {1, 1, 1});
  double total = 0;
  Vec3 moment{0, 0, 0};
  for (std::size_t j = 0; j < m.height; ++j)
    for (std::size_t i = 0; i < m.width; ++i) {
      total += envmap::pixel_solid_angle(m, j);
      const Vec3 v = envmap::pixel_moment(m, i, j);
      for (std::size_t d = 0; d < 3; ++d) moment[d] += v[d];
    }
  EXPECT_NEAR(total, 4 * M_PI, 1e-12);
  for (double x : moment) EXPECT_NEAR(x, 0, 1e-12);
  // Row 0 looks at the zenith, column 0 along +x, the centre along −x.
  EXPECT_GT(envmap::pixel_direction(m, 0, 0)[2], 0.99);
  EXPECT_GT(envmap::pixel_direction(m, 0, m.height / 2)[0], 0.99);
  EXPECT_LT(envmap::pixel_direction(m, m.width / 2, m.height / 2)[0], -0.99);
  EXPECT_LT(envmap::pixel_direction(m, m.width / 4, m.height / 2)[1], -0.99);
}

TEST(Envmap, ConstantMapIrradianceIsPiTimesRadiance) {
  const Vec3 radiance{1.0, 2.0, 0.5};
  for (std::size_t w : {32, 128}) {
    const Map m = constant_map(w, radiance);
    const auto normals = reference::fibonacci_normals(200);
    const auto e = envmap::irradiance(m, normals);
    // Exact but for the sub-pixels n's horizon cuts: an error that shrinks
    // with the pixel size.
    const double tol = w == 32 ? 3e-5 : 2e-6;  // measured 1.4e-5 and 8.4e-7
    double worst = 0;
    for (std::size_t k = 0; k < normals.size(); ++k)
      for (std::size_t ch = 0; ch < 3; ++ch) {
        worst = std::max(worst, std::abs(e[k][ch] / (M_PI * radiance[ch]) - 1));
        EXPECT_NEAR(e[k][ch] / (M_PI * radiance[ch]), 1.0, tol) << "width " << w << " normal " << k;
      }
    std::printf("constant map %zu x %zu: max |E/(πL) − 1| = %.3g\n", w, w / 2, worst);
    // At the poles the horizon runs along pixel edges: exact to rounding.
    const auto pole = envmap::irradiance(m, {{0, 0, 1}, {0, 0, -1}});
    for (const auto& v : pole)
      for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(v[ch] / (M_PI * radiance[ch]), 1.0, 1e-12);
  }
}

TEST(Envmap, DownsampleKeepsTheIntegral) {
  const Map fine = envmap::reconstruct(kKnown, 128, 64);
  const Map coarse = envmap::downsample(fine, 32);
  auto integral = [](const Map& m) {
    double s = 0;
    for (std::size_t j = 0; j < m.height; ++j)
      for (std::size_t i = 0; i < m.width; ++i)
        s += envmap::pixel_solid_angle(m, j) * m.at(i, j, 0);
    return s;
  };
  EXPECT_NEAR(integral(coarse) / integral(fine), 1.0, 1e-6);
}

// The fitting copy of a map wider than the fitting width (128) is the map area-averaged to that
// width (384 = 3 × 128); a map no wider is fitted as it is.
TEST(Envmap, WorkingCopyIsAtTheFittingWidth) {
  const Map wide = envmap::reconstruct(kKnown, 384, 192);
  const Map work = envmap::working_copy(wide);
  EXPECT_EQ(work.width, 128u);
  EXPECT_EQ(work.height, 64u);
  EXPECT_EQ(work.rgb, envmap::downsample(wide, 128).rgb);
  const Map narrow = envmap::reconstruct(kKnown, 64, 32);
  EXPECT_EQ(envmap::working_copy(narrow).rgb, narrow.rgb);
}

TEST(Envmap, FitRecoversKnownLobes) {
  const Map m = envmap::reconstruct(kKnown, 128, 64);
  envmap::FitOptions o;
  o.lobes = kKnown.size();
  o.objective = envmap::Objective::radiance;
  const envmap::FitReport r = envmap::fit(m, {}, o);
  ASSERT_EQ(r.lobes.size(), kKnown.size());
  for (const Lobe& truth : kKnown) {
    const Lobe* best = nullptr;
    double best_dot = -2;
    for (const Lobe& l : r.lobes) {
      const double d =
          l.axis[0] * truth.axis[0] + l.axis[1] * truth.axis[1] + l.axis[2] * truth.axis[2];
      if (d > best_dot) best_dot = d, best = &l;
    }
    ASSERT_NE(best, nullptr);
    EXPECT_GT(best_dot, std::cos(0.01)) << "axis within 0.01 rad";
    EXPECT_NEAR(best->sharpness / truth.sharpness, 1.0, 0.01);
    for (std::size_t ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(best->amplitude[ch] / truth.amplitude[ch], 1.0, 0.01);
  }
  // The irradiance of the fitted lobes matches the map's exact irradiance.
  const auto normals = reference::fibonacci_normals(300);
  const auto err = envmap::irradiance_error(envmap::lobes_irradiance_exact(r.lobes, normals),
                                            envmap::irradiance(m, normals));
  EXPECT_LT(err.max_rel, 2e-3);
}

TEST(Envmap, FitIsDeterministic) {
  const Map m = envmap::downsample(envmap::reconstruct(kKnown, 128, 64), 64);
  envmap::FitOptions o;
  o.lobes = 4;
  o.fit_normals = 256;
  const auto normals = reference::fibonacci_normals(o.fit_normals);
  const auto exact = envmap::irradiance(m, normals);
  const auto a = envmap::fit(m, exact, o), b = envmap::fit(m, exact, o);
  ASSERT_EQ(a.lobes.size(), b.lobes.size());
  for (std::size_t k = 0; k < a.lobes.size(); ++k) {
    EXPECT_EQ(a.lobes[k].sharpness, b.lobes[k].sharpness);
    EXPECT_EQ(a.lobes[k].axis, b.lobes[k].axis);
    EXPECT_EQ(a.lobes[k].amplitude, b.lobes[k].amplitude);
  }
}

// A lobe is no narrower than one pixel of the working copy: the fitted sharpness never exceeds
// (H/π)², H the height. A map lit by one pixel asks for an infinitely sharp lobe and gets the
// cap, (8/π)² = 6.48 for a 16 × 8 map (the width would allow four times that).
TEST(Envmap, FitCapsTheSharpnessAtOnePixelOfTheHeight) {
  Map m = constant_map(16, {1e-3, 1e-3, 1e-3});
  for (std::size_t ch = 0; ch < 3; ++ch) m.rgb[(2 * m.width + 5) * 3 + ch] = 50.0f;
  envmap::FitOptions o;
  o.lobes = 1;
  o.objective = envmap::Objective::radiance;
  const envmap::FitReport r = envmap::fit(m, {}, o);
  ASSERT_EQ(r.lobes.size(), 1u);
  const double cap = (8 / M_PI) * (8 / M_PI);
  EXPECT_LE(r.lobes[0].sharpness, cap * (1 + 1e-9));
  EXPECT_GE(r.lobes[0].sharpness, 0.9 * cap) << "the lobe should press against the cap";
}

// Lossy encoders leave tiny negative values: down to −5 % of the map's mean radiance they are
// read as 0, beyond that the map is refused naming the pixel.
TEST(Envmap, TinyNegativesAreZeroLargerOnesRefused) {
  Map ok = constant_map(16, {1, 1, 1});
  ok.rgb[(3 * ok.width + 4) * 3 + 1] = -0.01f;  // mean ≈ 1
  envmap::check_map(ok, "tiny.exr");
  EXPECT_EQ(ok.at(4, 3, 1), 0.0f);
  EXPECT_EQ(ok.at(4, 3, 0), 1.0f);
  Map bad = constant_map(16, {1, 1, 1});
  bad.rgb[(3 * bad.width + 4) * 3 + 1] = -0.1f;
  try {
    envmap::check_map(bad, "negative.exr");
    ADD_FAILURE() << "-0.1 x the mean accepted";
  } catch (const io::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("negative.exr: pixel (4, 3) channel G is negative"), std::string::npos)
        << msg;
  }
}

TEST(Envmap, ExrRoundTrip) {
  TempDir dir("envmap-rt");
  const Map m = envmap::reconstruct(kKnown, 32, 16);
  envmap::write_exr(dir.path / "m.exr", m);
  const Map r = envmap::read_map(dir.path / "m.exr");
  EXPECT_EQ(r.width, 32u);
  EXPECT_EQ(r.height, 16u);
  EXPECT_EQ(r.rgb, m.rgb);
}

// Every bad input exits 2 naming the problem, and leaves no --out file.
TEST(EnvmapCli, BadFilesExitTwo) {
  TempDir dir("envmap-bad");
  const auto p = [&](const char* name) { return (dir.path / name).string(); };
  { std::ofstream(p("text.exr")) << "not an image\n"; }
  envmap::write_exr(p("square.exr"), [] {
    Map m = constant_map(32, {1, 1, 1});
    m.height = 32;
    m.rgb.assign(32 * 32 * 3, 1.0f);
    return m;
  }());
  Map nan = constant_map(32, {1, 1, 1});
  nan.rgb[3 * 40 + 1] = std::numeric_limits<float>::quiet_NaN();
  envmap::write_exr(p("nan.exr"), nan);
  Map neg = constant_map(32, {1, 1, 1});
  neg.rgb[3 * 7 + 2] = -0.5f;
  envmap::write_exr(p("neg.exr"), neg);
  Map inf = constant_map(32, {1, 1, 1});
  inf.rgb[0] = std::numeric_limits<float>::infinity();
  envmap::write_exr(p("inf.exr"), inf);
  envmap::write_exr(p("good.exr"), constant_map(32, {1, 1, 1}));
  std::filesystem::create_directory(p("folder.exr"));

  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases = {
      {{"envmap", "fit", p("text.exr"), "--lobes", "2", "--out", p("o.json")}, "not an HDR image"},
      {{"envmap", "fit", p("missing.exr"), "--lobes", "2", "--out", p("o.json")}, "no such file"},
      {{"envmap", "fit", p("folder.exr"), "--lobes", "2", "--out", p("o.json")},
       "not a regular file"},
      {{"envmap", "fit", p("square.exr"), "--lobes", "2", "--out", p("o.json")},
       "not a 2:1 equirectangular"},
      {{"envmap", "fit", p("nan.exr"), "--lobes", "2", "--out", p("o.json")}, "channel G is NaN"},
      {{"envmap", "fit", p("neg.exr"), "--lobes", "2", "--out", p("o.json")},
       "channel B is negative"},
      {{"envmap", "fit", p("inf.exr"), "--lobes", "2", "--out", p("o.json")}, "is infinite"},
      {{"envmap", "fit", p("good.exr"), "--lobes", "0", "--out", p("o.json")}, "at least one lobe"},
      {{"envmap", "fit", p("good.exr"), "--lobes", "17", "--out", p("o.json")},
       "more than the map supports"},
      {{"envmap", "irradiance", p("nan.exr")}, "NaN"},
      {{"envmap", "recommend", p("square.exr"), "--budget", "0.01"}, "not a 2:1"},
      {{"envmap", "downsample", p("good.exr"), p("o.exr"), "--width", "9"}, "must be even"},
  };
  for (const Case& c : cases) {
    const auto r = run_sglab(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[2] << ": " << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args[2] << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(p("o.json")));
    EXPECT_FALSE(std::filesystem::exists(p("o.exr")));
  }
}

// The fit's scene file is read by `recommend --scene`, and the selector's
// choice, refitted and evaluated here, meets its budget against the map's
// exact irradiance.
TEST(EnvmapCli, SelectorChoiceMeetsItsBudget) {
  TempDir dir("envmap-select");
  const std::string map = (dir.path / "m.exr").string();
  envmap::write_exr(map, envmap::downsample(envmap::reconstruct(kKnown, 128, 64), 64));
  const std::string costs = std::string(SGLAB_TEST_SOURCE_DIR) + "/../data/results/costs.json";
  const double budget = 0.02;
  const auto r = run_sglab({"envmap", "recommend", map, "--budget", "0.02", "--max-lobes", "8",
                            "--normals", "500", "--json", "--costs", costs},
                           false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  ASSERT_TRUE(doc["choice"].is_object()) << r.output;
  const std::size_t lobes = doc["choice"]["lobes"].get<std::size_t>();
  const std::string method = doc["choice"]["method"].get<std::string>();
  EXPECT_LE(doc["choice"]["error"].get<double>(), budget);

  const std::string scene_file = (dir.path / "s.json").string();
  const auto f =
      run_sglab({"envmap", "fit", map, "--lobes", std::to_string(lobes), "--out", scene_file});
  ASSERT_EQ(f.exit_code, 0) << f.output;
  std::ifstream in(scene_file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const reference::Scene scene = reference::parse_scene(text, scene_file);
  ASSERT_EQ(scene.lights.size(), lobes);
  const auto normals = reference::fibonacci_normals(500);
  const Method* m = find_method(irradiance_methods, method);
  ASSERT_NE(m, nullptr);
  double largest = 0;
  for (const auto& l : scene.lights)
    for (double a : l.amplitude) largest = std::max(largest, a);
  auto approx = validate::scene_irradiance(scene, normals, *m, io::Precision::float32);
  for (auto& v : approx)
    for (double& x : v) x *= largest;
  const auto exact = envmap::irradiance(envmap::read_map(map), normals);
  EXPECT_LE(envmap::irradiance_error(approx, exact).max_rel, budget);

  const auto rec = run_sglab({"recommend", "--scene", scene_file, "--budget", "0.01", "--costs",
                              costs, "--normals", "200"});
  EXPECT_EQ(rec.exit_code, 0) << rec.output;
}

// The selector checks the budget on the dense error of the full map, not on
// its ranking normals. night.exr at 64 × 32, 30 ranking normals, 2 lobes,
// budget 0.2: at the ranking normals every pair's worst normal is missed
// (0.15 there, 0.18 to 0.21 between them). The cheapest pair (hill) meets
// 0.2 at the ranking normals and fails it at 50,000 other Fibonacci normals
// (the map's exact irradiance by its own pixel sum): it is not chosen. The
// choice and the runner-up report at least their error at those normals,
// which meets the budget. Reporting or checking the ranking error fails this.
TEST(EnvmapSelector, ReportsTheDenseErrorNotTheRankingNormals) {
  const Map map = envmap::downsample(envmap::read_map(std::filesystem::path(SGLAB_TEST_SOURCE_DIR) /
                                                      ".." / "data" / "envmaps" / "night.exr"),
                                     64);
  std::vector<report::MethodPoint> costs;
  for (const char* id : {"hill", "sglab_fast", "sglab_acc3"}) {
    report::MethodPoint p;
    p.method = id;
    p.cost = static_cast<double>(costs.size() + 1);
    p.cost_unit = "cycles";
    costs.push_back(p);
  }
  const double budget = 0.2;
  const auto sel =
      report::select_envmap_method(map, envmap::working_copy(map), budget, 2, 30,
                                   io::Precision::float32, costs, [](const std::string&) {});
  ASSERT_TRUE(sel.choice && sel.runner_up);
  ASSERT_EQ(sel.lobes.size(), sel.choice->lobes);
  const auto normals = reference::fibonacci_normals(50000);
  const auto exact = envmap::irradiance(map, normals);
  double largest = 0;
  for (const auto& l : sel.lobes)
    for (double a : l.amplitude) largest = std::max(largest, a);
  const auto error_elsewhere = [&](const std::string& method) {
    const Method* m = find_method(irradiance_methods, method);
    auto approx = validate::scene_irradiance(envmap::to_scene(sel.lobes), normals, *m,
                                             io::Precision::float32);
    for (auto& v : approx)
      for (double& x : v) x *= largest;
    return envmap::irradiance_error(approx, exact).max_rel;
  };
  for (const auto* c : {&*sel.choice, &*sel.runner_up}) {
    const double other = error_elsewhere(c->method);
    EXPECT_LT(c->error, 0.9 * other)
        << c->method << ": the ranking normals do not understate, the test shows nothing";
    ASSERT_TRUE(c->dense) << c->method;
    EXPECT_GE(c->dense->max_rel, other * (1 - 1e-3)) << c->method;
    EXPECT_LE(c->dense->max_rel, budget) << c->method;
    EXPECT_LE(other, budget) << c->method;
  }
  // hill, cheapest, meets the budget at the ranking normals only.
  bool cheaper_fails = false;
  for (const auto& t : sel.tried)
    if (t.lobes == sel.choice->lobes && t.method == "hill") {
      EXPECT_LE(t.error, budget);
      EXPECT_GT(error_elsewhere("hill"), budget);
      EXPECT_FALSE(report::meets_budget(t, budget));
      cheaper_fails = true;
    }
  EXPECT_TRUE(cheaper_fails);
  EXPECT_NE(sel.choice->method, "hill");
}

}  // namespace

namespace {

TEST(EnvmapScene, ProvenanceIsAnOptionalObject) {
  const std::string light = R"({"axis": [0, 0, 1], "sharpness": 2, "amplitude": [1, 1, 1]})";
  EXPECT_EQ(
      reference::parse_scene(
          R"({"lights": [)" + light + R"(], "provenance": {"map": "x.exr", "lobes": 1}})", "s")
          .lights.size(),
      1u);
  EXPECT_THROW(
      reference::parse_scene(R"({"lights": [)" + light + R"(], "provenance": "text"})", "s"),
      reference::SceneError);
  EXPECT_THROW(reference::parse_scene(R"({"lights": [)" + light + R"(], "other": {}})", "s"),
               reference::SceneError);
}

}  // namespace
