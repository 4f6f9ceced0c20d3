// `sglab export --probe` (export/probe_export.hpp): the exported
// probe_irradiance(n) run on the Vulkan device against the C++ probe
// (envmap::probe_irradiance_method: envmap::sh_basis, whose closed forms
// test_probes checks, and the runtime's method in double), and the probe
// file as untrusted input.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "envmap/probe.hpp"
#include "export/probe_export.hpp"
#include "export/vulkan_runner.hpp"
#include "reference/scene.hpp"
#include "tests/test_support.hpp"
#include "tests/vulkan_fixture.hpp"

namespace {

using namespace sglab;
using envmap::Probe;
using envmap::ProbeKind;
using envmap::Vec3;

// One probe of every kind, with coefficients drawn at random (fixed seed):
// every SH coefficient of L4, both halves of every m.
std::vector<Probe> probes_of_every_kind() {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto rgb = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  const auto lobe = [&] {
    Vec3 a = rgb();
    const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    a = {a[0] / len, a[1] / len, a[2] / len};
    const double kappa = std::pow(10.0, 2 * u(rng) + 1);  // 0.1 … 1000
    return envmap::Lobe{a, kappa, {1 + u(rng), 1 + u(rng), 1 + u(rng)}};
  };
  std::vector<Probe> out;
  for (int order = 0; order <= envmap::kMaxShOrder; ++order) {
    Probe p;
    p.kind = ProbeKind::sh;
    p.order = order;
    for (std::size_t k = 0; k < envmap::sh_count(order); ++k) p.sh.push_back(rgb());
    out.push_back(p);
  }
  Probe nn;
  nn.kind = ProbeKind::sh_nonneg;
  nn.order = 1;
  for (int k = 0; k < 4; ++k) nn.sh.push_back(rgb());
  out.push_back(nn);
  Probe zh3 = nn;
  zh3.kind = ProbeKind::zh3;
  zh3.zonal = rgb();
  out.push_back(zh3);
  Probe lobes;
  lobes.kind = ProbeKind::lobes;
  for (int k = 0; k < 4; ++k) lobes.lobes.push_back(lobe());
  out.push_back(lobes);
  Probe hybrid;
  hybrid.kind = ProbeKind::hybrid;
  hybrid.order = 2;
  for (int k = 0; k < 9; ++k) hybrid.sh.push_back(rgb());
  for (int k = 0; k < 3; ++k) hybrid.lobes.push_back(lobe());
  out.push_back(hybrid);
  return out;
}

std::string write_probe(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

// Max over normals and RGB of |E_device − E_probe|, relative to the largest
// |E_probe|, of `sglab export --probe FILE --lang L` run on the device.
TEST_F(OnVulkan, ExportedProbeMatchesTheProbe) {
  namespace vk = shader::vulkan;
  const sglab::test::TempDir dir("probe_export");
  auto normals = reference::fibonacci_normals(4096);
  for (const Vec3& v :
       std::vector<Vec3>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}})
    normals.push_back(v);
  std::vector<float> in;
  for (const Vec3& n : normals)
    for (double c : {n[0], n[1], n[2], 0.0}) in.push_back(static_cast<float>(c));
  const auto groups = static_cast<std::uint32_t>((normals.size() + 63) / 64);
  int index = 0;
  for (const Probe& probe : probes_of_every_kind()) {
    const std::string file =
        write_probe(dir.path / fmt::format("probe{}.json", index++), probe.to_json().dump(1));
    const auto cpu = envmap::probe_irradiance_method(Probe::from_json(probe.to_json()));
    for (const auto lang : {shader::Language::glsl, shader::Language::hlsl}) {
      SCOPED_TRACE(probe.label() + " " + std::string(shader::to_string(lang)));
      const auto r = sglab::test::run_sglab(
          {"export", "--probe", file, "--lang", std::string(shader::to_string(lang))}, false);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto spirv = vk::compile_compute(lang, shader::probe_compute_shader(lang, r.output));
      const auto out = device_->dispatch(spirv, {in}, 4 * normals.size(), groups);
      double peak = 0, worst = 0;
      for (std::size_t k = 0; k < normals.size(); ++k) {
        const Vec3 e = cpu(normals[k]);
        for (std::size_t ch = 0; ch < 3; ++ch) {
          peak = std::max(peak, std::abs(e[ch]));
          worst = std::max(worst, std::abs(static_cast<double>(out[4 * k + ch]) - e[ch]));
        }
      }
      // Float arithmetic of at most 25 basis terms and the method's float
      // rounding: a few float ulps of the largest term.
      EXPECT_LT(worst / peak, 2e-6) << "max |device - C++| / peak = " << worst / peak;
    }
  }
}

TEST(ProbeExport, BadProbeFileNamesTheFileAndTheKey) {
  const sglab::test::TempDir dir("probe_export_input");
  const auto run = [&](const std::string& name, const std::string& text) {
    const std::string file = write_probe(dir.path / name, text);
    const auto r = sglab::test::run_sglab({"export", "--probe", file, "--lang", "glsl"});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
    return r.output;
  };
  EXPECT_NE(run("short.json", R"({"kind": "sh", "sh_order": 2, "sh": [[1, 2, 3]]})").find("'sh'"),
            std::string::npos);
  EXPECT_NE(run("kind.json", R"({"kind": "octahedral"})").find("'kind'"), std::string::npos);
  EXPECT_NE(run("method.json",
                R"({"kind": "lobes", "method": "nope", "lobes": [{"axis": [0, 0, 1],
                   "sharpness": 2, "amplitude": [1, 1, 1]}]})")
                .find("'method'"),
            std::string::npos);
  EXPECT_NE(run("table.json", R"({"map": "city", "probes": []})").find("'probes'"),
            std::string::npos);
  EXPECT_NE(run("broken.json", R"({"kind": "sh",)").find("malformed"), std::string::npos);
}

}  // namespace
