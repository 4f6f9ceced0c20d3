// tests/test_support.hpp — shared helpers for the GoogleTest suites.
#pragma once

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <ostream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sglab/registry.hpp>

namespace sglab {
// Test names and failure messages show a method's id.
inline void PrintTo(const Method& m, std::ostream* os) { *os << m.id; }
}  // namespace sglab

namespace sglab::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// |got/want − 1|, or |got| where want is 0.
inline double rel_err(double got, double want) {
  return want == 0 ? std::abs(got) : std::abs(got / want - 1);
}

// A suite parameterized over methods names each instance by the method's id.
inline std::string method_name(const ::testing::TestParamInfo<Method>& info) {
  return std::string(info.param.id);
}

// Writes text to p, replacing what was there.
inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

// A value printed exactly (hex float) and in decimal, for failure messages.
template <class T>
std::string hex(T x) {
  return fmt::format("{:a} ({:.9g})", static_cast<double>(x), static_cast<double>(x));
}

// The standard sweep (docs/quantities.md).
inline std::vector<double> standard_kappas() {
  std::vector<double> k;
  for (int i = -12; i <= 16; ++i) k.push_back(std::pow(10.0, i / 4.0));
  return k;
}
inline std::vector<double> standard_cosines() {
  std::vector<double> c;
  for (int i = 0; i <= 40; ++i) c.push_back(-1.0 + 2.0 * i / 40.0);
  return c;
}

// The exit code and captured output of a program run by run_program.
struct CommandResult {
  int exit_code;
  std::string output;
};

// Splits at blanks into an argument vector (no quoting, no shell; for fixed
// option strings in tests): words("--kappa 1:10:5") == {"--kappa", "1:10:5"}.
inline std::vector<std::string> words(std::string_view text) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < text.size() && text[j] != ' ' && text[j] != '\t') ++j;
    if (j > i) out.emplace_back(text.substr(i, j - i));
    i = j;
  }
  return out;
}

// The checkout this test binary was built from (the folder above tests/).
inline std::filesystem::path checkout_dir() {
  return std::filesystem::path(SGLAB_TEST_SOURCE_DIR) / "..";
}

// The checkout as a path (its folders are named from it: kRoot / "data").
inline const std::filesystem::path kRoot =
    std::filesystem::path(SGLAB_TEST_SOURCE_DIR).parent_path();
// The runtime's generated constants header in the checkout.
inline const std::filesystem::path kConstantsHeader = kRoot / "include" / "sglab" / "constants.hpp";

// The registered irradiance method `id` (throws if there is none).
inline const Method& method(std::string_view id) {
  const Method* m = find_method(irradiance_methods, id);
  if (!m) throw std::runtime_error("method not registered: " + std::string(id));
  return *m;
}

// Runs in `dir` for the lifetime of the object (run_sglab spawns with our cwd).
struct WorkingDirectory {
  std::filesystem::path old = std::filesystem::current_path();
  explicit WorkingDirectory(const std::filesystem::path& dir) {
    std::filesystem::current_path(dir);
  }
  ~WorkingDirectory() { std::filesystem::current_path(old); }
};

// Makes `dir` a project as `sglab export` and gpucost find one: include/sglab/
// and data/results/ created, the checkout's data/constants copied in.
inline void make_scratch_project(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir / "include" / "sglab");
  fs::create_directories(dir / "data" / "results");
  fs::copy(checkout_dir() / "data" / "constants", dir / "data" / "constants");
}

// A fresh folder under the system's temporary directory, named after `name`
// and the process id with a random suffix (mkdtemp), so that no two tests,
// processes (ctest -j) or TempDirs of one test ever share it; removed with
// everything in it when the object goes. `name` may hold any characters but
// '/' (tests use spaces, quotes and semicolons to check that paths are taken
// literally).
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name) {
    std::string pattern = (std::filesystem::temp_directory_path() /
                           fmt::format("sglab-test-{}-{}-XXXXXX", name, ::getpid()))
                              .string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::system_error(errno, std::generic_category(), "mkdtemp " + pattern);
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// Runs a program with an argument vector (no shell: paths with spaces, quotes
// or semicolons are passed as they are), capturing stdout and, unless
// merge_stderr is false (stdout only, e.g. to parse JSON), stderr. Standard
// input is /dev/null. exit_code is -1 when the program did not exit normally.
inline CommandResult run_program(const std::vector<std::string>& argv, bool merge_stderr = true) {
  CommandResult r{-1, {}};
  if (argv.empty()) return r;
  int fds[2];
  if (::pipe(fds) != 0) return r;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  if (merge_stderr)
    posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  else
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid;
  const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc == 0) {
    char buffer[4096];
    ssize_t n;
    while ((n = ::read(fds[0], buffer, sizeof buffer)) > 0)
      r.output.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (rc != 0) return r;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

#ifdef SGLAB_BINARY
// `sglab ARGS...` with an argument vector: run_sglab({"sweep", "--out", dir}).
inline CommandResult run_sglab(std::vector<std::string> args, bool merge_stderr = true) {
  args.insert(args.begin(), SGLAB_BINARY);
  return run_program(args, merge_stderr);
}
#endif

// The cells of a Markdown pipe-table row "| a | b \| c |" (trimmed, split at unescaped '|',
// "\|" unescaped): {"a", "b | c"}.
inline std::vector<std::string> markdown_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (line[i] == '|') {
      const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

}  // namespace sglab::test
