// The cost table: `sglab bench` writes it, `sglab pareto` and `sglab recommend`
// read it and so answer the same on every run; a hand-made table changes the
// answer as it must; a missing or malformed table is refused (exit 2, file
// named). No timing assertions.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <sglab/registry.hpp>

#include "cost/cost_table.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::test::run_sglab;

using sglab::test::write_file;

// A well-formed table with a float batch cost for every irradiance method.
nlohmann::ordered_json hand_table(const std::map<std::string, double>& costs) {
  nlohmann::ordered_json doc;
  doc["format"] = "sglab-costs";
  doc["version"] = 1;
  doc["date"] = "2026-01-01T00:00:00Z";
  doc["command"] = "hand-made for test_costs";
  doc["machine"] = {{"cpu", "test"}, {"cores", 1}};
  doc["compiler"] = {{"id", "none"}, {"version", "0"}};
  doc["build_type"] = "none";
  doc["timer"] = "none";
  doc["inputs"] = "none";
  auto rows = nlohmann::ordered_json::array();
  for (const auto& [method, ns] : costs)
    rows.push_back({{"kind", "irradiance"},
                    {"method", method},
                    {"precision", "float"},
                    {"mode", "batch"},
                    {"ns_per_eval", ns}});
  doc["costs"] = rows;
  return doc;
}

std::map<std::string, double> all_methods_cost(double ns) {
  std::map<std::string, double> m;
  double step = 0;
  for (const sglab::Method& method : sglab::irradiance_methods)
    m[std::string(method.id)] = ns + (step += 10);
  return m;
}

nlohmann::json recommend_json(const fs::path& table, const std::string& kappa,
                              const std::string& budget) {
  const auto r = run_sglab({"recommend", "--kappa", kappa, "--budget", budget, "--json", "--costs",
                            table.string(), "--cost", "cpu-batch"},
                           /*merge_stderr=*/false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

// The cheapest qualifying method by the given costs (all > 5% apart, so no ties).
std::string cheapest_qualifying(const nlohmann::json& doc,
                                const std::map<std::string, double>& costs) {
  std::string best;
  double best_ns = std::numeric_limits<double>::infinity();
  for (const auto& c : doc.at("candidates")) {
    if (!c.at("qualifies").get<bool>()) continue;
    const double ns = costs.at(c.at("method").get<std::string>());
    if (ns < best_ns) {
      best_ns = ns;
      best = c.at("method");
    }
  }
  return best;
}

TEST(CostTable, HandMadeTableDecidesTheRecommendation) {
  const sglab::test::TempDir tmp("test_costs hand");
  const fs::path& dir = tmp.path;
  auto costs = all_methods_cost(100);
  costs["tokuyoshi2024"] = 1;
  write_file(dir / "a.json", hand_table(costs).dump(2));
  const auto a = recommend_json(dir / "a.json", "1:100", "1e-2");
  ASSERT_EQ(cheapest_qualifying(a, costs), "tokuyoshi2024");
  EXPECT_EQ(a.at("choice").at("method"), "tokuyoshi2024");
  EXPECT_EQ(a.at("choice").at("cost").get<double>(), 1.0);
  EXPECT_EQ(a.at("choice").at("cost_unit"), "ns");
  EXPECT_EQ(a.at("cost_source"), "cpu-batch");

  // Now the refit is the cheapest: the answer follows the table.
  costs["tokuyoshi2024"] = 50;
  costs["tokuyoshi2024_refit"] = 2;
  write_file(dir / "b.json", hand_table(costs).dump(2));
  const auto b = recommend_json(dir / "b.json", "1:100", "1e-2");
  ASSERT_EQ(cheapest_qualifying(b, costs), "tokuyoshi2024_refit");
  EXPECT_EQ(b.at("choice").at("method"), "tokuyoshi2024_refit");
  EXPECT_EQ(b.at("choice").at("cost").get<double>(), 2.0);
  EXPECT_NE(b.at("cost_from").get<std::string>().find("b.json"), std::string::npos);
}

TEST(CostTable, MissingMethodIsNamedAndLeftOut) {
  const sglab::test::TempDir tmp("test_costs missing");
  const fs::path& dir = tmp.path;
  auto costs = all_methods_cost(10);
  costs.erase("tokuyoshi2024");
  write_file(dir / "t.json", hand_table(costs).dump(2));
  const auto r = run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2", "--json",
                            "--costs", (dir / "t.json").string(), "--cost", "cpu-batch"},
                           /*merge_stderr=*/true);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no cpu-batch cost for method 'tokuyoshi2024' (float)"),
            std::string::npos)
      << r.output;
  const auto j = recommend_json(dir / "t.json", "1:100", "1e-2");
  for (const auto& c : j.at("candidates"))
    if (c.at("method") == "tokuyoshi2024") {
      EXPECT_TRUE(c.at("cost").is_null());
      EXPECT_FALSE(c.at("qualifies").get<bool>());
    }
  EXPECT_NE(j.at("choice").at("method"), "tokuyoshi2024");
}

TEST(CostTable, RecommendAndParetoAnswerTheSameTwice) {
  // The project's committed table (found from the working directory).
  const auto r1 = run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2"}, false);
  const auto r2 = run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2"}, false);
  ASSERT_EQ(r1.exit_code, 0) << r1.output;
  EXPECT_EQ(r1.output, r2.output);
  EXPECT_NE(r1.output.find("costs.json"), std::string::npos) << r1.output;
  const sglab::test::TempDir ta("test_costs pareto_a"), tb("test_costs pareto_b");
  const fs::path &a = ta.path, &b = tb.path;
  const auto p1 = run_sglab({"pareto", "--kappa", "1e-3:1e4", "--out", a.string()}, false);
  const auto p2 = run_sglab({"pareto", "--kappa", "1e-3:1e4", "--out", b.string()}, false);
  ASSERT_EQ(p1.exit_code, 0) << p1.output;
  ASSERT_EQ(p2.exit_code, 0) << p2.output;
  std::ifstream fa(a / "pareto.csv"), fb(b / "pareto.csv");
  const std::string ca((std::istreambuf_iterator<char>(fa)), {}),
      cb((std::istreambuf_iterator<char>(fb)), {});
  EXPECT_FALSE(ca.empty());
  EXPECT_EQ(ca, cb);
}

TEST(CostTable, MissingOrMalformedTableExits2NamingTheFile) {
  const sglab::test::TempDir tmp("test_costs bad");
  const fs::path& dir = tmp.path;
  const std::map<std::string, std::string> bad = {
      {"not_json.json", "{ this is not json"},
      {"no_costs.json",
       [] {
         auto d = hand_table(all_methods_cost(1));
         d.erase("costs");
         return d.dump();
       }()},
      {"negative.json",
       [] {
         auto d = hand_table(all_methods_cost(1));
         d["costs"][0]["ns_per_eval"] = -3.0;
         return d.dump();
       }()},
      {"bad_mode.json",
       [] {
         auto d = hand_table(all_methods_cost(1));
         d["costs"][0]["mode"] = "warp";
         return d.dump();
       }()},
      {"wrong_format.json", R"({"format": "something-else", "version": 1})"},
      {"array.json", "[1, 2, 3]"},
  };
  for (const auto& [name, text] : bad) {
    write_file(dir / name, text);
    for (const char* cmd : {"recommend", "pareto"}) {
      std::vector<std::string> args{cmd, "--kappa", "1:100", "--costs", (dir / name).string()};
      if (std::string(cmd) == "recommend")
        args.insert(args.end(), {"--budget", "1e-2"});
      else
        args.insert(args.end(), {"--out", (dir / "out").string()});
      const auto r = run_sglab(args);
      EXPECT_EQ(r.exit_code, 2) << name << " " << cmd << "\n" << r.output;
      EXPECT_NE(r.output.find(name), std::string::npos) << name << "\n" << r.output;
    }
  }
  const auto none = run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2", "--costs",
                               (dir / "does_not_exist.json").string()});
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("does_not_exist.json"), std::string::npos) << none.output;
  // Both sources at once is refused.
  const auto both = run_sglab({"recommend", "--kappa", "1:100", "--budget", "1e-2", "--live-timing",
                               "--costs", (dir / "not_json.json").string()});
  EXPECT_EQ(both.exit_code, 2) << both.output;
  // read_cost_table names the key.
  try {
    sglab::cost::read_cost_table(dir / "negative.json");
    ADD_FAILURE() << "no error";
  } catch (const sglab::cost::CostTableError& e) {
    EXPECT_NE(std::string(e.what()).find("costs[0].\"ns_per_eval\""), std::string::npos)
        << e.what();
  }
}

// The table compiled into sglab is the committed one, byte for byte as read:
// a build after the file changed compiles in the new one.
TEST(CostTable, TheCompiledInTableIsTheCommittedOne) {
  const fs::path committed = sglab::test::checkout_dir() / "data" / "results" / "costs.json";
  const auto builtin = sglab::cost::builtin_cost_table();
  EXPECT_EQ(builtin.path.string(), sglab::cost::kBuiltinCostTableName);
  EXPECT_EQ(sglab::cost::to_json(builtin).dump(),
            sglab::cost::to_json(sglab::cost::read_cost_table(committed)).dump());
}

// Outside a checkout (no --costs, no project above the working folder),
// `recommend`, `pareto` and `envmap recommend` use the compiled-in table and
// name it; a checkout's own table still comes first (test_cost_source).
TEST(CostTable, OutsideACheckoutTheCompiledInTableIsUsedAndNamed) {
  const sglab::test::TempDir tmp("costs-outside");
  const fs::path cwd = fs::current_path();
  fs::current_path(tmp.path);
  const std::string map =
      (sglab::test::checkout_dir() / "data" / "envmaps" / "city.exr").lexically_normal().string();
  const std::vector<std::vector<std::string>> runs = {
      {"recommend", "--kappa", "1:100", "--budget", "1e-2"},
      {"pareto", "--out", (tmp.path / "pareto").string()},
      {"envmap", "recommend", map, "--budget", "0.1", "--max-lobes", "1", "--normals", "50"}};
  for (const auto& args : runs) {
    const auto r = run_sglab(args);
    EXPECT_EQ(r.exit_code, 0) << args[0] << ": " << r.output;
    EXPECT_NE(r.output.find(std::string("from cost table ") +
                            std::string(sglab::cost::kBuiltinCostTableName)),
              std::string::npos)
        << args[0] << ": " << r.output;
  }
  fs::current_path(cwd);
}

TEST(CostTable, BenchWritesATableThatReadsBack) {
  const sglab::test::TempDir tmp("test_costs bench");
  const fs::path& dir = tmp.path;
  const auto r = run_sglab({"bench", "--filter", "^irradiance/(hill|tokuyoshi2024)/float/",
                            "--repetitions", "1", "--min-time", "0.01", "--out", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto t = sglab::cost::read_cost_table(dir / "costs.json");
  using sglab::cost::CostKind;
  using sglab::cost::CostMode;
  for (CostMode mode : {CostMode::scalar, CostMode::batch}) {
    EXPECT_TRUE(t.find(CostKind::irradiance, "hill", sglab::io::Precision::float32, mode));
    EXPECT_TRUE(t.find(CostKind::irradiance, "tokuyoshi2024", sglab::io::Precision::float32, mode));
  }
  // The per-light split is measured for tokuyoshi2024, not for hill (which has none).
  EXPECT_TRUE(t.find(CostKind::irradiance, "tokuyoshi2024", sglab::io::Precision::float32,
                     CostMode::light_setup));
  EXPECT_TRUE(t.find(CostKind::irradiance, "tokuyoshi2024", sglab::io::Precision::float32,
                     CostMode::light_eval));
  EXPECT_FALSE(
      t.find(CostKind::irradiance, "hill", sglab::io::Precision::float32, CostMode::light_setup));
  EXPECT_FALSE(
      t.find(CostKind::irradiance, "hill", sglab::io::Precision::float64, CostMode::batch));
  EXPECT_NE(t.info.inputs.find("1048576 inputs"), std::string::npos) << t.info.inputs;
  EXPECT_NE(t.info.inputs.find("log-uniform"), std::string::npos) << t.info.inputs;
  EXPECT_NE(t.info.command.find("--filter"), std::string::npos) << t.info.command;
  EXPECT_GT(t.info.cores, 0u);
  EXPECT_FALSE(t.info.compiler_version.empty());
  EXPECT_TRUE(fs::exists(dir / "bench_summary.csv"));
  // The output states the distribution.
  EXPECT_NE(r.output.find("log-uniform"), std::string::npos);
}

TEST(CostTable, LiveTimingStillAvailable) {
  const sglab::test::TempDir tmp("test_costs live");
  const fs::path& dir = tmp.path;
  const auto r = run_sglab({"pareto", "--kappa", "1:100", "--live-timing", "--out", dir.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("live timing"), std::string::npos) << r.output;
}

}  // namespace
