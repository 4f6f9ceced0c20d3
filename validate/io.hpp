// validate/io.hpp — file output shared by every command: atomic writes
// (temporary + rename, so no half-written file is ever left) and terminal
// progress that is quiet when stderr is not a terminal.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sglab::io {

// Writes `content` to `path` via a temporary in the same directory and an
// atomic rename. Creates parent directories. Throws std::runtime_error naming
// the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Reads a whole file; throws std::runtime_error naming the path on failure.
std::string read_file(const std::filesystem::path& path);

// A progress line on stderr, redrawn in place, shown only when stderr is a
// terminal. Thread-safe `advance`.
class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void advance(std::size_t n = 1);
  void finish();

 private:
  struct Impl;
  Impl* impl_;
};

bool stderr_is_terminal();

// Runs `argv[0]` (looked up in PATH) with the argument vector `argv`: no
// shell, so arguments are passed exactly as given. Standard input is
// /dev/null; standard output and error go to `output` (created or truncated,
// relative to `cwd` if relative) or are discarded when it is empty; `cwd`,
// when not empty, is the child's working directory. Returns the exit code,
// 128 + the signal number if it was killed, or -1 if it could not be started.
int run_program(const std::vector<std::string>& argv, const std::filesystem::path& cwd = {},
                const std::filesystem::path& output = {});

// `text` without a leading UTF-8 byte-order mark (EF BB BF), which some
// editors and spreadsheet programs write at the start of a CSV file.
std::string_view strip_utf8_bom(std::string_view text);

}  // namespace sglab::io
