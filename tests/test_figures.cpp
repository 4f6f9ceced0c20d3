// tests/test_figures.cpp — `sglab figures` output and the Pareto CSV reader
// (report/figures.hpp).
#include <algorithm>
#include <filesystem>
#include <string>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/io.hpp"
#include "report/figures.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace sglab::report;

TEST(Figures, ReadParetoCsvRejectsBadHeader) {
  const sglab::test::TempDir tmp("claims");
  const fs::path& dir = tmp.path;
  sglab::io::write_file_atomic(dir / "bad.csv", "method,cost\nx,1\n");
  EXPECT_THROW(read_pareto_csv(dir / "bad.csv"), std::invalid_argument);
}

TEST(Figures, ReadParetoCsvReadsOrigin) {
  const sglab::test::TempDir tmp("claims-origin");
  const fs::path& dir = tmp.path;
  const std::string header =
      "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,max_peak_rel,"
      "frontier\n";
  sglab::io::write_file_atomic(dir / "ok.csv",
                               header +
                                   "a,published,float,1,10,1,ns,cpu-batch,0.1,1\n"
                                   "b,refit,float,1,10,2,ns,cpu-batch,0.01,0\n"
                                   "c,sglab,double,1,10,3,ns,cpu-batch,0.001,true\n");
  const auto rows = read_pareto_csv(dir / "ok.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].origin, sglab::Origin::published);
  EXPECT_EQ(rows[1].origin, sglab::Origin::refit);
  EXPECT_EQ(rows[2].origin, sglab::Origin::sglab);
  EXPECT_TRUE(rows[0].frontier);
  EXPECT_FALSE(rows[1].frontier);
  EXPECT_TRUE(rows[2].frontier);
  // The old boolean column is not an origin.
  sglab::io::write_file_atomic(dir / "old.csv",
                               header + "a,true,float,1,10,1,ns,cpu-batch,0.1,1\n");
  EXPECT_THROW(read_pareto_csv(dir / "old.csv"), std::invalid_argument);
  sglab::io::write_file_atomic(
      dir / "oldheader.csv",
      "method,refit,precision,kappa_lo,kappa_hi,ns_per_eval,max_peak_rel,frontier\n"
      "a,0,float,1,10,1,0.1,1\n");
  EXPECT_THROW(read_pareto_csv(dir / "oldheader.csv"), std::invalid_argument);
  // A CSV without the cost columns (ns_per_eval alone) names the one it lacks.
  sglab::io::write_file_atomic(
      dir / "nocost.csv",
      "method,origin,precision,kappa_lo,kappa_hi,ns_per_eval,max_peak_rel,frontier\n"
      "a,published,float,1,10,1,0.1,1\n");
  try {
    read_pareto_csv(dir / "nocost.csv");
    ADD_FAILURE() << "a CSV without a cost column was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("header lacks column 'cost'"), std::string::npos)
        << e.what();
  }
}

TEST(Figures, CommandWritesPngAndSvg) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  const sglab::test::TempDir tmp("figures");
  const fs::path& dir = tmp.path;
  const fs::path pareto = dir / "pareto.csv";
  sglab::io::write_file_atomic(
      pareto,
      "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,max_peak_rel,frontier\n"
      "punctual,published,float,0.001,10000,0.8,ns,cpu-batch,0.9,true\n"
      "wang2009,published,float,0.001,10000,2.5,ns,cpu-batch,0.35,false\n"
      "hill,published,float,0.001,10000,3.0,ns,cpu-batch,3.1e7,false\n"
      "tokuyoshi2022,published,float,0.001,10000,12.0,ns,cpu-batch,0.0045,true\n"
      "tokuyoshi2024_refit,refit,float,0.001,10000,15.0,ns,cpu-batch,0.0014,true\n"
      "sglab_model,sglab,float,0.001,10000,4.0,ns,cpu-batch,0.002,true\n"
      "tokuyoshi2024,published,double,0.001,10000,20.0,ns,cpu-batch,0.0013,true\n"
      "\"meder2018\",published,double,0.001,10000,9.0,ns,cpu-batch,0.02,true\n");
  const fs::path out = dir / "figs";
  const auto r =
      sglab::test::run_sglab({"figures", "--out", out.string(), "--pareto", pareto.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* stem : {"a_clamped_cosine", "b_steepness", "c_irradiance_kappa4",
                           "d_peak_rel_heatmaps", "e_pareto", "f_erf_ulp", "g_peak_rel_vs_kappa"})
    for (const char* ext : {".png", ".svg"}) {
      const fs::path p = out / (std::string(stem) + ext);
      ASSERT_TRUE(fs::exists(p)) << p << "\n" << r.output;
      EXPECT_GT(fs::file_size(p), 1000u) << p;
    }
  EXPECT_TRUE(fs::exists(out / "index.md"));
  EXPECT_TRUE(fs::exists(out / "a_clamped_cosine.csv"));
  EXPECT_TRUE(fs::exists(out / "e_pareto_points.csv"));
  // A method failing on the range (hill, 3.1e7 > 1) is moved into the band, its true error kept;
  // the origin column is carried through.
  const std::string points = sglab::io::read_file(out / "e_pareto_points.csv");
  EXPECT_NE(points.find("3,31000000,10,hill,published,float,0,hill (3.1e+07)"), std::string::npos)
      << points;
  EXPECT_NE(points.find(",sglab_model,sglab,float,1,"), std::string::npos) << points;
  // Figure (g): one row per κ of the standard grid, float and double column per irradiance method.
  const std::string g = sglab::io::read_file(out / "g_peak_rel_vs_kappa.csv");
  EXPECT_EQ(std::count(g.begin(), g.end(), '\n'), 30) << g.substr(0, 500);
  EXPECT_EQ(g.rfind("kappa,wang2009_float,", 0), 0u) << g.substr(0, 200);
}

// Figure (e) draws one panel per cost source of the Pareto CSVs it is given
// (`sglab pareto --cost …`), in their order, each with its own points file and
// axis label; its legend names every method of every panel (sglab_min has a GPU
// cost only), in the panels' order.
TEST(Figures, OnePanelPerCostSource) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  sglab::test::TempDir dir("figures-panels");
  const std::string header =
      "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,cost_form,"
      "max_peak_rel,frontier\n";
  sglab::io::write_file_atomic(
      dir.path / "gpu.csv",
      header +
          "vsgl2015,published,float,0.001,10000,3,cycles,gpu:navi21,8-light loop (split),0.15,1\n"
          "sglab_min,sglab,float,0.001,10000,6,cycles,gpu:navi21,8-light loop (split),0.042,1\n"
          "sglab_acc3,sglab,float,0.001,10000,169,cycles,gpu:navi21,8-light loop (split),3e-5,"
          "1\n");
  sglab::io::write_file_atomic(
      dir.path / "cpu.csv",
      "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,max_peak_rel,frontier\n"
      "vsgl2015,published,float,0.001,10000,3.7,ns,cpu-batch,0.15,1\n"
      "sglab_acc3,sglab,float,0.001,10000,18.3,ns,cpu-batch,3e-5,1\n");
  // The cost table's GPU rows: beside the navi21 panel, a table of the other families (here
  // navi10) in the panel's figure, per light per pixel in the 8-light loop, the split form
  // where there is one (vsgl2015's: 36/8 = 4.5 beside its unsplit 5.5), not one call (1000).
  std::string gpu_rows;
  for (const auto& [method, family, harness, split, cycles] :
       {std::tuple{"vsgl2015", "navi21", "loop", true, 24},
        {"vsgl2015", "navi10", "loop", true, 36},
        {"vsgl2015", "navi10", "loop", false, 44},
        {"vsgl2015", "navi10", "single", false, 1000},
        {"sglab_acc3", "navi21", "loop", true, 1352},
        {"sglab_acc3", "navi10", "loop", true, 1416}})
    gpu_rows += fmt::format(
        R"({}{{"method": "{}", "family": "{}", "lang": "glsl", "compile": "none", "harness": "{}", )"
        R"("lights": {}, "split": {}, "precision": "float", "instructions": 1, )"
        R"("inverse_throughput": {}, "latency": 1, "vgprs": 1, "sgprs": 1, )"
        R"("code_size": 4, "branches": 0, "spirv_hash": "0"}})",
        gpu_rows.empty() ? "" : ", ", method, family, harness,
        harness == std::string("loop") ? 8 : 1, split, cycles);
  sglab::io::write_file_atomic(
      dir.path / "costs.json",
      R"({"format": "sglab-costs", "version": 1, "date": "2026-01-01T00:00:00Z", "command": "test", "machine": )"
      R"({"cpu": "t", "cores": 1}, "compiler": {"id": "none", "version": "0"}, "build_type": "none", "timer": "none", )"
      R"("inputs": "none", "costs": [], "gpu": {"driver": "radv test", "command": "test", "rows": [)" +
          gpu_rows + "]}}");
  const fs::path out = dir.path / "figs";
  const auto r = sglab::test::run_sglab(
      {"figures", "--out", out.string(), "--pareto", (dir.path / "gpu.csv").string(), "--pareto",
       (dir.path / "cpu.csv").string(), "--costs", (dir.path / "costs.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(sglab::io::read_file(out / "e_pareto_1_families.csv"),
            "method,navi10\nvsgl2015,4.5\nsglab_min,\nsglab_acc3,177\n");
  EXPECT_FALSE(fs::exists(out / "e_pareto_2_families.csv"));  // the CPU panel has none
  const std::string gpu = sglab::io::read_file(out / "e_pareto_1_points.csv");
  const std::string cpu = sglab::io::read_file(out / "e_pareto_2_points.csv");
  EXPECT_NE(gpu.find("169,3e-05,3e-05,sglab_acc3,sglab,float,1,"), std::string::npos) << gpu;
  EXPECT_NE(cpu.find("18.3,3e-05,3e-05,sglab_acc3,sglab,float,1,"), std::string::npos) << cpu;
  EXPECT_EQ(gpu.find("18.3"), std::string::npos) << gpu;
  const std::string script = sglab::io::read_file(out / "e_pareto.gp");
  EXPECT_NE(script.find("set title '--cost gpu:navi21'"), std::string::npos);
  EXPECT_NE(script.find("set xlabel 'GPU cycles per light per pixel on navi21 (ACO estimate)'"),
            std::string::npos);
  EXPECT_NE(script.find("set title '--cost cpu-batch'"), std::string::npos);
  EXPECT_NE(script.find("set xlabel 'CPU batch ns/eval'"), std::string::npos);
  const std::size_t published = script.find("title 'vsgl2015'"),
                    min = script.find("title 'sglab_min [sglab]'"),
                    acc3 = script.find("title 'sglab_acc3 [sglab]'");
  ASSERT_NE(min, std::string::npos) << script;
  ASSERT_NE(published, std::string::npos) << script;
  ASSERT_NE(acc3, std::string::npos) << script;
  EXPECT_LT(published, min);
  EXPECT_LT(min, acc3);
  // Once per rendering (the script draws the PNG and then the SVG), as every method.
  const auto count = [&script](const std::string& s) {
    std::size_t n = 0;
    for (std::size_t at = script.find(s); at != std::string::npos; at = script.find(s, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("title 'sglab_min [sglab]'"), count("title 'sglab_acc3 [sglab]'"));
  EXPECT_GT(fs::file_size(out / "e_pareto.png"), 1000u);
  // A header with cost but not its unit and source is refused.
  sglab::io::write_file_atomic(
      dir.path / "half.csv",
      "method,origin,precision,kappa_lo,kappa_hi,cost,max_peak_rel,frontier\n"
      "a,published,float,1,10,1,0.1,1\n");
  EXPECT_THROW(read_pareto_csv(dir.path / "half.csv"), std::invalid_argument);
}

// gnuplot is started with an argument vector, not through a shell: the
// program path is taken literally, whatever characters it holds.
TEST(Figures, GnuplotPathTakenLiterally) {
  EXPECT_FALSE(gnuplot_available(""));
  EXPECT_FALSE(gnuplot_available("/nonexistent/gnuplot"));
  // one program name, not a command line
  EXPECT_FALSE(gnuplot_available("gnuplot --version; true"));
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  const sglab::test::TempDir tmp("fig's $dir;");
  const fs::path& dir = tmp.path;
  std::string real;
  for (const char* p : {"/usr/bin/gnuplot", "/usr/local/bin/gnuplot", "/bin/gnuplot"})
    if (fs::exists(p)) real = p;
  if (real.empty()) GTEST_SKIP() << "gnuplot not in a standard directory";
  fs::create_symlink(real, dir / "gnu plot");
  EXPECT_TRUE(gnuplot_available((dir / "gnu plot").string()));
}

TEST(Figures, MissingParetoFileIsSkipped) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed";
  // Only checks the command line path: figure (e) skipped with a message, exit 0.
  const sglab::test::TempDir tmp("figures-np");
  const fs::path& dir = tmp.path;
  const auto r = sglab::test::run_sglab(
      {"figures", "--out", (dir / "figs").string(), "--pareto", (dir / "absent.csv").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("not found"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "figs" / "e_pareto.png"));
}
