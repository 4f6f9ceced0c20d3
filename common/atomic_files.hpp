// common/atomic_files.hpp — several files written as one unit: either every
// file gets its new content or none changes (the constant-set JSON files and
// the runtime header generated from them, for example).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/io.hpp"  // InputError

namespace sglab::io {

struct FileContent {
  std::filesystem::path path;
  std::string content;
};

// Writes each content to a temporary file in its destination folder (created
// when missing), flushed to disk, then renames the temporaries over the
// destinations in order. Before anything is written, every destination is
// checked (check_output_path): an empty path, a destination that exists and is
// not a regular file, or a folder that exists and is not a folder is refused
// with InputError (io.hpp; bad input, exit 2), naming the path and its type. When a temporary
// cannot be written nothing is replaced; when a rename fails, the destinations already replaced get
// their previous content back (or are removed when they did not exist before). Throws
// std::runtime_error naming the destination file and the OS reason.
void write_files_atomic(const std::vector<FileContent>& files);

// Refuses (InputError naming the path and what it is) an output path that is
// empty, that exists and is not a regular file (a directory, FIFO, device,
// socket or symbolic link: renaming over it would replace it, and opening it
// would write into whatever it names), or whose folder exists and is not a
// folder (a symbolic link to a folder is fine). Commands call it on their
// output paths before long work; the writers call it again.
void check_output_path(const std::filesystem::path& path);

// The same for an output folder (`--out DIR`): refused when empty or when it
// exists and is not a folder (a symbolic link to a folder is fine).
void check_output_folder(const std::filesystem::path& dir);

}  // namespace sglab::io
