#include "common/atomic_files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>  // renameat2
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/args.hpp"  // quote_escaped
#include "common/io.hpp"
#include "common/json_input.hpp"

namespace sglab::io {

namespace fs = std::filesystem;

namespace {

fs::path temporary_for(const fs::path& path) {
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  return parent / fmt::format(".{}.{}.tmp", path.filename().string(), ::getpid());
}

// Writes `content` to a new file `tmp`; on failure removes it and returns the errno.
// A leftover of the same name (a killed run with the same pid) is removed
// first, and the file is created, never opened through a link someone left there.
int write_new_file(const fs::path& tmp, std::string_view content) {
  ::unlink(tmp.c_str());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) return errno;
  const char* p = content.data();
  std::size_t left = content.size();
  int err = 0;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno;
      break;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (err == 0 && ::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err != 0) ::unlink(tmp.c_str());
  return err;
}

struct Pending {
  fs::path path, tmp;
  std::optional<std::string> previous;  // the content it had, if it was a regular file
  bool replaced = false;
};

// ---- temporaries removed on SIGINT, SIGTERM and SIGHUP ----------------------------
//
// The paths of the temporaries that exist now, for the signal handler: a fixed
// table of lock-free atomic pointers (the handler may only read memory without
// locks), each pointing into a path owned by the writer that registered it.

constexpr std::size_t kTemporarySlots = 1024;
std::array<std::atomic<const char*>, kTemporarySlots> g_temporaries{};
std::atomic<bool> g_dying{false};
static_assert(std::atomic<const char*>::is_always_lock_free);
static_assert(std::atomic<bool>::is_always_lock_free);
constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temporaries_and_end(int signal) {
  g_dying.store(true);
  for (const auto& slot : g_temporaries)
    if (const char* path = slot.load()) ::unlink(path);
  // SA_RESETHAND restored the default action; the signal, blocked while this
  // handler runs, ends the process when it returns.
  ::raise(signal);
}

// Installs the handler for each cleanup signal whose action is the default.
void install_cleanup_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int signal : kCleanupSignals) {
      struct sigaction old {};
      if (::sigaction(signal, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) ||
          old.sa_handler != SIG_DFL)
        continue;
      struct sigaction action {};
      action.sa_handler = remove_temporaries_and_end;
      sigemptyset(&action.sa_mask);
      action.sa_flags = SA_RESETHAND;
      ::sigaction(signal, &action, nullptr);
    }
  });
}

// The temporaries one writer registered, unregistered when it goes. A path
// must stay where it is (not be moved or changed) while registered. Should
// every slot be taken (more than kTemporarySlots temporaries at once), the
// rest are not removed on a signal.
class RegisteredTemporaries {
 public:
  RegisteredTemporaries() { install_cleanup_handlers(); }
  ~RegisteredTemporaries() {
    for (const std::size_t i : slots_) g_temporaries[i].store(nullptr);
    // A signal handler may be reading the paths now: they must outlive it,
    // and it ends the process.
    if (!slots_.empty() && g_dying.load())
      for (;;) ::pause();
  }
  RegisteredTemporaries(const RegisteredTemporaries&) = delete;
  RegisteredTemporaries& operator=(const RegisteredTemporaries&) = delete;

  void add(const fs::path& tmp) {
    for (std::size_t i = 0; i < kTemporarySlots; ++i) {
      const char* expected = nullptr;
      if (g_temporaries[i].compare_exchange_strong(expected, tmp.c_str())) {
        slots_.push_back(i);
        return;
      }
    }
  }

 private:
  std::vector<std::size_t> slots_;
};

}  // namespace

void check_output_folder(const fs::path& dir) {
  if (dir.empty()) throw InputError("an empty output folder name (give a folder, e.g. --out out)");
  std::error_code ec;
  // follows symbolic links: a link to a folder is fine
  const fs::file_status st = fs::status(dir, ec);
  if (st.type() == fs::file_type::not_found || st.type() == fs::file_type::directory) return;
  const std::string type = file_type_name(dir);
  throw InputError(fmt::format(
      "{}: is {}, not a folder; refusing to write into it", dir.string(),
      type == "a symbolic link" ? "a symbolic link to something that is not a folder" : type));
}

void check_output_path(const fs::path& path) {
  if (path.empty()) throw InputError("an empty output file name");
  const std::string type = file_type_name(path);
  if (!type.empty() && type != "a regular file")
    throw InputError(
        fmt::format("{}: is {}, not a regular file; refusing to replace it", path.string(), type));
  if (path.has_parent_path()) check_output_folder(path.parent_path());
}

namespace {

struct FileView {
  const fs::path& path;
  std::string_view content;
};

void write_all(const std::vector<FileView>& files) {
  for (const FileView& f : files) check_output_path(f.path);
  std::vector<Pending> pending;
  pending.reserve(files.size());  // no reallocation: the registered paths stay where they are
  std::vector<fs::path> restores(files.size());
  RegisteredTemporaries registered;  // destroyed first: unregistered before the paths go
  const auto discard_temporaries = [&] {
    for (const Pending& p : pending)
      if (!p.replaced) ::unlink(p.tmp.c_str());
  };
  // 1. Every temporary, before any destination changes.
  for (const FileView& f : files) {
    const fs::path parent = f.path.has_parent_path() ? f.path.parent_path() : fs::path(".");
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec) {
      discard_temporaries();
      throw std::runtime_error(fmt::format("cannot write {}: cannot create directory {}: {}",
                                           f.path.string(), parent.string(), ec.message()));
    }
    Pending p{f.path, temporary_for(f.path), std::nullopt, false};
    if (fs::is_regular_file(f.path, ec)) {
      try {
        p.previous = read_file(f.path);
      } catch (const std::exception&) {
        discard_temporaries();
        throw std::runtime_error(
            fmt::format("cannot write {}: cannot read its current content ({})", f.path.string(),
                        os_reason(errno)));
      }
    }
    pending.push_back(std::move(p));
    const Pending& added = pending.back();
    registered.add(added.tmp);
    if (const int err = write_new_file(added.tmp, f.content)) {
      discard_temporaries();
      throw std::runtime_error(fmt::format("cannot write {}: {} (temporary {})", f.path.string(),
                                           os_reason(err), added.tmp.string()));
    }
  }
  // 2. The renames; on failure put back what was replaced.
  for (std::size_t i = 0; i < pending.size(); ++i) {
    Pending& p = pending[i];
    if (::rename(p.tmp.c_str(), p.path.c_str()) == 0) {
      p.replaced = true;
      continue;
    }
    const int err = errno;
    std::string message = fmt::format("cannot write {}: {}", p.path.string(), os_reason(err));
    discard_temporaries();
    std::string restored;
    for (std::size_t j = 0; j < i; ++j) {
      const Pending& done = pending[j];
      if (done.previous) {
        const fs::path& tmp = restores[j] = temporary_for(done.path);
        registered.add(tmp);
        const int e = write_new_file(tmp, *done.previous);
        if (e == 0 && ::rename(tmp.c_str(), done.path.c_str()) == 0) {
          restored += fmt::format(" {}", done.path.string());
        } else {
          ::unlink(tmp.c_str());
          message += fmt::format("; could not restore {}: {}", done.path.string(),
                                 os_reason(e ? e : errno));
        }
      } else {
        ::unlink(done.path.c_str());
        restored += fmt::format(" {} (removed)", done.path.string());
      }
    }
    if (!restored.empty()) message += "; restored" + restored;
    throw std::runtime_error(message);
  }
}

}  // namespace

void write_files_atomic(const std::vector<FileContent>& files) {
  std::vector<FileView> views;
  for (const FileContent& f : files) views.push_back({f.path, f.content});
  write_all(views);
}

void write_file_atomic(const fs::path& path, std::string_view content) {
  write_all({{path, content}});
}

// ---- a folder replaced as a whole ------------------------------------------------

namespace {

// The folder `dir` stands for: made absolute, with every symbolic link of
// the part that exists resolved (a link D gives the folder it names).
fs::path resolved_folder(const fs::path& dir) {
  fs::path t = fs::weakly_canonical(fs::absolute(dir));
  while (!t.has_filename() && t.has_relative_path()) t = t.parent_path();
  return t;
}

// Whether `a` is `b` or one of its ancestors (both resolved_folder paths).
bool is_same_or_ancestor(const fs::path& a, const fs::path& b) {
  auto ia = a.begin(), ib = b.begin();
  for (; ia != a.end() && ib != b.end(); ++ia, ++ib)
    if (*ia != *ib) return false;
  return ia == a.end();
}

// Why `target` may never be replaced, or empty.
std::string forbidden_reason(const fs::path& target) {
  std::error_code ec;
  if (target == target.root_path()) return "is the root folder";
  const auto check = [&](const fs::path& place, std::string_view name) -> std::string {
    if (place.empty()) return {};
    if (target == place) return fmt::format("is {}", name);
    if (is_same_or_ancestor(target, place))
      return fmt::format("is an ancestor of {} ({})", name, place.string());
    return {};
  };
  const fs::path cwd = fs::current_path(ec);
  if (!ec) {
    if (const auto root = find_project_root(cwd))
      if (auto why = check(resolved_folder(*root), "the project root"); !why.empty()) return why;
    if (auto why = check(resolved_folder(cwd), "the working folder"); !why.empty()) return why;
  }
  if (const char* home = std::getenv("HOME"); home && *home)
    if (auto why = check(resolved_folder(home), "the home folder ($HOME)"); !why.empty())
      return why;
  if (fs::exists(fs::symlink_status(target / ".git", ec))) return "holds .git";
  if (const auto root = find_project_root(target); root && *root == target)
    return "is an sglab checkout (it has data/constants and include/sglab)";
  return {};
}

// The entries a manifest lists; throws InputError naming the manifest.
std::set<std::string> read_manifest_entries(const fs::path& manifest) {
  const nlohmann::ordered_json doc =
      read_json_file(manifest, kMaxOutputManifestBytes, "an output manifest");
  const auto bad = [&](std::string_view why) {
    return InputError(fmt::format("{}: {}", manifest.string(), why));
  };
  if (!doc.is_object() || doc.value("format", "") != "sglab-output")
    throw bad("not an sglab output manifest (\"format\" must be \"sglab-output\")");
  if (!doc.contains("version") || doc.at("version") != 1) throw bad("\"version\" must be 1");
  if (!doc.contains("entries") || !doc.at("entries").is_array())
    throw bad("\"entries\" must be an array");
  std::set<std::string> entries;
  for (const auto& e : doc.at("entries")) {
    if (!e.is_string()) throw bad("every entry must be a string");
    const std::string name = e.get<std::string>();
    const fs::path p(name);
    const bool clean =
        !name.empty() && p.is_relative() && name.find('\0') == std::string::npos &&
        std::none_of(p.begin(), p.end(),
                     [](const fs::path& part) { return part == ".." || part == "."; }) &&
        p.lexically_normal().generic_string() == name;
    if (!clean)
      throw bad(fmt::format("entry {} is not a plain relative path", quote_escaped(name)));
    entries.insert(name);
  }
  return entries;
}

// `entry`'s name in a manifest: relative to `base`, '/'-separated, '/' after a folder.
std::string manifest_name(const fs::directory_entry& entry, const fs::path& base) {
  std::string name = entry.path().lexically_relative(base).generic_string();
  std::error_code ec;
  if (entry.is_directory(ec) && !entry.is_symlink(ec)) name += '/';
  return name;
}

// Every entry under `folder` (symbolic links not followed), as manifest names.
std::vector<std::string> entries_under(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    names.push_back(manifest_name(e, folder));
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

void check_replaceable_folder(const fs::path& dir, std::string_view option) {
  check_output_folder(dir);
  const auto refuse = [&](std::string_view why) {
    return InputError(
        fmt::format("{} {}: {}; it is replaced as a whole, so it must be absent, an empty folder "
                    "or an earlier output that its {} lists whole: choose another folder",
                    option, dir.string(), why, kOutputManifest));
  };
  const auto forbid = [&](std::string_view why) {
    return InputError(fmt::format(
        "{} {}: {}, which is never replaced as a whole (nor is /, $HOME, the working folder, the "
        "project root, an ancestor of these, a checkout or a folder holding .git): choose another "
        "folder",
        option, dir.string(), why));
  };
  std::error_code ec;
  if (fs::is_symlink(dir, ec) && !fs::exists(dir, ec))
    throw refuse("is a symbolic link to nothing");
  const fs::path target = resolved_folder(dir);
  if (const std::string why = forbidden_reason(target); !why.empty()) throw forbid(why);
  if (!fs::exists(target, ec) || fs::is_empty(target, ec)) return;
  const fs::path manifest = target / kOutputManifest;
  if (!fs::exists(fs::symlink_status(manifest, ec)))
    throw refuse(fmt::format("is not empty and has no {}", kOutputManifest));
  std::set<std::string> listed;
  try {
    listed = read_manifest_entries(manifest);
  } catch (const InputError& e) {
    throw refuse(e.what());
  }
  listed.insert(std::string(kOutputManifest));
  std::vector<std::string> foreign;
  try {
    for (const std::string& name : entries_under(target))
      if (!listed.count(name)) foreign.push_back(name);
  } catch (const fs::filesystem_error& e) {
    throw refuse(fmt::format("cannot be read whole: {}", e.what()));
  }
  if (!foreign.empty())
    throw refuse(fmt::format(
        "holds {} that its {} does not list{}", (target / foreign[0]).string(), kOutputManifest,
        foreign.size() > 1 ? fmt::format(" (and {} more)", foreign.size() - 1) : std::string()));
}

fs::path make_staging_folder(const fs::path& dir) {
  const fs::path target = resolved_folder(dir);
  fs::create_directories(target.parent_path());
  // mkdir, not mkdtemp: the folder gets the permissions the umask gives, as D would.
  std::random_device random;
  for (int attempt = 0;; ++attempt) {
    const fs::path staging =
        target.string() + fmt::format(".staging-{}-{:08x}", ::getpid(), random());
    if (::mkdir(staging.c_str(), 0777) == 0) return staging;
    if (errno != EEXIST || attempt == 100)
      throw std::runtime_error(fmt::format("cannot create the staging folder {}: {}",
                                           staging.string(), os_reason(errno)));
  }
}

void write_output_manifest(const fs::path& staging, std::string_view command) {
  nlohmann::ordered_json doc;
  doc["format"] = "sglab-output";
  doc["version"] = 1;
  doc["command"] = std::string(command);
  doc["entries"] = entries_under(staging);
  write_file_atomic(staging / kOutputManifest, doc.dump(1) + "\n");
}

std::string replace_folder(const fs::path& staging, const fs::path& dir, std::string_view option) {
  try {
    check_replaceable_folder(dir, option);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{} (the new output is in {})", e.what(), staging.string()));
  }
  const fs::path target = resolved_folder(dir);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(target, ec))) {
    fs::rename(staging, target);
    return {};
  }
  fs::path previous = staging;  // after the exchange
  if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) != 0) {
    previous = staging.string() + ".previous";
    fs::rename(target, previous);
    fs::rename(staging, target);
  }
  // Of the previous output, only what its manifest lists; children before
  // their folders (a name sorts after its folder's), never through a
  // symbolic link.
  const std::string kept =
      fmt::format("kept {}: the previous {} held files it did not write (they are there)\n",
                  previous.string(), dir.string());
  std::set<std::string> listed;
  try {
    if (fs::exists(fs::symlink_status(previous / kOutputManifest, ec)))
      listed = read_manifest_entries(previous / kOutputManifest);
  } catch (const InputError&) {
    return kept;  // changed since it was checked: nothing is removed
  }
  for (auto it = listed.rbegin(); it != listed.rend(); ++it) {
    const fs::path path = previous / fs::path(*it).parent_path();
    bool through_link = false;
    for (fs::path p = path; p != previous && p.has_relative_path(); p = p.parent_path())
      through_link = through_link || fs::is_symlink(p, ec);
    if (!through_link) fs::remove(previous / fs::path(*it), ec);  // a folder only when empty
  }
  fs::remove(previous / kOutputManifest, ec);
  if (!fs::remove(previous, ec) || ec) return kept;
  return {};
}

}  // namespace sglab::io
