#include "io.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace sglab::io {

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  namespace fs = std::filesystem;
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot create directory {}: {}", parent.string(), ec.message()));
  const fs::path tmp = parent / fmt::format(".{}.{}.tmp", path.filename().string(), ::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("cannot write {}", tmp.string()));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      fs::remove(tmp, ec);
      throw std::runtime_error(fmt::format("cannot write {}", tmp.string()));
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ec2;
    fs::remove(tmp, ec2);
    throw std::runtime_error(fmt::format("cannot replace {}: {}", path.string(), ec.message()));
  }
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read {}", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

int run_program(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                const std::filesystem::path& output) {
  if (argv.empty()) return -1;
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return -1;
  // In order: the working directory first, so that a relative output path is
  // opened inside it.
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, output.empty() ? "/dev/null" : output.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // A program named by a relative path is resolved before the chdir.
  std::string program = argv[0];
  if (!cwd.empty() && program.find('/') != std::string::npos) program = std::filesystem::absolute(program).string();
  std::vector<char*> args;
  args.push_back(program.data());
  for (std::size_t i = 1; i < argv.size(); ++i) args.push_back(const_cast<char*>(argv[i].c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
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

struct Progress::Impl {
  std::string label;
  std::size_t total;
  std::atomic<std::size_t> done{0};
  bool enabled;
  std::mutex mutex;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last{};
  bool finished = false;
};

Progress::Progress(std::string label, std::size_t total) : impl_(new Impl) {
  impl_->label = std::move(label);
  impl_->total = total;
  impl_->enabled = stderr_is_terminal();
}

Progress::~Progress() {
  finish();
  delete impl_;
}

void Progress::advance(std::size_t n) {
  const std::size_t done = impl_->done.fetch_add(n) + n;
  if (!impl_->enabled) return;
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock lock(impl_->mutex, std::try_to_lock);
  if (!lock.owns_lock()) return;
  if (now - impl_->last < std::chrono::milliseconds(100) && done < impl_->total) return;
  impl_->last = now;
  const double secs = std::chrono::duration<double>(now - impl_->start).count();
  const double pct = impl_->total ? 100.0 * static_cast<double>(done) / static_cast<double>(impl_->total) : 100.0;
  std::fprintf(stderr, "\r%s: %zu/%zu (%.0f%%) %.1fs   ", impl_->label.c_str(), done, impl_->total, pct, secs);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!impl_->enabled || impl_->finished) return;
  impl_->finished = true;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
}

}  // namespace sglab::io
