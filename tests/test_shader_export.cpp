// `sglab export` and the Vulkan backend of the sweep: every registered
// irradiance method exports to GLSL and HLSL that glslang compiles; the C++
// export, compiled by the system compiler, agrees with the runtime; the shader
// exports run on a Vulkan device (lavapipe on CI) agree with the runtime; the
// elementary tiers are chosen by the model's accuracy; bad input exits 2.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/closed_forms.hpp>
#include <sglab/registry.hpp>

#include "export/shader_elementary.hpp"
#include "export/shader_export.hpp"
#include "export/shader_text.hpp"
#include "export/vulkan_runner.hpp"
#include "tests/test_support.hpp"
#include "tests/tolerances.hpp"
#include "tests/vulkan_fixture.hpp"
#include "validate/kappa_range.hpp"
#include "validate/sweep.hpp"

namespace fs = std::filesystem;
namespace sh = sglab::shader;
namespace vk = sglab::shader::vulkan;
using sglab::test::run_program;
using sglab::test::run_sglab;

namespace {

// The standard sweep grid as float (cosine, κ) points, κ-major.
struct Grid {
  std::vector<float> cosine, kappa;
};
Grid standard_grid() {
  Grid g;
  for (double k : sglab::test::standard_kappas())
    for (double c : sglab::test::standard_cosines()) {
      g.kappa.push_back(static_cast<float>(k));
      g.cosine.push_back(static_cast<float>(c));
    }
  return g;
}

// max over the grid of |values − runtime double| / E(1, κ), and the same for
// the runtime's own float path: the exported code must be no worse than twice
// the runtime's float rounding plus a small allowance for its own erf/expm1.
struct Deviation {
  double exported = 0, runtime_float = 0;
  std::size_t worst = 0;
};
Deviation deviation(const sglab::Method& m, const Grid& g, const std::vector<double>& values) {
  Deviation d;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double k = g.kappa[i], c = g.cosine[i];
    const double peak = sglab::irradiance_upper(k);
    const double ref = m.f64(c, k);
    const double e = std::fabs(values[i] - ref) / peak;
    if (!(e <= d.exported)) {
      d.exported = std::isnan(e) ? INFINITY : e;
      d.worst = i;
    }
    d.runtime_float =
        std::max(d.runtime_float, std::fabs(double(m.f32(float(c), float(k))) - ref) / peak);
  }
  return d;
}
// The exported code's allowance over twice the runtime's own float error
// (tests/tolerances.hpp, with its reason).
constexpr double kAllowance = sglab::test::kExportAllowance;

// Registered methods with an export entry (CoversEveryRegisteredIrradianceMethod
// names any without one).
bool exportable(std::string_view id) {
  const auto all = sh::exportable_methods();
  return std::find(all.begin(), all.end(), id) != all.end();
}

std::string export_text(sh::Language lang, const std::string& method) {
  return sh::export_source(sh::standard_request(lang, method)).source;
}

// Compiles C++ exports (each `source` defines `entry`) into one program with a
// driver that evaluates every entry at every grid point, with the system
// compiler (argument vector, no shell; one compile for all, each export in its
// own namespace). Returns one column of values per export.
struct CppExport {
  std::string source, entry;
};
std::vector<std::vector<double>> run_cpp_exports(const std::vector<CppExport>& exports,
                                                 const Grid& g, const fs::path& dir,
                                                 bool vector_form = false) {
  {
    std::ofstream in(dir / "points.txt");
    for (std::size_t i = 0; i < g.kappa.size(); ++i)
      in << fmt::format("{:a} {:a}\n", g.cosine[i], g.kappa[i]);
    std::ofstream main(dir / "main.cpp");
    main << "#include <cstdio>\n#include <cstdlib>\n#include <cmath>\n";
    for (std::size_t e = 0; e < exports.size(); ++e) {
      const std::string header = fmt::format("export{}.hpp", e);
      std::ofstream(dir / header) << exports[e].source;
      main << "#include \"" << header << "\"\n";
    }
    main << "int main(int, char** argv) {\n"
         << "  std::FILE* f = std::fopen(argv[1], \"r\");\n"
         << "  char a[64], b[64];\n"
         << "  while (std::fscanf(f, \"%63s %63s\", a, b) == 2) {\n"
         << "    float c = std::strtof(a, nullptr), k = std::strtof(b, nullptr);\n"
         << "    float s = std::sqrt(std::fmax(0.0f, 1.0f - c * c));\n"
         << "    (void)s;\n";
    for (const CppExport& ex : exports) {
      const std::string ns = "sglab_export_" + ex.entry.substr(17);
      if (vector_form)
        main << "    std::printf(\"%a \", (double)" << ex.entry << "(" << ns
             << "::float3(s, 0.0f, c), k, " << ns << "::float3(0.0f, 0.0f, 1.0f)));\n";
      else
        main << "    std::printf(\"%a \", (double)" << ex.entry << "(c, k));\n";
    }
    main << "    std::printf(\"\\n\");\n  }\n  return 0;\n}\n";
  }
  const auto build =
      run_program({SGLAB_CXX_COMPILER, "-std=c++17", "-O2", "-ffp-contract=off", "-Wall", "-Werror",
                   (dir / "main.cpp").string(), "-o", (dir / "prog").string()});
  EXPECT_EQ(build.exit_code, 0) << build.output;
  if (build.exit_code != 0) return {};
  const auto run = run_program({(dir / "prog").string(), (dir / "points.txt").string()}, false);
  EXPECT_EQ(run.exit_code, 0);
  std::vector<std::vector<double>> out(exports.size());
  std::istringstream lines(run.output);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream row(line);
    std::string field;
    for (auto& column : out)
      if (row >> field) column.push_back(std::strtod(field.c_str(), nullptr));
  }
  return out;
}

std::vector<double> run_cpp_export(const std::string& source, const std::string& entry,
                                   const Grid& g, const fs::path& dir, bool vector_form = false) {
  auto columns = run_cpp_exports({{source, entry}}, g, dir, vector_form);
  return columns.empty() ? std::vector<double>{} : std::move(columns[0]);
}

}  // namespace

// Every registered irradiance method has an export entry (a new method
// without one fails here) and nothing else is exported.
TEST(ShaderExport, CoversEveryRegisteredIrradianceMethod) {
  std::vector<std::string> registered;
  for (const sglab::Method& m : sglab::irradiance_methods) registered.emplace_back(m.id);
  EXPECT_EQ(sh::exportable_methods(), registered);
}

TEST(ShaderExport, EntryPointName) {
  EXPECT_EQ(sh::entry_point_name("tokuyoshi2024"), "sglab_irradiance_tokuyoshi2024");
  EXPECT_EQ(sh::entry_point_name("a-b.c"), "sglab_irradiance_a_b_c");
}

// The half translation of a float literal (export/shader_text.cpp): rounded to the nearest
// half and written so that the language reads exactly that half; a literal beyond the largest
// half (65504; 65520 and above round to infinity) is refused, not written as inf.
TEST(ShaderExport, HalfLiteralsRoundToHalfAndRefuseOverflow) {
  const sh::detail::Ctx glsl{sh::Language::glsl, "m", "sglab_m_"};
  const sh::detail::Ctx hlsl{sh::Language::hlsl, "m", "sglab_m_"};
  EXPECT_EQ(sh::detail::to_half_code("y = 65504.0f * x;", glsl), "y = 65504.0hf * x;");
  EXPECT_EQ(sh::detail::to_half_code("y = 65519.0f;", glsl), "y = 65504.0hf;");  // rounds down
  EXPECT_EQ(sh::detail::to_half_code("y = 0.1f;", hlsl), "y = 0.0999755859h;");
  EXPECT_EQ(sh::detail::to_half_code("y = 1e-9f;", glsl), "y = 0.0hf;");  // underflows to 0
  EXPECT_EQ(sh::detail::to_half_code("y = 3;", glsl), "y = 3;");          // not a float literal
  for (const char* big : {"y = 65520.0f;", "y = 1e5f;", "y = 3.4e38f;"}) {
    try {
      sh::detail::to_half_code(big, glsl);
      ADD_FAILURE() << big << " written in half";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("not finite in half"), std::string::npos) << e.what();
    }
  }
}

// Every irradiance export states its method's registry card: what it is and its source, the
// bound and the κ range it holds on (sglab_fast's stops at 1.1e4).
TEST(ShaderExport, HeaderStatesTheRegistryCard) {
  for (const sglab::Method& m : sglab::irradiance_methods)
    for (sh::Language lang : {sh::Language::glsl, sh::Language::cpp}) {
      const std::string src =
          sh::export_source(sh::standard_request(lang, std::string(m.id))).source;
      const std::string line = fmt::format(
          "max |E~ - E|/E(1, kappa) <= {:.2g} for kappa in {}; outside it that bound does not hold",
          m.valid.max_peak_rel, sglab::validate::kappa_range_text(m.valid));
      EXPECT_NE(src.find(line), std::string::npos) << m.id << ": " << line;
      const std::string what =
          fmt::format("// {}: {}.\n// Source: {}.\n", m.id, m.summary, m.source);
      EXPECT_NE(src.find(what), std::string::npos) << m.id << ": " << what;
    }
  const std::string fast =
      sh::export_source(sh::standard_request(sh::Language::hlsl, "sglab_fast")).source;
  EXPECT_NE(fast.find("<= 0.0026 for kappa in [0, 1.1e+04]"), std::string::npos);
}

// glslang compiles every GLSL and HLSL export inside the compute shader of
// the Vulkan backend (GLSL 4.50, HLSL through the HLSL front end).
TEST(ShaderExport, EveryMethodCompilesToSpirv) {
  for (const std::string& id : sh::exportable_methods())
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      const std::string text = export_text(lang, id);
      EXPECT_NE(text.find("float sglab_irradiance_" + id + "(float cosine, float kappa)"),
                std::string::npos)
          << id;
      EXPECT_NE(text.find("Produced by: sglab export --lang " + std::string(sh::to_string(lang)) +
                          " --method " + id),
                std::string::npos);
      EXPECT_EQ(text.find("#extension"), std::string::npos);
      try {
        vk::check_compiles(lang, text);
      } catch (const vk::CompileError& e) {
        ADD_FAILURE() << id << " " << sh::to_string(lang) << ": " << e.what();
      }
    }
}

// The SPIR-V glslang produced passes SPIRV-Tools' validator (an independent
// implementation) for Vulkan 1.0.
TEST(ShaderExport, SpirvPassesSpirvVal) {
  const sglab::test::TempDir tmp("shader-spirv");
  const fs::path& dir = tmp.path;
  for (const std::string id : {"tokuyoshi2024", "tokuyoshi2022_listing5", "meder2018"})
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      const sh::ExportResult ex = sh::export_source(sh::standard_request(lang, id));
      const auto spirv =
          vk::compile_compute(lang, sh::compute_shader(lang, ex.source, ex.entry_point));
      const fs::path file = dir / fmt::format("{}_{}.spv", id, sh::to_string(lang));
      std::ofstream(file, std::ios::binary)
          .write(reinterpret_cast<const char*>(spirv.data()),
                 static_cast<std::streamsize>(spirv.size() * 4));
      const auto r = run_program({"spirv-val", "--target-env", "vulkan1.0", file.string()});
      EXPECT_EQ(r.exit_code, 0) << id << " " << sh::to_string(lang) << ": " << r.output;
    }
}

// The compiler must reject broken code (so the test above can fail).
TEST(ShaderExport, BrokenSourceDoesNotCompile) {
  std::string text = export_text(sh::Language::glsl, "tokuyoshi2024");
  const auto pos = text.find("return 6.28318548f");
  ASSERT_NE(pos, std::string::npos);
  text.insert(pos, "undefined_symbol + ");
  EXPECT_THROW(vk::check_compiles(sh::Language::glsl, text), vk::CompileError);
}

// The C++ export, compiled by the system compiler, against the runtime.
TEST(ShaderExport, CppExportMatchesRuntime) {
  const Grid g = standard_grid();
  std::vector<const sglab::Method*> methods;
  std::vector<CppExport> exports;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    if (!exportable(m.id)) continue;
    const sh::ExportResult ex =
        sh::export_source(sh::standard_request(sh::Language::cpp, std::string(m.id)));
    methods.push_back(&m);
    exports.push_back({ex.source, ex.entry_point});
  }
  const sglab::test::TempDir tmp("shader-cpp_all");
  const fs::path& dir = tmp.path;
  const auto columns = run_cpp_exports(exports, g, dir);
  ASSERT_EQ(columns.size(), methods.size());
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const sglab::Method& m = *methods[i];
    const auto& values = columns[i];
    ASSERT_EQ(values.size(), g.kappa.size()) << m.id;
    const Deviation d = deviation(m, g, values);
    EXPECT_LE(d.exported, 2 * d.runtime_float + kAllowance)
        << m.id << ": worst at kappa = " << g.kappa[d.worst] << ", cosine = " << g.cosine[d.worst]
        << ": exported " << values[d.worst] << ", runtime double "
        << m.f64(g.cosine[d.worst], g.kappa[d.worst]);
  }
}

// The vector form equals the scalar form at c = v·n.
TEST(ShaderExport, VectorFormMatchesScalarForm) {
  Grid g;
  for (float k : {0.01f, 1.0f, 30.0f})
    for (float c : {-1.0f, -0.3f, 0.0f, 0.5f, 1.0f}) {
      g.kappa.push_back(k);
      g.cosine.push_back(c);
    }
  const sglab::test::TempDir tmp("shader-vector");
  const fs::path& dir = tmp.path;
  const sh::ExportResult ex =
      sh::export_source(sh::standard_request(sh::Language::cpp, "tokuyoshi2024"));
  const auto scalar = run_cpp_export(ex.source, ex.entry_point, g, dir);
  const auto vector = run_cpp_export(ex.source, ex.entry_point, g, dir, true);
  ASSERT_EQ(scalar.size(), vector.size());
  for (std::size_t i = 0; i < scalar.size(); ++i)
    EXPECT_NEAR(vector[i], scalar[i], 1e-6 * sglab::irradiance_upper(double(g.kappa[i])))
        << "kappa " << g.kappa[i] << " cosine " << g.cosine[i];
}

// --constants replaces the compiled-in set of the same type: tokuyoshi2024
// with the refitted steepness is tokuyoshi2024_refit.
TEST(ShaderExport, ConstantsFileOverridesTheCompiledInSet) {
  const fs::path file = fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants" /
                        "steepness2024-irradiance.json";
  const auto r = run_sglab(
      {"export", "--lang", "cpp", "--method", "tokuyoshi2024", "--constants", file.string()},
      false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("steepness2024_irradiance"), std::string::npos);
  EXPECT_NE(r.output.find("--constants " + file.string()), std::string::npos);
  const Grid g = standard_grid();
  const sglab::test::TempDir tmp("shader-override");
  const fs::path& dir = tmp.path;
  const auto values = run_cpp_export(r.output, "sglab_irradiance_tokuyoshi2024", g, dir);
  const sglab::Method* refit = sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024_refit");
  const sglab::Method* published = sglab::find_method(sglab::irradiance_methods, "tokuyoshi2024");
  ASSERT_TRUE(refit && published);
  const Deviation d = deviation(*refit, g, values);
  EXPECT_LE(d.exported, 2 * d.runtime_float + kAllowance);
  // …and is measurably not the published method.
  EXPECT_GT(deviation(*published, g, values).exported, 10 * kAllowance);
}

TEST(ShaderExport, BadInputExitsWithCode2) {
  auto r = run_sglab({"export", "--lang", "glsl", "--method", "no_such_method"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no_such_method"), std::string::npos);
  r = run_sglab({"export", "--lang", "metal", "--method", "tokuyoshi2024"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("metal"), std::string::npos);
  // A constant set of a type the method does not use.
  const fs::path hill =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants" / "hill-published.json";
  r = run_sglab(
      {"export", "--lang", "glsl", "--method", "tokuyoshi2024", "--constants", hill.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("HillParams"), std::string::npos) << r.output;
  // Malformed JSON.
  const sglab::test::TempDir tmp("shader-bad");
  const fs::path& dir = tmp.path;
  std::ofstream(dir / "bad.json") << "{ not json";
  r = run_sglab({"export", "--lang", "glsl", "--method", "tokuyoshi2024", "--constants",
                 (dir / "bad.json").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.json"), std::string::npos);
}

// ---------------------------------------------------------------------------
// A constants file is untrusted input: its text reaches the export only inside
// comments, it is read by the strict loader of `sglab constants`, and a
// coefficient the float code cannot hold is refused.

namespace {

const fs::path kConstantsDir = fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants";

nlohmann::ordered_json read_json(const fs::path& file) {
  return nlohmann::ordered_json::parse(std::ifstream(file));
}

// The lines of `source` that contain `marker` outside a // comment.
std::vector<std::string> code_lines_with(const std::string& source, const std::string& marker) {
  std::vector<std::string> out;
  std::istringstream lines(source);
  for (std::string line; std::getline(lines, line);)
    if (line.find(marker) != std::string::npos && line.rfind("//", 0) != 0) out.push_back(line);
  return out;
}

// Compiles a C++ export on its own (-fsyntax-only), with the system compiler.
sglab::test::CommandResult compile_cpp(const std::string& source, const fs::path& dir) {
  std::ofstream(dir / "export.cpp") << source;
  return run_program({SGLAB_CXX_COMPILER, "-std=c++17", "-fsyntax-only", "-Wall", "-Werror",
                      (dir / "export.cpp").string()});
}

}  // namespace

// Each provenance text field and the --constants file name carry
// a line break followed by code; in every language the export keeps them in
// its comments (no line outside a comment carries the payload) and compiles.
TEST(ShaderExport, ConstantsTextCannotLeaveTheComments) {
  sglab::test::TempDir dir("export_injection");
  nlohmann::ordered_json j = read_json(kConstantsDir / "sglab-acc-acc1.json");
  j["provenance"]["objective"] = "x\n#error INJECTED_OBJECTIVE\n//";
  j["provenance"]["command"] = "x\nfloat INJECTED_COMMAND = 1.0;\n//";
  j["provenance"]["date"] = "x\r\n#error INJECTED_DATE\r\n//";
  j["provenance"]["source"] = "x\n#define INJECTED_SOURCE 1\n//";
  const fs::path file = dir.path / "acc1\n#define INJECTED_PATH 1\nx.json";
  std::ofstream(file) << j.dump(2);
  for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl, sh::Language::cpp}) {
    const std::string l(sh::to_string(lang));
    const auto r = run_sglab(
        {"export", "--lang", l, "--method", "sglab_acc1", "--constants", file.string()}, false);
    ASSERT_EQ(r.exit_code, 0) << l;
    for (const char* marker : {"INJECTED_OBJECTIVE", "INJECTED_COMMAND", "INJECTED_DATE",
                               "INJECTED_SOURCE", "INJECTED_PATH"}) {
      EXPECT_NE(r.output.find(marker), std::string::npos)
          << l << ": the text is kept, escaped: " << marker;
      for (const std::string& line : code_lines_with(r.output, marker))
        ADD_FAILURE() << l << ": injected: " << line;
    }
    if (lang == sh::Language::cpp) {
      const auto build = compile_cpp(r.output, dir.path);
      EXPECT_EQ(build.exit_code, 0) << build.output;
    } else {
      try {
        vk::check_compiles(lang, r.output);
      } catch (const vk::CompileError& e) {
        ADD_FAILURE() << l << ": " << e.what();
      }
    }
  }
}

// --constants is read by the strict loader of `sglab constants` and fit: a
// duplicated key is refused (it is not "last one wins"), naming the file.
TEST(ShaderExport, ConstantsWithADuplicateKeyAreRefused) {
  sglab::test::TempDir dir("export_duplicate");
  const std::string text = read_json(kConstantsDir / "sglab-acc-acc1.json").dump(2);
  const fs::path file = dir.path / "duplicate.json";
  std::ofstream(file) << "{\n  \"cpp_name\": \"first_of_two\"," << text.substr(1);
  const auto r = run_sglab(
      {"export", "--lang", "glsl", "--method", "sglab_acc1", "--constants", file.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("duplicate.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("duplicate key"), std::string::npos) << r.output;
  // `sglab constants` refuses the same file the same way.
  const auto c = run_sglab({"constants", "--dir", dir.path.string()});
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("duplicate key"), std::string::npos) << c.output;
}

// A coefficient beyond the largest float is refused (exit 2, file and key
// named): the export is float code, and inf is no literal. The boundary is
// where binary32 rounding overflows, FLT_MAX + half an ulp = (2 - 2^-24) 2^127:
// just below it rounds to FLT_MAX and is accepted, just above it is refused.
TEST(ShaderExport, CoefficientNotFiniteInFloatIsRefused) {
  sglab::test::TempDir dir("export_overflow");
  const double overflow = std::ldexp(2.0 - std::ldexp(1.0, -24), 127);
  struct Case {
    double value;
    int exit_code;
    sh::Language lang;
  };
  for (const Case& c : {Case{1e308, 2, sh::Language::glsl}, Case{1e308, 2, sh::Language::cpp},
                        Case{-1e308, 2, sh::Language::hlsl},
                        Case{std::nextafter(overflow, 0.0), 0, sh::Language::glsl},
                        Case{std::nextafter(overflow, INFINITY), 2, sh::Language::glsl}}) {
    nlohmann::ordered_json j = read_json(kConstantsDir / "sglab-acc-acc1.json");
    j["coefficients"]["num"][1] = c.value;
    const fs::path file = dir.path / "overflow.json";
    std::ofstream(file) << j.dump(2);
    const auto r = run_sglab({"export", "--lang", std::string(sh::to_string(c.lang)), "--method",
                              "sglab_acc1", "--constants", file.string()});
    EXPECT_EQ(r.exit_code, c.exit_code) << sglab::test::hex(c.value) << ": " << r.output;
    if (c.exit_code == 2) {
      EXPECT_NE(r.output.find("overflow.json"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("coefficients.num[1]"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("not finite in float"), std::string::npos) << r.output;
    } else {
      EXPECT_EQ(r.output.find("inf"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("3.40282347e+38f"), std::string::npos) << "FLT_MAX, written exactly";
    }
  }
}

// ---------------------------------------------------------------------------
// Every float literal of every export is exactly the float the
// runtime uses. The expected values do not come from the exporter: a declared
// constant `{P}<role>_<member>[i]` of the set named in the comment above it
// must equal float(coefficients.<member>[i]) of that set's JSON in
// data/constants (which the compiled-in header is generated from,
// Constants.HeaderMatchesJson), the sets must be the ones the registry lists
// for the method (plus the erf of the export's tier), and every other literal
// must be one of the fixed constants of the snippets below, computed here.

namespace {

struct Literal {
  std::string text;  // as written, sign included
  float value;       // as a compiler reads it (correctly rounded)
};

// The numeric literals of `code` (comments stripped): every token that starts
// with a digit (or '.' and a digit) outside an identifier, with a unary minus
// in front of it (at the start, or after '(', ',', '=', '?' or ':'). A token
// that is not a decimal float literal with an 'f' suffix has a NaN value.
std::vector<Literal> numeric_literals(const std::string& code) {
  std::vector<Literal> out;
  const auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < code.size();) {
    const bool starts = std::isdigit(static_cast<unsigned char>(code[i])) ||
                        (code[i] == '.' && i + 1 < code.size() &&
                         std::isdigit(static_cast<unsigned char>(code[i + 1])));
    if (ident(code[i]) && !starts) {
      while (i < code.size() && ident(code[i])) ++i;
      continue;
    }
    if (!starts) {
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < code.size() && (ident(code[end]) || code[end] == '.' ||
                                 ((code[end] == '+' || code[end] == '-') &&
                                  (code[end - 1] == 'e' || code[end - 1] == 'E'))))
      ++end;
    std::string text = code.substr(i, end - i);
    std::size_t before = i;
    while (before > 0 && code[before - 1] == ' ') --before;
    if (before > 0 && code[before - 1] == '-') {
      std::size_t op = before - 1;
      while (op > 0 && code[op - 1] == ' ') --op;
      if (op == 0 || std::string_view("(,=?:").find(code[op - 1]) != std::string_view::npos)
        text = "-" + text;
    }
    static const std::regex float_literal(R"(-?(\d+\.\d*|\.\d+|\d+(?=[eE]))([eE][+-]?\d+)?f)");
    float value = NAN;
    if (std::regex_match(text, float_literal)) value = std::strtof(text.c_str(), nullptr);
    out.push_back({text, value});
    i = end;
  }
  return out;
}

// Fixed constants of the export's snippets, each exactly as a float, a row per
// value with where it is used. The simple ones (exact, or pi's multiples) occur
// with either sign (clamp(x, -1.0f, 1.0f), e^(-2.0f kappa)); the series
// coefficients carry theirs.
std::vector<std::pair<float, std::string>> fixed_constants() {
  std::vector<std::pair<float, std::string>> t = {
      {0.0f, "zero"},
      {0.25f, "sglab_fast: series below kappa = 1/4"},
      {0.5f, "halves (lerp factors, ramp, steepness)"},
      {1.0f, "one"},
      {2.0f, "two (erfc(-x) = 2 - erfc(x), product of SGs)"},
      {4.0f, "Hill: c1 = 1/(4 c0)"},
      {80.0f, "sglab_fast: e^-kappa argument stop"},
      {32.0f, "sglab_tab: its 32 cells"},
      {31.0f, "sglab_tab: its last cell"},
      {0x1p-13f, "[Tokuyoshi2022] Listing 3: erf ratio is c below t = 2^-13"},
      {static_cast<float>(2 * std::numbers::pi), "2 pi"},
      {static_cast<float>(4 * std::numbers::pi), "4 pi, S(d) of [Wang2009]"},
      {static_cast<float>(std::numbers::inv_sqrtpi), "1/sqrt(pi), [Tokuyoshi2024] Listing 7"},
      {static_cast<float>(std::numbers::inv_sqrtpi / 2),
       "1/(2 sqrt(pi)), [Tokuyoshi2024] Listing 7 tail (sglab_acc)"},
  };
  for (std::size_t i = 0, n = t.size(); i < n; ++i) t.emplace_back(-t[i].first, "-" + t[i].second);
  // Taylor coefficients in long double: (e^x - 1)/x = sum x^n/(n+1)!, and the
  // poles of [Tokuyoshi2024] at small kappa, sum (-kappa)^m/(m+2)! and
  // sum (-kappa)^m (m+1)/(m+2)! (sglab/closed_forms.hpp).
  long double factorial = 1;
  for (int n = 1; n <= 12; ++n) {
    factorial *= n;  // n!
    t.emplace_back(static_cast<float>(1 / factorial), fmt::format("1/{}!", n));
    if (n >= 2) {
      const long double sign = (n % 2 ? -1 : 1);
      t.emplace_back(static_cast<float>(sign / factorial), fmt::format("(-1)^{}/{}!", n - 2, n));
      t.emplace_back(static_cast<float>(sign * (n - 1) / factorial),
                     fmt::format("(-1)^{} {}/{}!", n - 2, n - 1, n));
    }
  }
  return t;
}

std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x); }

// Every set's coefficients by cpp_name, from data/constants/*.json.
std::map<std::string, nlohmann::ordered_json> json_sets() {
  std::map<std::string, nlohmann::ordered_json> sets;
  for (const auto& entry : fs::directory_iterator(kConstantsDir))
    if (entry.path().extension() == ".json") {
      auto j = read_json(entry.path());
      sets[j.at("cpp_name").get<std::string>()] = j.at("coefficients");
    }
  return sets;
}

// Checks every literal of one export (see above); returns the cpp_names of the
// sets it declares constants of, in order.
std::vector<std::string> check_export_literals(
    const std::string& source, const std::string& method,
    const std::map<std::string, nlohmann::ordered_json>& sets) {
  const std::string what = method + " " + source.substr(0, source.find('\n'));
  const std::string prefix = "sglab_" + sh::entry_point_name(method).substr(17) + "_";
  static const std::regex set_line(R"(// (\w+): \w+<[^>]*> (\w+))");
  static const std::regex decl(
      R"((?:const float|static const float|inline constexpr float) (\w+) = ([^;]+);)");
  // A table (export/shader_text.hpp is_table): one array of 4-vectors over several lines,
  // GLSL `vec4 x[n] = vec4[n](vec4(v0, v1, v2, v3), …);`, HLSL `static float4 x[n] =
  // {float4(v0, …), …};`, C++ `inline constexpr float4 …`.
  static const std::regex table_decl(
      R"((?:vec4|static float4|inline constexpr float4) (\w+)\[(\d+)\] = (?:vec4\[\d+\]\(|\{)(.*))");
  static const auto fixed = fixed_constants();
  std::vector<std::string> declared_sets;
  std::string role, set_name, code;
  std::set<std::string> seen;  // "set.member[i]" declared
  bool has_table = false;
  std::istringstream lines(source);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, table_decl)) {
      const std::string name = m[1];
      const auto size = 4 * std::stoul(m[2]);
      has_table = true;
      std::string text = m[3];
      while (text.find(';') == std::string::npos && std::getline(lines, line)) text += line;
      text = text.substr(0, text.find_last_of(")}"));
      const auto lits = numeric_literals(text);
      const std::string member = name.substr(prefix.size() + role.size() + 1);
      const bool known = sets.count(set_name) && sets.at(set_name).contains(member);
      EXPECT_TRUE(known) << what << ": " << name << " is no member of " << set_name;
      if (!known) continue;
      const auto& value = sets.at(set_name).at(member);
      EXPECT_EQ(lits.size(), size) << what << ": " << name;
      EXPECT_EQ(value.size(), size) << what << ": " << name;
      if (lits.size() != size || value.size() != size) continue;
      for (std::size_t i = 0; i < size; ++i) {
        EXPECT_EQ(bits(lits[i].value), bits(static_cast<float>(value[i].get<double>())))
            << what << ": " << name << "[" << i << "]";
        seen.insert(fmt::format("{}.{}[{}]", set_name, member, i));
      }
      continue;
    }
    if (std::regex_match(line, m, set_line)) {
      role = m[1];
      set_name = m[2];
      declared_sets.push_back(set_name);
      EXPECT_TRUE(sets.count(set_name)) << what << ": no data/constants set named " << set_name;
      continue;
    }
    if (!std::regex_match(line, m, decl)) {
      code += line.substr(0, line.find("//")) + "\n";
      continue;
    }
    // A declared constant: {P}<role>_<member> (scalar) or {P}<role>_<member><i>.
    const std::string name = m[1], text = m[2];
    const auto lits = numeric_literals(text);
    const bool one_literal =
        lits.size() == 1 && lits[0].text == text && name.rfind(prefix + role + "_", 0) == 0;
    EXPECT_TRUE(one_literal) << what << ": not {P}<role>_<member> = <float literal>: " << line;
    if (!one_literal || !sets.count(set_name)) continue;
    const std::string rest = name.substr(prefix.size() + role.size() + 1);
    bool matched = false;
    for (const auto& [member, value] : sets.at(set_name).items()) {
      const std::size_t n = value.is_array() ? value.size() : 1;
      for (std::size_t i = 0; i < n; ++i) {
        if (rest != (value.is_array() ? member + std::to_string(i) : member)) continue;
        const double want = value.is_array() ? value[i].get<double>() : value.get<double>();
        EXPECT_EQ(bits(lits[0].value), bits(static_cast<float>(want)))
            << what << ": " << line << " reads as " << sglab::test::hex(lits[0].value)
            << ", the runtime's float is " << sglab::test::hex(static_cast<float>(want)) << " ("
            << set_name << "." << member << ")";
        EXPECT_TRUE(seen.insert(fmt::format("{}.{}[{}]", set_name, member, i)).second)
            << what << ": twice: " << line;
        matched = true;
      }
    }
    EXPECT_TRUE(matched) << what << ": " << line << " is no coefficient of " << set_name;
  }
  // Every coefficient of every declared set is declared.
  for (const std::string& name : declared_sets) {
    if (!sets.count(name)) continue;
    for (const auto& [member, value] : sets.at(name).items())
      for (std::size_t i = 0; i < (value.is_array() ? value.size() : 1); ++i)
        EXPECT_TRUE(seen.count(fmt::format("{}.{}[{}]", name, member, i)))
            << what << ": " << name << "." << member << "[" << i << "] is not declared";
  }
  // Every other literal is a fixed constant of the snippets; an export with a table also
  // indexes it, with integer literals (the rows of a cell, 0 … 7).
  const std::vector<Literal> inline_literals = numeric_literals(code);
  EXPECT_FALSE(inline_literals.empty()) << what;
  static const std::regex index_literal(R"(\d{1,2})");
  for (const Literal& l : inline_literals) {
    if (has_table && std::regex_match(l.text, index_literal) && std::stoi(l.text) <= 7) continue;
    const bool known = std::any_of(fixed.begin(), fixed.end(),
                                   [&](const auto& f) { return bits(f.first) == bits(l.value); });
    EXPECT_TRUE(known) << what << ": literal " << l.text << " (" << sglab::test::hex(l.value)
                       << ") is neither a coefficient nor a fixed constant of the export";
  }
  return declared_sets;
}

std::vector<std::string> split_names(std::string_view list) {
  std::vector<std::string> out;
  for (const auto& w : sglab::test::words(std::string(list))) {
    std::string name = w;
    if (!name.empty() && name.back() == ',') name.pop_back();
    if (!name.empty()) out.push_back(name);
  }
  return out;
}

}  // namespace

// Every method in every language, with the constant sets of its standard
// export: exactly the runtime's floats, no digit lost.
TEST(ShaderExport, EveryLiteralIsTheRuntimesFloat) {
  const auto sets = json_sets();
  const std::set<std::string> tier_sets = {"erf_as7125_float", "erf_listing5_float"};
  std::set<std::string> covered;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    if (!exportable(m.id)) continue;
    sh::ExportRequest req = sh::standard_request(sh::Language::glsl, std::string(m.id));
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl, sh::Language::cpp}) {
      req.lang = lang;
      const std::string source = sh::export_source(req).source;
      std::vector<std::string> declared = check_export_literals(source, std::string(m.id), sets);
      covered.insert(declared.begin(), declared.end());
      // The sets are the registry's, plus at most one erf of a tier.
      std::vector<std::string> expected = split_names(m.constants), extra;
      for (const std::string& d : declared)
        if (std::find(expected.begin(), expected.end(), d) == expected.end()) extra.push_back(d);
      for (const std::string& e : expected)
        EXPECT_NE(std::find(declared.begin(), declared.end(), e), declared.end())
            << m.id << " does not bake in " << e;
      EXPECT_LE(extra.size(), 1u) << m.id;
      for (const std::string& e : extra)
        EXPECT_TRUE(tier_sets.count(e)) << m.id << " bakes in " << e;
    }
  }
  EXPECT_TRUE(covered.count("erf_listing5_float"));
}

// Every constant set of data/constants, baked in as a --constants override of
// the first export that has a slot of its type (the AbramowitzStegunParams
// erf sets: the cheap erf tier, taken for a coarse model): its literals are
// exactly its floats.
TEST(ShaderExport, EveryConstantSetOverrideKeepsItsFloats) {
  const auto sets = json_sets();
  std::vector<sh::ExportRequest> candidates;
  for (const std::string& method : sh::exportable_methods()) {
    candidates.emplace_back();
    candidates.back().method = method;
  }
  candidates.emplace_back();
  candidates.back().method = "tokuyoshi2024";
  const sh::ElementaryError as7125 = sh::measure_elementary("as7125");
  // takes as7125
  candidates.back().budget.model = 100 * std::max(as7125.max_abs(), as7125.erf_rel_small) * 1.01;
  for (const auto& entry : fs::directory_iterator(kConstantsDir)) {
    if (entry.path().extension() != ".json") continue;
    const auto j = read_json(entry.path());
    sh::ConstantSet o;
    o.cpp_type = j.at("cpp_type").get<std::string>();
    o.cpp_name = j.at("cpp_name").get<std::string>();
    for (const auto& [member, value] : j.at("coefficients").items())
      o.members.emplace_back(member, value.is_array() ? value.get<std::vector<double>>()
                                                      : std::vector<double>{value.get<double>()});
    bool exported = false;
    for (sh::ExportRequest req : candidates) {
      req.overrides = {o};
      for (sh::Language lang :
           {sh::Language::glsl}) {  // one lit() for all: every language in the test above
        req.lang = lang;
        sh::ExportResult ex;
        try {
          ex = sh::export_source(req);
        } catch (const std::invalid_argument&) {
          break;  // no slot of this type
        }
        const auto declared = check_export_literals(ex.source, req.method, sets);
        EXPECT_NE(std::find(declared.begin(), declared.end(), o.cpp_name), declared.end())
            << req.method << " " << o.cpp_name;
        exported = true;
      }
      if (exported) break;
    }
    EXPECT_TRUE(exported) << o.cpp_name << " (" << o.cpp_type << "): no export takes it";
  }
}

// The tiers: the measured erf/erfc errors of each, and the choice by model error.
TEST(ShaderExport, ElementaryTiersAreChosenByTheModelError) {
  const auto listing5 = sh::measure_elementary("listing5");
  const auto as7125 = sh::measure_elementary("as7125");
  EXPECT_LT(listing5.erf_abs, 2e-7);
  EXPECT_LT(listing5.erfc_abs, 2e-7);
  EXPECT_LT(listing5.erf_rel_small, 1e-6);
  EXPECT_LT(listing5.expm1_over_x_rel, 3e-7);
  EXPECT_GT(as7125.erf_abs, 1e-5);  // [AS1964] 7.1.25: |error| ≤ 2.5e-5 claimed
  EXPECT_LT(as7125.erf_abs, 2.5e-5);
  EXPECT_EQ(sh::choose_tier(std::nullopt).id, "listing5");
  EXPECT_EQ(sh::choose_tier(1.55e-3).id, "listing5");  // tokuyoshi2024 needs the accurate erfc
  const double as_worst = std::max(as7125.max_abs(), as7125.erf_rel_small);
  // a coarse model takes the cheap tier
  EXPECT_EQ(sh::choose_tier(100 * as_worst * 1.01).id, "as7125");
}

// ---------------------------------------------------------------------------
// On a Vulkan device (lavapipe needs no GPU; tests/vulkan_fixture.hpp). Skipped
// only when no device can be created.

TEST_F(OnVulkan, EveryMethodMatchesTheRuntime) {
  const Grid g = standard_grid();
  std::vector<float> pairs;
  for (std::size_t i = 0; i < g.kappa.size(); ++i) {
    pairs.push_back(g.cosine[i]);
    pairs.push_back(g.kappa[i]);
  }
  for (const sglab::Method& m : sglab::irradiance_methods)
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      if (!exportable(m.id)) continue;
      const sh::ExportResult ex = sh::export_source(sh::standard_request(lang, std::string(m.id)));
      const auto spirv =
          vk::compile_compute(lang, sh::compute_shader(lang, ex.source, ex.entry_point));
      const auto out = device_->run(spirv, pairs);
      ASSERT_EQ(out.size(), g.kappa.size());
      const std::vector<double> values(out.begin(), out.end());
      const Deviation d = deviation(m, g, values);
      EXPECT_LE(d.exported, 2 * d.runtime_float + kAllowance)
          << m.id << " " << sh::to_string(lang) << " on " << device_->name()
          << ": worst at kappa = " << g.kappa[d.worst] << ", cosine = " << g.cosine[d.worst]
          << ": device " << values[d.worst] << ", runtime double "
          << m.f64(g.cosine[d.worst], g.kappa[d.worst]);
    }
}

// `sglab sweep --backend vulkan --json`: the sweep's schema with "vulkan"
// rows; published tokuyoshi2024 within a few percent of its C++ float error.
TEST_F(OnVulkan, SweepBackendReportsVulkanRows) {
  const sglab::test::TempDir tmp("shader-sweep");
  const fs::path& dir = tmp.path;
  const auto r = run_sglab({"sweep", "--backend", "cpu,vulkan", "--method", "tokuyoshi2024",
                            "--method", "tokuyoshi2022_listing5", "--out", dir.string(), "--json"},
                           false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  EXPECT_EQ(doc.at("device"), device_->name());
  double cpu_float = NAN, glsl = NAN, hlsl = NAN;
  for (const auto& rec : doc.at("results")) {
    if (rec.at("method") != "tokuyoshi2024") continue;
    if (rec.at("precision") == "float") cpu_float = rec.at("max_peak_rel");
    if (rec.at("precision") == "vulkan") glsl = rec.at("max_peak_rel");
    if (rec.at("precision") == "vulkan_hlsl") hlsl = rec.at("max_peak_rel");
  }
  EXPECT_NEAR(cpu_float, 1.55e-3, 0.01e-3);
  EXPECT_NEAR(glsl, cpu_float, 0.03 * cpu_float);
  EXPECT_NEAR(hlsl, cpu_float, 0.03 * cpu_float);
}

// Without a Vulkan driver: `--backend vulkan` fails with the reason,
// `--backend auto` reports it and still writes the CPU rows.
TEST(ShaderExport, SweepWithoutAVulkanDriver) {
  const char* old = std::getenv("VK_ICD_FILENAMES");
  const std::string saved = old ? old : "";
  ::setenv("VK_ICD_FILENAMES", "/nonexistent/sglab_no_icd.json", 1);
  const sglab::test::TempDir tmp("shader-noicd");
  const fs::path& dir = tmp.path;
  auto r = run_sglab(
      {"sweep", "--backend", "vulkan", "--method", "tokuyoshi2024", "--out", dir.string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no Vulkan instance"), std::string::npos) << r.output;
  r = run_sglab(
      {"sweep", "--backend", "auto", "--method", "tokuyoshi2024", "--out", dir.string(), "--json"},
      false);
  if (old)
    ::setenv("VK_ICD_FILENAMES", saved.c_str(), 1);
  else
    ::unsetenv("VK_ICD_FILENAMES");
  ASSERT_EQ(r.exit_code, 0);
  const auto doc = nlohmann::json::parse(r.output);
  EXPECT_FALSE(doc.contains("device"));
  std::vector<std::string> precisions;
  for (const auto& rec : doc.at("results")) precisions.push_back(rec.at("precision"));
  EXPECT_EQ(precisions, (std::vector<std::string>{"float", "double"}));
}

// ---------------------------------------------------------------------------
// sglab's own models.

// The exporter gives a method the first erfc tier good to 1/100 of the
// method's error, else the best tier. sglab_acc3 is accurate to 1e-5 of the
// peak (its bound in tests/tolerances.hpp) and sglab_acc4 to 5e-6: no tier
// reaches 1e-7, so both get the best, `listing5`, whose measured float erfc
// error is below 3e-7 (an erfc error e moves the lerp factor by at most e,
// i.e. the result by at most e of the peak): under 1/16 of their errors.
TEST(ShaderExport, SglabAccTakesTheBestErfcTier) {
  for (const char* id : {"sglab_acc3", "sglab_acc4"}) {
    SCOPED_TRACE(id);
    const sh::ErrorBudget b = sh::runtime_budget(id);
    ASSERT_TRUE(b.model.has_value());
    EXPECT_GT(*b.model, 1e-6);
    EXPECT_LE(*b.model, 1e-5);
    const sh::ExportResult ex = sh::export_source(sh::standard_request(sh::Language::glsl, id));
    EXPECT_EQ(ex.tier.id, "listing5");
    EXPECT_EQ(ex.tier.id, sh::detail::elementary_tiers().back().id);
    EXPECT_LE(ex.budget.elementary.erfc_abs, *b.model / 16);
    EXPECT_LE(ex.budget.elementary.erfc_abs, 3e-7);
  }
}

// --constants for the sglab parameter types: a set of the method's type
// replaces the compiled-in one. With every correction numerator 0 the model
// is [Tokuyoshi2024] with the set's steepness, computed here by the runtime.
TEST(ShaderExport, SglabAccConstantsOverride) {
  const sglab::test::TempDir tmp("shader-sglab_acc_override");
  const fs::path& dir = tmp.path;
  const fs::path src =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants" / "sglab-acc-acc3.json";
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(std::ifstream(src));
  for (auto& x : j["coefficients"]["num"]) x = 0.0;
  j["cpp_name"] = "sglab_acc3_no_correction";
  const fs::path file = dir / "no_correction.json";
  std::ofstream(file) << j.dump(2);
  const auto r = run_sglab(
      {"export", "--lang", "cpp", "--method", "sglab_acc3", "--constants", file.string()}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sglab_acc3_no_correction"), std::string::npos);
  const Grid g = standard_grid();
  const auto values = run_cpp_export(r.output, "sglab_irradiance_sglab_acc3", g, dir);
  ASSERT_EQ(values.size(), g.kappa.size());
  std::vector<double> steep;
  for (const auto& x : j["coefficients"]["steep"]) steep.push_back(x.get<double>());
  // acc3's t(κ) is of order 3: κ√(0.5 P/Q), P = ((κ + s0)κ + s1)κ + s2, Q = (((κ + s3)κ + s4)κ +
  // s5)κ + s6 (params.hpp); SteepnessRationalParams lists p and q lowest order first.
  ASSERT_EQ(steep.size(), 7u);
  const sglab::SteepnessRationalParams<double, 3> p{{steep[2], steep[1], steep[0]},
                                                    {steep[6], steep[5], steep[4], steep[3]}};
  double worst = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double k = g.kappa[i], c = g.cosine[i];
    const double want = sglab::irradiance_tokuyoshi2024(c, k, p);
    worst = std::max(worst, std::fabs(values[i] - want) / sglab::irradiance_upper(k));
  }
  EXPECT_LE(worst, 2e-6);
  // …and the compiled-in acc3 (with its correction) is measurably different.
  const sglab::Method* acc3 = sglab::find_method(sglab::irradiance_methods, "sglab_acc3");
  ASSERT_TRUE(acc3);
  EXPECT_GT(deviation(*acc3, g, values).exported, 1e-4);
  // A set of another SglabAccParams shape is refused, naming its type.
  const fs::path acc1 =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants" / "sglab-acc-acc1.json";
  const auto bad = run_sglab(
      {"export", "--lang", "glsl", "--method", "sglab_acc3", "--constants", acc1.string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("SglabAccParams<double, 1, 3, 2>"), std::string::npos) << bad.output;
  // sglab_fast reads its own committed set.
  const fs::path fast =
      fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants" / "sglab-fast-float.json";
  const auto rf = run_sglab(
      {"export", "--lang", "cpp", "--method", "sglab_fast", "--constants", fast.string()}, false);
  ASSERT_EQ(rf.exit_code, 0) << rf.output;
  const auto fv = run_cpp_export(rf.output, "sglab_irradiance_sglab_fast", g, dir);
  const sglab::Method* fm = sglab::find_method(sglab::irradiance_methods, "sglab_fast");
  ASSERT_TRUE(fm);
  const Deviation d = deviation(*fm, g, fv);
  EXPECT_LE(d.exported, 2 * d.runtime_float + kAllowance);
}

// `sglab sweep --backend vulkan`: sglab_acc3 on the device within a few
// percent of its C++ float error (the standard-grid error its fit recorded,
// 2.07e-5), and within float noise of the C++ float runtime at every point.
TEST_F(OnVulkan, SglabAcc3OnTheDeviceKeepsItsAccuracy) {
  const sglab::test::TempDir tmp("shader-sweep_acc3");
  const fs::path& dir = tmp.path;
  const auto r = run_sglab({"sweep", "--backend", "cpu,vulkan", "--method", "sglab_acc3", "--out",
                            dir.string(), "--json"},
                           false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto doc = nlohmann::json::parse(r.output);
  double cpu_float = NAN, glsl = NAN, hlsl = NAN;
  for (const auto& rec : doc.at("results")) {
    if (rec.at("method") != "sglab_acc3") continue;
    if (rec.at("precision") == "float") cpu_float = rec.at("max_peak_rel");
    if (rec.at("precision") == "vulkan") glsl = rec.at("max_peak_rel");
    if (rec.at("precision") == "vulkan_hlsl") hlsl = rec.at("max_peak_rel");
  }
  const auto recorded = sh::runtime_budget("sglab_acc3").model;
  ASSERT_TRUE(recorded.has_value());
  EXPECT_NEAR(cpu_float, *recorded, 0.02 * *recorded);
  EXPECT_NEAR(glsl, cpu_float, 0.03 * cpu_float);
  EXPECT_NEAR(hlsl, cpu_float, 0.03 * cpu_float);
}

// ---------------------------------------------------------------------------
// Per-light split exports (`sglab export --split`).

namespace {

sh::ExportResult split_export(sh::Language lang, const std::string& method) {
  sh::ExportRequest request = sh::standard_request(lang, method);
  request.split = true;
  return sh::export_source(request);
}

}  // namespace

// Every method whose kappa-only work is separable has a split form (the 2022 and 2024 families
// and sglab's models at least); a method without one is refused by the library (invalid_argument)
// and by the CLI (exit 2, naming --split).
TEST(ShaderExport, SplitFormsAndRefusals) {
  // Every registered method but those whose product SG with the normal makes
  // all their work depend on the cosine (wang2009 and its refit, meder2018).
  std::vector<std::string> expected;
  for (const sglab::Method& m : sglab::irradiance_methods)
    if (m.id != "wang2009" && m.id != "wang2009_refit" && m.id != "meder2018")
      expected.emplace_back(m.id);
  EXPECT_EQ(sh::split_methods(), expected);
  for (const char* id : {"tokuyoshi2024", "tokuyoshi2024_refit", "tokuyoshi2022",
                         "tokuyoshi2022_listing5", "tokuyoshi2022_refit", "sglab_fast",
                         "sglab_acc1", "sglab_acc2", "sglab_acc3", "sglab_acc4"})
    EXPECT_NE(std::find(expected.begin(), expected.end(), id), expected.end()) << id;
  EXPECT_THROW(split_export(sh::Language::glsl, "wang2009"), std::invalid_argument);
  const auto r = run_sglab({"export", "--lang", "glsl", "--method", "wang2009", "--split"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--split"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wang2009"), std::string::npos) << r.output;
  const auto ok =
      run_sglab({"export", "--lang", "hlsl", "--method", "sglab_acc3", "--split"}, false);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("struct SglabLight_sglab_acc3 {"), std::string::npos);
  EXPECT_NE(ok.output.find("SglabLight_sglab_acc3 sglab_light_sglab_acc3(float kappa)"),
            std::string::npos);
  EXPECT_NE(ok.output.find(
                "float sglab_irradiance_sglab_acc3(SglabLight_sglab_acc3 light, float cosine)"),
            std::string::npos);
  EXPECT_NE(ok.output.find("Produced by: sglab export --lang hlsl --method sglab_acc3 --split"),
            std::string::npos);
  EXPECT_NE(ok.output.find("std430"), std::string::npos);
}

// The split export is float only: split with half precision is refused by the
// library (invalid_argument), by `sglab export` and by `sglab gpucost --form
// split --precision half` (exit 2, naming both options); the half export alone
// and the float split alone still work.
TEST(ShaderExport, SplitWithHalfIsRefused) {
  sh::ExportRequest request =
      sh::standard_request(sh::Language::glsl, "sglab_acc3", sh::Precision::float16);
  request.split = true;
  EXPECT_THROW(sh::export_source(request), std::invalid_argument);
  request.split = false;
  EXPECT_NO_THROW(sh::export_source(request));
  auto r = run_sglab(
      {"export", "--lang", "glsl", "--method", "sglab_acc3", "--split", "--precision", "half"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--split with --precision half"), std::string::npos) << r.output;
  r = run_sglab({"gpucost", "--families", "navi21", "--method", "sglab_acc3", "--form", "split",
                 "--precision", "half"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--form split with --precision half"), std::string::npos) << r.output;
  r = run_sglab({"export", "--lang", "glsl", "--method", "sglab_acc3", "--split"}, false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// glslang compiles every split export, GLSL and HLSL, in both of its
// wrappers: the per-pixel one (lights from a buffer) and the light pre-pass.
TEST(ShaderExport, SplitExportsCompileToSpirv) {
  for (const std::string& id : sh::split_methods())
    for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl}) {
      const sh::ExportResult ex = split_export(lang, id);
      EXPECT_EQ(ex.light_struct, "SglabLight_" + id);
      EXPECT_EQ(ex.light_function, "sglab_light_" + id);
      try {
        vk::compile_compute(lang, sh::split_compute_shader(lang, ex.source, ex));
        vk::compile_compute(lang, sh::light_compute_shader(lang, ex.source, ex));
      } catch (const vk::CompileError& e) {
        ADD_FAILURE() << id << " " << sh::to_string(lang) << ": " << e.what();
      }
    }
}

// The C++ split exports, compiled with the unsplit ones in one program (each
// in its own namespace): per pixel from sglab_light_<ID>(κ), the split form is
// within 1e-6 of the peak E(1, κ) of the unsplit export at every grid point.
// Where the runtime splits the method, its light_setup32 state copied byte for
// byte into the struct (as a host fills the shader's buffer) gives the same
// values, and the struct's floats are the runtime's, field by field.
TEST(ShaderExport, SplitCppExportMatchesTheUnsplitOneAndTheRuntimeState) {
  const Grid g = standard_grid();
  const sglab::test::TempDir tmp("shader-cpp_split");
  const fs::path& dir = tmp.path;
  struct Item {
    const sglab::Method* method;
    sh::ExportResult split;
    bool host;  // the runtime has light_setup32
  };
  std::vector<Item> items;
  std::ofstream main(dir / "main.cpp");
  main << "#include <cstdio>\n#include <cstdlib>\n#include <cstring>\n";
  for (const std::string& id : sh::split_methods()) {
    const sglab::Method* m = sglab::find_method(sglab::irradiance_methods, id);
    ASSERT_TRUE(m) << id;
    items.push_back({m, split_export(sh::Language::cpp, id), m->light_setup32 != nullptr});
    std::ofstream(dir / (id + "_split.hpp")) << items.back().split.source;
    std::ofstream(dir / (id + ".hpp")) << export_text(sh::Language::cpp, id);
    main << "#include \"" << id << ".hpp\"\n#include \"" << id << "_split.hpp\"\n";
  }
  main << "int main(int, char** argv) {\n  std::FILE* f = std::fopen(argv[1], \"r\");\n  char "
          "a[64];\n"
       << "  auto next = [&] { return std::fscanf(f, \"%63s\", a) == 1 ? std::strtof(a, nullptr) : "
          "0.0f; };\n"
       << "  while (std::fscanf(f, \"%63s\", a) == 1) {\n    float c = std::strtof(a, nullptr), k "
          "= next();\n";
  for (const Item& it : items) {
    const std::string& L = it.split.light_struct;
    const std::size_t n = it.split.light_floats;
    main << fmt::format(
        "    {{\n      static_assert(sizeof({0}) == {1} * sizeof(float), \"std430: no padding\");\n"
        "      {0} l = {2}(k);\n      float lf[{1}];\n      std::memcpy(lf, &l, sizeof l);\n"
        "      std::printf(\"%a %a \", (double){3}(c, k), (double){3}(l, c));\n"
        "      for (float x : lf) std::printf(\"%a \", (double)x);\n",
        L, n, it.split.light_function, it.split.entry_point);
    if (it.host)
      main << fmt::format(
          "      float s[{0}];\n      for (float& x : s) x = next();\n      {1} h;\n"
          "      std::memcpy(&h, s, sizeof h);\n      std::printf(\"%a \", (double){2}(h, c));\n"
          "      for (float x : s) std::printf(\"%a \", (double)x);\n",
          n, L, it.split.entry_point);
    main << "    }\n";
  }
  main << "    std::printf(\"\\n\");\n  }\n  return 0;\n}\n";
  main.close();
  {
    std::ofstream in(dir / "points.txt");
    for (std::size_t i = 0; i < g.kappa.size(); ++i) {
      in << fmt::format("{:a} {:a}", g.cosine[i], g.kappa[i]);
      for (const Item& it : items) {
        if (!it.host) continue;
        float state[sglab::kLightStateFloats] = {};
        it.method->light_setup32(g.kappa[i], state);
        for (std::size_t j = 0; j < it.split.light_floats; ++j)
          in << fmt::format(" {:a}", state[j]);
      }
      in << "\n";
    }
  }
  const auto build =
      run_program({SGLAB_CXX_COMPILER, "-std=c++17", "-O2", "-ffp-contract=off", "-Wall", "-Werror",
                   (dir / "main.cpp").string(), "-o", (dir / "prog").string()});
  ASSERT_EQ(build.exit_code, 0) << build.output;
  const auto run = run_program({(dir / "prog").string(), (dir / "points.txt").string()}, false);
  ASSERT_EQ(run.exit_code, 0);
  std::istringstream lines(run.output);
  std::string line;
  std::size_t point = 0;
  std::map<std::string, double> worst_unsplit, worst_host;
  std::map<std::string, std::string> where;
  while (std::getline(lines, line)) {
    ASSERT_LT(point, g.kappa.size());
    std::istringstream row(line);
    const auto next = [&] {
      std::string field;
      row >> field;
      return std::strtod(field.c_str(), nullptr);
    };
    const double k = g.kappa[point], c = g.cosine[point], peak = sglab::irradiance_upper(k);
    for (const Item& it : items) {
      const std::string id(it.method->id);
      const double unsplit = next(), split = next();
      std::vector<double> fields(it.split.light_floats);
      for (double& x : fields) x = next();
      if (std::fabs(split - unsplit) / peak > worst_unsplit[id]) {
        worst_unsplit[id] = std::fabs(split - unsplit) / peak;
        where[id] = fmt::format("kappa {}, cosine {}: split {}, unsplit {}", k, c, split, unsplit);
      }
      if (!it.host) continue;
      const double host = next();
      worst_host[id] = std::max(worst_host[id], std::fabs(host - split) / peak);
      for (std::size_t j = 0; j < fields.size(); ++j) {
        const double state = next();
        EXPECT_LE(std::fabs(fields[j] - state),
                  1e-5 * std::max(std::fabs(fields[j]), std::fabs(state)) + 1e-6)
            << id << " field " << j << " at kappa " << k << ": export " << fields[j] << ", runtime "
            << state;
      }
    }
    ++point;
  }
  EXPECT_EQ(point, g.kappa.size());
  for (const Item& it : items) {
    const std::string id(it.method->id);
    EXPECT_LE(worst_unsplit[id], 1e-6)
        << id << ": split against unsplit export, worst at " << where[id];
    if (it.host) {
      EXPECT_LE(worst_host[id], 1e-6) << id << ": struct filled from light_setup32";
    }
  }
}

// On the device: every split export in GLSL, four of them in HLSL (every
// one compiles: SplitExportsCompileToSpirv). With its lights from its own
// sglab_light_<ID> run on the device (a pre-pass), the split export is within
// 1e-6 of the peak of the unsplit export at every grid point (the same
// arithmetic, split in two). With the lights the sweep uses (split_lights: the
// runtime's light_setup32 state, filled on the host, where the runtime splits
// the method), it is within 1e-6 of the peak of the runtime's own per-pixel
// light_eval32 on the same state.
TEST_F(OnVulkan, SplitExportsMatchTheUnsplitOnes) {
  std::vector<sglab::validate::SweepMethod> methods;
  const auto split_ids = sh::split_methods();
  for (const sglab::validate::SweepMethod& sm : sglab::validate::registered_sweep_methods())
    if (sm.quantity == sglab::validate::Quantity::irradiance &&
        std::find(split_ids.begin(), split_ids.end(), sm.method.id) != split_ids.end())
      methods.push_back(sm);
  ASSERT_EQ(methods.size(), split_ids.size());
  const std::set<std::string> hlsl_ids = {"tokuyoshi2024", "tokuyoshi2022", "sglab_fast",
                                          "sglab_acc3"};
  std::vector<sglab::validate::SweepMethod> hlsl_methods;
  for (const auto& sm : methods)
    if (hlsl_ids.count(std::string(sm.method.id))) hlsl_methods.push_back(sm);
  sglab::validate::SweepOptions options;
  options.precisions.clear();
  options.progress = false;
  sglab::validate::SweepResult r =
      sglab::validate::sweep(sglab::validate::SweepGrid{}, methods, options);
  vk::add_device_entries(r, methods, sh::Language::glsl, *device_);
  vk::add_device_entries(r, hlsl_methods, sh::Language::hlsl, *device_);
  const std::vector<float> kappas(r.kappas.begin(), r.kappas.end()),
      cosines(r.cosines.begin(), r.cosines.end());
  const sglab::validate::Quantity E = sglab::validate::Quantity::irradiance;
  for (sh::Language lang : {sh::Language::glsl, sh::Language::hlsl})
    for (const auto& sm : lang == sh::Language::glsl ? methods : hlsl_methods) {
      const std::string id(sm.method.id);
      SCOPED_TRACE(id + " " + std::string(sh::to_string(lang)));
      const auto* unsplit =
          r.find(id, E, sglab::io::on_vulkan(lang, sglab::io::Precision::float32));
      ASSERT_TRUE(unsplit);
      const sh::ExportResult ex = split_export(lang, id);
      const std::vector<float> prepass =
          vk::run_split(ex, lang, vk::device_lights(ex, lang, kappas, *device_), cosines, *device_);
      const std::vector<float> host = vk::run_split(
          ex, lang, vk::split_lights(sm.method, ex, lang, kappas, *device_), cosines, *device_);
      ASSERT_EQ(prepass.size(), unsplit->values.size());
      ASSERT_EQ(host.size(), unsplit->values.size());
      double worst_prepass = 0, worst_runtime = 0;
      for (std::size_t k = 0; k < r.kappas.size(); ++k) {
        float state[sglab::kLightStateFloats] = {};
        if (sm.method.light_setup32) sm.method.light_setup32(kappas[k], state);
        for (std::size_t j = 0; j < r.cosines.size(); ++j) {
          const std::size_t i = r.index(k, j);
          const double peak = r.peak_value(E, k);
          const double d = std::fabs(prepass[i] - unsplit->values[i]) / peak;
          worst_prepass = std::isnan(d) ? INFINITY : std::max(worst_prepass, d);
          if (!sm.method.light_setup32) continue;
          const double e = std::fabs(host[i] - sm.method.light_eval32(state, cosines[j])) / peak;
          worst_runtime = std::isnan(e) ? INFINITY : std::max(worst_runtime, e);
        }
      }
      EXPECT_LE(worst_prepass, 1e-6);
      EXPECT_LE(worst_runtime, 1e-6);
    }
}

// `sglab sweep --backend vulkan` reports the split rows as their own precisions.
TEST_F(OnVulkan, SweepReportsSplitRows) {
  const sglab::test::TempDir tmp("shader-sweep_split");
  const fs::path& dir = tmp.path;
  const auto r = run_sglab({"sweep", "--backend", "cpu,vulkan", "--method", "sglab_acc3",
                            "--method", "wang2009", "--out", dir.string(), "--json"},
                           false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, std::set<std::string>> precisions;
  const auto doc = nlohmann::json::parse(r.output);
  for (const auto& rec : doc.at("results"))
    precisions[rec.at("method").get<std::string>()].insert(rec.at("precision").get<std::string>());
  EXPECT_EQ(precisions["sglab_acc3"],
            (std::set<std::string>{"float", "double", "vulkan", "vulkan_hlsl", "vulkan_split",
                                   "vulkan_hlsl_split"}));
  EXPECT_EQ(precisions["wang2009"],
            (std::set<std::string>{"float", "double", "vulkan", "vulkan_hlsl"}));
}
