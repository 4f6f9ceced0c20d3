// Progress on stderr (common/io.hpp): drawn only on a terminal. The helper
// with an injected "is a terminal" flag and a string sink; the commands with
// long work (`sglab erf`, `sglab fit`) print nothing extra when stderr is not
// a terminal (a pipe, as under ctest) and draw their line when it is a
// pseudo-terminal.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/io.hpp"
#include "tests/test_support.hpp"

namespace {

using sglab::io::Progress;
using sglab::io::ProgressSink;
using sglab::test::run_sglab;

ProgressSink string_sink(std::string& out, bool terminal) {
  return {terminal, [&out](std::string_view text) { out.append(text); }};
}

// `sglab ARGS...` with stderr on a new pseudo-terminal and stdout on
// /dev/null; returns what arrived on the terminal ("" if no pty is available).
std::string run_sglab_on_pty(const std::vector<std::string>& args, int& exit_code) {
  exit_code = -1;
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0) return "";
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    ::close(master);
    return "";
  }
  const std::string slave = ::ptsname(master);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, slave.c_str(), O_RDWR | O_NOCTTY, 0);
  posix_spawn_file_actions_addclose(&actions, master);
  std::vector<std::string> argv = args;
  argv.insert(argv.begin(), SGLAB_BINARY);
  std::vector<char*> cargs;
  for (std::string& a : argv) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t pid;
  const int rc = ::posix_spawn(&pid, cargs[0], &actions, nullptr, cargs.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  std::string out;
  if (rc == 0) {
    char buffer[4096];
    for (;;) {  // until the child's side closes (EIO on Linux)
      const ssize_t n = ::read(master, buffer, sizeof buffer);
      if (n > 0) {
        out.append(buffer, static_cast<std::size_t>(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      break;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  ::close(master);
  return out;
}

}  // namespace

TEST(Progress, NotATerminalWritesNothing) {
  std::string out;
  {
    Progress p("work", 4, string_sink(out, false));
    p.advance();
    p.note("stage b");
    p.advance(3);
    p.finish();
  }
  EXPECT_EQ(out, "");
}

TEST(Progress, TerminalDrawsCountPercentNoteAndClears) {
  std::string out;
  Progress p("work", 4, string_sink(out, true));
  p.advance();  // the first advance always draws
  EXPECT_EQ(out.rfind("\rwork: 1/4 (25%) ", 0), 0u) << out;
  EXPECT_NE(out.find("\033[K"), std::string::npos) << out;
  out.clear();
  p.note("stage b");  // a note draws at once
  EXPECT_EQ(out.rfind("\rwork: 1/4 (25%) ", 0), 0u) << out;
  EXPECT_NE(out.find("s  stage b\033[K"), std::string::npos) << out;
  out.clear();
  p.advance(3);  // reaching the total always draws
  EXPECT_EQ(out.rfind("\rwork: 4/4 (100%) ", 0), 0u) << out;
  EXPECT_NE(out.find("stage b"), std::string::npos) << out;
  out.clear();
  p.finish();
  EXPECT_EQ(out, "\r\033[K");
  out.clear();
  p.advance();  // nothing after finish
  p.note("late");
  p.finish();
  EXPECT_EQ(out, "");
}

TEST(Progress, OpenEndedCountWithoutTotal) {
  std::string out;
  Progress p("fit erf, solves", 0, string_sink(out, true));
  p.advance();
  EXPECT_EQ(out.rfind("\rfit erf, solves: 1 ", 0), 0u) << out;
  EXPECT_EQ(out.find('%'), std::string::npos) << out;
}

TEST(Progress, NothingDrawnNothingCleared) {
  std::string out;
  { Progress p("idle", 3, string_sink(out, true)); }  // never advanced: no line to clear
  EXPECT_EQ(out, "");
  // a terminal without a writer draws nothing
  Progress no_writer("work", 1, ProgressSink{true, nullptr});
  no_writer.advance();
  no_writer.finish();
}

// Under ctest stderr is a pipe: the merged output of a run has no progress
// line (no carriage return, no erase-line escape, no label).
TEST(Progress, ErfPrintsNothingExtraWhenStderrIsNotATerminal) {
  const auto r = run_sglab({"erf", "--variant", "std", "--double-points", "10000", "--bins", "10"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("\033["), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("erf std float"), std::string::npos) << r.output;
}

TEST(Progress, FitPrintsNothingExtraWhenStderrIsNotATerminal) {
  const auto r =
      run_sglab({"fit", "steepness2022", "--kappa", "1:2", "--max-error", "1", "--dry-run"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("\033["), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("solves"), std::string::npos) << r.output;
}

// On a terminal the same runs draw their line on stderr.
TEST(Progress, ErfAndFitDrawOnATerminal) {
  int code = -1;
  const std::string erf = run_sglab_on_pty(
      {"erf", "--variant", "std", "--double-points", "10000", "--bins", "10"}, code);
  if (code == -1 && erf.empty()) GTEST_SKIP() << "no pseudo-terminal available";
  ASSERT_EQ(code, 0) << erf;
  EXPECT_NE(erf.find("\rerf std float: "), std::string::npos) << erf;
  const std::string fit = run_sglab_on_pty(
      {"fit", "steepness2022", "--kappa", "1:2", "--max-error", "1", "--dry-run"}, code);
  ASSERT_EQ(code, 0) << fit;
  EXPECT_NE(fit.find("\rfit steepness2022, solves: "), std::string::npos) << fit;
  EXPECT_NE(fit.find("  rational order 0"), std::string::npos) << fit;  // the driver's note
}
