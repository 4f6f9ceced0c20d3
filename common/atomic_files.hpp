// common/atomic_files.hpp — several files written as one unit: either every
// file gets its new content or none changes (the constant-set JSON files and
// the runtime header generated from them, for example); and a folder replaced
// as a whole (`sglab run --out D`), which never deletes what its writer did
// not write.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
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
//
// The temporaries are named .NAME.PID.tmp. Should SIGINT, SIGTERM or SIGHUP arrive while
// they exist, they are removed before the process ends by the signal as it would have
// (the handler is installed at the first write, for each of these signals whose action is
// the default; an ignored signal stays ignored). Destinations already renamed keep their
// new content.
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

// ---- a folder replaced as a whole ---------------------------------------------
//
// A command that replaces its output folder D (rather than writing files into
// it) builds the new content in a staging folder beside D, writes a manifest
// there listing everything it wrote, and swaps it in. D may be replaced only
// when it is absent, an empty folder, or the output of such a command whose
// manifest lists everything D holds; and never when D (or the folder a
// symbolic link D names) is `/`, $HOME, the working folder, the project root
// (io::find_project_root of the working folder), an ancestor of any of them,
// an sglab checkout, or a folder holding `.git`. Of the previous D, only what
// its manifest lists is removed.

// The manifest's name inside the folder: JSON {"format": "sglab-output",
// "version": 1, "command": "...", "entries": ["index.md", "logs/", "logs/fit.log",
// ...]} (paths relative to the folder, '/'-separated, folders with a trailing '/').
inline constexpr std::string_view kOutputManifest = "sglab-output.json";
// The largest manifest read.
inline constexpr std::size_t kMaxOutputManifestBytes = 16 << 20;

// Refuses (InputError "OPTION DIR: why", exit 2) a folder that may not be
// replaced by the rules above; the message names D and, for a folder with
// files its manifest does not list, the first of them.
void check_replaceable_folder(const std::filesystem::path& dir, std::string_view option);

// A new empty folder beside D (beside the folder it names, when D is a symbolic
// link), on the same file system: D.staging-PID-RANDOM.
std::filesystem::path make_staging_folder(const std::filesystem::path& dir);

// Writes the manifest of `staging`, listing every file and folder in it
// (`command` recorded); the last thing written into it.
void write_output_manifest(const std::filesystem::path& staging, std::string_view command);

// Checks D again (check_replaceable_folder: it may have changed since; a
// refusal names `staging`, which keeps the new content), then
// puts `staging` in D's place (an atomic exchange where the file system allows
// it, else two renames) and removes from the previous D what its manifest
// lists. Anything else found there (written into D while the command ran) is
// kept: the folder holding it is left beside D and named in the returned
// notes, one per line (empty when nothing was kept).
std::string replace_folder(const std::filesystem::path& staging, const std::filesystem::path& dir,
                           std::string_view option);

}  // namespace sglab::io
