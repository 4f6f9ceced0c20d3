// tests/test_support.hpp — shared helpers for the GoogleTest suites.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace sglab::test {

// A value printed exactly (hex float) and in decimal, for failure messages.
template <class T> std::string hex(T x) { return fmt::format("{:a} ({:.9g})", static_cast<double>(x), static_cast<double>(x)); }

// SPEC §4 standard sweep.
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

// Runs a shell command, returning its exit code and capturing stdout and,
// unless merge_stderr is false (stdout only, e.g. to parse JSON), stderr.
struct CommandResult {
  int exit_code;
  std::string output;
};
inline CommandResult run_command(const std::string& command, bool merge_stderr = true) {
  CommandResult r{-1, {}};
  FILE* pipe = ::popen((command + (merge_stderr ? " 2>&1" : " 2>/dev/null")).c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace sglab::test
