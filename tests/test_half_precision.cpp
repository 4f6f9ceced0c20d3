// tests/test_half_precision.cpp — `sglab export --precision half`:
// every method's half export compiles (GLSL float16_t, HLSL half) to SPIR-V
// that computes in 16-bit floats; its literals are halves; C++ half and
// coefficients beyond the largest half are refused; on a Vulkan device with
// shaderFloat16 (lavapipe) the device rounds to half, the target methods meet
// 5e-3 of the peak against the reference engine over κ ∈ [1e-2, 1e3], and
// `stability --half` finds κ beyond the largest half; on RADV's null devices
// `gpucost --precision half` reports half rows; the floor of any function of half
// (c, κ) returning half (docs/models.md). Device tests skip with the reason.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "export/gpu_cost.hpp"
#include "export/shader_export.hpp"
#include "export/vulkan_runner.hpp"
#include "reference/reference.hpp"
#include "tests/test_support.hpp"
#include "tests/tolerances.hpp"
#include "tests/vulkan_fixture.hpp"
#include "validate/sweep.hpp"

namespace {

namespace sh = sglab::shader;
namespace vk = sglab::shader::vulkan;
namespace gpu = sglab::shader::gpu;
namespace cost = sglab::cost;
using sglab::test::run_sglab;
using sglab::test::TempDir;
namespace tol = sglab::test;

// The methods whose row of `q` (tests/tolerances.hpp, half) has a bound.
std::vector<const tol::Tolerance*> half_claims(tol::Quantity q) {
  std::vector<const tol::Tolerance*> out;
  for (const tol::Tolerance& t : tol::kTolerances)
    if (t.quantity == q && t.bound != tol::kNone) out.push_back(&t);
  return out;
}

sh::ExportResult half_export(sh::Language lang, const std::string& method) {
  return sh::export_source(sh::standard_request(lang, method, sh::Precision::float16));
}

// The code of an export without its // comments.
std::string code_of(const std::string& source) {
  return std::regex_replace(source, std::regex("//[^\n]*"), "");
}

// SPIR-V declares a 16-bit float type: OpTypeFloat (opcode 22, 3 words) of width 16.
bool declares_float16(const std::vector<std::uint32_t>& spirv) {
  for (std::size_t i = 5; i + 2 < spirv.size();) {
    const std::uint32_t words = spirv[i] >> 16, opcode = spirv[i] & 0xffffu;
    if (opcode == 22 && words == 3 && spirv[i + 2] == 16) return true;
    if (words == 0) return false;
    i += words;
  }
  return false;
}

TEST(HalfExport, EveryMethodCompilesToHalfSpirv) {
  for (const std::string& id : sh::exportable_methods())
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      SCOPED_TRACE(fmt::format("{} {}", id, sh::to_string(lang)));
      const sh::ExportResult ex = half_export(lang, id);
      EXPECT_NO_THROW(vk::check_compiles(lang, ex.source, sh::Precision::float16));
      const auto spirv = vk::compile_compute(
          lang, sh::compute_shader(lang, ex.source, ex.entry_point, sh::Precision::float16),
          sh::Precision::float16);
      EXPECT_TRUE(declares_float16(spirv));
      // The float export declares no 16-bit type: the check can fail.
      const sh::ExportResult fl = sh::export_source(sh::standard_request(lang, id));
      EXPECT_FALSE(declares_float16(
          vk::compile_compute(lang, sh::compute_shader(lang, fl.source, fl.entry_point))));
      EXPECT_NE(ex.source.find("--precision half"), std::string::npos);
    }
}

// Every literal of a half export is a binary16 value (so the shading language
// reads exactly it), and a method without a half form of its own has no float
// left in its code.
TEST(HalfExport, LiteralsAreHalvesAndNoFloatIsLeft) {
  const std::regex literal(R"((\d+\.\d*(?:e[-+]?\d+)?)(hf|h)\b)");
  for (const std::string& id : sh::exportable_methods())
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      SCOPED_TRACE(fmt::format("{} {}", id, sh::to_string(lang)));
      const std::string source = half_export(lang, id).source;
      const std::string code = code_of(source);
      // The header states the card's own half form (what stays float), or that everything is
      // half; the code keeps float exactly where the card says so.
      const sglab::Method* card = sglab::find_method(sglab::irradiance_methods, id);
      ASSERT_NE(card, nullptr);
      EXPECT_NE(
          source.find(card->half.empty() ? std::string("every operation and constant in half.")
                                         : fmt::format("the method's half form: {}.", card->half)),
          std::string::npos);
      std::size_t count = 0;
      for (auto it = std::sregex_iterator(code.begin(), code.end(), literal);
           it != std::sregex_iterator(); ++it) {
        const float v = std::stof((*it)[1].str());
        EXPECT_EQ(static_cast<float>(static_cast<_Float16>(v)), v) << (*it)[0].str();
        ++count;
      }
      if (!card->half.empty()) continue;  // its own half form keeps float (registry card)
      EXPECT_GT(count, 0u);
      // The HLSL prelude converts to float for exp, exp2, log and sqrt only.
      const std::string rest = std::regex_replace(
          code, std::regex(R"(\(float\)x|\(half\)(exp|exp2|log|sqrt)\(\(float\)x\))"), "");
      EXPECT_FALSE(
          std::regex_search(rest, std::regex(R"(\bfloat\b|\bvec[23]\b|\bfloat[23]\b|\d[.]\d*f\b)")))
          << rest;
    }
}

TEST(HalfExport, CppHalfAndBadPrecisionAreRefused) {
  EXPECT_THROW(half_export(sh::Language::cpp, "tokuyoshi2024"), std::invalid_argument);
  auto r =
      run_sglab({"export", "--lang", "cpp", "--method", "tokuyoshi2024", "--precision", "half"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--precision half"), std::string::npos) << r.output;
  r = run_sglab(
      {"export", "--lang", "glsl", "--method", "tokuyoshi2024", "--precision", "quarter"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--precision"), std::string::npos) << r.output;
  r = run_sglab({"sweep", "--backend", "vulkan", "--precision", "double", "--method", "hill"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_sglab({"sweep", "--precision", "half", "--method", "hill"});  // the CPU rows have no half
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("vulkan backend"), std::string::npos) << r.output;
  r = run_sglab({"gpucost", "--precision", "quarter"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_sglab({"export", "--lang", "hlsl", "--method", "sglab_acc3", "--precision", "half"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("half sglab_irradiance_sglab_acc3(half cosine, half kappa)"),
            std::string::npos);
}

// A coefficient beyond 65504 would be an infinite half literal: refused naming
// the set and the key (the same value is fine in a float export).
TEST(HalfExport, CoefficientNotFiniteInHalfIsRefused) {
  sh::ExportRequest req =
      sh::standard_request(sh::Language::glsl, "tokuyoshi2024", sh::Precision::float16);
  sh::ConstantSet set = sh::method_constants("tokuyoshi2024").at(0);
  for (auto& [name, values] : set.members)
    if (name == "E") values = {1e5};
  req.overrides.push_back(set);
  try {
    sh::export_source(req);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("coefficients.E"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not finite in half"), std::string::npos) << e.what();
  }
  req.precision = sh::Precision::float32;
  EXPECT_NO_THROW(sh::export_source(req));
}

// ---------------------------------------------------------------------------
// On a Vulkan device with half arithmetic (lavapipe; tests/vulkan_fixture.hpp).
// Skipped with the reason.

// The device computes in half: punctual's max(c, 0) 2π/κ at c = 1,
// κ = 1e-3 is the binary16 quotient of the half 2π by the half κ (6280),
// not float's 6278.7.
TEST_F(OnVulkanHalf, TheDeviceRoundsToHalf) {
  for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
    const sh::ExportResult ex = half_export(lang, "punctual");
    const auto spirv = vk::compile_compute(
        lang, sh::compute_shader(lang, ex.source, ex.entry_point, sh::Precision::float16),
        sh::Precision::float16);
    const auto out = device_->run(spirv, {1.0f, 1e-3f, 0.5f, 3.0f});
    const auto h = [](float x) { return static_cast<float>(static_cast<_Float16>(x)); };
    // A quotient of two halves rounded once through float is the correctly rounded half quotient.
    EXPECT_EQ(out[0], h(h(6.28318548f) / h(1e-3f))) << sh::to_string(lang);
    EXPECT_EQ(out[0], 6280.0f);
    EXPECT_EQ(out[1], h(h(0.5f) * h(h(6.28318548f) / h(3.0f)))) << sh::to_string(lang);
  }
}

// The floor of the sweep's half column (docs/models.md, "Half precision: the floor"): the
// device gets c and κ rounded float → half and returns a half, so every (c, κ) whose halves
// are (ĉ, κ̂), a cell, gets the same half value v. Over a cell's corners and midpoints, the v
// that minimaxes |v − E(c, κ)|/E(1, κ) bounds every function of the half inputs, and the
// halves on either side of it every such function returning half (the error is convex in v).
double to_half(double x) {
  return static_cast<double>(static_cast<_Float16>(static_cast<float>(x)));
}
double half_spacing(double x) { return std::ldexp(1.0, std::ilogb(x) - 10); }  // normal halves

struct CellFloor {
  double exact_output = 0;  // the minimax v's error
  double half_output = 0;   // the better of the two halves around it
};
CellFloor cell_floor(double kappa_h, double cos_h) {
  const auto& engine = sglab::reference::reference_engine();
  EXPECT_EQ(to_half(kappa_h), kappa_h);
  EXPECT_EQ(to_half(cos_h), cos_h);
  // Just under half a spacing either side rounds to (κ̂, ĉ) through float (a float step from the
  // midpoint would make it a tie); c stops at 1.
  const double dk = 0.5 * half_spacing(kappa_h) * (1 - 1e-3);
  const double dc = 0.5 * half_spacing(cos_h) * (1 - 1e-3);
  std::vector<double> value, weight;
  for (double kappa : {kappa_h - dk, kappa_h, kappa_h + dk}) {
    EXPECT_EQ(to_half(kappa), kappa_h);
    const double e1 = engine.evaluate(kappa, 1.0).irradiance;
    for (double c : {cos_h - dc, cos_h, std::min(1.0, cos_h + dc)}) {
      EXPECT_EQ(to_half(c), cos_h);
      value.push_back(engine.evaluate(kappa, c).irradiance);
      weight.push_back(e1);
    }
  }
  const auto error = [&](double v) {
    double e = 0;
    for (std::size_t i = 0; i < value.size(); ++i)
      e = std::max(e, std::abs(v - value[i]) / weight[i]);
    return e;
  };
  // The minimax v: bisection on the level e, feasible when the intervals [E − e w, E + e w] meet.
  double lo = 0, hi = 1;
  for (int it = 0; it < 80; ++it) {
    const double e = 0.5 * (lo + hi);
    double v_lo = -1e300, v_hi = 1e300;
    for (std::size_t i = 0; i < value.size(); ++i) {
      v_lo = std::max(v_lo, value[i] - e * weight[i]);
      v_hi = std::min(v_hi, value[i] + e * weight[i]);
    }
    (v_lo <= v_hi ? hi : lo) = e;
  }
  double v_star = -1e300;
  for (std::size_t i = 0; i < value.size(); ++i)
    v_star = std::max(v_star, value[i] - hi * weight[i]);
  const double below =
      to_half(v_star) <= v_star ? to_half(v_star) : to_half(v_star) - half_spacing(v_star);
  const double above = below + half_spacing(below);
  EXPECT_LE(below, v_star);
  EXPECT_GE(above, v_star);
  return {error(v_star), std::min(error(below), error(above))};
}

// κ̂ = 399.75 (spacing 0.25), ĉ = 1 − 2⁻¹⁰ (spacing 2⁻¹¹): the inputs' rounding alone costs
// 5.56e-4, but the minimax value lies halfway between two halves, and both err 1.042e-3: no half
// export of any model holds 1e-3 there. κ̂ = 8200, ĉ = 1 − 2⁻¹¹: the largest floor of the
// inputs' rounding alone, 7.32e-4 at the cell's edges (7.31e-4 a float step inside them).
TEST(HalfFloor, NoHalfResultMeets1e3InTheWorstCell) {
  const CellFloor worst = cell_floor(399.75, 1.0 - std::ldexp(1.0, -10));
  EXPECT_NEAR(worst.exact_output, 5.56e-4, 0.01e-4);
  EXPECT_GT(worst.half_output, 1e-3);
  EXPECT_NEAR(worst.half_output, 1.042e-3, 0.001e-3);
  const CellFloor inputs = cell_floor(8200.0, 1.0 - std::ldexp(1.0, -11));
  EXPECT_NEAR(inputs.exact_output, 7.31e-4, 0.01e-4);
  EXPECT_LT(inputs.half_output, 1e-3);
}

// The exact E at the half inputs, and rounded to half, against E(c, κ): max over a sweep grid.
struct GridFloor {
  double inputs = 0, with_result = 0;
};
GridFloor grid_floor(const sglab::validate::SweepGrid& grid) {
  std::vector<sglab::reference::Query> exact, rounded;
  const std::vector<double> cosines = grid.cosines();
  for (double kappa : grid.kappas()) {
    exact.push_back({kappa, 1.0});
    rounded.push_back({kappa, 1.0});  // keeps the two lists aligned
    for (double c : cosines) {
      exact.push_back({kappa, c});
      rounded.push_back({to_half(kappa), to_half(c)});
    }
  }
  const auto& engine = sglab::reference::reference_engine();
  const auto e = engine.evaluate(exact), eh = engine.evaluate(rounded);
  GridFloor out;
  double e1 = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (i % (cosines.size() + 1) == 0) {
      e1 = e[i].irradiance;
      continue;
    }
    const double v = eh[i].irradiance, truth = e[i].irradiance;
    out.inputs = std::max(out.inputs, std::abs(v - truth) / e1);
    out.with_result = std::max(out.with_result, std::abs(to_half(v) - truth) / e1);
  }
  return out;
}

// The exact E at the half inputs errs at most 4.51e-4 on the standard grid (29 κ × 41 c), and
// rounded to half 6.14e-4: the grid does not see the floor above. On the held-out grid (217 κ
// over [1.1e-3, 9.7e3] × 401 c) 6.83e-4 and 9.50e-4.
TEST(HalfFloor, TheSweepGridsSeeLessThanTheFloor) {
  const GridFloor standard = grid_floor({});
  EXPECT_NEAR(standard.inputs, 4.51e-4, 0.01e-4);
  EXPECT_NEAR(standard.with_result, 6.14e-4, 0.01e-4);
  const GridFloor held_out = grid_floor({1.1e-3, 9.7e3, 217, 401});
  EXPECT_NEAR(held_out.inputs, 6.83e-4, 0.01e-4);
  EXPECT_NEAR(held_out.with_result, 9.50e-4, 0.01e-4);
}

// `sweep --backend vulkan --precision half`: the rows vulkan_half and
// vulkan_hlsl_half, measured against the reference engine. Every method with a
// half_peak_rel bound in tests/tolerances.hpp (5e-3 over κ in [1e-2, 1e3] for
// sglab_fast, in its half form, and sglab_acc3; 2.5e-3 for sglab_mid) meets it on the
// standard grid restricted to that range and on a held-out grid no fit used.
TEST_F(OnVulkanHalf, TargetMethodsMeetTheHalfBudget) {
  TempDir dir("half_sweep");
  for (const std::vector<std::string>& grid :
       {std::vector<std::string>{"--kappa", "1e-2:1e3:21"},
        std::vector<std::string>{"--kappa", "1.13e-2:8.9e2:53", "--cosines", "101"}}) {
    std::vector<std::string> args = {"sweep",  "--backend", "vulkan", "--precision",     "half",
                                     "--lang", "both",      "--out",  dir.path.string(), "--json"};
    std::map<std::string, const tol::Tolerance*> claims;
    for (const tol::Tolerance* t : half_claims(tol::half_peak_rel)) {
      claims[std::string(t->method)] = t;
      args.insert(args.end(), {"--method", std::string(t->method)});
    }
    ASSERT_FALSE(claims.empty());
    args.insert(args.end(), grid.begin(), grid.end());
    const auto r = run_sglab(args, false);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto doc = nlohmann::json::parse(r.output);
    int rows = 0;
    for (const auto& rec : doc.at("results")) {
      const std::string precision = rec.at("precision");
      ASSERT_TRUE(precision == "vulkan_half" || precision == "vulkan_hlsl_half") << precision;
      const tol::Tolerance* t = claims.at(rec.at("method").get<std::string>());
      EXPECT_LE(rec.at("max_peak_rel").get<double>(), t->bound) << t->reason << "; " << rec.dump();
      EXPECT_EQ(rec.at("nonfinite").get<int>(), 0) << rec.dump();
      ++rows;
    }
    EXPECT_EQ(rows, static_cast<int>(2 * claims.size()));
  }
}

// `stability --half`: every method's half export against its float export.
// κ = 7.5e4 is beyond the largest half (65504), so no method survives it;
// every method with a half_vs_float bound in tests/tolerances.hpp survives
// [1e-2, 1e3] within it.
TEST_F(OnVulkanHalf, StabilityFindsWhereHalfFails) {
  TempDir dir("half_stability");
  const auto r = run_sglab({"stability", "--half", "--json", "--out", dir.path.string()}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  ASSERT_TRUE(doc.contains("half"));
  int rows = 0, claimed = 0;
  for (const auto& rec : doc.at("half")) {
    ++rows;
    const std::string m = rec.at("method");
    if (rec.at("survives_kappa_hi").is_number()) {
      EXPECT_LT(rec.at("survives_kappa_hi").get<double>(), 65504) << m;
    }
    const tol::Tolerance* t = tol::find_tolerance(m, tol::half_vs_float, tol::f16);
    ASSERT_NE(t, nullptr) << "tests/tolerances.hpp has no half_vs_float row for " << m;
    if (t->bound != tol::kNone) {
      ++claimed;
      EXPECT_LE(rec.at("survives_kappa_lo").get<double>(), 1e-2) << m;
      EXPECT_GE(rec.at("survives_kappa_hi").get<double>(), 1e3) << m;
      EXPECT_LE(rec.at("max_diff_in_range").get<double>(), t->bound) << t->reason << "; " << m;
    }
  }
  EXPECT_EQ(rows, static_cast<int>(sh::exportable_methods().size()));
  EXPECT_EQ(claimed, static_cast<int>(half_claims(tol::half_vs_float).size()));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.path / "stability_half.md"));
}

// The header of a half export states the cost of a "half" row of the cost
// table whose SPIR-V hash is that of this very code, and never a float row's.
TEST(HalfGpuCost, ExportHeaderReadsTheHalfRow) {
  namespace fs = std::filesystem;
  TempDir dir("half-export-cost");
  const fs::path checkout = sglab::test::checkout_dir();
  sglab::test::make_scratch_project(dir.path);
  auto doc = nlohmann::ordered_json::parse(
      sglab::io::read_file(checkout / "data" / "results" / "costs.json"));
  const std::string half_hash =
      gpu::spirv_hash(gpu::method_shader("hill", sh::Language::glsl, sh::Precision::float16).spirv);
  cost::gpu::Statistics s;
  s.instructions = s.inverse_throughput = s.latency = 777;
  cost::gpu::Report report{"radv Mesa (test rows)", "test", {}};
  report.rows = {// not a half row
                 {"hill", "navi21", sh::Language::glsl, false, "half", s, half_hash},
                 {"hill", "gfx1100", sh::Language::glsl, false, "float", s, half_hash}};
  doc["gpu"] = cost::gpu::to_json(report);
  sglab::io::write_file_atomic(dir.path / "data" / "results" / "costs.json", doc.dump());
  const fs::path old = fs::current_path();
  fs::current_path(dir.path);
  const auto half =
      run_sglab({"export", "--lang", "glsl", "--method", "hill", "--precision", "half"}, false);
  const auto single = run_sglab({"export", "--lang", "glsl", "--method", "hill"}, false);
  fs::current_path(old);
  ASSERT_EQ(half.exit_code, 0) << half.output;
  EXPECT_NE(half.output.find("costs.json): navi21 777, gfx1100 not measured\n"), std::string::npos)
      << half.output;
  ASSERT_EQ(single.exit_code, 0) << single.output;
  EXPECT_EQ(single.output.find("777"), std::string::npos) << single.output;
}

// ---------------------------------------------------------------------------
// RADV's null devices: `gpucost --precision half` (RDNA has packed 16-bit math).

TEST(OnRadvHalf, HalfRowsCostTheHalfExports) {
  const auto manifest = gpu::find_radv_manifest();
  if (!manifest)
    GTEST_SKIP() << "no RADV null device: no radeon_icd.*.json in the Vulkan loader's folders";
  try {
    gpu::measure(SGLAB_BINARY, *manifest, {"navi21"}, {gpu::baseline_shader(sh::Language::glsl)});
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << "no RADV null device: " << e.what();
  }
  // The half wrapper alone costs nothing: what is subtracted is the half baseline.
  const gpu::Shader baseline = gpu::baseline_shader(sh::Language::glsl, sh::Precision::float16);
  gpu::Shader same = baseline;
  same.method = "same";
  const cost::gpu::Report alone =
      gpu::measure(SGLAB_BINARY, *manifest, {"navi21"}, {baseline, same});
  ASSERT_EQ(alone.rows.size(), 1u);
  EXPECT_EQ(alone.rows[0].precision, "half");
  EXPECT_EQ(alone.rows[0].stats.inverse_throughput, 0);
  EXPECT_EQ(alone.rows[0].stats.instructions, 0);

  const auto r = run_sglab(
      {"gpucost", "--families", "navi21,gfx1100", "--precision", "both", "--lang", "both",
       "--method", "sglab_fast", "--method", "sglab_acc3", "--harness", "single", "--json"},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  int half = 0, single = 0, half_split = 0, single_split = 0;
  for (const auto& row : doc.at("rows")) {
    EXPECT_EQ(row.at("harness"), "single");
    if (row.at("split").get<bool>())
      (row.at("precision") == "half" ? half_split : single_split) += 1;
    else
      (row.at("precision") == "half" ? half : single) += 1;
    EXPECT_GT(row.at("inverse_throughput").get<int>(), 0) << row.dump();
  }
  EXPECT_EQ(half, 2 * 2 * 2);  // methods × families × languages
  EXPECT_EQ(single, 2 * 2 * 2);
  // The default --form both adds the split rows, float only: the split export has no half form.
  EXPECT_EQ(single_split, 2 * 2 * 2);
  EXPECT_EQ(half_split, 0);
  // The loop and setup harnesses are float only: with half alone they have nothing to cost.
  const auto loop = run_sglab({"gpucost", "--families", "navi21", "--precision", "half", "--method",
                               "sglab_fast", "--harness", "loop", "--json"},
                              false);
  EXPECT_EQ(loop.exit_code, 2) << loop.output;
}

}  // namespace
