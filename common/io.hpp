// common/io.hpp — file input and output shared by every command: bounded
// reads of input files, atomic writes (temporary + rename, so no half-written
// file is ever left, never over anything but a regular file) and terminal
// progress that is quiet when stderr is not a terminal.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sglab::io {

// Bad input from the user (a malformed or refused file, an out-of-range
// value): the message names what was wrong. `sglab` exits with code 2
// (app/commands.hpp, run_and_map_exit_code; app::InputError is this type).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes `content` to `path` as io::write_files_atomic (common/atomic_files.hpp)
// writes one file: a temporary in the same directory renamed over `path`;
// parent directories created; an empty path or one that exists and is not a
// regular file refused (InputError). Throws std::runtime_error naming the
// path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Reads a whole file that sglab wrote itself (a log, a step's Markdown);
// throws std::runtime_error naming the path on failure. Input from the user
// goes through read_input_file.
std::string read_file(const std::filesystem::path& path);

// The operating system's message for the errno value `err`.
std::string os_reason(int err);

// What is at `path`, not following a final symbolic link, for messages: "a
// regular file", "a directory", "a FIFO", "a symbolic link", "a character
// device", "a block device", "a socket" (or "an unknown file type"); empty
// when nothing is there.
std::string file_type_name(const std::filesystem::path& path);

// The whole of the user's input file `path` (`what` names it in messages,
// e.g. "a scene file"), which must be a regular file (a symbolic link to one
// is fine) of at most `max_bytes`: never more than max_bytes + 1 bytes are
// read, so /dev/zero, a FIFO or a huge file cannot exhaust memory or block.
// Throws InputError naming the path and what is wrong (missing, unreadable,
// not a regular file and what it is, too large).
std::string read_input_file(const std::filesystem::path& path, std::size_t max_bytes,
                            std::string_view what);

// Where a Progress line goes: `terminal` says whether anything is drawn at
// all, `write` receives every redraw. standard_error() is stderr, drawn only
// when stderr is a terminal; tests inject the flag and a string sink.
struct ProgressSink {
  bool terminal = false;
  std::function<void(std::string_view)> write;
  static ProgressSink standard_error();
};

// A progress line, redrawn in place (at most every 100 ms, and when the count
// reaches the total), shown only on a terminal: under ctest, in pipes and
// redirected runs nothing extra is printed. Thread-safe `advance` and `note`.
// Line: "label: done/total (p%) 12.3s  note"; with total 0 (open-ended work,
// such as a fit's solves) "label: done 12.3s  note". `note` redraws at once. `finish` clears it.
class Progress {
 public:
  Progress(std::string label, std::size_t total);  // on stderr
  Progress(std::string label, std::size_t total, ProgressSink sink);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void advance(std::size_t n = 1);
  // Replaces the text shown after the count (what the work is doing now).
  void note(std::string status);
  void finish();

 private:
  struct Impl;
  Impl* impl_;
};

bool stderr_is_terminal();

// The sglab checkout holding `start` (made absolute): the nearest folder at or
// above it with both data/constants and include/sglab; nullopt when none.
// Every default path of the tools (constants, header, cost table, results)
// is found from the working directory this way, never compiled in.
std::optional<std::filesystem::path> find_project_root(const std::filesystem::path& start);

// Runs `argv[0]` (looked up in PATH) with the argument vector `argv`: no
// shell, so arguments are passed exactly as given. Standard input is
// /dev/null; standard output and error go to `output` (created or truncated,
// relative to `cwd` if relative) or are discarded when it is empty; `cwd`,
// when not empty, is the child's working directory; `environment`, when
// given, is the child's whole environment ("NAME=value" entries) instead of
// this process's. Returns the exit code, 128 + the signal number if it was
// killed, or -1 if it could not be started.
int run_program(const std::vector<std::string>& argv, const std::filesystem::path& cwd = {},
                const std::filesystem::path& output = {},
                const std::optional<std::vector<std::string>>& environment = std::nullopt);

// `text` without a leading UTF-8 byte-order mark (EF BB BF), which some
// editors and spreadsheet programs write at the start of a CSV file.
std::string_view strip_utf8_bom(std::string_view text);

}  // namespace sglab::io
