// Command-line conventions of `sglab`: --version, a clear message for an
// unknown subcommand, documented exit codes (0 success, 1 failure, 2 bad
// input, CLI11's parse errors included).
#include <string>

#include <gtest/gtest.h>

#include <sglab/version.hpp>

#include "tests/test_support.hpp"

namespace {

using sglab::test::run_sglab;

TEST(Cli, VersionPrintsTheVersion) {
  const auto r = run_sglab({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, std::string("sglab ") + SGLAB_VERSION + "\n");
}

TEST(Cli, UnknownSubcommandIsNamed) {
  auto r = run_sglab({"swep"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown subcommand 'swep'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did you mean 'sweep'?"), std::string::npos) << r.output;
  r = run_sglab({"x"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown subcommand 'x'"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("did you mean"), std::string::npos) << r.output;
}

TEST(Cli, CommandLineErrorsExitWithTwo) {
  for (const std::vector<std::string>& args : {std::vector<std::string>{},
                                               {"sweep", "--no-such-option"},
                                               {"recommend", "--kappa", "1:2"},
                                               {"fit"},
                                               {"table", "--kappa"}}) {
    const auto r = run_sglab(args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_EQ(r.exit_code, 2) << joined << "\n" << r.output;
  }
}

TEST(Cli, HelpDocumentsTheExitCodes) {
  const auto r = run_sglab({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Exit codes: 0 success; 1 failure"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2 bad input"), std::string::npos) << r.output;
}

}  // namespace
