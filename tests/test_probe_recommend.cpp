// `sglab envmap recommend --by storage` (report/probe_recommend.hpp) on maps
// whose best probe is known: a constant map is exactly SH L0, a map that is one
// SG light is one lobe (found where it is).
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "envmap/envmap.hpp"
#include "envmap/probe.hpp"
#include "report/probe_recommend.hpp"
#include "tests/map_of.hpp"
#include "tests/test_support.hpp"

namespace {

using namespace sglab;
using envmap::Map;
using envmap::Vec3;

using sglab::test::map_of;

const envmap::Lobe kLight{{0.36, 0.48, 0.8}, 20.0, {3.0, 2.0, 1.0}};

Map one_light_map() {
  return map_of(64, [](const Vec3& w) {
    const auto& a = kLight.axis;
    const double g = std::exp(kLight.sharpness * (w[0] * a[0] + w[1] * a[1] + w[2] * a[2] - 1));
    return Vec3{kLight.amplitude[0] * g, kLight.amplitude[1] * g, kLight.amplitude[2] * g};
  });
}

const auto quiet = [](const std::string&) {};

TEST(ProbeRecommend, ConstantMapIsShL0) {
  const Vec3 L{1.5, 0.25, 3.0};
  const Map m = map_of(32, [&](const Vec3&) { return L; });
  const auto r = report::recommend_probe_by_storage(m, 1e-4, 4, quiet);
  ASSERT_TRUE(r.choice);
  const auto& c = r.tried[*r.choice];
  EXPECT_EQ(c.probe.label(), "SH L0");
  EXPECT_EQ(c.probe.floats(), 3u);
  // E = πL at every normal (a constant map's irradiance, [Ramamoorthi2001]
  // Â_0 = π), to the map's own horizon sub-pixel error at 32 × 16 (~1e−5: the
  // least-squares L0, of equal floats and smaller error, may be chosen).
  const auto e = envmap::probe_irradiance_method(c.probe)(Vec3{0.6, 0, 0.8});
  for (std::size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(e[ch], M_PI * L[ch], 1e-4 * M_PI * L[ch]);
  ASSERT_TRUE(r.runner_up);
  EXPECT_NE(r.tried[*r.runner_up].probe.label(), "SH L0");
  EXPECT_GE(r.tried[*r.runner_up].probe.floats(), 3u);
}

TEST(ProbeRecommend, OneSgLightIsOneLobeWhereItIs) {
  const Map m = one_light_map();
  const double budget = 2e-3;
  const auto r = report::recommend_probe_by_storage(m, budget, 4, quiet);
  ASSERT_TRUE(r.choice);
  const auto& c = r.tried[*r.choice];
  EXPECT_EQ(c.probe.label(), "1 SG");
  EXPECT_LE(c.error.max_rel, budget);
  ASSERT_EQ(c.probe.lobes.size(), 1u);
  const auto& l = c.probe.lobes[0];
  const double cosine =
      l.axis[0] * kLight.axis[0] + l.axis[1] * kLight.axis[1] + l.axis[2] * kLight.axis[2];
  EXPECT_GT(cosine, std::cos(0.02)) << "axis " << l.axis[0] << " " << l.axis[1] << " " << l.axis[2];
  EXPECT_NEAR(l.sharpness, kLight.sharpness, 0.1 * kLight.sharpness);
  // Every candidate of fewer floats fails the budget (SH L0 cannot hold a light).
  for (const auto& t : r.tried)
    if (t.probe.floats() < c.probe.floats()) {
      EXPECT_GT(t.error.max_rel, budget) << t.probe.label();
    }
}

TEST(ProbeRecommend, CliWritesAProbeThatExports) {
  const sglab::test::TempDir dir("probe_recommend");
  const auto map_file = (dir.path / "light.exr").string();
  envmap::write_exr(map_file, one_light_map());
  const auto probe_file = (dir.path / "probe.json").string();
  const auto r =
      sglab::test::run_sglab({"envmap", "recommend", map_file, "--budget", "2e-3", "--by",
                              "storage", "--max-lobes", "4", "--write-probe", probe_file, "--json"},
                             false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  EXPECT_EQ(doc["choice"]["label"], "1 SG");
  EXPECT_LE(doc["choice"]["max_rel"].get<double>(), 2e-3);
  const auto e = sglab::test::run_sglab({"export", "--probe", probe_file, "--lang", "cpp"});
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_NE(e.output.find("probe_irradiance"), std::string::npos);
  const auto bad = sglab::test::run_sglab(
      {"envmap", "recommend", map_file, "--budget", "2e-3", "--by", "gpu:navi21"});
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

}  // namespace
