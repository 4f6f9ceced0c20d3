// validate/atomic_files.hpp — several files written as one unit: either every
// file gets its new content or none changes (the constant-set JSON files and
// the runtime header generated from them, for example).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sglab::io {

struct FileContent {
  std::filesystem::path path;
  std::string content;
};

// Writes each content to a temporary file in its destination folder (created
// when missing), flushed to disk, then renames the temporaries over the
// destinations in order. When a temporary cannot be written nothing is
// replaced; when a rename fails, the destinations already replaced get their
// previous content back (or are removed when they did not exist before).
// Throws std::runtime_error naming the destination file and the OS reason.
void write_files_atomic(const std::vector<FileContent>& files);

}  // namespace sglab::io
