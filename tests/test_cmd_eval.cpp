// `sglab eval` (app/cmd_eval.cpp): one row per point in the requested
// precision, each the registry function's value to the last digit, streamed;
// bad input named with its line and exit code 2.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include <sglab/sglab.hpp>

#include "tests/test_support.hpp"

namespace {

using sglab::test::run_sglab;

using sglab::test::method;

// Writes `text` to dir/name and returns the path.
std::filesystem::path temp_file(const sglab::test::TempDir& dir, const std::string& name,
                                const std::string& text) {
  const auto path = dir.path / name;
  std::ofstream(path) << text;
  return path;
}

TEST(EvalCommand, PrintsEveryRowInBothPrecisions) {
  const sglab::test::TempDir dir("eval-rows");
  const auto points = temp_file(dir, "points.csv", "kappa,cosine\n4,0.25\n0.001,-1\n10000, 1\n");
  const auto d = run_sglab(
      {"eval", "--method", "sglab_acc2", "--points", points.string(), "--precision", "double"},
      false);
  ASSERT_EQ(d.exit_code, 0) << d.output;
  std::istringstream lines(d.output);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "kappa,cosine,value");
  const sglab::Method& m = method("sglab_acc2");
  const double kappas[] = {4, 0.001, 10000}, cosines[] = {0.25, -1, 1};
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    double k, c, v;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &k, &c, &v), 3) << line;
    EXPECT_EQ(k, kappas[i]);
    EXPECT_EQ(c, cosines[i]);
    EXPECT_EQ(v, m.f64(cosines[i], kappas[i])) << line;  // %.17g round-trips
  }
  const auto f =
      run_sglab({"eval", "--method", "tokuyoshi2024", "--points", points.string()}, false);
  ASSERT_EQ(f.exit_code, 0) << f.output;
  std::istringstream flines(f.output);
  std::getline(flines, line);
  const sglab::Method& t = method("tokuyoshi2024");
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::getline(flines, line));
    double k, c, v;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &k, &c, &v), 3) << line;
    EXPECT_EQ(float(v), t.f32(float(cosines[i]), float(kappas[i])))
        << line;  // %.9g round-trips a float
  }
}

TEST(EvalCommand, RejectsBadInputWithExitCode2) {
  const sglab::test::TempDir dir("eval-bad");
  const auto good = temp_file(dir, "good.csv", "kappa,cosine\n1,0\n");
  const auto negative = temp_file(dir, "negative.csv", "kappa,cosine\n1,0\n-2,0.5\n");
  const auto malformed = temp_file(dir, "malformed.csv", "kappa,cosine\n1,zero\n");
  auto r = run_sglab({"eval", "--method", "no_such_method", "--points", good.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown irradiance method 'no_such_method'"), std::string::npos)
      << r.output;
  r = run_sglab({"eval", "--method", "sglab_acc2", "--points", negative.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(":3: kappa must be finite and >= 0"), std::string::npos) << r.output;
  // Streamed: the row before the bad one was printed (docs/cli.md, `sglab eval`).
  EXPECT_EQ(r.output.find("kappa,cosine,value\n1,0,"), 0u) << r.output;
  r = run_sglab({"eval", "--method", "sglab_acc2", "--points", malformed.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cosine is not a number"), std::string::npos) << r.output;
  r = run_sglab(
      {"eval", "--method", "sglab_acc2", "--points", good.string(), "--precision", "half"});
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
