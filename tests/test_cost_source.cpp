// The cost source of `sglab pareto` and `sglab recommend` (--cost gpu:FAMILY |
// cpu-batch | cpu-scalar, cost/cost_source.hpp): the parser, the default
// (GPU inverse throughput on navi21), a cost table without GPU costs, and the
// recommendation under GPU cost checked against the table itself. No timing.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "cost/cost_source.hpp"
#include "cost/cost_table.hpp"
#include "report/pareto.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::cost::CostSource;
using sglab::cost::CostSourceKind;
using sglab::cost::parse_cost_source;
using sglab::test::run_sglab;
using sglab::test::TempDir;

// ---- the parser ------------------------------------------------------------------

TEST(CostSource, ParsesTheThreeForms) {
  struct Case {
    const char* text;
    CostSourceKind kind;
    const char* family;
    const char* unit;
  };
  for (const Case& c : {Case{"gpu:navi21", CostSourceKind::gpu, "navi21", "cycles"},
                        Case{"gpu:gfx1100", CostSourceKind::gpu, "gfx1100", "cycles"},
                        Case{"gpu:polaris10", CostSourceKind::gpu, "polaris10", "cycles"},
                        Case{"gpu-single:navi21", CostSourceKind::gpu, "navi21", "cycles"},
                        Case{"cpu-batch", CostSourceKind::cpu_batch, "", "ns"},
                        Case{"cpu-scalar", CostSourceKind::cpu_scalar, "", "ns"}}) {
    const auto parsed = parse_cost_source(c.text);
    ASSERT_TRUE(std::holds_alternative<CostSource>(parsed))
        << c.text << ": " << std::get<std::string>(parsed);
    const CostSource& s = std::get<CostSource>(parsed);
    EXPECT_EQ(s.kind, c.kind) << c.text;
    if (s.kind == CostSourceKind::gpu) {
      EXPECT_EQ(s.family, c.family) << c.text;
      EXPECT_EQ(s.figure == sglab::cost::GpuFigure::single,
                std::string(c.text).starts_with("gpu-single:"))
          << c.text;
    }
    EXPECT_EQ(s.unit(), c.unit) << c.text;
    EXPECT_EQ(s.name(), c.text);  // the name is what --cost takes back
  }
  EXPECT_EQ(std::get<CostSource>(parse_cost_source("cpu-batch")).cpu_mode(),
            sglab::cost::CostMode::batch);
  EXPECT_EQ(std::get<CostSource>(parse_cost_source("cpu-scalar")).cpu_mode(),
            sglab::cost::CostMode::scalar);
}

TEST(CostSource, RefusesEverythingElseQuotingIt) {
  for (const std::string& bad : std::vector<std::string>{"",
                                                         "gpu",
                                                         "gpu:",
                                                         "gpu:Navi21",
                                                         "GPU:navi21",
                                                         "gpu:navi 21",
                                                         " cpu-batch",
                                                         "cpu-batch ",
                                                         "gpu-single",
                                                         "gpu-single:",
                                                         "gpu-single:Navi21",
                                                         "gpu_single:navi21",
                                                         "gpu-loop:navi21",
                                                         "cpu",
                                                         "cpu_batch",
                                                         "cpu-batch,gpu:navi21",
                                                         "gpu:navi21:x",
                                                         "gpu:navi-21",
                                                         std::string("gpu:navi21\0x", 12),
                                                         "gpu:" + std::string(33, 'a')}) {
    const auto parsed = parse_cost_source(bad);
    ASSERT_TRUE(std::holds_alternative<std::string>(parsed)) << "accepted '" << bad << "'";
    const std::string& why = std::get<std::string>(parsed);
    EXPECT_NE(why.find("gpu:navi21"), std::string::npos) << why;  // says what is expected
    EXPECT_EQ(why.find('\0'), std::string::npos) << why;          // the text quoted escaped
  }
  EXPECT_TRUE(std::holds_alternative<CostSource>(parse_cost_source("gpu:" + std::string(32, 'a'))));
}

TEST(CostSource, DefaultIsGpuInverseThroughputOnNavi21ForFloat) {
  const CostSource f = sglab::cost::default_cost_source(sglab::io::Precision::float32);
  EXPECT_EQ(f.kind, CostSourceKind::gpu);
  EXPECT_EQ(f.family, "navi21");
  EXPECT_EQ(f.unit(), "cycles");
  // The shader exports are float: double is costed on the CPU.
  const CostSource d = sglab::cost::default_cost_source(sglab::io::Precision::float64);
  EXPECT_EQ(d.name(), "cpu-batch");
}

// ---- cost tables ------------------------------------------------------------------

// A well-formed table with a float batch cost for every irradiance method and,
// when `gpu` is not empty, a GPU section with those costs (method → cycles) on
// `family`: rows of the renderer's loop over 8 lights (8 × cycles for all of
// them, so cycles per light) and, at 1000 + cycles, of one call.
nlohmann::ordered_json table_json(double ns, const std::map<std::string, long>& gpu,
                                  const std::string& family = "navi21") {
  nlohmann::ordered_json doc = {{"format", "sglab-costs"},
                                {"version", 1},
                                {"date", "2026-01-01T00:00:00Z"},
                                {"command", "hand-made for test_cost_source"},
                                {"machine", {{"cpu", "t"}, {"cores", 1}}},
                                {"compiler", {{"id", "none"}, {"version", "0"}}},
                                {"build_type", "none"},
                                {"timer", "none"},
                                {"inputs", "none"}};
  auto rows = nlohmann::ordered_json::array();
  for (const sglab::Method& m : sglab::irradiance_methods)
    rows.push_back({{"kind", "irradiance"},
                    {"method", m.id},
                    {"precision", "float"},
                    {"mode", "batch"},
                    {"ns_per_eval", ns}});
  doc["costs"] = rows;
  if (gpu.empty()) return doc;
  auto g = nlohmann::ordered_json::array();
  for (const char* harness : {"loop", "single"})
    for (const auto& [method, cycles] : gpu)
      g.push_back(
          {{"method", method},
           {"family", family},
           {"lang", "glsl"},
           {"compile", "none"},
           {"harness", harness},
           {"lights", harness == std::string("loop") ? 8 : 1},
           {"split", false},
           {"precision", "float"},
           {"instructions", 1},
           {"inverse_throughput", harness == std::string("loop") ? 8 * cycles : 1000 + cycles},
           {"latency", 1},
           {"vgprs", 1},
           {"sgprs", 1},
           {"code_size", 4},
           {"branches", 0},
           {"spirv_hash", "0000000000000000"}});
  doc["gpu"] = {{"driver", "radv test"}, {"command", "hand-made"}, {"rows", g}};
  return doc;
}

fs::path write_table(const TempDir& dir, const std::string& name,
                     const nlohmann::ordered_json& doc) {
  const fs::path p = dir.path / name;
  std::ofstream(p) << doc.dump(2);
  return p;
}

// Every method at `cycles` + 10 per registry position (all more than 5% apart from 100 on).
std::map<std::string, long> gpu_costs(long cycles) {
  std::map<std::string, long> m;
  long step = 0;
  for (const sglab::Method& method : sglab::irradiance_methods)
    m[std::string(method.id)] = cycles + (step += 10);
  return m;
}

nlohmann::json recommend_json(const std::vector<std::string>& extra) {
  std::vector<std::string> args = {"recommend", "--kappa", "1:100", "--budget", "1e-2", "--json"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = run_sglab(args, /*merge_stderr=*/false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.exit_code == 0 ? nlohmann::json::parse(r.output) : nlohmann::json::object();
}

TEST(CostSourceCli, TableWithoutGpuSectionRefusesGpuAndServesCpu) {
  TempDir dir("cost-source-nogpu");
  const fs::path t = write_table(dir, "cpu_only.json", table_json(5, {}));
  for (const std::vector<std::string>& cost :
       {std::vector<std::string>{}, {"--cost", "gpu:navi21"}}) {
    std::vector<std::string> args = {"recommend", "--kappa", "1:100",   "--budget",
                                     "1e-2",      "--costs", t.string()};
    args.insert(args.end(), cost.begin(), cost.end());
    const auto r = run_sglab(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("cpu_only.json has no \"gpu\" section"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("gpu:navi21"), std::string::npos) << r.output;
  }
  const auto p = run_sglab(
      {"pareto", "--kappa", "1:100", "--costs", t.string(), "--out", (dir.path / "p").string()});
  EXPECT_EQ(p.exit_code, 2) << p.output;
  EXPECT_NE(p.output.find("cpu_only.json"), std::string::npos) << p.output;
  const auto batch = recommend_json({"--costs", t.string(), "--cost", "cpu-batch"});
  EXPECT_EQ(batch.value("cost_source", ""), "cpu-batch");
  EXPECT_EQ(batch.value("cost_unit", ""), "ns");
  // No scalar rows in this table: every method is listed with no cost, none is chosen.
  const auto scalar = recommend_json({"--costs", t.string(), "--cost", "cpu-scalar"});
  EXPECT_EQ(scalar.value("cost_source", ""), "cpu-scalar");
  ASSERT_TRUE(scalar.contains("candidates"));
  EXPECT_EQ(scalar["candidates"].size(), std::size(sglab::irradiance_methods));
  for (const auto& c : scalar["candidates"]) EXPECT_TRUE(c["cost"].is_null()) << c.dump();
  EXPECT_TRUE(scalar["choice"].is_null());
}

TEST(CostSourceCli, FamilyNotInTheTableIsNamedWithTheOnesItHas) {
  TempDir dir("cost-source-family");
  const fs::path t = write_table(dir, "navi10.json", table_json(5, gpu_costs(100), "navi10"));
  const auto r =
      run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2", "--costs", t.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("navi10.json has no GLSL rows of the renderer's loop (harness loop) "
                          "for family 'navi21' (it has: navi10)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(
      recommend_json({"--costs", t.string(), "--cost", "gpu:navi10"}).value("cost_source", ""),
      "gpu:navi10");
}

// The cost column of `sglab fit sglab-acc` (report::default_float_costs): the
// table's navi21 cycles when it has them; with only another family, or no GPU
// section, its CPU batch ns; a method without a row is left out.
TEST(CostSource, FitCostColumnIsNavi21CyclesElseCpuBatch) {
  TempDir dir("cost-source-fit");
  std::map<std::string, long> gpu = gpu_costs(100);
  gpu.erase("sglab_acc2");
  const auto navi21 =
      sglab::cost::read_cost_table(write_table(dir, "navi21.json", table_json(5, gpu)));
  const auto with_gpu = sglab::report::default_float_costs(navi21);
  EXPECT_EQ(with_gpu.source.name(), "gpu:navi21");
  EXPECT_EQ(with_gpu.cost.size(), gpu.size());
  for (const auto& [method, cycles] : gpu)
    EXPECT_EQ(with_gpu.cost.at(method), static_cast<double>(cycles)) << method;
  EXPECT_EQ(with_gpu.cost.count("sglab_acc2"), 0u);
  for (const auto& table : {table_json(5, gpu_costs(100), "navi10"), table_json(5, {})}) {
    const auto cpu = sglab::report::default_float_costs(
        sglab::cost::read_cost_table(write_table(dir, "other.json", table)));
    EXPECT_EQ(cpu.source.name(), "cpu-batch");
    EXPECT_EQ(cpu.cost.size(), std::size(sglab::irradiance_methods));
    for (const auto& [method, ns] : cpu.cost) EXPECT_EQ(ns, 5.0) << method;
  }
}

TEST(CostSourceCli, BadValuesExit2NamingTheOption) {
  TempDir dir("cost-source-bad");
  const fs::path scene = dir.path / "scene.json";
  std::ofstream(scene)
      << R"({"lights": [{"axis": [0, 0, 1], "sharpness": 4, "amplitude": [1, 1, 1]}]})";
  const std::vector<std::vector<std::string>> commands = {
      {"pareto", "--kappa", "1:100", "--out", (dir.path / "p").string()},
      {"recommend", "--kappa", "1:100", "--budget", "1e-2"},
      {"recommend", "--scene", scene.string(), "--budget", "1e-2", "--normals", "16"}};
  for (const auto& command : commands) {
    std::vector<std::string> good = command;
    good.insert(good.end(), {"--cost", "cpu-scalar"});
    EXPECT_EQ(run_sglab(good).exit_code, 0)
        << command[0];  // the option exists and takes a good value
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"--cost", "gpu:Navi21"},
                                                {"--cost", ""},
                                                {"--cost", "gpu"},
                                                {"--cost", "cpu"},
                                                {"--cost", "gpu:navi21", "--precision", "double"},
                                                {"--cost", "gpu:navi21", "--live-timing"}}) {
      std::vector<std::string> args = command;
      args.insert(args.end(), bad.begin(), bad.end());
      const auto r = run_sglab(args);
      EXPECT_EQ(r.exit_code, 2) << args[0] << " " << bad[1] << "\n" << r.output;
      EXPECT_NE(r.output.find("--cost"), std::string::npos) << r.output;
    }
  }
}

// ---- the default and the recommendation under GPU cost -------------------------------

// The project's committed cost table, parsed here as plain JSON: navi21's
// cycles per light per pixel of each method's float GLSL export (no spirv-opt)
// in the 8-light loop, its split form where it has one (`single`: the
// inverse throughput of one unsplit call instead).
std::map<std::string, double> committed_navi21(bool single = false) {
  std::ifstream in(fs::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "results" / "costs.json");
  std::stringstream text;
  text << in.rdbuf();
  const auto doc = nlohmann::json::parse(text.str());
  std::map<std::string, double> out;
  std::map<std::string, bool> split;
  for (const auto& row : doc.at("gpu").at("rows")) {
    if (row.at("family") != "navi21" || row.at("lang") != "glsl" || row.at("compile") != "none" ||
        row.at("precision") != "float" || row.at("harness") != (single ? "single" : "loop") ||
        row.at("lights") != (single ? 1 : 8))
      continue;
    const std::string method = row.at("method");
    const bool is_split = row.at("split").get<bool>();
    if (single ? is_split : (out.count(method) && split[method] && !is_split)) continue;
    out[method] = row.at("inverse_throughput").get<double>() / row.at("lights").get<double>();
    split[method] = is_split;
  }
  return out;
}

TEST(CostSourceCli, DefaultIsNavi21FromTheCostTable) {
  const auto navi21 = committed_navi21();
  ASSERT_FALSE(navi21.empty());
  const auto doc = recommend_json({});
  EXPECT_EQ(doc.value("cost_source", ""), "gpu:navi21");
  EXPECT_EQ(doc.value("cost_unit", ""), "cycles");
  ASSERT_TRUE(doc.contains("candidates"));
  for (const auto& c : doc["candidates"]) {
    ASSERT_TRUE(navi21.count(c["method"])) << c.dump();
    EXPECT_EQ(c["cost"].get<double>(), navi21.at(c["method"])) << c.dump();
    EXPECT_EQ(c["cost_unit"], "cycles");
  }
  // pareto writes the same source into every row of its CSV.
  TempDir dir("cost-source-default");
  const auto r = run_sglab({"pareto", "--kappa", "1:100", "--out", dir.path.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("gpu:navi21"), std::string::npos) << r.output;
  std::ifstream csv(dir.path / "pareto.csv");
  std::string line;
  std::getline(csv, line);
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_NE(line.find(",cycles,gpu:navi21,"), std::string::npos) << line;
    const std::string method = line.substr(0, line.find(','));
    std::vector<std::string> fields;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    ASSERT_GE(fields.size(), 9u) << line;
    EXPECT_NEAR(std::stod(fields[5]), navi21.at(method), 5e-3 * navi21.at(method)) << line;
    EXPECT_TRUE(fields[8] == "8-light loop (split)" ||
                fields[8] == "8-light loop (kappa per light)")
        << line;
  }
  EXPECT_EQ(rows, std::size(sglab::irradiance_methods));
  // gpu-single:navi21: one unsplit call.
  const auto single = committed_navi21(/*single=*/true);
  const auto one_call = recommend_json({"--cost", "gpu-single:navi21"});
  EXPECT_EQ(one_call.value("cost_source", ""), "gpu-single:navi21");
  for (const auto& c : one_call["candidates"]) {
    EXPECT_EQ(c["cost"].get<double>(), single.at(c["method"])) << c.dump();
    EXPECT_EQ(c["cost_form"], "single call") << c.dump();
  }
}

// docs/costs.md names the driver that measured the committed GPU costs: the one the
// cost table records (it must follow the table when the table is regenerated).
TEST(CostSourceCli, CostsPageNamesTheDriverOfTheCommittedTable) {
  const fs::path root = fs::path(SGLAB_TEST_SOURCE_DIR) / "..";
  std::ifstream table(root / "data" / "results" / "costs.json"), readme(root / "docs" / "costs.md");
  std::stringstream t, r;
  t << table.rdbuf();
  r << readme.rdbuf();
  const std::string driver = nlohmann::json::parse(t.str()).at("gpu").at("driver");
  EXPECT_NE(r.str().find("table's `gpu.driver` is `" + driver + "`"), std::string::npos) << driver;
}

// The choice is the cheapest method meeting the budget by the table's cycles:
// no qualifying candidate costs less than the choice by more than the tie
// margin, and every candidate cheaper than that misses the budget.
TEST(CostSourceCli, ChoiceUnderGpuCostIsTheCheapestMeetingTheBudget) {
  const auto navi21 = committed_navi21();
  for (const char* budget : {"1e-2", "2e-3", "1e-4"}) {
    SCOPED_TRACE(budget);
    const auto r =
        run_sglab({"recommend", "--kappa", "1e-3:1e4", "--budget", budget, "--json"}, false);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto doc = nlohmann::json::parse(r.output);
    ASSERT_TRUE(doc["choice"].is_object()) << r.output;
    const double choice = navi21.at(doc["choice"]["method"]);
    const double margin = doc["tie_margin"].get<double>();
    for (const auto& c : doc["candidates"]) {
      const double cycles = navi21.at(c["method"]);
      const bool meets =
          c["max_peak_rel"].is_number() && c["max_peak_rel"].get<double>() <= std::stod(budget);
      EXPECT_EQ(c["qualifies"].get<bool>(), meets) << c.dump();
      if (meets) {
        EXPECT_GE(cycles * (1 + margin), choice) << c.dump();
      }
    }
  }
  // A hand-made table decides: the answer follows its cycles, not the CPU ns.
  TempDir dir("cost-source-hand");
  auto cycles = gpu_costs(100);
  cycles["tokuyoshi2024"] = 1;
  const fs::path a = write_table(dir, "a.json", table_json(5, cycles));
  EXPECT_EQ(recommend_json({"--costs", a.string()})["choice"].value("method", ""), "tokuyoshi2024");
  cycles["tokuyoshi2024"] = 1000;
  cycles["sglab_acc3"] = 2;
  const fs::path b = write_table(dir, "b.json", table_json(5, cycles));
  const auto doc = recommend_json({"--costs", b.string()});
  EXPECT_EQ(doc["choice"].value("method", ""), "sglab_acc3");
  EXPECT_EQ(doc["choice"]["cost"].get<double>(), 2.0);
  // A method without a GPU row is listed with no cost, never chosen.
  cycles.erase("sglab_acc3");
  const fs::path c = write_table(dir, "c.json", table_json(5, cycles));
  const auto r =
      run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2", "--costs", c.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no gpu:navi21 cost for method 'sglab_acc3'"), std::string::npos)
      << r.output;
  EXPECT_NE(recommend_json({"--costs", c.string()})["choice"].value("method", ""), "sglab_acc3");
}

}  // namespace
