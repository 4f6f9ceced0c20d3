// `sglab run`: the steps run without a shell (an output path with spaces,
// quotes and a semicolon works and runs nothing), OUT/index.md is a clean
// report (every relative link resolves to a file, no image is shown twice,
// heading levels never skip, no long table is inlined), and OUT is replaced
// only when it is absent, empty or an earlier output listed whole by its
// manifest, never the checkout, the working folder, $HOME or /.
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
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "reference/reference.hpp"
#include "tests/test_support.hpp"

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
  // The two fastest steps only; the report checks below cover the rest.
  const auto r = sglab::test::run_sglab(
      {"run",    "--quick", "--out",  dir.out.string(), "--skip", "fit",    "--skip", "erf",
       "--skip", "claims",  "--skip", "bench",          "--skip", "pareto", "--skip", "pareto-cpu",
       "--skip", "figures", "--skip", "envmap",         "--skip", "gpucost"});
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
  // Each section names its form; a sampled step names its full command.
  const std::string index = sglab::io::read_file(dir.out / "index.md");
  const auto section = [&index](std::string_view name) {
    const std::size_t at = index.find(fmt::format("\n## {}\n", name));
    if (at == std::string::npos) return std::string();
    return index.substr(at + 1, index.find("\n## ", at + 1) - at - 1);
  };
  EXPECT_NE(section("erf").find("Form: quick ("), std::string::npos) << section("erf");
  EXPECT_NE(section("erf").find("Full form (scripts/results.sh runs it, through `sglab run "
                                "--full`): `sglab erf --exhaustive --out "),
            std::string::npos)
      << section("erf");
  EXPECT_TRUE(section("erf").starts_with("## erf\n\n`sglab erf --out "))
      << "the step itself ran without --exhaustive: " << section("erf");
  EXPECT_NE(section("stability").find("Form: full.\n"), std::string::npos) << section("stability");
  // GPU costs: navi21 in GLSL, the full form every chip in both languages.
  EXPECT_TRUE(
      section("gpucost").starts_with("## gpucost\n\n`sglab gpucost --skip-unavailable --out "))
      << section("gpucost");
  EXPECT_NE(section("gpucost").find(" --family navi21`"), std::string::npos) << section("gpucost");
  EXPECT_NE(section("gpucost").find("Form: quick ("), std::string::npos) << section("gpucost");
  EXPECT_NE(section("gpucost").find("`sglab gpucost --skip-unavailable --lang both --out "),
            std::string::npos)
      << section("gpucost");
  EXPECT_NE(index.find("Produced by `sglab run --out "), std::string::npos);
  EXPECT_NE(index.find(" --quick --skip fit"), std::string::npos) << index.substr(0, 400);
}

TEST(RunCommand, FullAndQuickAreExclusive) {
  HostileOut dir;
  const auto r = sglab::test::run_sglab({"run", "--full", "--quick", "--out", dir.out.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(dir.out));
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

// The folder of `out.staging-PID-*` beside `out`, or an empty path.
fs::path staging_of(const fs::path& out, pid_t pid) {
  const std::string prefix = fmt::format("{}.staging-{}-", out.filename().string(), pid);
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    if (e.path().filename().string().rfind(prefix, 0) == 0) return e.path();
  return {};
}

TEST(RunCommand, InterruptedRunLeavesThePreviousOutputAsItWas) {
  sglab::test::TempDir base("run-interrupted");
  const fs::path out = base.path / "out";
  // The sweep and stability steps only (the run is interrupted in the first).
  const std::vector<std::string> args = {
      "run",    "--quick", "--out",  out.string(), "--skip", "fit",    "--skip", "erf",
      "--skip", "claims",  "--skip", "bench",      "--skip", "pareto", "--skip", "pareto-cpu",
      "--skip", "figures", "--skip", "envmap",     "--skip", "gpucost"};
  // A complete earlier output, its files marked so that a change shows.
  ASSERT_EQ(sglab::test::run_sglab(args).exit_code, 0);
  for (const char* name : {"index.md", "logs/sweep.log", "sweep/summary.csv"})
    sglab::io::write_file_atomic(out / name, fmt::format("previous {}\n", name));
  const auto before = files_under(out);
  for (const int signal : {SIGINT, SIGTERM}) {
    const pid_t pid = spawn_sglab(args);
    ASSERT_GT(pid, 0);
    // Interrupt it while its first step (sweep) is writing its log.
    fs::path partial_log;
    for (int i = 0; i < 2000 && !fs::exists(partial_log); ++i) {
      ::usleep(10'000);
      if (const fs::path staging = staging_of(out, pid); !staging.empty())
        partial_log = staging / "logs" / ".sweep.log.partial";
    }
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
  EXPECT_NE(after.at("sweep/summary.csv"), before.at("sweep/summary.csv"));
  EXPECT_NE(after.at("index.md").find("## stability"), std::string::npos);
  for (const auto& [name, text] : after)
    EXPECT_EQ(name.find(".partial"), std::string::npos) << name;
}

// ---- `run --out D` replaces only what it wrote ------------------------------------

// `sglab run` with every step skipped: it writes only index.md, logs/ and
// its manifest, at once.
std::vector<std::string> empty_run(const fs::path& out) {
  std::vector<std::string> args = {"run", "--out", out.string()};
  for (const char* step : {"fit", "sweep", "erf", "stability", "claims", "bench", "gpucost",
                           "pareto", "pareto-cpu", "figures", "envmap"})
    args.insert(args.end(), {"--skip", step});
  return args;
}

// Every entry under `dir` (files with their content, folders, links), by path
// relative to it, not following links.
std::map<std::string, std::string> everything_under(const fs::path& dir) {
  std::map<std::string, std::string> all;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = fs::relative(e.path(), dir).generic_string();
    all[name] = e.is_symlink()        ? "link to " + fs::read_symlink(e.path()).string()
                : e.is_regular_file() ? sglab::io::read_file(e.path())
                                      : "folder";
  }
  return all;
}

// Runs in `dir` with $HOME set to `home` for the lifetime of the object.
struct InFolderWithHome {
  fs::path cwd = fs::current_path();
  std::string home = std::getenv("HOME") ? std::getenv("HOME") : "";
  InFolderWithHome(const fs::path& dir, const fs::path& home_dir) {
    fs::current_path(dir);
    ::setenv("HOME", home_dir.c_str(), 1);
  }
  ~InFolderWithHome() {
    fs::current_path(cwd);
    ::setenv("HOME", home.c_str(), 1);
  }
};

TEST(RunCommand, NeverReplacesTheCheckoutHomeOrAFolderItDidNotWrite) {
  sglab::test::TempDir base("run-refuses");
  // A checkout with its .git and an untracked note, the working folder below it.
  const fs::path checkout = base.path / "checkout";
  fs::create_directories(checkout / "data" / "constants");
  fs::create_directories(checkout / "include" / "sglab");
  fs::create_directories(checkout / ".git");
  fs::create_directories(checkout / "work");
  sglab::io::write_file_atomic(checkout / "notes.txt", "untracked notes\n");
  const fs::path home = base.path / "home";
  fs::create_directories(home);
  sglab::io::write_file_atomic(home / ".profile", "mine\n");
  const fs::path repo = base.path / "repo";  // another folder holding .git
  fs::create_directories(repo / ".git");
  const fs::path precious = base.path / "precious";  // a folder of the user's
  fs::create_directories(precious);
  sglab::io::write_file_atomic(precious / "precious.txt", "keep\n");
  const fs::path tarball = base.path / "tarball";  // a checkout without .git
  fs::create_directories(tarball / "data" / "constants");
  fs::create_directories(tarball / "include" / "sglab");
  fs::create_directory_symlink(checkout, base.path / "link-to-checkout");
  const auto before = everything_under(base.path);

  struct Case {
    std::string out, why;
  };
  const Case cases[] = {
      {".", "is the working folder"},
      {"..", "is the project root"},
      {checkout.string(), "is the project root"},
      {(checkout / "work" / ".." / "..").string(), "is an ancestor of the project root"},
      {base.path.string(), "is an ancestor of the project root"},
      {"/", "is the root folder"},
      {home.string(), "is the home folder"},
      {(base.path / "link-to-checkout").string(), "is the project root"},
      {repo.string(), "holds .git"},
      {tarball.string(), "is an sglab checkout"},
      {precious.string(), "is not empty and has no sglab-output.json"},
  };
  {
    const InFolderWithHome here(checkout / "work", home);
    for (const Case& c : cases) {
      const auto r = sglab::test::run_sglab(empty_run(c.out));
      EXPECT_EQ(r.exit_code, 2) << c.out << ": " << r.output;
      EXPECT_NE(r.output.find("--out " + c.out + ": " + c.why), std::string::npos)
          << c.out << ": " << r.output;
    }
  }
  EXPECT_EQ(everything_under(base.path), before) << "a refused run changed something";
}

TEST(RunCommand, ReplacesAnEarlierOutputButNothingItDidNotWrite) {
  sglab::test::TempDir base("run-replaces");
  const fs::path out = base.path / "out";
  // Absent, then its own earlier output: replaced.
  auto r = sglab::test::run_sglab(empty_run(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto manifest = nlohmann::json::parse(sglab::io::read_file(out / "sglab-output.json"));
  EXPECT_EQ(manifest.at("format"), "sglab-output");
  EXPECT_EQ(manifest.at("entries"), nlohmann::json::array({"index.md", "logs/"}));
  sglab::io::write_file_atomic(out / "index.md", "edited\n");  // a listed file may change
  r = sglab::test::run_sglab(empty_run(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(sglab::io::read_file(out / "index.md"), "edited\n");
  // A file it did not write, anywhere inside: refused, the file kept.
  sglab::io::write_file_atomic(out / "logs" / "mine.txt", "keep\n");
  const auto before = everything_under(base.path);
  r = sglab::test::run_sglab(empty_run(out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((out / "logs" / "mine.txt").string()), std::string::npos) << r.output;
  EXPECT_EQ(everything_under(base.path), before);
  // A folder it listed turned into a link to the user's files: refused, nothing followed.
  fs::remove_all(out / "logs");
  const fs::path elsewhere = base.path / "elsewhere";
  fs::create_directories(elsewhere);
  sglab::io::write_file_atomic(elsewhere / "f.txt", "keep\n");
  fs::create_directory_symlink(elsewhere, out / "logs");
  r = sglab::test::run_sglab(empty_run(out));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(sglab::io::read_file(elsewhere / "f.txt"), "keep\n");
  // An empty folder, and a link to one (the link stays, its folder is replaced).
  const fs::path empty = base.path / "empty", link = base.path / "link";
  fs::create_directories(empty);
  fs::create_directory_symlink(empty, link);
  r = sglab::test::run_sglab(empty_run(link));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::is_regular_file(empty / "index.md"));
  // Only the outputs are left: no staging folder beside them.
  for (const auto& e : fs::directory_iterator(base.path))
    EXPECT_EQ(e.path().filename().string().find(".staging-"), std::string::npos) << e.path();
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
                   : sglab::reference::reference_engine().evaluate(kappa, c).irradiance;
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
