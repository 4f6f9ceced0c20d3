// Scenes of SG lights (reference/scene.hpp, validate/scene_errors.hpp) and `sglab recommend
// --scene`: the scene sums against independent computations, and bad scene files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "tests/test_support.hpp"
#include "validate/scene_errors.hpp"

namespace {

namespace fs = std::filesystem;
using namespace sglab::reference;
using namespace sglab::validate;

TEST(Scene, FibonacciNormalsAreUnitAndBalanced) {
  const auto n = fibonacci_normals(1000);
  ASSERT_EQ(n.size(), 1000u);
  Vec3 sum{0, 0, 0};
  for (const auto& v : n) {
    EXPECT_NEAR(std::hypot(v[0], v[1], v[2]), 1.0, 1e-14);
    for (int i = 0; i < 3; ++i) sum[i] += v[i];
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(sum[i] / 1000, 0.0, 1e-2);  // spread over the sphere
}

// A single light along +z: the normal's cosine is its z = 1 − (2i + 1)/n, so
// the scene value is amplitude × the method's Ê(z, κ), computed here directly.
TEST(Scene, SingleLightEqualsMethodTimesAmplitude) {
  const Scene scene = parse_scene(
      R"({"lights": [{"axis": [0, 0, 2], "sharpness": 7.5, "amplitude": [1, 0.5, 2]}]})", "test");
  const std::size_t n = 257;
  const auto normals = fibonacci_normals(n);
  for (const char* id : {"tokuyoshi2024", "sglab_fast", "vsgl2015"}) {
    const auto* m = sglab::find_method(sglab::irradiance_methods, id);
    ASSERT_NE(m, nullptr) << id;
    const auto v64 = scene_irradiance(scene, normals, *m, sglab::io::Precision::float64);
    const auto v32 = scene_irradiance(scene, normals, *m, sglab::io::Precision::float32);
    for (std::size_t i = 0; i < n; ++i) {
      const double z = 1 - (2.0 * double(i) + 1) / double(n);
      const double e64 = m->f64(z, 7.5);
      const double e32 = m->f32(float(z), 7.5f);
      // In units of the scene's largest amplitude (2).
      const double amp[3] = {0.5, 0.25, 1};
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(v64[i][ch], amp[ch] * e64, 1e-13) << id << " normal " << i;
        EXPECT_NEAR(v32[i][ch], amp[ch] * e32, 1e-6) << id << " normal " << i;
      }
    }
  }
}

// E(n) = ∫_{ω·n>0} Σ_k a_k e^{κ_k(ω·v_k − 1)} (ω·n) dω by direct quadrature
// over the hemisphere around n: Gauss–Legendre in u = ω·n, trapezoid in the
// azimuth (periodic, so exponentially convergent). No closed form and no
// reference-engine code is shared with scene_irradiance_reference.
double direct_irradiance(const Scene& scene, const Vec3& n, std::size_t channel) {
  // Tangent frame of n.
  const Vec3 a = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 t1{a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0]};
  const double l = std::hypot(t1[0], t1[1], t1[2]);
  for (double& x : t1) x /= l;
  const Vec3 t2{n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2],
                n[0] * t1[1] - n[1] * t1[0]};
  // Gauss–Legendre nodes on [0, 1] by Newton's method on P_N.
  const int N = 160, M = 512;
  double total = 0;
  for (int i = 1; i <= N; ++i) {
    double x = std::cos(M_PI * (i - 0.25) / (N + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= N; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = N * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    const double w = 2 / ((1 - x * x) * dp * dp) / 2;  // on [0, 1]
    const double u = (x + 1) / 2, r = std::sqrt(1 - u * u);
    double ring = 0;
    for (int j = 0; j < M; ++j) {
      const double phi = 2 * M_PI * j / M;
      Vec3 w3;
      for (int d = 0; d < 3; ++d)
        w3[d] = u * n[d] + r * (std::cos(phi) * t1[d] + std::sin(phi) * t2[d]);
      for (const auto& light : scene.lights) {
        const double c = w3[0] * light.axis[0] + w3[1] * light.axis[1] + w3[2] * light.axis[2];
        ring += light.amplitude[channel] * std::exp(light.sharpness * (c - 1));
      }
    }
    total += w * u * ring * (2 * M_PI / M);
  }
  return total;
}

TEST(Scene, ExactSumMatchesDirectQuadratureOfTheSum) {
  const Scene scene = parse_scene(R"({"lights": [
      {"axis": [1, 1, 0], "sharpness": 3.0, "amplitude": [1, 0.2, 0.4]},
      {"axis": [0, -0.3, 1], "sharpness": 20.0, "amplitude": [0.5, 1.5, 0.0]}]})",
                                  "test");
  const auto normals = fibonacci_normals(23);
  const auto exact = scene_irradiance_reference(scene, normals);
  double peak = 0;
  for (const auto& e : exact) peak = std::max({peak, e[0], e[1], e[2]});
  const double largest_amplitude = 1.5;  // the sums are in its units
  for (std::size_t i = 0; i < normals.size(); ++i)
    for (std::size_t ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(exact[i][ch] * largest_amplitude, direct_irradiance(scene, normals[i], ch),
                  1e-10 * peak * largest_amplitude)
          << "normal " << i << " ch " << ch;
}

TEST(Scene, RelativeErrorIsScaledByTheLargestIrradiance) {
  const std::vector<Vec3> exact = {{2, 1, 0}, {4, 0, 1}};
  const std::vector<Vec3> approx = {{2, 1.2, 0}, {4, 0, 1}};
  EXPECT_DOUBLE_EQ(scene_relative_error(approx, exact), 0.2 / 4);
  const std::vector<Vec3> bad = {{2, NAN, 0}, {4, 0, 1}};
  EXPECT_TRUE(std::isinf(scene_relative_error(bad, exact)));
}

TEST(Scene, ShippedExamplesParse) {
  for (const char* name : {"studio.json", "sun_and_sky.json", "soft_room.json"}) {
    const fs::path path = fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "scenes" / name;
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const Scene s = parse_scene(text, name);
    EXPECT_GE(s.lights.size(), 3u) << name;
    for (const auto& l : s.lights)
      EXPECT_NEAR(std::hypot(l.axis[0], l.axis[1], l.axis[2]), 1.0, 1e-15);
  }
}

struct BadScene {
  const char* text;
  const char* expect;  // a substring of the message
};

TEST(Scene, BadFilesNameTheLineOrKey) {
  const BadScene cases[] = {
      {"{\"lights\": [\n  {\"axis\": [0, 0, 1], \"sharpness\": 1, \"amplitude\": [1, 1, 1]},\n]}",
       "line 3"},
      {"", "malformed JSON"},
      {"[1, 2]", "expected an object"},
      {"{}", "lights: missing key"},
      {"{\"lights\": {}}", "lights: expected an array"},
      {"{\"lights\": []}", "lights: no lights"},
      {"{\"lights\": [{\"sharpness\": 1, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].axis: missing key"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"amplitude\": [1, 1, 1]}]}",
       "lights[0].sharpness: missing key"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpness\": 1}]}",
       "lights[0].amplitude: missing key"},
      {"{\"lights\": [{\"axis\": [0, 0, 0], \"sharpness\": 1, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].axis: cannot be normalized"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpness\": -2, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].sharpness: must be >= 0"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpness\": \"4\", \"amplitude\": [1, 1, 1]}]}",
       "lights[0].sharpness: expected a number, got string"},
      {"{\"lights\": [{\"axis\": [0, 1], \"sharpness\": 4, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].axis: expected 3 numbers"},
      {"{\"lights\": [{\"axis\": [0, \"x\", 1], \"sharpness\": 4, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].axis[1]: expected a number"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpness\": 4, \"amplitude\": [1, -1, 1]}]}",
       "lights[0].amplitude[1]: must be >= 0"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpness\": 4, \"amplitude\": [0, 0, 0]}]}", "dark"},
      {"{\"lights\": [{\"axis\": [0, 0, 1], \"sharpnes\": 4, \"amplitude\": [1, 1, 1]}]}",
       "lights[0].sharpnes: unknown key"},
  };
  for (const auto& c : cases) {
    try {
      parse_scene(c.text, "s.json");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const SceneError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.expect), std::string::npos)
          << "message '" << msg << "' lacks '" << c.expect << "'";
      EXPECT_EQ(msg.rfind("s.json: ", 0), 0u) << msg;
    }
  }
}

// A sharpness beyond the largest float is refused at its light, whatever the
// precision the methods are then run in.
TEST(Scene, SharpnessAboveFloatMaxIsRefusedAtItsLight) {
  const std::string light = R"({"axis": [0, 0, 1], "sharpness": 2, "amplitude": [1, 1, 1]})";
  for (const char* kappa : {"3.5e38", "1e300", "1.7976931348623157e308"}) {
    const std::string bad =
        fmt::format(R"({{"axis": [1, 0, 0], "sharpness": {}, "amplitude": [1, 1, 1]}})", kappa);
    const std::string text = fmt::format(R"({{"lights": [{0}, {0}, {0}, {1}]}})", light, bad);
    try {
      parse_scene(text, "s.json");
      ADD_FAILURE() << "accepted κ = " << kappa;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("s.json: lights[3].sharpness: must be at most"),
                std::string::npos)
          << e.what();
    }
  }
  // The largest float itself is a valid κ.
  const Scene s = parse_scene(
      fmt::format(
          R"({{"lights": [{{"axis": [0, 0, 1], "sharpness": {:.17g}, "amplitude": [1, 1, 1]}}]}})",
          double(std::numeric_limits<float>::max())),
      "s.json");
  EXPECT_EQ(s.lights[0].sharpness, double(std::numeric_limits<float>::max()));
}

// The scene error is a ratio of irradiances: scaling every amplitude by s
// must not change it, from s = 1e−300 to 1e300 (with κ up to 1e30, whose
// irradiance 2π/κ times 1e−300 is below the smallest double).
Scene scaled(const Scene& base, double s) {
  Scene out = base;
  for (auto& l : out.lights)
    for (double& a : l.amplitude) a *= s;
  return out;
}

TEST(Scene, ErrorIsIndependentOfTheAmplitudeUnit) {
  const Scene base = parse_scene(R"({"lights": [
      {"axis": [0.2, 0.3, 0.9], "sharpness": 1e30, "amplitude": [1, 0.5, 0.25]},
      {"axis": [0, -0.3, 1], "sharpness": 20.0, "amplitude": [0.5, 1, 0]},
      {"axis": [1, 1, 0], "sharpness": 0.5, "amplitude": [0.1, 0.2, 0.4]}]})",
                                 "test");
  const auto normals = fibonacci_normals(97);
  const std::span<const sglab::Method> methods = sglab::irradiance_methods;
  const auto want = scene_errors(base, normals, methods, sglab::io::Precision::float32);
  for (double s : {1e-300, 1e-200, 1e-100, 1e-10, 1e10, 1e100, 1e200, 1e300}) {
    const Scene scene = scaled(base, s);
    const auto got = scene_errors(scene, normals, methods, sglab::io::Precision::float32);
    const auto exact = scene_irradiance_reference(scene, normals);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      SCOPED_TRACE(fmt::format("{} at amplitude scale {:g}", methods[m].id, s));
      const double one = scene_relative_error(
          scene_irradiance(scene, normals, methods[m], sglab::io::Precision::float32), exact);
      if (std::isinf(want[m])) {  // a published method failing at κ = 1e30 (meder2018's t(κ)) fails
                                  // at every scale
        EXPECT_TRUE(std::isinf(got[m]));
        EXPECT_TRUE(std::isinf(one));
        continue;
      }
      EXPECT_NEAR(got[m], want[m], 1e-9 * want[m]);
      EXPECT_NEAR(one, want[m], 1e-9 * want[m]);
    }
  }
}

// Extreme amplitudes: one dim sharp light, two 1e308-bright lights,
// and a 1e−323 (subnormal) amplitude, each against the same scene in unit amplitudes.
TEST(Scene, ErrorOfExtremeAmplitudesEqualsUnitAmplitudes) {
  const auto normals = fibonacci_normals(128);
  const auto* m = sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024");
  ASSERT_NE(m, nullptr);
  const auto error = [&](const std::string& text) {
    const Scene s = parse_scene(text, "test");
    return scene_relative_error(scene_irradiance(s, normals, *m, sglab::io::Precision::float32),
                                scene_irradiance_reference(s, normals));
  };
  const auto one_light = [](const char* kappa, const char* a) {
    return fmt::format(
        R"({{"lights": [{{"axis": [0, 0, 1], "sharpness": {0}, "amplitude": [{1}, {1}, {1}]}}]}})",
        kappa, a);
  };
  EXPECT_NEAR(error(one_light("1e30", "1e-300")), error(one_light("1e30", "1")), 1e-12);
  EXPECT_NEAR(error(one_light("4", "1e-323")), error(one_light("4", "1")), 1e-12);
  const auto two_lights = [](const char* a) {
    return fmt::format(
        R"({{"lights": [{{"axis": [0, 0, 1], "sharpness": 4, "amplitude": [{0}, {0}, {0}]}},
                                      {{"axis": [0, 0.6, 0.8], "sharpness": 4, "amplitude": [{0}, {0}, {0}]}}]}})",
        a);
  };
  const double bright = error(two_lights("1e308"));
  EXPECT_TRUE(std::isfinite(bright));
  EXPECT_NEAR(bright, error(two_lights("1")), 1e-12);
}

// The all-methods pass equals the per-method sums, over many blocks of normals
// and a partial one; lights with the same sharpness and axis
// are one lobe (two half-amplitude copies give the same errors exactly).
TEST(Scene, ErrorsOfAllMethodsEqualPerMethodSumsAcrossBlocks) {
  const Scene scene = parse_scene(R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 6, "amplitude": [0.5, 0.5, 0.5]},
      {"axis": [1, 0, 1], "sharpness": 60, "amplitude": [1, 0.25, 0]},
      {"axis": [0, 0, 1], "sharpness": 6, "amplitude": [0.5, 0.5, 0.5]}]})",
                                  "test");
  const Scene merged = parse_scene(R"({"lights": [
      {"axis": [1, 0, 1], "sharpness": 60, "amplitude": [1, 0.25, 0]},
      {"axis": [0, 0, 1], "sharpness": 6, "amplitude": [1, 1, 1]}]})",
                                   "test");
  const std::size_t n = 100 * kSceneBlockNormals + 7;
  const auto normals = fibonacci_normals(n);
  const std::span<const sglab::Method> methods = sglab::irradiance_methods;
  const auto errors = scene_errors(scene, normals, methods, sglab::io::Precision::float32);
  EXPECT_EQ(errors, scene_errors(merged, normals, methods, sglab::io::Precision::float32));
  const auto exact = scene_irradiance_reference(scene, normals);
  for (const char* id : {"tokuyoshi2024", "sglab_acc3", "punctual"}) {
    const auto* m = sglab::find_method(sglab::irradiance_methods, id);
    ASSERT_NE(m, nullptr) << id;
    const std::size_t i = static_cast<std::size_t>(m - sglab::irradiance_methods.data());
    EXPECT_DOUBLE_EQ(
        errors[i], scene_relative_error(
                       scene_irradiance(scene, normals, *m, sglab::io::Precision::float32), exact))
        << id;
  }
}

TEST(Scene, LimitsAreRefusedWithTheMemory) {
  EXPECT_NO_THROW(check_scene_limits(1000, 4096));
  EXPECT_NO_THROW(check_scene_limits(1, kMaxSceneNormals));
  for (auto [lights, normals] : {std::pair<std::size_t, std::size_t>{1000, 1000000},
                                 {1, kMaxSceneNormals + 1},
                                 {kMaxSceneLights + 1, 1}}) {
    try {
      check_scene_limits(lights, normals);
      ADD_FAILURE() << lights << " lights x " << normals << " normals accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("MB"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
    }
  }
  // Bounded: the memory does not grow with the (light, normal) pairs beyond
  // the lights and normals themselves.
  EXPECT_LT(scene_memory_bytes(1000, 4096), std::size_t{16} << 20);
}

// Writes `text` to dir/name and returns the path.
fs::path write_temp(const sglab::test::TempDir& dir, const std::string& name,
                    const std::string& text) {
  const fs::path p = dir.path / name;
  std::ofstream(p) << text;
  return p;
}

TEST(RecommendScene, BadFilesExitTwoWithTheKey) {
  const sglab::test::TempDir dir("scene-bad");
  const auto negative =
      write_temp(dir, "negative.json",
                 R"({"lights": [{"axis": [0, 0, 1], "sharpness": -1, "amplitude": [1, 1, 1]}]})");
  auto r = sglab::test::run_sglab({"recommend", "--scene", negative.string(), "--budget", "1e-2"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lights[0].sharpness"), std::string::npos) << r.output;
  const auto malformed = write_temp(dir, "malformed.json", "{\"lights\": [\n");
  r = sglab::test::run_sglab({"recommend", "--scene", malformed.string(), "--budget", "1e-2"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("line 2"), std::string::npos) << r.output;
  r = sglab::test::run_sglab(
      {"recommend", "--scene", (negative.parent_path() / "absent.json").string(), "--budget", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = sglab::test::run_sglab({"recommend", "--budget", "1e-2"});  // neither --kappa nor --scene
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST(RecommendScene, LimitsAndHugeSharpnessExitTwo) {
  const sglab::test::TempDir dir("scene-limits");
  std::string lights;
  for (int i = 0; i < 1000; ++i)
    lights += fmt::format(R"({}{{"axis": [{}, 1, 0.5], "sharpness": {}, "amplitude": [1, 1, 1]}})",
                          i ? "," : "", std::cos(i), 1 + i % 50);
  const auto many = write_temp(dir, "many.json", R"({"lights": [)" + lights + "]}");
  auto r = sglab::test::run_sglab(
      {"recommend", "--scene", many.string(), "--budget", "1e-2", "--normals", "1000000"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("MB"), std::string::npos) << r.output;
  const auto huge = write_temp(dir, "huge.json", R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 2, "amplitude": [1, 1, 1]},
      {"axis": [0, 1, 1], "sharpness": 3, "amplitude": [1, 1, 1]},
      {"axis": [1, 0, 1], "sharpness": 4, "amplitude": [1, 1, 1]},
      {"axis": [1, 1, 1], "sharpness": 1e300, "amplitude": [1, 1, 1]}]})");
  for (const char* precision : {"float", "double"}) {
    r = sglab::test::run_sglab({"recommend", "--scene", huge.string(), "--budget", "1e-2",
                                "--normals", "16", "--precision", precision});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("lights[3].sharpness: must be at most"), std::string::npos) << r.output;
  }
}

// A light of subnormal κ (2e−39: a subnormal float) is a valid light: every
// sglab model gets a finite scene error.
TEST(RecommendScene, SubnormalSharpnessGivesFiniteErrors) {
  const sglab::test::TempDir dir("scene-subnormal");
  const auto scene = write_temp(dir, "subnormal.json", R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 2e-39, "amplitude": [1, 1, 1]},
      {"axis": [1, 0, 0], "sharpness": 5, "amplitude": [0.5, 0.5, 0.5]}]})");
  const auto r = sglab::test::run_sglab(
      {"recommend", "--scene", scene.string(), "--budget", "1e-2", "--normals", "64", "--json"},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  for (const auto& row : doc["methods"])
    if (row["origin"] != "published") {
      EXPECT_TRUE(row["scene_error"].is_number()) << row.dump();
    }
}

// A light beyond a method's valid κ range (its registry card) puts the method out of the
// ranking, flagged in JSON and in text: sglab_fast above 1.1e4, sglab_lite above 1e4,
// punctual and Hill's curves below 1e-3.
TEST(RecommendScene, FlagsMethodsOutsideTheirValidRange) {
  const sglab::test::TempDir dir("scene-range");
  const auto scene = write_temp(dir, "sharp.json", R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 1e5, "amplitude": [1, 1, 1]},
      {"axis": [1, 0, 0], "sharpness": 1e-4, "amplitude": [0.2, 0.3, 0.4]}]})");
  const auto r = sglab::test::run_sglab(
      {"recommend", "--scene", scene.string(), "--budget", "1", "--normals", "64", "--json"},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  std::vector<std::string> outside;
  for (const auto& row : doc["methods"]) {
    const auto* m = sglab::find_method(sglab::irradiance_methods, row["method"].get<std::string>());
    ASSERT_NE(m, nullptr) << row.dump();
    const bool in = m->valid.covers(1e-4, 1e5);
    EXPECT_EQ(row["in_valid_range"].get<bool>(), in) << row.dump();
    if (!in) {
      outside.push_back(row["method"]);
      EXPECT_FALSE(row["qualifies"].get<bool>()) << row.dump();  // the budget is 1: all else do
      EXPECT_NE(doc["choice"]["method"], row["method"]);
    }
  }
  EXPECT_EQ(outside, (std::vector<std::string>{"punctual", "hill", "hill_exact", "sglab_fast",
                                               "sglab_lite"}));
  EXPECT_EQ(doc["outside_valid_range"], nlohmann::json(outside));
  for (const auto& m : doc["errors_on_kappa_range"]["models"])
    EXPECT_EQ(m["in_valid_range"].get<bool>(),
              m["method"] != "sglab_fast" && m["method"] != "sglab_lite")
        << m.dump();
  EXPECT_NE(doc["errors_on_kappa_range"]["sufficient"], "sglab_fast");
  const auto text = sglab::test::run_sglab(
      {"recommend", "--scene", scene.string(), "--budget", "1", "--normals", "64"});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("not considered: a light's κ is outside their valid κ range"),
            std::string::npos)
      << text.output;
  EXPECT_NE(text.output.find("sglab_fast (valid for κ in [0, 1.1e+04])"), std::string::npos)
      << text.output;
}

TEST(RecommendScene, ChoiceMeetsTheBudgetAndMatchesItsRow) {
  const sglab::test::TempDir dir("scene-choice");
  const auto scene = write_temp(dir, "two.json", R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 30, "amplitude": [1, 1, 1]},
      {"axis": [1, 0, 0], "sharpness": 0.5, "amplitude": [0.2, 0.3, 0.4]}]})");
  const auto r = sglab::test::run_sglab(
      {"recommend", "--scene", scene.string(), "--budget", "5e-3", "--normals", "512", "--json"},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  ASSERT_TRUE(doc["choice"].is_object()) << r.output;
  EXPECT_LE(doc["choice"]["scene_error"].get<double>(), 5e-3);
  EXPECT_EQ(doc["normals"].get<int>(), 512);
  // The reported error of one method, recomputed here in-process.
  const Scene s = parse_scene(R"({"lights": [
      {"axis": [0, 0, 1], "sharpness": 30, "amplitude": [1, 1, 1]},
      {"axis": [1, 0, 0], "sharpness": 0.5, "amplitude": [0.2, 0.3, 0.4]}]})",
                              "x");
  const auto normals = fibonacci_normals(512);
  const auto exact = scene_irradiance_reference(s, normals);
  for (const auto& row : doc["methods"]) {
    if (row["method"] != "vsgl2015") continue;
    const auto* m = sglab::find_method(sglab::irradiance_methods, "vsgl2015");
    const double want = scene_relative_error(
        scene_irradiance(s, normals, *m, sglab::io::Precision::float32), exact);
    EXPECT_NEAR(row["scene_error"].get<double>(), want, 1e-12 * want);
    EXPECT_GT(want, 5e-3);  // vsgl2015 is far off: it must not qualify
    EXPECT_FALSE(row["qualifies"].get<bool>());
  }
  EXPECT_EQ(doc["kappa_range"][0].get<double>(), 0.5);
  EXPECT_EQ(doc["kappa_range"][1].get<double>(), 30.0);
}

}  // namespace
