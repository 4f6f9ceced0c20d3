// Resources and files of the command line: a sweep grid beyond the documented
// limit is refused before anything is allocated, `sglab reference` streams
// (its memory does not grow with the points file), a UTF-8 byte-order mark
// at the start of a CSV is accepted, and `--json` without `--out` writes no
// file; progress goes to standard error only when it is a terminal.
//
// This file runs no reference engine in the test process, so that forking
// (to measure a child's peak memory) is safe.
#include <fcntl.h>
#include <pty.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/io.hpp"
#include "report/figures.hpp"
#include "tests/test_support.hpp"
#include "validate/sweep.hpp"

namespace {

namespace fs = std::filesystem;

using sglab::test::TempDir;

// ---- sweep grid limit ------------------------------------------------------

TEST(SweepLimit, GridValidateRefusesMoreThanTheLimit) {
  using sglab::validate::SweepGrid;
  const int cosines = 41;
  const int fits = static_cast<int>(SweepGrid::kMaxPoints / cosines);
  EXPECT_NO_THROW((SweepGrid{1e-3, 1e4, fits, cosines}.validate()));
  EXPECT_THROW((SweepGrid{1e-3, 1e4, fits + 1, cosines}.validate()), std::invalid_argument);
  EXPECT_THROW((SweepGrid{1, 2, 50000, 50000}.validate()), std::invalid_argument);
  EXPECT_EQ((SweepGrid{1, 2, 50000, 50000}.point_count()), 2'500'000'000u);
  // no overflow
  EXPECT_EQ((SweepGrid{1, 2, 2147483647, 2147483647}.point_count()), 4611686014132420609u);
  try {
    SweepGrid{1e-3, 1e4, 100'000'000, 41}.validate();
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("4100000000 points"), std::string::npos) << m;
    EXPECT_NE(m.find(fmt::format("{} points", SweepGrid::kMaxPoints)), std::string::npos) << m;
    EXPECT_NE(m.find("GB"), std::string::npos) << m;
  }
}

TEST(SweepLimit, MemoryEstimateGrowsWithPointsAndEntries) {
  using sglab::validate::SweepGrid;
  const SweepGrid small{1, 2, 10, 10}, large{1, 2, 100, 10};
  EXPECT_EQ(sweep_memory_estimate(large, 4), 10 * sweep_memory_estimate(small, 4));
  EXPECT_GT(sweep_memory_estimate(small, 8), sweep_memory_estimate(small, 4));
  // The standard grid stays well under 100 MB for the full registry.
  EXPECT_LT(
      sweep_memory_estimate(SweepGrid{}, 2 * sglab::validate::registered_sweep_methods().size()),
      100'000'000u);
}

TEST(SweepLimit, CommandLineRefusesHugeGridsWithExitTwoAndWritesNothing) {
  TempDir dir("sweep-limit");
  const fs::path out = dir.path / "out";
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"--kappa", "1e-3:1e4:100000000"},
                                             {"--kappa", "1e-3:1e4:100000"},
                                             {"--kappa", "1:2:50000", "--cosines", "50000"}}) {
    std::vector<std::string> argv = {"sweep", "--out", out.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto r = sglab::test::run_sglab(argv);
    EXPECT_EQ(r.exit_code, 2) << args[1] << "\n" << r.output;
    EXPECT_NE(r.output.find("exceeds the limit"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("GB"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << args[1];
  }
}

// ---- --json writes no file unless --out is given --------------------------

// Runs `sglab ARGS` with the working directory `cwd` (restored afterwards).
sglab::test::CommandResult run_in(const fs::path& cwd, const std::vector<std::string>& args) {
  const fs::path here = fs::current_path();
  fs::current_path(cwd);
  auto r = sglab::test::run_sglab(args, false);
  fs::current_path(here);
  return r;
}

TEST(JsonOutput, SweepAndStabilityWriteNoFileWithoutOut) {
  TempDir dir("json-cwd");
  auto r = run_in(
      dir.path, {"sweep", "--json", "--kappa", "1:1:1", "--cosines", "3", "--method", "punctual"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"results\""), std::string::npos) << r.output;
  r = run_in(dir.path, {"stability", "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find("\"results\""), std::string::npos);
  EXPECT_TRUE(fs::is_empty(dir.path)) << "files were written to the working directory";
  // With --out, the files go there.
  r = run_in(dir.path, {"sweep", "--json", "--kappa", "1:1:1", "--cosines", "3", "--method",
                        "punctual", "--out", "here"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir.path / "here" / "summary.json"));
}

// ---- UTF-8 byte-order mark ----------------------------------------------------

TEST(ByteOrderMark, StripsOnlyALeadingMark) {
  EXPECT_EQ(sglab::io::strip_utf8_bom("\xEF\xBB\xBFkappa"), "kappa");
  EXPECT_EQ(sglab::io::strip_utf8_bom("kappa"), "kappa");
  EXPECT_EQ(sglab::io::strip_utf8_bom("\xEF\xBB"), "\xEF\xBB");
  EXPECT_EQ(sglab::io::strip_utf8_bom("k\xEF\xBB\xBF"), "k\xEF\xBB\xBF");
}

TEST(ByteOrderMark, ReferencePointsFileWithAMarkGivesTheSameOutput) {
  TempDir dir("bom-ref");
  const std::string body = "kappa,cosine\r\n1,0.5\r\n2.5,-0.25\r\n";
  sglab::io::write_file_atomic(dir.path / "plain.csv", body);
  sglab::io::write_file_atomic(dir.path / "bom.csv", "\xEF\xBB\xBF" + body);
  const auto plain =
      sglab::test::run_sglab({"reference", "--points", (dir.path / "plain.csv").string()});
  const auto bom =
      sglab::test::run_sglab({"reference", "--points", (dir.path / "bom.csv").string()});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(bom.exit_code, 0) << bom.output;
  EXPECT_EQ(bom.output, plain.output);
  // A mark anywhere else is still an error.
  // (the literal is split after the mark: "\xBF1" would be one hex escape)
  sglab::io::write_file_atomic(dir.path / "late.csv",
                               "kappa,cosine\n\xEF\xBB\xBF"
                               "1,0.5\n");
  EXPECT_EQ(
      sglab::test::run_sglab({"reference", "--points", (dir.path / "late.csv").string()}).exit_code,
      2);
}

TEST(ByteOrderMark, ParetoCsvWithAMarkIsRead) {
  TempDir dir("bom-pareto");
  const std::string body =
      "method,origin,precision,kappa_lo,kappa_hi,cost,cost_unit,cost_source,max_peak_rel,"
      "frontier\n"
      "punctual,published,float,0.001,10000,0.8,ns,cpu-batch,0.9,true\n";
  sglab::io::write_file_atomic(dir.path / "p.csv", "\xEF\xBB\xBF" + body);
  const auto rows = sglab::report::read_pareto_csv(dir.path / "p.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].method, "punctual");
}

// ---- reference streams --------------------------------------------------------

// Peak resident memory (KiB) of `sglab ARGS`, measured in a forked helper
// process whose only child is that command; -1 if it failed.
long peak_rss_kib(const std::vector<std::string>& args) {
  int fds[2];
  if (::pipe(fds) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    const auto r = sglab::test::run_sglab(args);
    rusage ru{};
    ::getrusage(RUSAGE_CHILDREN, &ru);
    const long kib = r.exit_code == 0 ? ru.ru_maxrss : -1;
    (void)!::write(fds[1], &kib, sizeof kib);
    ::_exit(0);
  }
  ::close(fds[1]);
  long kib = -1;
  if (pid < 0 || ::read(fds[0], &kib, sizeof kib) != static_cast<ssize_t>(sizeof kib)) kib = -1;
  ::close(fds[0]);
  if (pid > 0) ::waitpid(pid, nullptr, 0);
  return kib;
}

void write_points(const fs::path& file, int rows) {
  std::ofstream out(file);
  out << "kappa,cosine\n";
  for (int i = 0; i < rows; ++i)
    out << fmt::format("{},{}\n", 0.5 + 1e-4 * i, -1.0 + 2.0 * (i % 997) / 996.0);
}

TEST(ReferenceStreaming, OutputKeepsEveryRowInOrderAcrossChunks) {
  TempDir dir("ref-stream");
  const int rows = 10'000;  // more than one chunk
  write_points(dir.path / "p.csv", rows);
  const auto r =
      sglab::test::run_sglab({"reference", "--points", (dir.path / "p.csv").string()}, false);
  ASSERT_EQ(r.exit_code, 0);
  std::size_t lines = 0, start = 0;
  while (start < r.output.size()) {
    const std::size_t end = r.output.find('\n', start);
    ASSERT_NE(end, std::string::npos);
    const std::string line = r.output.substr(start, end - start);
    if (lines > 0) {
      const int i = static_cast<int>(lines) - 1;
      const double kappa = std::stod(line.substr(0, line.find(',')));
      ASSERT_EQ(kappa, 0.5 + 1e-4 * i) << "row " << i << ": " << line;
    }
    ++lines;
    start = end + 1;
  }
  EXPECT_EQ(lines, static_cast<std::size_t>(rows) + 1);
}

// `sglab reference --check-table`: one line per piece of the irradiance table
// and the whole, within the bound; exactly one of --points and --check-table,
// and an odd --oversample (an even one puts grid points on the nodes), else exit 2.
TEST(ReferenceCheckTable, ReportsEveryPieceWithinTheBoundAndRefusesBadArguments) {
  const auto r = sglab::test::run_sglab({"reference", "--check-table", "--oversample", "1"}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::regex piece(R"(\n  \[[^\]]+\] in .+? +\d+x\d+ +\d+ +([0-9.e+-]+)  \()");
  int pieces = 0;
  for (auto it = std::sregex_iterator(r.output.begin(), r.output.end(), piece);
       it != std::sregex_iterator(); ++it, ++pieces)
    EXPECT_LE(std::stod((*it)[1].str()), 1e-10) << (*it)[0].str();
  EXPECT_EQ(pieces, 7) << r.output;
  std::smatch all;
  ASSERT_TRUE(
      std::regex_search(r.output, all, std::regex(R"(all: (\d+) points, .* = ([0-9.e+-]+) at)")))
      << r.output;
  EXPECT_GT(std::stoul(all[1].str()), 5000u);
  EXPECT_LE(std::stod(all[2].str()), 1e-10);
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"reference"},
        {"reference", "--check-table", "--points", "points.csv"},
        {"reference", "--check-table", "--oversample", "2"},
        {"reference", "--check-table", "--oversample", "0"}}) {
    const auto b = sglab::test::run_sglab(bad);
    EXPECT_EQ(b.exit_code, 2) << bad.back() << ": " << b.output;
    EXPECT_EQ(b.output.find("irradiance table:"), std::string::npos) << b.output;
  }
}

TEST(ReferenceStreaming, MemoryDoesNotGrowWithTheFile) {
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer keeps freed memory in quarantine, so peak RSS grows with
  // the work done whatever the program holds; the plain build measures it.
  GTEST_SKIP() << "peak RSS is not a measure of what sglab holds under AddressSanitizer";
#endif
  TempDir dir("ref-memory");
  write_points(dir.path / "small.csv", 1'000);
  write_points(dir.path / "large.csv", 200'000);
  const long small = peak_rss_kib({"reference", "--points", (dir.path / "small.csv").string()});
  const long large = peak_rss_kib({"reference", "--points", (dir.path / "large.csv").string()});
  ASSERT_GT(small, 0);
  ASSERT_GT(large, 0);
  // Holding every row (query, result, output line and cache entry) costs
  // about 400 bytes a row, 80 MB here; streaming holds a few chunks.
  EXPECT_LT(large - small, 24 * 1024)
      << "peak RSS " << small << " KiB for 1,000 rows, " << large << " KiB for 200,000 rows";
}

TEST(EvalStreaming, MemoryDoesNotGrowWithTheFile) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "peak RSS is not a measure of what sglab holds under AddressSanitizer";
#endif
  TempDir dir("eval-memory");
  write_points(dir.path / "small.csv", 1'000);
  write_points(dir.path / "large.csv", 1'000'000);
  const auto eval = [&](const char* file) {
    return peak_rss_kib(
        {"eval", "--method", "tokuyoshi2024", "--points", (dir.path / file).string()});
  };
  const long small = eval("small.csv"), large = eval("large.csv");
  ASSERT_GT(small, 0);
  ASSERT_GT(large, 0);
  // Holding every row (query and output line) costs about 80 bytes a row,
  // 80 MB here; streaming holds one line and a 64 KB output buffer.
  EXPECT_LT(large - small, 24 * 1024)
      << "peak RSS " << small << " KiB for 1,000 rows, " << large << " KiB for 1,000,000 rows";
}

// ---- io::run_program: an argument vector, no shell ---------------------------

TEST(RunProgram, PassesArgumentsAsGivenInTheWorkingDirectory) {
  TempDir dir("run-program");
  const std::string hostile = "a b;touch marker;'q'\"x\" $(touch marker2)";
  EXPECT_EQ(sglab::io::run_program({"printf", "%s", hostile}, dir.path, "out.txt"), 0);
  EXPECT_EQ(sglab::io::read_file(dir.path / "out.txt"), hostile);
  EXPECT_FALSE(fs::exists(dir.path / "marker"));
  EXPECT_FALSE(fs::exists(dir.path / "marker2"));
  EXPECT_EQ(sglab::io::run_program({"false"}), 1);
  EXPECT_EQ(sglab::io::run_program({"sglab-no-such-program-xyz"}), -1);
}

// ---- progress on a terminal only -------------------------------------------

// What a run with standard error on a terminal printed, and its exit code.
struct TerminalRun {
  std::string out, terminal;
  int exit_code = -1;
};

// Runs `sglab ARGS` with standard error on a pseudo-terminal and standard
// output on a pipe.
TerminalRun run_with_terminal_stderr(const std::vector<std::string>& args) {
  int master = -1, slave = -1;
  if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) return {};
  int out[2];
  if (::pipe(out) != 0) return {};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawn_file_actions_adddup2(&actions, slave, 2);
  for (int fd : {master, slave, out[0], out[1]}) posix_spawn_file_actions_addclose(&actions, fd);
  std::vector<std::string> argv = {SGLAB_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargs;
  for (const std::string& a : argv) cargs.push_back(const_cast<char*>(a.c_str()));
  cargs.push_back(nullptr);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, cargs[0], &actions, nullptr, cargs.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(slave);
  ::close(out[1]);
  std::string stdout_text, terminal;
  char buffer[4096];
  ssize_t n;
  if (rc == 0)
    while ((n = ::read(out[0], buffer, sizeof buffer)) > 0)
      stdout_text.append(buffer, static_cast<std::size_t>(n));
  ::close(out[0]);
  int status = 0;
  if (rc == 0) ::waitpid(pid, &status, 0);
  while ((n = ::read(master, buffer, sizeof buffer)) > 0)
    terminal.append(buffer, static_cast<std::size_t>(n));
  ::close(master);
  return {stdout_text, terminal, rc == 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

TEST(Progress, ReferenceShowsProgressOnATerminalOnly) {
  TempDir dir("progress");
  write_points(dir.path / "p.csv", 5'000);
  const std::string file = (dir.path / "p.csv").string();
  const auto [out, terminal, exit_code] = run_with_terminal_stderr({"reference", "--points", file});
  EXPECT_EQ(exit_code, 0);
  EXPECT_EQ(out.rfind("kappa,cosine,", 0), 0u) << out.substr(0, 200);
  EXPECT_EQ(out.find("reference:"), std::string::npos);
  // The file is read once, so the count is open-ended: "reference: ROWS 0.1s".
  EXPECT_TRUE(std::regex_search(terminal, std::regex(R"(reference: [0-9]+ [0-9]+\.[0-9]s)")))
      << terminal;
  // Not a terminal: no progress at all, on either stream.
  const auto piped = sglab::test::run_sglab({"reference", "--points", file});
  EXPECT_EQ(piped.exit_code, 0);
  EXPECT_EQ(piped.output.find("reference:"), std::string::npos);
  EXPECT_EQ(piped.output.find('\r'), std::string::npos);
}

// Outputs are checked before the work: `gpucost --out /dev/null` and `fit
// TARGET --out FILE` (a regular file where a folder belongs) exit 2 at once.
// On a terminal, work would show: progress on stderr (gpucost notes each
// export it compiles) and each fit's report on stdout.
TEST(Progress, OutputsAreCheckedBeforeAnyWork) {
  TempDir dir("outputs-first");
  sglab::io::write_file_atomic(dir.path / "file", "not a folder\n");
  const std::string file = (dir.path / "file").string();
  struct Case {
    std::vector<std::string> args;
    std::string error;
  };
  for (const Case& c : std::vector<Case>{
           {{"gpucost", "--families", "navi21", "--method", "hill", "--out", "/dev/null"},
            "/dev/null: is a character device, not a folder"},
           {{"fit", "clamped-cosine", "--out", file}, file + ": is a regular file, not a folder"},
           {{"fit", "clamped-cosine", "--out", dir.path.string(), "--header", "/dev/null"},
            "/dev/null: is a character device, not a regular file"}}) {
    const TerminalRun r = run_with_terminal_stderr(c.args);
    const std::string what = fmt::format("{}: {}{}", fmt::join(c.args, " "), r.out, r.terminal);
    EXPECT_EQ(r.exit_code, 2) << what;
    EXPECT_NE(r.terminal.find(c.error), std::string::npos) << what;
    // a progress line ends by clearing the rest of the line
    EXPECT_EQ(r.terminal.find("\033[K"), std::string::npos) << "progress was shown: " << what;
    EXPECT_EQ(r.out, "") << what;
  }
  EXPECT_EQ(sglab::io::read_file(dir.path / "file"), "not a folder\n");
}

}  // namespace
