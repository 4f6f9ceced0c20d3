#include "common/atomic_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <optional>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "common/io.hpp"

namespace sglab::io {

namespace fs = std::filesystem;

namespace {

std::string os_reason(int err) { return std::error_code(err, std::generic_category()).message(); }

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
    if (const int err = write_new_file(p.tmp, f.content)) {
      discard_temporaries();
      throw std::runtime_error(fmt::format("cannot write {}: {} (temporary {})", f.path.string(),
                                           os_reason(err), p.tmp.string()));
    }
    pending.push_back(std::move(p));
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
        const fs::path tmp = temporary_for(done.path);
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

}  // namespace sglab::io
