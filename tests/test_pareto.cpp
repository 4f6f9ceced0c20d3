// Speed against accuracy: the Pareto frontier and the recommendation on
// synthetic points, and `sglab recommend` against `sglab sweep`. No timing
// assertions (costs are measured, hence noisy).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "common/args.hpp"
#include "report/pareto.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::report::MethodPoint;
using sglab::report::recommend;

using sglab::test::kInf;
using sglab::test::kNaN;

MethodPoint pt(std::string id, double ns, double err) {
  MethodPoint p;
  p.method = std::move(id);
  p.cost = ns;
  p.max_peak_rel = err;
  return p;
}

bool on_frontier(const std::vector<MethodPoint>& v, const std::string& id) {
  for (const auto& p : v)
    if (p.method == id) return p.frontier;
  ADD_FAILURE() << "no point " << id;
  return false;
}

// The origin of each point comes from the registry (Method::origin) and the
// table writes it as text: published, refit or sglab.
TEST(Pareto, OriginFromRegistryInTable) {
  const auto points = sglab::report::irradiance_errors(1, 10, sglab::io::Precision::float64);
  ASSERT_EQ(points.size(), std::size(sglab::irradiance_methods));
  bool published = false, refit = false;
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i].method, sglab::irradiance_methods[i].id);
    EXPECT_EQ(points[i].origin, sglab::irradiance_methods[i].origin) << points[i].method;
    published |= points[i].origin == sglab::Origin::published;
    refit |= points[i].origin == sglab::Origin::refit;
  }
  EXPECT_TRUE(published && refit);  // both kinds exist in the registry today
  const std::string csv = sglab::validate::to_csv(
      sglab::report::pareto_table(points, sglab::io::Precision::float64, 1, 10,
                                  sglab::cost::default_cost_source(sglab::io::Precision::float64)));
  for (const auto& m : sglab::irradiance_methods) {
    const std::string row = fmt::format("\n{},{},double,", m.id, sglab::to_string(m.origin));
    EXPECT_NE(csv.find(row), std::string::npos) << row << "\n" << csv;
  }
}

TEST(Frontier, SyntheticPoints) {
  std::vector<MethodPoint> v{
      pt("fast_bad", 1.0, 1e-1),    // cheapest finite: frontier
      pt("mid", 2.0, 1e-2),         // frontier
      pt("dominated", 3.0, 5e-2),   // mid is cheaper and more accurate
      pt("slow_good", 10.0, 1e-4),  // most accurate: frontier
      pt("nan_err", 0.5, kNaN),     // non-finite error: never, and dominates nothing
      pt("inf_err", 0.25, kInf),    // same
      pt("same_cost", 2.0, 2e-2),   // equal cost to mid, worse error: dominated
      pt("same_err", 12.0, 1e-4),   // equal error to slow_good, dearer: dominated
  };
  sglab::report::mark_frontier(v);
  EXPECT_TRUE(on_frontier(v, "fast_bad"));
  EXPECT_TRUE(on_frontier(v, "mid"));
  EXPECT_FALSE(on_frontier(v, "dominated"));
  EXPECT_TRUE(on_frontier(v, "slow_good"));
  EXPECT_FALSE(on_frontier(v, "nan_err"));
  EXPECT_FALSE(on_frontier(v, "inf_err"));
  EXPECT_FALSE(on_frontier(v, "same_cost"));
  EXPECT_FALSE(on_frontier(v, "same_err"));
}

// Two methods at the same cost and error: neither dominates the other (domination needs one
// strictly better coordinate), so both stay on the frontier; a third, worse in both, does not.
TEST(Frontier, EqualPointsAreBothOnIt) {
  std::vector<MethodPoint> v{pt("twin_a", 2.0, 1e-3), pt("twin_b", 2.0, 1e-3),
                             pt("worse", 2.5, 2e-3)};
  sglab::report::mark_frontier(v);
  EXPECT_TRUE(on_frontier(v, "twin_a"));
  EXPECT_TRUE(on_frontier(v, "twin_b"));
  EXPECT_FALSE(on_frontier(v, "worse"));
}

// A point outside its method's valid κ range is never on the frontier and dominates nothing.
TEST(Frontier, OutsideItsValidRangeNeverOnItNorDominating) {
  std::vector<MethodPoint> v{pt("outside", 1.0, 1e-4), pt("inside", 2.0, 1e-3)};
  v[0].in_valid_range = false;
  sglab::report::mark_frontier(v);
  EXPECT_FALSE(on_frontier(v, "outside"));
  EXPECT_TRUE(on_frontier(v, "inside"));
}

TEST(Frontier, AllNaNHasNoFrontier) {
  std::vector<MethodPoint> v{pt("a", 1, kNaN), pt("b", 2, kNaN)};
  sglab::report::mark_frontier(v);
  EXPECT_FALSE(v[0].frontier);
  EXPECT_FALSE(v[1].frontier);
}

TEST(Recommend, CheapestQualifyingAndRunnerUp) {
  const std::vector<MethodPoint> v{pt("cheap_bad", 1.0, 1e-1), pt("a", 3.0, 5e-4),
                                   pt("b", 2.0, 9e-4), pt("c", 5.0, 1e-5), pt("nan", 0.1, kNaN)};
  const auto r = recommend(v, 1e-3);
  ASSERT_TRUE(r.choice);
  EXPECT_EQ(r.choice->method, "b");
  ASSERT_TRUE(r.runner_up);
  EXPECT_EQ(r.runner_up->method, "a");
  ASSERT_TRUE(r.most_accurate);
  EXPECT_EQ(r.most_accurate->method, "c");
  ASSERT_EQ(r.ranked.size(), 3u);
  EXPECT_EQ(r.ranked[2].method, "c");
}

TEST(Recommend, BudgetIsInclusive) {
  const auto r = recommend({pt("x", 1.0, 1e-3), pt("y", 2.0, 1e-4)}, 1e-3);
  ASSERT_TRUE(r.choice);
  EXPECT_EQ(r.choice->method, "x");
}

// Of two methods equally accurate the cheaper is the most accurate one, in either order.
TEST(Recommend, MostAccurateTieGoesToTheCheaper) {
  for (const bool cheap_first : {true, false}) {
    std::vector<MethodPoint> v{pt("cheap", 1.0, 1e-4), pt("dear", 3.0, 1e-4),
                               pt("poor", 0.5, 1e-2)};
    if (!cheap_first) std::swap(v[0], v[1]);
    const auto r = recommend(v, 1e-1);
    ASSERT_TRUE(r.most_accurate);
    EXPECT_EQ(r.most_accurate->method, "cheap") << (cheap_first ? "cheap first" : "dear first");
  }
}

TEST(Recommend, TiesWithinMarginBrokenByError) {
  // b is 3% dearer than a but more accurate: a tie, b wins; c is 20% dearer.
  const std::vector<MethodPoint> v{pt("a", 1.00, 8e-4), pt("b", 1.03, 1e-4), pt("c", 1.2, 1e-6)};
  const auto r = recommend(v, 1e-3);
  ASSERT_TRUE(r.choice);
  EXPECT_EQ(r.choice->method, "b");
  ASSERT_TRUE(r.runner_up);
  EXPECT_EQ(r.runner_up->method, "a");
}

TEST(Recommend, NoneQualifiesNamesMostAccurate) {
  const std::vector<MethodPoint> v{pt("a", 1.0, 1e-1), pt("b", 2.0, 1e-2), pt("c", 0.5, kNaN),
                                   pt("d", 0.2, kInf)};
  const auto r = recommend(v, 1e-3);
  EXPECT_FALSE(r.choice);
  EXPECT_FALSE(r.runner_up);
  ASSERT_TRUE(r.most_accurate);
  EXPECT_EQ(r.most_accurate->method, "b");
}

// Outside its valid κ range a method is neither chosen nor the most accurate, however cheap
// and accurate its measured error looks.
TEST(Recommend, OutsideItsValidRangeIsNotConsidered) {
  std::vector<MethodPoint> v{pt("outside", 1.0, 1e-5), pt("a", 2.0, 5e-4), pt("b", 3.0, 1e-2)};
  v[0].in_valid_range = false;
  auto r = recommend(v, 1e-3);
  ASSERT_TRUE(r.choice);
  EXPECT_EQ(r.choice->method, "a");
  EXPECT_FALSE(r.runner_up);
  ASSERT_TRUE(r.most_accurate);
  EXPECT_EQ(r.most_accurate->method, "a");
  ASSERT_EQ(r.ranked.size(), 1u);
  v[0].in_valid_range = true;  // the same point in range is the choice
  r = recommend(v, 1e-3);
  ASSERT_TRUE(r.choice);
  EXPECT_EQ(r.choice->method, "outside");
}

// mark_valid_range reads each method's registry card: [LO, HI] must lie in its range,
// compared as floats; an id the registry does not have is outside.
TEST(Recommend, ValidRangeFromTheRegistryCard) {
  std::vector<MethodPoint> v;
  for (const auto& m : sglab::irradiance_methods) v.push_back(pt(std::string(m.id), 1.0, 1e-3));
  v.push_back(pt("no_such_method", 1.0, 1e-3));
  const std::pair<double, double> ranges[] = {
      {1e-3, 1e4}, {1, 2e4}, {1e-4, 1}, {0, 1e30}, {1e-45, 1e-40}, {1e10, 3.4028234663852886e38}};
  for (const auto& [lo, hi] : ranges) {
    sglab::report::mark_valid_range(v, lo, hi);
    for (std::size_t i = 0; i < std::size(sglab::irradiance_methods); ++i)
      EXPECT_EQ(v[i].in_valid_range, sglab::irradiance_methods[i].valid.covers(lo, hi))
          << v[i].method << " [" << lo << ", " << hi << "]";
    EXPECT_FALSE(v.back().in_valid_range);
  }
  // The fitted range lies in every card (1e-3 compared as the float 1e-3f), and the cards that
  // end short say so.
  sglab::report::mark_valid_range(v, 1e-3, 1e4);
  for (std::size_t i = 0; i < std::size(sglab::irradiance_methods); ++i)
    EXPECT_TRUE(v[i].in_valid_range) << v[i].method;
  sglab::report::mark_valid_range(v, 1, 2e4);
  const auto* fast = sglab::find_method(sglab::irradiance_methods, "sglab_fast");
  EXPECT_FALSE(v[static_cast<std::size_t>(fast - sglab::irradiance_methods.data())].in_valid_range);
  EXPECT_TRUE(sglab::report::outside_valid_range_text(v).find(
                  "sglab_fast (valid for κ in [0, 1.1e+04])") != std::string::npos)
      << sglab::report::outside_valid_range_text(v);
}

TEST(Recommend, ParseKappaRange) {
  // The shared parser (common/args.hpp; tests/test_args.cpp has the rules).
  using sglab::io::KappaRange;
  const sglab::io::KappaRangeRules rules;  // LO:HI, used in float
  const auto ok = sglab::io::parse_kappa_range("1e-3:1e4", rules);
  ASSERT_TRUE(std::holds_alternative<KappaRange>(ok));
  EXPECT_EQ(std::get<KappaRange>(ok).lo, 1e-3);
  EXPECT_EQ(std::get<KappaRange>(ok).hi, 1e4);
  for (const char* bad : {"0:1", "2:1", "a:1", "1:2:3", "1"})
    EXPECT_TRUE(std::holds_alternative<std::string>(sglab::io::parse_kappa_range(bad, rules)))
        << bad;
}

// ---- CLI -------------------------------------------------------------------

// stdout only (stderr discarded), so JSON can be parsed.
struct Output {
  int exit_code;
  std::string out;
};
Output run_stdout(const std::string& args) {
  const auto r = sglab::test::run_sglab(sglab::test::words(args), false);
  return {r.exit_code, r.output};
}

double sweep_max_peak_rel(const std::string& kappa, const std::string& method,
                          const std::string& precision) {
  const sglab::test::TempDir dir("pareto-sweep");
  const Output s =
      run_stdout(fmt::format("sweep --kappa {}:29 --cosines 41 --json --method {} --out {}", kappa,
                             method, dir.path.string()));
  EXPECT_EQ(s.exit_code, 0) << s.out;
  const auto doc = nlohmann::json::parse(s.out);
  for (const auto& row : doc.at("results"))
    if (row.at("method") == method && row.at("precision") == precision &&
        row.at("quantity") == "irradiance")
      return row.at("max_peak_rel").get<double>();
  ADD_FAILURE() << "sweep has no row for " << method << " " << precision;
  return kNaN;
}

void check_recommend(const std::string& kappa, double budget) {
  SCOPED_TRACE(fmt::format("--kappa {} --budget {}", kappa, budget));
  const Output r =
      run_stdout(fmt::format("recommend --kappa {} --budget {} --json", kappa, budget));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc.at("precision"), "float");
  EXPECT_EQ(doc.at("budget").get<double>(), budget);
  ASSERT_TRUE(doc.at("most_accurate").is_object());
  const auto& choice = doc.at("choice");
  const auto& candidates = doc.at("candidates");
  ASSERT_FALSE(candidates.empty());
  if (choice.is_null()) {
    // Then nothing qualifies, and the most accurate misses the budget.
    for (const auto& c : candidates) EXPECT_FALSE(c.at("qualifies").get<bool>()) << c.dump();
    const auto& best = doc.at("most_accurate");
    const double best_err = best.at("max_peak_rel").get<double>();
    EXPECT_GT(best_err, budget);
    const double swept = sweep_max_peak_rel(kappa, best.at("method"), "float");
    EXPECT_LE(std::abs(best_err - swept), 1e-12 * std::abs(swept))
        << best.dump() << " sweep " << swept;
    for (const auto& c : candidates)
      if (c.at("max_peak_rel").is_number()) {
        EXPECT_GE(c.at("max_peak_rel").get<double>(), best_err) << c.dump();
      }
    return;
  }
  const std::string method = choice.at("method");
  const double err = choice.at("max_peak_rel").get<double>();
  const double ns = choice.at("cost").get<double>();
  EXPECT_LE(err, budget);
  const double swept = sweep_max_peak_rel(kappa, method, "float");
  EXPECT_LE(std::abs(err - swept), 1e-12 * std::abs(swept))
      << method << ": recommend " << err << " sweep " << swept;
  const double margin = doc.at("tie_margin").get<double>();
  for (const auto& c : candidates) {
    if (!c.at("qualifies").get<bool>()) {
      if (c.at("max_peak_rel").is_number() && c.at("in_valid_range").get<bool>()) {
        EXPECT_GT(c.at("max_peak_rel").get<double>(), budget) << c.dump();
      }
      continue;
    }
    EXPECT_TRUE(c.at("in_valid_range").get<bool>()) << c.dump();
    // No qualifying method is cheaper than the choice by more than the tie margin.
    EXPECT_GE(c.at("cost").get<double>() * (1 + margin) * (1 + 1e-12), ns) << c.dump();
  }
  if (!doc.at("runner_up").is_null()) {
    EXPECT_NE(doc.at("runner_up").at("method"), method);
    EXPECT_LE(doc.at("runner_up").at("max_peak_rel").get<double>(), budget);
  }
}

TEST(RecommendCli, Kappa1To100Budget1e3) { check_recommend("1:100", 1e-3); }
TEST(RecommendCli, StandardRangeBudget2e3) { check_recommend("1e-3:1e4", 2e-3); }

// Down to the smallest float subnormal (1e−45 rounds to 2^−149): every model
// of origin sglab or refit has a finite error (sglab_acc2/3 were NaN there).
TEST(RecommendCli, SubnormalRangeGivesEverySglabModelAnError) {
  const Output r = run_stdout("recommend --kappa 1e-45:1 --budget 1e-2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto doc = nlohmann::json::parse(r.out);
  std::size_t own = 0;
  for (const auto& c : doc.at("candidates"))
    if (c.at("origin") != "published") {
      ++own;
      EXPECT_TRUE(c.at("max_peak_rel").is_number()) << c.dump();
    }
  EXPECT_GE(own, 4u);
}

// Above sglab_fast's valid range (κ ≤ 1.1e4 on its card; sglab_lite's, 1e4, alike) it is
// listed, flagged and not considered, in JSON and in text; within the range it is considered.
TEST(RecommendCli, FlagsMethodsOutsideTheirValidRange) {
  const Output r = run_stdout("recommend --kappa 1e3:1e5 --budget 1e-2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto doc = nlohmann::json::parse(r.out);
  bool seen = false;
  for (const auto& c : doc.at("candidates")) {
    const auto* m =
        sglab::find_method(sglab::irradiance_methods, c.at("method").get<std::string>());
    ASSERT_NE(m, nullptr) << c.dump();
    EXPECT_EQ(c.at("in_valid_range").get<bool>(), m->valid.covers(1e3, 1e5)) << c.dump();
    EXPECT_EQ(c.at("valid_kappa")[1].get<double>(), double(m->valid.kappa_hi)) << c.dump();
    if (c.at("method") == "sglab_fast") {
      seen = true;
      EXPECT_FALSE(c.at("in_valid_range").get<bool>());
      EXPECT_FALSE(c.at("qualifies").get<bool>());
      EXPECT_LE(c.at("max_peak_rel").get<double>(), 1e-2);  // it would meet the budget
    }
  }
  EXPECT_TRUE(seen);
  EXPECT_NE(doc.at("choice").at("method"), "sglab_fast");
  EXPECT_EQ(doc.at("outside_valid_range"), nlohmann::json::array({"sglab_fast", "sglab_lite"}));
  const auto text = sglab::test::run_sglab({"recommend", "--kappa", "1e3:1e5", "--budget", "1e-2"});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("not considered: outside their valid κ range"), std::string::npos)
      << text.output;
  EXPECT_NE(text.output.find("sglab_fast (valid for κ in [0, 1.1e+04])"), std::string::npos)
      << text.output;
  const Output inside = run_stdout("recommend --kappa 1e3:1e4 --budget 1e-2 --json");
  ASSERT_EQ(inside.exit_code, 0) << inside.out;
  EXPECT_TRUE(nlohmann::json::parse(inside.out).at("outside_valid_range").empty()) << inside.out;
}

TEST(RecommendCli, NoneQualifyingExitsZero) {
  const Output r = run_stdout("recommend --kappa 1:100 --budget 1e-300 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_TRUE(doc.at("choice").is_null());
  EXPECT_TRUE(doc.at("runner_up").is_null());
  EXPECT_TRUE(doc.at("most_accurate").is_object());
}

TEST(RecommendCli, BadOptionsExit2) {
  for (const char* args :
       {"--kappa 0:10 --budget 1e-3", "--kappa 10:1 --budget 1e-3", "--kappa a:b --budget 1e-3",
        "--kappa 1 --budget 1e-3", "--kappa 1:10 --budget 0", "--kappa 1:10 --budget -1",
        "--kappa 1:10 --budget abc", "--kappa 1:10 --budget 1e-3 --precision half"}) {
    auto argv = sglab::test::words(args);
    argv.insert(argv.begin(), "recommend");
    const auto r = sglab::test::run_sglab(argv);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  }
  const auto r = sglab::test::run_sglab({"recommend", "--kappa", "1:10", "--budget", "abc"});
  EXPECT_NE(r.output.find("--budget"), std::string::npos) << r.output;
  const auto k = sglab::test::run_sglab({"recommend", "--kappa", "0:10", "--budget", "1"});
  EXPECT_NE(k.output.find("--kappa"), std::string::npos) << k.output;
}

TEST(ParetoCli, WritesCsvWithExactHeader) {
  const sglab::test::TempDir tmp("pareto");
  const std::string dir = tmp.path.string();
  const auto r = sglab::test::run_sglab({"pareto", "--kappa", "1:100", "--out", dir});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  FILE* f = std::fopen((std::filesystem::path(dir) / "pareto.csv").c_str(), "r");
  ASSERT_TRUE(f);
  char line[512] = {};
  ASSERT_TRUE(std::fgets(line, sizeof line, f));
  std::fclose(f);
  EXPECT_EQ(std::string(line),
            "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,cost_form,"
            "max_peak_rel,frontier,in_valid_range\n");
  // The column as read back, and a method flagged above its valid range.
  for (const auto& row : sglab::report::read_pareto_csv(std::filesystem::path(dir) / "pareto.csv"))
    EXPECT_TRUE(row.in_valid_range) << row.method;
  ASSERT_EQ(sglab::test::run_sglab({"pareto", "--kappa", "1e3:1e5", "--out", dir}).exit_code, 0);
  for (const auto& row :
       sglab::report::read_pareto_csv(std::filesystem::path(dir) / "pareto.csv")) {
    EXPECT_EQ(row.in_valid_range, row.method != "sglab_fast" && row.method != "sglab_lite")
        << row.method;
    if (!row.in_valid_range) {
      EXPECT_FALSE(row.frontier) << row.method;
    }
  }
  EXPECT_EQ(sglab::test::run_sglab({"pareto", "--kappa", "0:1", "--out", dir}).exit_code, 2);
}

}  // namespace
