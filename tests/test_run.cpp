// `sglab run`: the steps run without a shell (an output path with spaces,
// quotes and a semicolon works and runs nothing), and OUT/index.md is a
// clean report: every relative link resolves to a file, no image is shown
// twice, heading levels never skip, and no long table is inlined.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "tests/test_support.hpp"
#include "validate/reference.hpp"

namespace {

namespace fs = std::filesystem;

struct Link {
  bool image;
  std::string target;
  std::size_t line;
};

// Every Markdown link and image of `text` outside fenced code blocks and
// inline code spans. The link text may hold balanced brackets.
std::vector<Link> markdown_links(const std::string& text) {
  std::vector<Link> links;
  bool fenced = false;
  std::size_t line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (fenced) continue;
    // Blank out code spans.
    for (std::size_t i = 0; i < line.size(); ++i)
      if (line[i] == '`') {
        const std::size_t close = line.find('`', i + 1);
        const std::size_t stop = close == std::string::npos ? line.size() : close + 1;
        std::fill(line.begin() + static_cast<std::ptrdiff_t>(i),
                  line.begin() + static_cast<std::ptrdiff_t>(stop), ' ');
        i = stop;
      }
    for (std::size_t at = line.find("]("); at != std::string::npos; at = line.find("](", at + 1)) {
      int depth = 0;
      std::size_t open = std::string::npos;
      for (std::size_t k = at + 1; k-- > 0;) {
        if (line[k] == ']') ++depth;
        if (line[k] == '[' && --depth == 0) {
          open = k;
          break;
        }
      }
      if (open == std::string::npos) continue;
      const std::size_t close = line.find(')', at + 2);
      if (close == std::string::npos) continue;
      std::string target = line.substr(at + 2, close - at - 2);
      target = target.substr(0, target.find(' '));
      links.push_back({open > 0 && line[open - 1] == '!', target, line_number});
    }
  }
  return links;
}

bool is_relative(const std::string& t) {
  return !t.empty() && t.front() != '/' && t.front() != '#' && t.find("://") == std::string::npos &&
         t.rfind("mailto:", 0) != 0;
}

// The checks on OUT/index.md; `context` is printed with every failure.
void check_index(const fs::path& out, std::size_t min_images) {
  ASSERT_TRUE(fs::exists(out / "index.md")) << out;
  const std::string text = sglab::io::read_file(out / "index.md");
  const auto links = markdown_links(text);
  std::map<std::string, int> images;
  std::size_t relative = 0;
  for (const Link& l : links) {
    if (!is_relative(l.target)) continue;
    ++relative;
    const std::string path = l.target.substr(0, l.target.find('#'));
    EXPECT_TRUE(fs::is_regular_file(out / path))
        << "index.md:" << l.line << ": broken link " << l.target;
    if (l.image) ++images[fs::path(path).lexically_normal().generic_string()];
  }
  EXPECT_GT(relative, 0u);
  EXPECT_GE(images.size(), min_images);
  for (const auto& [target, count] : images)
    EXPECT_EQ(count, 1) << target << " is shown " << count << " times";

  // One H1, first; a heading is at most one level below the one before it.
  int previous = 0;
  int h1 = 0;
  std::size_t line_number = 0, table_run = 0, longest_table = 0;
  bool fenced = false;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    start = end + 1;
    ++line_number;
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    if (fenced) continue;
    table_run = line.rfind("|", 0) == 0 ? table_run + 1 : 0;
    longest_table = std::max(longest_table, table_run);
    int level = 0;
    while (level < static_cast<int>(line.size()) && line[static_cast<std::size_t>(level)] == '#')
      ++level;
    if (level == 0 || level > 6 ||
        (static_cast<std::size_t>(level) < line.size() &&
         line[static_cast<std::size_t>(level)] != ' '))
      continue;
    if (level == 1) ++h1;
    if (previous == 0) {
      EXPECT_EQ(level, 1) << "index.md:" << line_number << ": the first heading is not an H1";
    }
    EXPECT_LE(level, previous + 1)
        << "index.md:" << line_number << ": H" << level << " under H" << previous << ": " << line;
    previous = level;
  }
  EXPECT_EQ(h1, 1);
  EXPECT_LE(longest_table, 150u) << "a table of " << longest_table << " lines is inlined";
}

// An output folder whose name holds a space, both quotes and a semicolon
// followed by a command: through a shell, that command would create `marker`.
struct HostileOut {
  sglab::test::TempDir base{"run"};
  fs::path marker = base.path / "marker";
  // Through a shell: `.../a b;touch MARKER;'q'"x"/...` runs `touch MARKER`.
  fs::path out = base.path / fmt::format("a b;touch {};'q'\"x\"", marker.string());
};

TEST(RunCommand, HostilePathWorksAndRunsNothing) {
  HostileOut dir;
  // The fast steps only; the report checks below cover the rest.
  const auto r = sglab::test::run_sglab(
      {"run",    "--quick",    "--out",  dir.out.string(), "--skip", "fit",    "--skip",
       "erf",    "--skip",     "claims", "--skip",         "bench",  "--skip", "pareto",
       "--skip", "pareto-cpu", "--skip", "figures",        "--skip", "envmap"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir.marker)) << "a command in the output path was run";
  EXPECT_TRUE(fs::is_regular_file(dir.out / "sweep" / "summary.csv")) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir.out / "stability" / "stability.csv")) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir.out / "logs" / "sweep.log")) << r.output;
  check_index(dir.out, 0);
}

TEST(RunCommand, QuickRunIndexHasNoBrokenLinkAndEachFigureOnce) {
  // Every step of the quick run except the slow fit, bench and envmap (figures
  // read the pareto table, which falls back to no cost data without bench;
  // envmap's quick step fits eight maps, 50 s of CPU, and draws no figure).
  HostileOut dir;
  const auto r = sglab::test::run_sglab({"run", "--quick", "--out", dir.out.string(), "--skip",
                                         "fit", "--skip", "bench", "--skip", "envmap"});
  EXPECT_FALSE(fs::exists(dir.marker));
  // Steps may fail for reasons outside the report (e.g. no gnuplot); the
  // report must be clean whatever happened.
  const bool gnuplot = sglab::test::run_program({"gnuplot", "--version"}).exit_code == 0;
  if (gnuplot) {
    EXPECT_EQ(r.exit_code, 0) << r.output;
  }
  check_index(dir.out, gnuplot ? 5 : 0);
}

TEST(RunCommand, UnknownSkipIsBadInput) {
  HostileOut dir;
  const auto r = sglab::test::run_sglab({"run", "--out", dir.out.string(), "--skip", "nonsense"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nonsense"), std::string::npos) << r.output;
}

// ---- an interrupted run leaves the previous output as it was ------------------

// Every regular file under `dir` with its content, by path relative to it.
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).generic_string()] = sglab::io::read_file(e.path());
  return files;
}

// Starts `sglab ARGS` (argument vector, no shell; output discarded); returns its pid.
pid_t spawn_sglab(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {SGLAB_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargs;
  for (const std::string& a : argv) cargs.push_back(const_cast<char*>(a.c_str()));
  cargs.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  if (::posix_spawn(&pid, cargs[0], &actions, nullptr, cargs.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// Where gpucost found no RADV null device, the cost table has no GPU costs:
// the pareto step (GPU cost by default) is skipped with the reason and the run
// succeeds; pareto-cpu still writes the CPU-cost table. (A project of its own,
// found from the working directory, whose committed table is CPU only.)
TEST(RunCommand, ParetoWithoutGpuCostsIsSkippedWithTheReason) {
  sglab::test::TempDir project("run-no-gpu");
  fs::create_directories(project.path / "include" / "sglab");
  // what marks a project (io::find_project_root)
  fs::create_directories(project.path / "data" / "constants");
  fs::create_directories(project.path / "data" / "results");
  std::string rows;
  for (const sglab::Method& m : sglab::irradiance_methods)
    rows += fmt::format(
        R"({}{{"kind": "irradiance", "method": "{}", "precision": "float", "mode": "batch", "ns_per_eval": 5}})",
        rows.empty() ? "" : ", ", m.id);
  sglab::io::write_file_atomic(
      project.path / "data" / "results" / "costs.json",
      R"({"format": "sglab-costs", "version": 1, "date": "2026-01-01T00:00:00Z", "command": "test", "machine": {"cpu": "t", "cores": 1}, )"
      R"("compiler": {"id": "none", "version": "0"}, "build_type": "none", "timer": "none", "inputs": "none", "costs": [)" +
          rows + "]}");
  const fs::path here = fs::current_path();
  fs::current_path(project.path);
  const fs::path out = project.path / "out";
  const auto r = sglab::test::run_sglab(
      {"run",    "--out",  out.string(), "--skip",    "fit",     "--skip", "sweep",
       "--skip", "erf",    "--skip",     "stability", "--skip",  "claims", "--skip",
       "bench",  "--skip", "gpucost",    "--skip",    "figures", "--skip", "envmap"});
  fs::current_path(here);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped: the cost table has no GPU costs"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out / "pareto" / "pareto.csv"));
  ASSERT_TRUE(fs::is_regular_file(out / "pareto-cpu" / "pareto.csv")) << r.output;
  EXPECT_NE(sglab::io::read_file(out / "pareto-cpu" / "pareto.csv").find(",ns,cpu-batch,"),
            std::string::npos);
  EXPECT_NE(sglab::io::read_file(out / "index.md").find("no GPU costs"), std::string::npos);
}

TEST(RunCommand, InterruptedRunLeavesThePreviousOutputAsItWas) {
  sglab::test::TempDir base("run-interrupted");
  const fs::path out = base.path / "out";
  // A complete earlier output: its index says the sweep step was ok, with its log.
  fs::create_directories(out / "logs");
  fs::create_directories(out / "sweep");
  sglab::io::write_file_atomic(out / "index.md",
                               "# sglab results\n\n## sweep\n\n`sglab sweep` — ok\n");
  sglab::io::write_file_atomic(out / "logs" / "sweep.log", "the previous sweep's log\n");
  sglab::io::write_file_atomic(out / "sweep" / "summary.csv", "previous\n");
  const auto before = files_under(out);
  const std::vector<std::string> args = {
      "run",    "--quick",    "--out",  out.string(), "--skip", "fit",    "--skip",
      "erf",    "--skip",     "claims", "--skip",     "bench",  "--skip", "pareto",
      "--skip", "pareto-cpu", "--skip", "figures",    "--skip", "envmap"};
  for (const int signal : {SIGINT, SIGTERM}) {
    const pid_t pid = spawn_sglab(args);
    ASSERT_GT(pid, 0);
    // Interrupt it while its first step (sweep) is writing its log.
    const fs::path partial_log =
        base.path / fmt::format("out.staging-{}", pid) / "logs" / ".sweep.log.partial";
    for (int i = 0; i < 2000 && !fs::exists(partial_log); ++i) ::usleep(10'000);
    ASSERT_TRUE(fs::exists(partial_log)) << "the run did not start its first step within 20 s";
    ::kill(pid, signal);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before the signal; status " << status;
    EXPECT_EQ(files_under(out), before) << "signal " << signal << " changed the previous output";
  }
  // A run that finishes replaces it as a whole.
  const auto r = sglab::test::run_sglab(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto after = files_under(out);
  EXPECT_NE(after.at("logs/sweep.log"), before.at("logs/sweep.log"));
  EXPECT_TRUE(after.count("stability/stability.csv"));
  EXPECT_NE(after.at("sweep/summary.csv"), "previous\n");
  EXPECT_NE(after.at("index.md").find("## stability"), std::string::npos);
  for (const auto& [name, text] : after)
    EXPECT_EQ(name.find(".partial"), std::string::npos) << name;
}

// ---- `sglab table` prints every value with 5 significant digits --------------

// The cells of the rows of a Markdown table printed by `sglab table`.
std::vector<std::vector<std::string>> table_rows(const std::string& output) {
  std::vector<std::vector<std::string>> rows;
  std::size_t start = 0;
  while (start < output.size()) {
    std::size_t end = output.find('\n', start);
    if (end == std::string::npos) end = output.size();
    const std::string line = output.substr(start, end - start);
    start = end + 1;
    if (line.rfind("|", 0) != 0 || line.rfind("|:", 0) == 0) continue;
    std::vector<std::string> cells;
    std::size_t a = 1;
    for (std::size_t b = line.find('|', a); b != std::string::npos;
         a = b + 1, b = line.find('|', a)) {
      std::string c = line.substr(a, b - a);
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    rows.push_back(cells);
  }
  return rows;
}

// strtod, not stod: stod throws on subnormal results.
double number(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

TEST(TableCommand, KeepsFourSignificantDigitsAtEveryKappa) {
  for (const double kappa : {1e-3, 4.0, 1e4}) {
    const auto r = sglab::test::run_sglab({"table", "--kappa", fmt::format("{}", kappa)}, false);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto rows = table_rows(r.output);
    ASSERT_GE(rows.size(), 3u) << r.output;
    const auto& header = rows[0];
    std::vector<double> cosines;
    for (std::size_t i = 1; i + 1 < header.size(); ++i) cosines.push_back(number(header[i]));
    ASSERT_EQ(cosines.size(), 9u);
    std::size_t checked = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto& row = rows[k];
      ASSERT_EQ(row.size(), header.size()) << r.output;
      const sglab::Method* method = nullptr;
      for (const auto& m : sglab::irradiance_methods)
        if (row[0] == m.id) method = &m;
      ASSERT_TRUE(row[0] == "reference" || method) << row[0];
      for (std::size_t i = 0; i < cosines.size(); ++i) {
        const double c = -1.0 + 2.0 * static_cast<double>(i) / 8.0;
        const double truth =
            method ? method->f64(c, kappa)
                   : sglab::validate::reference_engine().evaluate(kappa, c).irradiance;
        const double printed = number(row[i + 1]);
        if (truth == 0) {
          EXPECT_EQ(printed, 0) << row[0] << " c = " << c;
          continue;
        }
        EXPECT_LE(std::abs(printed - truth), 1e-4 * std::abs(truth))
            << row[0] << " at κ = " << kappa << ", c = " << c << ": printed " << row[i + 1]
            << ", value " << truth;
        ++checked;
      }
    }
    EXPECT_GT(checked, 9u * 5);
  }
}

}  // namespace
