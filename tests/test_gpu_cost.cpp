// tests/test_gpu_cost.cpp — `sglab gpucost`: ACO statistics on RADV null
// devices. The tests that need a null device skip, with the reason, when RADV
// cannot create one.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "common/io.hpp"
#include "cost/cost_table.hpp"
#include "export/gpu_cost.hpp"
#include "export/vulkan_runner.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
namespace gpu = sglab::shader::gpu;
namespace cost = sglab::cost;
namespace shader = sglab::shader;
using sglab::test::run_sglab;
using sglab::test::TempDir;

// The single harness around `body` (a function float NAME(float cosine, float kappa)).
gpu::Shader synthetic(const std::string& name, const std::string& body) {
  const std::string src = fmt::format("float {}(float cosine, float kappa) {{ {} }}\n", name, body);
  return {name, shader::Language::glsl,
          sglab::shader::vulkan::compile_compute(
              shader::Language::glsl,
              shader::compute_shader(shader::Language::glsl, src, name, shader::Precision::float32,
                                     shader::Dispatch::whole_groups))};
}

// The loop harness over `lights` lights around `body` (kappa per light).
gpu::Shader synthetic_loop(const std::string& name, const std::string& body, int lights) {
  const std::string src = fmt::format("float {}(float cosine, float kappa) {{ {} }}\n", name, body);
  gpu::Shader s{name, shader::Language::glsl,
                sglab::shader::vulkan::compile_compute(
                    shader::Language::glsl,
                    shader::loop_compute_shader(shader::Language::glsl, src, name, {}, lights))};
  s.harness = cost::gpu::Harness::loop;
  s.lights = lights;
  return s;
}

class OnRadv : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    manifest_ = gpu::find_radv_manifest();
    if (!manifest_) {
      skip_reason_ = "no radeon_icd.*.json (mesa-vulkan-drivers) in the Vulkan loader's folders";
      return;
    }
    try {
      gpu::measure(SGLAB_BINARY, *manifest_, {"navi21"},
                   {gpu::baseline_shader(shader::Language::glsl)});
    } catch (const gpu::Unavailable& e) {
      skip_reason_ = e.what();
    }
  }
  void SetUp() override {
    if (!skip_reason_.empty()) GTEST_SKIP() << "no RADV null device: " << skip_reason_;
  }
  static cost::gpu::Report measure(const std::vector<std::string>& families,
                                   const std::vector<gpu::Shader>& shaders) {
    return gpu::measure(SGLAB_BINARY, *manifest_, families, shaders);
  }
  static std::optional<fs::path> manifest_;
  static std::string skip_reason_;
};
std::optional<fs::path> OnRadv::manifest_;
std::string OnRadv::skip_reason_;

// The wrapper measured as if it were a method costs nothing: what is
// subtracted is exactly the wrapper's own code.
TEST_F(OnRadv, TheWrapperAloneCostsNothing) {
  const gpu::Shader baseline = gpu::baseline_shader(shader::Language::glsl);
  gpu::Shader same = baseline;
  same.method = "same";
  const cost::gpu::Report r = measure({"navi21", "gfx1100"}, {baseline, same});
  ASSERT_EQ(r.rows.size(), 2u);
  for (const cost::gpu::Row& row : r.rows) {
    SCOPED_TRACE(row.family);
    EXPECT_EQ(row.stats.instructions, 0);
    EXPECT_EQ(row.stats.inverse_throughput, 0);
    EXPECT_EQ(row.stats.latency, 0);
    EXPECT_EQ(row.stats.code_size, 0);
    EXPECT_EQ(row.stats.branches, 0);
    EXPECT_GT(row.stats.vgprs, 0);  // the pipeline's registers, not a difference
  }
}

// More work costs more: one exp, then two exps, then a chain of eight
// dependent exps and divisions, then a loop; instructions grow with the work,
// the estimated inverse throughput with the chain, branches with the loop.
TEST_F(OnRadv, MoreWorkCostsMore) {
  const cost::gpu::Report r = measure(
      {"navi21"},
      {gpu::baseline_shader(shader::Language::glsl),
       synthetic("one_exp", "return exp(-kappa) * cosine;"),
       synthetic("two_exp", "return exp(-kappa) * cosine + exp(kappa * cosine);"),
       synthetic(
           "chain",
           "float x = cosine; for (int i = 0; i < 8; ++i) x = exp(-x) / (kappa + x); return x;"),
       synthetic(
           "loop",
           "float s = 0.0; for (int i = 0; i < int(kappa); ++i) s += exp(s * cosine); return s;")});
  ASSERT_EQ(r.rows.size(), 4u);
  const cost::gpu::Statistics &one = r.rows[0].stats, &two = r.rows[1].stats,
                              &chain = r.rows[2].stats, &loop = r.rows[3].stats;
  EXPECT_GT(one.instructions, 0);
  EXPECT_GT(two.instructions, one.instructions);
  EXPECT_GT(chain.instructions, two.instructions);
  EXPECT_GE(two.inverse_throughput, one.inverse_throughput);
  EXPECT_GT(chain.inverse_throughput, 4 * one.inverse_throughput);
  EXPECT_GT(chain.latency, two.latency);
  EXPECT_EQ(one.branches, 0);
  EXPECT_EQ(chain.branches, 0);  // unrolled
  EXPECT_GT(loop.branches, 0);
  EXPECT_NE(r.rows[0].spirv_hash, r.rows[1].spirv_hash);
}

// What a bounds check around the call hides: the sweep's wrapper, which checks
// each invocation's index against the buffer's length, puts the method in a
// divergent branch, and ACO's estimate counts a divergent branch's code at
// 0.75 of its cost (aco_statistics.cpp). Measured there, minus the same
// wrapper around the trivial body, a method costs about a quarter less than
// in gpucost's single harness, which has no branch (its baseline has none
// either: no branch is left in the difference of two branch-free shaders).
TEST_F(OnRadv, ABoundsCheckHidesAQuarterOfTheCost) {
  const auto in_sweep_wrapper = [](const std::string& method, const std::string& entry,
                                   const std::string& source) {
    return gpu::Shader{
        method, shader::Language::glsl,
        sglab::shader::vulkan::compile_compute(
            shader::Language::glsl, shader::compute_shader(shader::Language::glsl, source, entry))};
  };
  const std::vector<std::string> methods = {"tokuyoshi2024", "sglab_acc3", "sglab_fast",
                                            "meder2018"};
  std::vector<gpu::Shader> checked = {
      in_sweep_wrapper(std::string(gpu::kBaseline), "base",
                       "float base(float cosine, float kappa) { return cosine + kappa; }\n")};
  std::vector<gpu::Shader> whole = {gpu::baseline_shader(shader::Language::glsl)};
  for (const std::string& m : methods) {
    const auto ex = shader::export_source(shader::standard_request(shader::Language::glsl, m));
    checked.push_back(in_sweep_wrapper(m, ex.entry_point, ex.source));
    whole.push_back(gpu::method_shader(m, shader::Language::glsl));
  }
  const cost::gpu::Report a = measure({"navi21"}, checked), b = measure({"navi21"}, whole);
  ASSERT_EQ(a.rows.size(), methods.size());
  ASSERT_EQ(b.rows.size(), methods.size());
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const double in_branch = static_cast<double>(a.rows[i].stats.inverse_throughput),
                 free = static_cast<double>(b.rows[i].stats.inverse_throughput);
    const std::string figures =
        fmt::format("{}: {} cycles in the bounds check, {} without", methods[i], in_branch, free);
    std::printf("navi21 %s\n", figures.c_str());  // docs/costs.md quotes these
    SCOPED_TRACE(figures);
    EXPECT_LT(in_branch, 0.85 * free);
    EXPECT_GT(in_branch, 0.6 * free);
    EXPECT_EQ(a.rows[i].stats.branches, b.rows[i].stats.branches);  // the method's own branches
  }
}

// gpucost's single harness is a branch-free wrapper: rebuilt here by hand (its
// own text, one load and one store, no bounds check) around the exports of
// tokuyoshi2024 and sglab_acc3 and around a trivial body, the difference is
// what `sglab gpucost --json` reports, within 2%.
TEST_F(OnRadv, SingleHarnessAgreesWithAnIndependentBranchFreeWrapper) {
  const auto wrap = [](const std::string& method, const std::string& source,
                       const std::string& entry) {
    const std::string text = fmt::format(
        "#version 450\nlayout(local_size_x = 64) in;\n"
        "layout(std430, binding = 0) readonly buffer In {{ vec2 ck[]; }};\n"
        "layout(std430, binding = 1) writeonly buffer Out {{ float e[]; }};\n{}\n"
        "void main() {{ e[gl_GlobalInvocationID.x] = {}(ck[gl_GlobalInvocationID.x].x, "
        "ck[gl_GlobalInvocationID.x].y); }}\n",
        source, entry);
    return gpu::Shader{method, shader::Language::glsl,
                       sglab::shader::vulkan::compile_compute(shader::Language::glsl, text)};
  };
  std::vector<gpu::Shader> shaders = {
      wrap(std::string(gpu::kBaseline), "float f(float c, float k) { return c + k; }", "f")};
  for (const char* m : {"tokuyoshi2024", "sglab_acc3"}) {
    const auto ex = shader::export_source(shader::standard_request(shader::Language::glsl, m));
    shaders.push_back(wrap(m, ex.source, ex.entry_point));
  }
  const cost::gpu::Report mine = measure({"navi21"}, shaders);
  const auto r =
      run_sglab({"gpucost", "--families", "navi21", "--method", "tokuyoshi2024", "--method",
                 "sglab_acc3", "--harness", "single", "--form", "unsplit", "--json"},
                false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = nlohmann::json::parse(r.output).at("rows");
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(mine.rows.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const double here = static_cast<double>(mine.rows[i].stats.inverse_throughput),
                 there = rows[i].at("inverse_throughput").get<double>();
    EXPECT_EQ(rows[i].at("method").get<std::string>(), mine.rows[i].method);
    EXPECT_NEAR(there, here, 0.02 * here) << mine.rows[i].method;
  }
}

// The loop harness counts every light: a body of 4 dependent exps costs per
// light the same over 8 and 64 written-out lights (within 5%), and its
// instructions grow 8-fold. A loop over a light count read at run time instead
// has no trip count for ACO's estimate, which counts its body 8 times whatever
// the count, each iteration waiting on its light's loads: minus the same loop
// around the trivial body it comes out below even 8 written-out lights, so it
// cannot say what many lights cost; hence the harness writes its lights out.
TEST_F(OnRadv, LoopHarnessCountsEveryLight) {
  const std::string body =
      "float x = cosine; for (int i = 0; i < 4; ++i) x = exp(x * kappa); return x;";
  std::vector<gpu::Shader> shaders;
  for (int n : {8, 64}) {
    shaders.push_back(gpu::baseline_shader(shader::Language::glsl, shader::Precision::float32,
                                           cost::gpu::Harness::loop, n));
    shaders.push_back(synthetic_loop("chain", body, n));
  }
  const cost::gpu::Report r = measure({"navi21"}, shaders);
  ASSERT_EQ(r.rows.size(), 2u);
  const double per8 = cost::gpu::cycles_per_light(r.rows[0]),
               per64 = cost::gpu::cycles_per_light(r.rows[1]);
  EXPECT_GT(per8, 0);
  EXPECT_NEAR(per64, per8, 0.05 * per8);
  EXPECT_NEAR(static_cast<double>(r.rows[1].stats.instructions),
              8.0 * static_cast<double>(r.rows[0].stats.instructions),
              0.05 * 8.0 * static_cast<double>(r.rows[0].stats.instructions));
  // The same lights in a loop whose count the shader reads from a buffer.
  const auto runtime_loop = [](const std::string& method, const std::string& fn) {
    const std::string text = fmt::format(
        "#version 450\nlayout(local_size_x = 64) in;\n"
        "layout(std430, binding = 0) readonly buffer N {{ vec4 normals[]; }};\n"
        "layout(std430, binding = 1) writeonly buffer Out {{ float result[]; }};\n"
        "layout(std430, binding = 2) readonly buffer A {{ vec4 axes[]; }};\n"
        "layout(std430, binding = 3) readonly buffer K {{ uint count; float kappas[]; }};\n"
        "float f(float cosine, float kappa) {{ {} }}\n"
        "void main() {{\n  uint i = gl_GlobalInvocationID.x;\n  vec3 n = normals[i].xyz;\n"
        "  float e = 0.0;\n  for (uint k = 0u; k < count; ++k)\n"
        "    e += axes[k].w * f(dot(axes[k].xyz, n), kappas[k]);\n  result[i] = e;\n}}\n",
        fn);
    gpu::Shader s{method, shader::Language::glsl,
                  sglab::shader::vulkan::compile_compute(shader::Language::glsl, text)};
    s.harness = cost::gpu::Harness::loop;
    return s;
  };
  const cost::gpu::Report runtime =
      measure({"navi21"}, {runtime_loop(std::string(gpu::kBaseline), "return cosine + kappa;"),
                           runtime_loop("chain", body)});
  ASSERT_EQ(runtime.rows.size(), 1u);
  const double looped = static_cast<double>(runtime.rows[0].stats.inverse_throughput);
  EXPECT_LT(looped, 8 * per8);
}

// Two runs print the same bytes; the JSON carries every field the cost table
// needs, for every method asked on every family asked.
TEST_F(OnRadv, TwoRunsGiveTheSameBytes) {
  const std::vector<std::string> args = {"gpucost", "--families", "navi21,gfx1100", "--method",
                                         "hill",    "--lang",     "both",           "--json"};
  const auto a = run_sglab(args, false);
  const auto b = run_sglab(args, false);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  EXPECT_EQ(a.output, b.output);
  const auto doc = nlohmann::json::parse(a.output);
  EXPECT_NE(doc.at("driver").get<std::string>().find("Mesa"), std::string::npos);
  // 2 families × 1 method × 2 languages × (single unsplit and split, loop of 8 lights
  // unsplit and split, setup)
  ASSERT_EQ(doc.at("rows").size(), 2u * 2u * (2u + 2u + 1u));
  std::map<std::string, int> harnesses;
  for (const auto& row : doc.at("rows")) {
    for (const char* key : {"method", "family", "lang", "compile", "harness", "lights", "split",
                            "precision", "instructions", "inverse_throughput", "latency", "vgprs",
                            "sgprs", "code_size", "branches", "spirv_hash"})
      EXPECT_TRUE(row.contains(key)) << key;
    EXPECT_GT(row.at("instructions").get<long long>(), 0) << row.dump();
    EXPECT_EQ(row.at("compile"), "none");
    ++harnesses[row.at("harness").get<std::string>()];
  }
  EXPECT_EQ(harnesses["single"], 8);
  EXPECT_EQ(harnesses["loop"], 8);
  EXPECT_EQ(harnesses["setup"], 4);
}

// --out fills the "gpu" section of DIR/costs.json and keeps the CPU rows;
// a re-run leaves the file byte for byte as it was.
TEST_F(OnRadv, OutKeepsTheCpuCostsAndIsReproducible) {
  TempDir dir("gpucost-out");
  const fs::path committed =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "results" / "costs.json";
  // A table whose gpu section an older gpucost wrote (rows without a harness):
  // --out replaces that section, whatever it holds.
  auto old_doc = nlohmann::ordered_json::parse(sglab::io::read_file(committed));
  for (auto& row : old_doc.at("gpu").at("rows")) row.erase("harness");
  sglab::io::write_file_atomic(dir.path / "costs.json", old_doc.dump(2));
  EXPECT_THROW(sglab::cost::read_cost_table(dir.path / "costs.json"), sglab::cost::CostTableError);
  const auto before =
      sglab::cost::read_cost_table(dir.path / "costs.json", sglab::cost::GpuSection::skip);
  const std::vector<std::string> args = {"gpucost",  "--families", "navi21",
                                         "--method", "hill",       "--harness",
                                         "single",   "--out",      dir.path.string()};
  const auto run = run_sglab(args);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto after = sglab::cost::read_cost_table(dir.path / "costs.json");
  ASSERT_EQ(after.costs.size(), before.costs.size());
  for (std::size_t i = 0; i < before.costs.size(); ++i)
    EXPECT_EQ(after.costs[i].ns_per_eval, before.costs[i].ns_per_eval);
  ASSERT_TRUE(after.gpu.has_value());
  ASSERT_EQ(after.gpu->rows.size(), 2u);  // unsplit and split
  EXPECT_EQ(after.gpu->rows[0].method, "hill");
  EXPECT_EQ(after.gpu->rows[0].family, "navi21");
  EXPECT_EQ(after.gpu->rows[0].harness, cost::gpu::Harness::single);
  EXPECT_FALSE(after.gpu->rows[0].split);
  EXPECT_TRUE(after.gpu->rows[1].split);
  EXPECT_TRUE(fs::is_regular_file(dir.path / "gpu_costs.md"));
  const std::string first = sglab::io::read_file(dir.path / "costs.json");
  ASSERT_EQ(run_sglab(args).exit_code, 0);
  EXPECT_EQ(sglab::io::read_file(dir.path / "costs.json"), first);
}

// --disasm prints the final assembly: the wrapper's load and store, and for
// tokuyoshi2024 the hardware exp its erfc and e^{-κ} need.
TEST_F(OnRadv, DisasmPrintsTheAssembly) {
  const auto r =
      run_sglab({"gpucost", "--disasm", "--method", "tokuyoshi2024", "--family", "navi21"}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("buffer_load_dwordx2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("buffer_store_dword"), std::string::npos);
  EXPECT_NE(r.output.find("v_exp_f32"), std::string::npos);
  EXPECT_NE(r.output.find("s_endpgm"), std::string::npos);
  const auto two = run_sglab(
      {"gpucost", "--disasm", "--method", "hill", "--method", "vsgl2015", "--family", "navi21"});
  EXPECT_EQ(two.exit_code, 2) << two.output;
  EXPECT_NE(two.output.find("--disasm"), std::string::npos) << two.output;
}

// An HLSL user pays what a GLSL user pays: for every export, unsplit and split,
// ACO's inverse throughput of the HLSL form is within 5% of the GLSL form's on
// RDNA2 and RDNA3 as glslang writes them, and at most 5% above it after
// SPIRV-Tools' legalization (what glslangValidator and DXC give HLSL users) or
// its performance passes (compared with the GLSL after the same). Both are the
// same function, so the compiler should see the same control flow; glslang's
// HLSL front end evaluates both arms of ?:, and the legalization's
// merge-return turns an early return into code that ACO flattens into selects
// (the exports have one return per function).
TEST_F(OnRadv, HlslCostsWhatGlslCosts) {
  const std::vector<std::string> methods = shader::exportable_methods();
  const std::vector<std::string> split = shader::split_methods();
  std::vector<gpu::Shader> shaders;
  for (shader::Language lang : {shader::Language::glsl, shader::Language::hlsl})
    for (cost::gpu::CompilePath c :
         {cost::gpu::CompilePath::none, cost::gpu::CompilePath::legalized,
          cost::gpu::CompilePath::optimized}) {
      if (c == cost::gpu::CompilePath::legalized && lang == shader::Language::glsl) continue;
      shaders.push_back(
          gpu::baseline_shader(lang, shader::Precision::float32, cost::gpu::Harness::single, 1, c));
      for (const std::string& m : methods)
        shaders.push_back(gpu::method_shader(m, lang, shader::Precision::float32, c));
      for (const std::string& m : split) shaders.push_back(gpu::split_method_shader(m, lang, c));
    }
  const cost::gpu::Report r = measure({"navi21", "gfx1100"}, shaders);
  ASSERT_EQ(r.rows.size(), 2 * 5 * (methods.size() + split.size()));
  // (family, method, split, compile) → GLSL cycles
  std::map<std::tuple<std::string, std::string, bool, cost::gpu::CompilePath>, std::int64_t> glsl;
  for (const cost::gpu::Row& row : r.rows)
    if (row.lang == shader::Language::glsl)
      glsl[{row.family, row.method, row.split, row.compile}] = row.stats.inverse_throughput;
  std::size_t compared = 0;
  for (const cost::gpu::Row& row : r.rows) {
    if (row.lang != shader::Language::hlsl) continue;
    // HLSL none and legalized against the GLSL as glslang writes it; optimized against optimized.
    const cost::gpu::CompilePath against = row.compile == cost::gpu::CompilePath::optimized
                                               ? cost::gpu::CompilePath::optimized
                                               : cost::gpu::CompilePath::none;
    const std::int64_t g = glsl.at({row.family, row.method, row.split, against}),
                       h = row.stats.inverse_throughput;
    const std::string what =
        fmt::format("{} {}{} HLSL {}: GLSL {}, HLSL {} cycles", row.family, row.method,
                    row.split ? " (split)" : "", cost::gpu::to_string(row.compile), g, h);
    EXPECT_GE(g, 0) << what;
    // The same code through both front ends costs the same; after spirv-opt HLSL may be cheaper.
    EXPECT_LE(
        static_cast<double>(row.compile == cost::gpu::CompilePath::none ? std::abs(h - g) : h - g),
        0.05 * static_cast<double>(g))
        << what;
    ++compared;
  }
  EXPECT_EQ(compared, 2 * 3 * (methods.size() + split.size()));
}

// The renderer's loop (8 lights, split form, the default GPU figure): HLSL
// after legalization costs what GLSL costs as glslang writes it, within 5 %,
// on navi21 (spirv-opt must not undo what the exports leave ACO to fold).
TEST_F(OnRadv, HlslCostsWhatGlslCostsInTheLoop) {
  std::vector<gpu::Shader> shaders;
  for (const auto& [lang, c] :
       {std::pair{shader::Language::glsl, cost::gpu::CompilePath::none},
        std::pair{shader::Language::hlsl, cost::gpu::CompilePath::legalized}}) {
    shaders.push_back(
        gpu::baseline_shader(lang, shader::Precision::float32, cost::gpu::Harness::loop, 8, c));
    for (const std::string& m : shader::split_methods())
      shaders.push_back(gpu::loop_shader(m, lang, /*split=*/true, 8, c));
  }
  const cost::gpu::Report r = measure({"navi21"}, shaders);
  ASSERT_EQ(r.rows.size(), 2 * shader::split_methods().size());
  std::map<std::string, std::int64_t> glsl;
  for (const cost::gpu::Row& row : r.rows)
    if (row.lang == shader::Language::glsl) glsl[row.method] = row.stats.inverse_throughput;
  std::size_t compared = 0;
  for (const cost::gpu::Row& row : r.rows) {
    if (row.lang != shader::Language::hlsl) continue;
    const std::int64_t g = glsl.at(row.method), h = row.stats.inverse_throughput;
    EXPECT_GT(g, 0) << row.method;
    EXPECT_LE(static_cast<double>(h - g), 0.05 * static_cast<double>(g))
        << row.method << " (split, 8 lights): GLSL " << g << ", HLSL legalized " << h;
    ++compared;
  }
  EXPECT_EQ(compared, shader::split_methods().size());
}

// Split rows: the per-pixel function of `sglab export --split`,
// the light struct loaded from a buffer, for the methods that have a split
// (none for wang2009). On RDNA2 and RDNA3 the per-pixel cost of split
// tokuyoshi2024 and split sglab_acc3 is at most 0.6× the unsplit tokuyoshi2024
// inverse throughput, and every split row costs less than its unsplit row.
TEST_F(OnRadv, SplitRowsCostThePerPixelFunction) {
  const auto r =
      run_sglab({"gpucost", "--families", "navi21,gfx1100", "--method", "tokuyoshi2024", "--method",
                 "sglab_acc3", "--method", "wang2009", "--harness", "single", "--json"},
                false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  // (family, method, split)
  std::map<std::tuple<std::string, std::string, bool>, nlohmann::json> rows;
  for (const auto& row : doc.at("rows"))
    rows[{row.at("family").get<std::string>(), row.at("method").get<std::string>(),
          row.at("split").get<bool>()}] = row;
  EXPECT_EQ(rows.size(), 2u * 5u);  // 2 families × (3 unsplit + 2 split)
  for (const std::string family : {"navi21", "gfx1100"}) {
    SCOPED_TRACE(family);
    EXPECT_FALSE(rows.count({family, "wang2009", true}));
    ASSERT_TRUE(rows.count({family, "tokuyoshi2024", false}) &&
                rows.count({family, "tokuyoshi2024", true}) &&
                rows.count({family, "sglab_acc3", false}) &&
                rows.count({family, "sglab_acc3", true}));
    const auto cycles = [&](const char* method, bool split) {
      return rows.at({family, method, split}).at("inverse_throughput").get<double>();
    };
    const double reference = cycles("tokuyoshi2024", false);
    EXPECT_GT(cycles("tokuyoshi2024", true), 0);
    EXPECT_LE(cycles("tokuyoshi2024", true), 0.6 * reference);
    EXPECT_LE(cycles("sglab_acc3", true), 0.6 * reference);
    EXPECT_LT(cycles("sglab_acc3", true), cycles("sglab_acc3", false));
    EXPECT_NE(rows.at({family, "sglab_acc3", true}).at("spirv_hash"),
              rows.at({family, "sglab_acc3", false}).at("spirv_hash"));
  }
  const auto only = run_sglab({"gpucost", "--families", "navi21", "--form", "split", "--method",
                               "sglab_fast", "--harness", "single", "--json"},
                              false);
  ASSERT_EQ(only.exit_code, 0) << only.output;
  const auto only_doc = nlohmann::json::parse(only.output);
  ASSERT_EQ(only_doc.at("rows").size(), 1u);
  EXPECT_TRUE(only_doc.at("rows")[0].at("split").get<bool>());
  const auto none =
      run_sglab({"gpucost", "--families", "navi21", "--form", "split", "--method", "wang2009"});
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("wang2009"), std::string::npos) << none.output;
  const auto bad = run_sglab({"gpucost", "--families", "navi21", "--form", "halfway"});
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--form"), std::string::npos) << bad.output;
}

// Every family `gpucost --families` takes is one the installed RADV makes a
// null device for (a compiler statistic of the trivial wrapper, measured
// against itself, on each).
TEST_F(OnRadv, EveryKnownFamilyHasANullDevice) {
  const gpu::Shader baseline = gpu::baseline_shader(shader::Language::glsl);
  gpu::Shader same = baseline;
  same.method = "same";
  const std::vector<std::string> known(std::begin(cost::gpu::kKnownFamilies),
                                       std::end(cost::gpu::kKnownFamilies));
  const cost::gpu::Report r = measure(known, {baseline, same});
  ASSERT_EQ(r.rows.size(), known.size());
  for (std::size_t i = 0; i < known.size(); ++i) {
    EXPECT_EQ(r.rows[i].family, known[i]);
    EXPECT_GT(r.rows[i].stats.vgprs, 0) << known[i];
  }
  for (const cost::gpu::Family& f : cost::gpu::kDefaultFamilies)
    EXPECT_NE(std::find(known.begin(), known.end(), f.name), known.end()) << f.name;
}

// A family RADV does not know, or an empty item of the list, is refused
// before any work (exit 2), naming --families and listing the known ones.
TEST(GpuCostCli, AnUnknownFamilyOrAnEmptyItemIsRefusedListingTheKnownOnes) {
  for (const char* families :
       {"gfx9999", "nosuchchip", "navi21,,", ",navi21", "navi21,,gfx1100", ""}) {
    const auto r = run_sglab({"gpucost", "--families", families, "--method", "hill"});
    EXPECT_EQ(r.exit_code, 2) << families << ": " << r.output;
    EXPECT_NE(r.output.find("--families: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("the families RADV knows: tahiti,pitcairn,"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("navi21,navi22"), std::string::npos) << r.output;
  }
  // Repeated lists and repeated names are one list.
  const auto r = run_sglab({"gpucost", "--families", "navi21,gfx1100", "--families", "navi21",
                            "--disasm", "--method", "hill"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--disasm: takes one --method, one --family"), std::string::npos)
      << r.output;
}

// Every output of `gpucost --out D` is checked before anything is measured or
// written: D/gpu_costs.md a folder or a link leaves D/costs.json as it was.
// (That nothing is measured first: test_cli_inputs, OutputsAreCheckedBeforeAnyWork.)
TEST(GpuCostCli, EveryOutputIsCheckedBeforeAnyWork) {
  TempDir dir("gpucost-outputs");
  const fs::path committed =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "results" / "costs.json";
  fs::copy_file(committed, dir.path / "costs.json");
  const std::string before = sglab::io::read_file(dir.path / "costs.json");
  fs::create_directories(dir.path / "elsewhere");
  for (const bool link : {false, true}) {
    fs::remove_all(dir.path / "gpu_costs.md");
    if (link)
      fs::create_symlink(dir.path / "elsewhere" / "gpu_costs.md", dir.path / "gpu_costs.md");
    else
      fs::create_directories(dir.path / "gpu_costs.md");
    const auto r = run_sglab(
        {"gpucost", "--families", "navi21", "--method", "hill", "--out", dir.path.string()});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("gpu_costs.md: is a"), std::string::npos) << r.output;
    EXPECT_EQ(sglab::io::read_file(dir.path / "costs.json"), before);
  }
  EXPECT_FALSE(fs::exists(dir.path / "elsewhere" / "gpu_costs.md"));
  // A malformed cost table in D is refused before the work too.
  fs::remove(dir.path / "gpu_costs.md");
  sglab::io::write_file_atomic(dir.path / "costs.json", "{}");
  const auto r = run_sglab({"gpucost", "--out", dir.path.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("costs.json"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.path / "gpu_costs.md"));
}

TEST(GpuCostCli, BadInputExitsTwoNamingIt) {
  struct Case {
    std::vector<std::string> args;
    const char* names;
  };
  const Case cases[] = {
      {{"gpucost", "--families", "NAVI21"}, "--families"},
      {{"gpucost", "--families", "navi21;rm"}, "--families"},
      {{"gpucost", "--method", "nope"}, "--method"},
      {{"gpucost", "--lang", "cpp"}, "--lang"},
      {{"gpucost", "--out", ""}, "--out"},
  };
  for (const Case& c : cases) {
    const auto r = run_sglab(c.args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(c.args, " ")) << "\n" << r.output;
    EXPECT_NE(r.output.find(c.names), std::string::npos) << r.output;
  }
}

TEST(GpuCostCli, BadHarnessLightsOrCompileExitTwoNamingIt) {
  struct Case {
    std::vector<std::string> args;
    const char* names;
  };
  const Case cases[] = {
      {{"gpucost", "--harness", "double"}, "--harness"},
      {{"gpucost", "--lights", "0"}, "--lights"},
      {{"gpucost", "--lights", "65"}, "--lights"},
      {{"gpucost", "--lights", "8x"}, "--lights"},
      {{"gpucost", "--lights", "8", "--harness", "single"}, "--lights"},
      {{"gpucost", "--compile", "fast"}, "--compile"},
      {{"gpucost", "--compile", "legalized"}, "--compile legalized"},
      {{"gpucost", "--harness", "loop", "--precision", "half"}, "nothing to cost"},
      {{"gpucost", "--harness", "setup", "--form", "unsplit"}, "nothing to cost"},
  };
  for (const Case& c : cases) {
    const auto r = run_sglab(c.args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(c.args, " ")) << "\n" << r.output;
    EXPECT_NE(r.output.find(c.names), std::string::npos) << r.output;
  }
}

// The compile paths are SPIRV-Tools' optimizer: legalization is HLSL's; it and
// the performance passes inline every function call glslang left (glslang's
// SPIR-V keeps the export's functions), and `none` is glslang's SPIR-V as it is.
TEST(GpuCost, CompilePathsRunSpirvToolsPasses) {
  const auto calls = [](const std::vector<std::uint32_t>& words) {
    std::size_t n = 0;
    for (std::size_t i = 5; i < words.size(); i += words[i] >> 16) {
      if ((words[i] & 0xffffu) == 57u) ++n;  // OpFunctionCall
      if ((words[i] >> 16) == 0) break;
    }
    return n;
  };
  const auto ex =
      shader::export_source(shader::standard_request(shader::Language::hlsl, "tokuyoshi2024"));
  const auto spirv = sglab::shader::vulkan::compile_compute(
      shader::Language::hlsl,
      shader::compute_shader(shader::Language::hlsl, ex.source, ex.entry_point,
                             shader::Precision::float32, shader::Dispatch::whole_groups));
  EXPECT_GT(calls(spirv), 0u);
  EXPECT_EQ(gpu::apply_compile_path(shader::Language::hlsl, cost::gpu::CompilePath::none, spirv),
            spirv);
  for (cost::gpu::CompilePath c :
       {cost::gpu::CompilePath::legalized, cost::gpu::CompilePath::optimized}) {
    const auto out = gpu::apply_compile_path(shader::Language::hlsl, c, spirv);
    EXPECT_EQ(calls(out), 0u) << cost::gpu::to_string(c);
    EXPECT_NE(gpu::spirv_hash(out), gpu::spirv_hash(spirv)) << cost::gpu::to_string(c);
  }
  EXPECT_EQ(
      gpu::method_shader("tokuyoshi2024", shader::Language::hlsl, shader::Precision::float32,
                         cost::gpu::CompilePath::legalized)
          .spirv,
      gpu::apply_compile_path(shader::Language::hlsl, cost::gpu::CompilePath::legalized, spirv));
  EXPECT_THROW(
      gpu::apply_compile_path(shader::Language::glsl, cost::gpu::CompilePath::legalized, spirv),
      std::invalid_argument);
  EXPECT_THROW(
      gpu::apply_compile_path(shader::Language::hlsl, cost::gpu::CompilePath::optimized,
                              std::vector<std::uint32_t>(spirv.begin(), spirv.begin() + 9)),
      std::runtime_error);
}

// The cost table reader refuses a malformed "gpu" section, naming the key.
TEST(GpuCostTable, MalformedSectionIsRefusedNamingTheKey) {
  TempDir dir("gpucost-table");
  const fs::path committed =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "results" / "costs.json";
  auto doc = nlohmann::ordered_json::parse(sglab::io::read_file(committed));
  doc["gpu"] = {{"driver", "radv Mesa"},
                {"command", "x"},
                {"rows", {{{"method", "hill"}, {"family", "navi21"}}}}};
  sglab::io::write_file_atomic(dir.path / "costs.json", doc.dump());
  try {
    sglab::cost::read_cost_table(dir.path / "costs.json");
    FAIL() << "accepted a row without lang";
  } catch (const sglab::cost::CostTableError& e) {
    EXPECT_NE(std::string(e.what()).find("rows[0].lang"), std::string::npos) << e.what();
  }
  // A row of the committed table, then spoilt one key at a time.
  const auto committed_doc = nlohmann::ordered_json::parse(sglab::io::read_file(committed));
  const nlohmann::ordered_json good = committed_doc.at("gpu").at("rows").at(0);
  struct Spoil {
    const char* key;
    nlohmann::ordered_json value;  // null: the key removed
    const char* names;
  };
  for (const Spoil& spoil :
       {Spoil{"harness", nullptr, "older `sglab gpucost`"}, Spoil{"harness", "double", "harness"},
        Spoil{"compile", "fast", "compile"}, Spoil{"lights", 2, "lights"},
        Spoil{"lights", 0, "lights"}, Spoil{"lights", "8", "lights"}}) {
    nlohmann::ordered_json row = good;
    if (spoil.value.is_null())
      row.erase(spoil.key);
    else
      row[spoil.key] = spoil.value;
    doc["gpu"] = {{"driver", "radv Mesa"}, {"command", "x"}, {"rows", {row}}};
    sglab::io::write_file_atomic(dir.path / "costs.json", doc.dump());
    try {
      sglab::cost::read_cost_table(dir.path / "costs.json");
      ADD_FAILURE() << "accepted " << row.dump();
    } catch (const sglab::cost::CostTableError& e) {
      EXPECT_NE(std::string(e.what()).find(spoil.names), std::string::npos) << e.what();
    }
  }
  // The good row is read back.
  doc["gpu"] = {{"driver", "radv Mesa"}, {"command", "x"}, {"rows", {good}}};
  sglab::io::write_file_atomic(dir.path / "costs.json", doc.dump());
  EXPECT_EQ(sglab::cost::read_cost_table(dir.path / "costs.json").gpu->rows.size(), 1u);
}

using sglab::test::WorkingDirectory;

// `sglab export`'s header states the GPU cost that the project's cost table
// holds for exactly the exported code: the rows of the method and language
// whose SPIR-V hash is that of the export in gpucost's wrapper (the header's
// other comments, provenance and Vulkan error, do not change the code). A row
// of other code is not this export's cost: "not measured". No device needed.
TEST(GpuCostInExport, HeaderStatesTheCostOfThisVeryCode) {
  TempDir dir("gpucost-export");
  const fs::path checkout = sglab::test::checkout_dir();
  sglab::test::make_scratch_project(dir.path);
  fs::copy_file(checkout / "data" / "results" / "vulkan_sweep.json",
                dir.path / "data" / "results" / "vulkan_sweep.json");
  auto doc = nlohmann::ordered_json::parse(
      sglab::io::read_file(checkout / "data" / "results" / "costs.json"));
  cost::gpu::Report report{"radv Mesa (test rows)", "test", {}};
  const auto row = [](const std::string& family, shader::Language lang, std::int64_t cycles,
                      std::string hash) {
    cost::gpu::Statistics s;
    s.instructions = s.inverse_throughput = s.latency = cycles;
    return cost::gpu::Row{"hill", family, lang, false, "float", s, std::move(hash)};
  };
  const std::string glsl_hash =
      gpu::spirv_hash(gpu::method_shader("hill", shader::Language::glsl).spirv);
  const std::string hlsl_hash =
      gpu::spirv_hash(gpu::method_shader("hill", shader::Language::hlsl).spirv);
  ASSERT_NE(glsl_hash, hlsl_hash);
  report.rows = {row("navi21", shader::Language::glsl, 1234, glsl_hash),
                 // another code's hash
                 row("gfx1100", shader::Language::glsl, 2345, glsl_hash),
                 row("navi21", shader::Language::hlsl, 3456, glsl_hash)};
  doc["gpu"] = cost::gpu::to_json(report);
  sglab::io::write_file_atomic(dir.path / "data" / "results" / "costs.json", doc.dump());

  WorkingDirectory cwd(dir.path);
  const auto glsl = run_sglab({"export", "--lang", "glsl", "--method", "hill"}, false);
  ASSERT_EQ(glsl.exit_code, 0) << glsl.output;
  EXPECT_NE(glsl.output.find("measured on Vulkan"), std::string::npos) << glsl.output;
  EXPECT_NE(glsl.output.find(
                "radv Mesa (test rows), data/results/costs.json): navi21 1234, gfx1100 2345\n"),
            std::string::npos)
      << glsl.output;
  const auto hlsl = run_sglab({"export", "--lang", "hlsl", "--method", "hill"}, false);
  ASSERT_EQ(hlsl.exit_code, 0) << hlsl.output;
  EXPECT_EQ(hlsl.output.find("3456"), std::string::npos) << hlsl.output;
  EXPECT_NE(
      hlsl.output.find("`sglab gpucost`): not measured for this code in radv Mesa (test rows)"),
      std::string::npos)
      << hlsl.output;
  // The right hash for HLSL: its row is read.
  report.rows[2].spirv_hash = hlsl_hash;
  doc["gpu"] = cost::gpu::to_json(report);
  sglab::io::write_file_atomic(dir.path / "data" / "results" / "costs.json", doc.dump());
  const auto hlsl2 = run_sglab({"export", "--lang", "hlsl", "--method", "hill"}, false);
  EXPECT_NE(hlsl2.output.find("costs.json): navi21 3456, gfx1100 not measured\n"),
            std::string::npos)
      << hlsl2.output;
  // C++ is costed by `sglab bench`, not here.
  const auto cpp = run_sglab({"export", "--lang", "cpp", "--method", "hill"}, false);
  ASSERT_EQ(cpp.exit_code, 0) << cpp.output;
  EXPECT_EQ(cpp.output.find("GPU cost"), std::string::npos);
}

// `export --split` states the cost of the split row (split = true, the hash of
// the split export in the split wrapper), the unsplit export that of its own row.
TEST(GpuCostInExport, SplitHeaderReadsTheSplitRow) {
  TempDir dir("gpucost-export-split");
  const fs::path checkout = sglab::test::checkout_dir();
  sglab::test::make_scratch_project(dir.path);
  auto doc = nlohmann::ordered_json::parse(
      sglab::io::read_file(checkout / "data" / "results" / "costs.json"));
  cost::gpu::Statistics unsplit_stats, split_stats;
  unsplit_stats.inverse_throughput = 4321;
  split_stats.inverse_throughput = 1234;
  const std::string unsplit_hash =
      gpu::spirv_hash(gpu::method_shader("sglab_fast", shader::Language::glsl).spirv);
  const std::string split_hash =
      gpu::spirv_hash(gpu::split_method_shader("sglab_fast", shader::Language::glsl).spirv);
  ASSERT_NE(unsplit_hash, split_hash);
  cost::gpu::Report report{"radv Mesa (test rows)", "test", {}};
  report.rows = {
      {"sglab_fast", "navi21", shader::Language::glsl, false, "float", unsplit_stats, unsplit_hash},
      {"sglab_fast", "navi21", shader::Language::glsl, true, "float", split_stats, split_hash}};
  doc["gpu"] = cost::gpu::to_json(report);
  sglab::io::write_file_atomic(dir.path / "data" / "results" / "costs.json", doc.dump());
  WorkingDirectory cwd(dir.path);
  const auto split =
      run_sglab({"export", "--lang", "glsl", "--method", "sglab_fast", "--split"}, false);
  ASSERT_EQ(split.exit_code, 0) << split.output;
  EXPECT_NE(split.output.find("costs.json): navi21 1234, gfx1100 not measured\n"),
            std::string::npos)
      << split.output;
  const auto unsplit = run_sglab({"export", "--lang", "glsl", "--method", "sglab_fast"}, false);
  ASSERT_EQ(unsplit.exit_code, 0) << unsplit.output;
  EXPECT_NE(unsplit.output.find("costs.json): navi21 4321, gfx1100 not measured\n"),
            std::string::npos)
      << unsplit.output;
}

TEST(GpuCost, SpirvHashIsFnv1aOfTheBytes) {
  EXPECT_EQ(gpu::spirv_hash({}), "cbf29ce484222325");  // FNV-1a 64 offset basis: no bytes hashed
  // The bytes in memory order: one word and its byte-swapped twin differ.
  EXPECT_NE(gpu::spirv_hash({0x07230203u}), gpu::spirv_hash({0x03022307u}));
}

}  // namespace
