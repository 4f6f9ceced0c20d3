// `sglab fit` writes only where asked: a fit into --out DIR never touches the
// checkout (the header goes into DIR, holding the project's sets with DIR's in
// their place); sets and header are written all or nothing; an option that
// does not apply to the target is refused; --dry-run says nothing was written.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/io.hpp"
#include "fit/constants_io.hpp"
#include "fit/targets.hpp"
#include "tests/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using sglab::test::run_sglab;

using sglab::test::kRoot;

using sglab::test::TempDir;

// Inside the checkout (wherever the build folder is), so that the project is found.
struct InCheckout {
  fs::path old = fs::current_path();
  InCheckout() { fs::current_path(kRoot); }
  ~InCheckout() { fs::current_path(old); }
};

// lambda-d sphere-ls is a one-parameter least-squares fit: instant.
const std::vector<std::string> kQuickFit = {"fit", "lambda-d", "--objective", "sphere-ls"};
std::vector<std::string> quick_fit(std::vector<std::string> more) {
  std::vector<std::string> args = kQuickFit;
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(FitCli, FitIntoAFolderNeverTouchesTheCheckout) {
  InCheckout cwd;
  TempDir tmp("fit_out");
  const std::string header_before = sglab::io::read_file(sglab::test::kConstantsHeader);
  const fs::path out = tmp.path / "mine";
  const auto r = run_sglab(quick_fit({"--out", out.string(), "--force"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(sglab::io::read_file(sglab::test::kConstantsHeader), header_before)
      << "the checkout's header changed";
  ASSERT_TRUE(fs::exists(out / "constants.hpp")) << r.output;
  ASSERT_TRUE(fs::exists(out / "lambda-d-diffuse-lobe-sphere-ls.json")) << r.output;
  EXPECT_NE(r.output.find("regenerated " + (out / "constants.hpp").string()), std::string::npos)
      << r.output;
  // The header is the checkout's sets with the new one in its place: exactly
  // what rendering that collection gives, and it holds every required set.
  std::vector<sglab::fit::ordered_json> sets;
  for (auto& f : sglab::fit::load_constant_set_files(kRoot / "data" / "constants"))
    sets.push_back(f.file.filename() == "lambda-d-diffuse-lobe-sphere-ls.json"
                       ? sglab::fit::load_constant_set(out / "lambda-d-diffuse-lobe-sphere-ls.json")
                       : f.set);
  const std::string header = sglab::io::read_file(out / "constants.hpp");
  EXPECT_EQ(header, sglab::fit::render_constants_header(sets));
  for (const auto& req : sglab::fit::required_sets())
    EXPECT_NE(header.find(fmt::format(" {}{{", req.cpp_name)), std::string::npos) << req.cpp_name;
}

TEST(FitCli, SetsAndHeaderAreOneUnit) {
  InCheckout cwd;
  TempDir tmp("fit_unit");
  const fs::path out = tmp.path / "sets";
  fs::create_directories(out);
  const fs::path json = out / "lambda-d-diffuse-lobe-sphere-ls.json";
  fs::copy_file(kRoot / "data" / "constants" / "lambda-d-diffuse-lobe-sphere-ls.json", json);
  const std::string before = sglab::io::read_file(json);
  // The header cannot be written (a directory is in its place): the set is not replaced either.
  const fs::path blocked = tmp.path / "header.hpp";
  fs::create_directories(blocked);
  auto r = run_sglab(quick_fit({"--out", out.string(), "--header", blocked.string(), "--force"}));
  EXPECT_EQ(r.exit_code, 2) << r.output;  // an output that is not a regular file is bad input
  EXPECT_NE(r.output.find(blocked.string() + ": is a directory, not a regular file"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(sglab::io::read_file(json), before);
  // An invalid set already in --out (tagged as a constant set): refused before anything is written.
  std::ofstream(out / "zz-bad.json")
      << "{\"format\": \"sglab-constants\", \"version\": 1, \"target\": 1}";
  const fs::path header = tmp.path / "h.hpp";
  r = run_sglab(quick_fit({"--out", out.string(), "--header", header.string(), "--force"}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nothing was written"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("zz-bad.json"), std::string::npos) << r.output;
  EXPECT_EQ(sglab::io::read_file(json), before);
  EXPECT_FALSE(fs::exists(header));
}

// Without --force a set in --out is kept when it scores better than the new
// fit, but only against a set of the same form and objective: one fitted for
// another objective (or form) is replaced, and the report says so.
TEST(FitCli, ABetterSetIsKeptOnlyForTheSameObjective) {
  InCheckout cwd;
  TempDir tmp("fit_keep");
  const fs::path out = tmp.path / "sets";
  fs::create_directories(out);
  const fs::path json = out / "lambda-d-diffuse-lobe-sphere-ls.json";
  auto set = sglab::fit::load_constant_set(kRoot / "data" / "constants" /
                                           "lambda-d-diffuse-lobe-sphere-ls.json");
  set["provenance"]["achieved"]["objective"] = 1e-300;  // better than any fit
  std::ofstream(json) << set.dump(2);
  const std::string better = sglab::io::read_file(json);
  auto r = run_sglab(quick_fit({"--out", out.string()}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("kept " + json.string()), std::string::npos) << r.output;
  EXPECT_EQ(sglab::io::read_file(json), better);

  set["provenance"]["objective"] = "another objective";
  std::ofstream(json) << set.dump(2);
  r = run_sglab(quick_fit({"--out", out.string()}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("replacing " + json.string() + ": its form or objective differs"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(sglab::fit::load_constant_set(json)["provenance"]["objective"],
            sglab::fit::load_constant_set(
                kRoot / "data" / "constants" /
                "lambda-d-diffuse-lobe-sphere-ls.json")["provenance"]["objective"]);
}

TEST(FitCli, OptionsThatDoNotApplyAreRefused) {
  const std::vector<std::vector<std::string>> refused = {
      {"fit", "erf", "--alpha-free"},
      {"fit", "erf", "--kappa", "1:10"},
      {"fit", "lambda-d", "--kappa", "1:10"},
      {"fit", "lambda-d", "--objective", "sphere-ls", "--kappa", "1:10"},
      {"fit", "steepness2022", "--precision", "half"},
      {"fit", "steepness2024", "--alpha-free"},
      {"fit", "clamped-cosine", "--max-error", "1e-3"},
      {"fit", "lambda-d", "--max-error", "1e-3"},
      {"fit", "all", "--objective", "irradiance"},
      {"fit", "all", "--precision", "double"},
      {"fit", "erf", "--cold-start"},
      {"fit", "clamped-cosine", "--costs", "costs.json"},
  };
  for (auto args : refused) {
    args.push_back("--dry-run");
    const auto r = run_sglab(args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_EQ(r.exit_code, 2) << joined << "\n" << r.output;
    EXPECT_NE(r.output.find("does not apply"), std::string::npos) << joined << "\n" << r.output;
  }
  // Where it applies, the same option is accepted.
  const auto r = run_sglab(
      {"fit", "lambda-d", "--objective", "irradiance", "--kappa", "1:10", "--dry-run", "--json"},
      false);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// The help lists every target of the one target table, and nothing is
// dispatched that the table does not hold.
TEST(FitCli, HelpListsEveryTargetOfTheTable) {
  const auto help = run_sglab({"fit", "--help"}, false);
  ASSERT_EQ(help.exit_code, 0) << help.output;
  for (const auto& t : sglab::fit::fit_targets()) {
    EXPECT_NE(help.output.find(std::string(t.name)), std::string::npos) << t.name;
    EXPECT_FALSE(t.all.empty()) << t.name << " has no `fit all` run";
  }
  const auto r = run_sglab({"fit", "no-such-target", "--dry-run"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(sglab::fit::fit_target_names()), std::string::npos) << r.output;
}

TEST(FitCli, DryRunSaysNothingWasWritten) {
  TempDir tmp("fit_dry");
  const fs::path out = tmp.path / "never";
  auto r = run_sglab(quick_fit({"--out", out.string(), "--dry-run"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dry run: nothing was written"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
  r = run_sglab(quick_fit({"--out", out.string(), "--dry-run", "--json"}), false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["dry_run"], true);
  EXPECT_TRUE(j["written"].empty());
  EXPECT_FALSE(fs::exists(out));
}

// The output folder may hold other files: the report of `sglab fit … --out D
// > D/r.json` (empty while the fit runs), a cost table, any JSON. Only files
// tagged "format": "sglab-constants" are read as constant sets; every other
// file is named in the report as skipped and left as it is.
TEST(FitCli, ForeignFilesInTheOutputFolderAreSkippedAndNamed) {
  InCheckout cwd;
  TempDir tmp("fit_foreign");
  const fs::path out = tmp.path / "D";
  fs::create_directories(out);
  const std::vector<std::pair<std::string, std::string>> foreign = {
      {"r.json", ""},
      {"costs.json", sglab::io::read_file(kRoot / "data" / "results" / "costs.json")},
      {"notes.json", "[1, 2]"},
      {"partial.json", "sglab-acc model order, kappa in [2, 50]\n"}};
  for (const auto& [name, text] : foreign) std::ofstream(out / name, std::ios::binary) << text;
  const auto r = run_sglab(quick_fit({"--out", out.string(), "--force", "--json"}), false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(fs::exists(out / "lambda-d-diffuse-lobe-sphere-ls.json")) << r.output;
  ASSERT_TRUE(fs::exists(out / "constants.hpp")) << r.output;
  std::set<std::string> skipped;
  for (const auto& s : j["skipped"]) {
    skipped.insert(fs::path(s["file"].get<std::string>()).filename().string());
    EXPECT_NE(s["reason"].get<std::string>().find("\"sglab-constants\""), std::string::npos) << s;
  }
  EXPECT_EQ(skipped, (std::set<std::string>{"r.json", "costs.json", "notes.json", "partial.json"}))
      << r.output;
  for (const auto& [name, text] : foreign)
    EXPECT_EQ(sglab::io::read_file(out / name), text) << name;
  // The text report names them too.
  const auto t = run_sglab(quick_fit({"--out", out.string(), "--force"}));
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("skipped " + (out / "r.json").string() + ": not a constant set"),
            std::string::npos)
      << t.output;
}

}  // namespace
