#include "common/io.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace sglab::io {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read {}", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string file_type_name(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  switch (fs::symlink_status(path, ec).type()) {
    case fs::file_type::not_found:
    case fs::file_type::none:
      return "";
    case fs::file_type::regular:
      return "a regular file";
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::symlink:
      return "a symbolic link";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "an unknown file type";
  }
}

std::string os_reason(int err) { return std::error_code(err, std::generic_category()).message(); }

namespace {

// Appends what `fd` holds to `out`, at most `limit` bytes; returns 0 or the errno.
int read_at_most(int fd, std::size_t limit, std::string& out) {
  char buffer[65536];
  while (out.size() < limit) {
    const ssize_t n = ::read(fd, buffer, std::min(sizeof buffer, limit - out.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) break;
    out.append(buffer, static_cast<std::size_t>(n));
  }
  return 0;
}

}  // namespace

std::string read_input_file(const std::filesystem::path& path, std::size_t max_bytes,
                            std::string_view what) {
  namespace fs = std::filesystem;
  const std::string name = path.string();
  if (path.empty()) throw InputError(fmt::format("an empty file name for {}", what));
  std::error_code ec;
  // follows symbolic links: a link to a file is fine
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found)
    throw InputError(fmt::format("{}: no such file ({})", name, what));
  if (ec) throw InputError(fmt::format("{}: cannot read: {}", name, ec.message()));
  const auto refuse_type = [&](const std::string& type) {
    return InputError(
        fmt::format("{}: is {}, not a regular file ({} must be one)", name, type, what));
  };
  if (st.type() != fs::file_type::regular) {
    const std::string type = file_type_name(path);
    throw refuse_type(type == "a symbolic link"
                          ? "a symbolic link to " + file_type_name(fs::canonical(path, ec))
                          : type);
  }
  // O_NONBLOCK: should a FIFO replace the file after the check, opening it does not wait for a
  // writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) throw InputError(fmt::format("{}: cannot read: {}", name, os_reason(errno)));
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    ::close(fd);
    throw refuse_type("no longer a regular file");
  }
  const auto too_large = [&](std::uintmax_t size) {
    return InputError(fmt::format("{}: {} bytes, more than the {} bytes {} may have", name, size,
                                  max_bytes, what));
  };
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
    ::close(fd);
    throw too_large(static_cast<std::uintmax_t>(info.st_size));
  }
  std::string text;
  text.reserve(static_cast<std::size_t>(info.st_size));
  // one byte more: the file may have grown since fstat
  const int err = read_at_most(fd, max_bytes + 1, text);
  ::close(fd);
  if (err != 0) throw InputError(fmt::format("{}: cannot read: {}", name, os_reason(err)));
  if (text.size() > max_bytes) throw too_large(text.size());
  return text;
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

std::optional<std::filesystem::path> find_project_root(const std::filesystem::path& start) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path dir = fs::absolute(start, ec);
  if (ec) return std::nullopt;
  for (;;) {
    if (fs::is_directory(dir / "data" / "constants", ec) &&
        fs::is_directory(dir / "include" / "sglab", ec))
      return dir;
    if (!dir.has_parent_path() || dir.parent_path() == dir) return std::nullopt;
    dir = dir.parent_path();
  }
}

int run_program(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                const std::filesystem::path& output,
                const std::optional<std::vector<std::string>>& environment) {
  if (argv.empty()) return -1;
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return -1;
  // In order: the working directory first, so that a relative output path is
  // opened inside it.
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO,
                                   output.empty() ? "/dev/null" : output.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // A program named by a relative path is resolved before the chdir.
  std::string program = argv[0];
  if (!cwd.empty() && program.find('/') != std::string::npos)
    program = std::filesystem::absolute(program).string();
  std::vector<char*> args;
  args.push_back(program.data());
  for (std::size_t i = 1; i < argv.size(); ++i) args.push_back(const_cast<char*>(argv[i].c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  if (environment) {
    for (const std::string& entry : *environment) env.push_back(const_cast<char*>(entry.c_str()));
    env.push_back(nullptr);
  }
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(),
                                environment ? env.data() : environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

std::string_view strip_utf8_bom(std::string_view text) {
  constexpr std::string_view bom = "\xEF\xBB\xBF";
  if (text.substr(0, bom.size()) == bom) text.remove_prefix(bom.size());
  return text;
}

ProgressSink ProgressSink::standard_error() {
  return {stderr_is_terminal(), [](std::string_view text) {
            std::fwrite(text.data(), 1, text.size(), stderr);
            std::fflush(stderr);
          }};
}

struct Progress::Impl {
  std::string label;
  std::size_t total;
  std::atomic<std::size_t> done{0};
  ProgressSink sink;
  std::mutex mutex;
  std::string status;  // guarded by mutex
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last{};
  bool drawn = false;
  bool finished = false;

  // Redraws if due; the caller holds `mutex`.
  void draw(std::size_t count, bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && drawn && now - last < std::chrono::milliseconds(100) &&
        (total == 0 || count < total))
      return;
    last = now;
    drawn = true;
    const double secs = std::chrono::duration<double>(now - start).count();
    std::string line;
    if (total == 0)
      line = fmt::format("\r{}: {} {:.1f}s", label, count, secs);
    else
      line = fmt::format("\r{}: {}/{} ({:.0f}%) {:.1f}s", label, count, total,
                         100.0 * static_cast<double>(count) / static_cast<double>(total), secs);
    if (!status.empty()) line += "  " + status;
    line += "\033[K";  // clear what a longer previous line left
    sink.write(line);
  }
};

Progress::Progress(std::string label, std::size_t total)
    : Progress(std::move(label), total, ProgressSink::standard_error()) {}

Progress::Progress(std::string label, std::size_t total, ProgressSink sink) : impl_(new Impl) {
  impl_->label = std::move(label);
  impl_->total = total;
  impl_->sink = std::move(sink);
  if (!impl_->sink.write) impl_->sink.terminal = false;
}

Progress::~Progress() {
  finish();
  delete impl_;
}

void Progress::advance(std::size_t n) {
  const std::size_t done = impl_->done.fetch_add(n) + n;
  if (!impl_->sink.terminal) return;
  std::unique_lock lock(impl_->mutex, std::try_to_lock);
  if (!lock.owns_lock() || impl_->finished) return;
  impl_->draw(done, false);
}

void Progress::note(std::string status) {
  if (!impl_->sink.terminal) return;
  std::lock_guard lock(impl_->mutex);
  if (impl_->finished) return;
  impl_->status = std::move(status);
  impl_->draw(impl_->done.load(), true);  // a new stage is shown at once (notes are rare)
}

void Progress::finish() {
  if (!impl_->sink.terminal) return;
  std::lock_guard lock(impl_->mutex);
  if (impl_->finished) return;
  impl_->finished = true;
  if (impl_->drawn) impl_->sink.write("\r\033[K");
}

}  // namespace sglab::io
