// fit/constants_io.hpp — the constant sets in data/constants/*.json and the
// runtime header include/sglab/constants.hpp generated from them.
//
// Each JSON file holds one constant set: its format tag ("format":
// "sglab-constants", "version": 1; files without it are not read), target, variant, the C++ name
// and parameter type it becomes in the header, the functional form, the coefficients (at full
// double precision, named by the members of the parameter struct of include/sglab/params.hpp) and
// its provenance. What a set may contain is fit/constants_schema.hpp; every file is checked against
// it when loaded, and a header is only written from a complete, valid collection.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/constants_schema.hpp"

namespace sglab::fit {

using ordered_json = nlohmann::ordered_json;

// The sglab project around `start`: the nearest folder at or above it that
// holds both data/constants and include/sglab; nullopt when there is none.
std::optional<std::filesystem::path> find_project_root(const std::filesystem::path& start);
// The project around the working directory; throws ConstantsError (bad input)
// saying there is none and which options to pass instead.
std::filesystem::path project_root();

// <project>/data/constants and <project>/include/sglab/constants.hpp of the
// project around the working directory (throw like project_root()).
std::filesystem::path default_constants_dir();
std::filesystem::path default_header_path();

// The header that goes with the constant sets in `dir` when no --header is
// given: the project's include/sglab/constants.hpp when `dir` is the
// project's data/constants, otherwise dir/constants.hpp (a fit or a header
// regeneration into another folder never touches the checkout).
std::filesystem::path default_header_for(const std::filesystem::path& dir);

struct ConstantSetFile {
  std::filesystem::path file;
  ordered_json set;
};

// A file of a folder of constant sets that is not one (why_not_a_constant_set).
struct SkippedFile {
  std::filesystem::path file;
  std::string reason;
};

// One constants file, parsed as untrusted input and validated. Throws ConstantsError.
ordered_json load_constant_set(const std::filesystem::path& file);
// The constant sets among the *.json files of `dir` (by their format tag,
// why_not_a_constant_set), sorted by file name, each validated. Every other
// file is appended to `skipped`, or, when `skipped` is null, named on stderr
// ("sglab: note: skipped FILE: reason"). Throws ConstantsError naming the file
// and the key (or the folder and the OS reason).
std::vector<ConstantSetFile> load_constant_set_files(const std::filesystem::path& dir,
                                                     std::vector<SkippedFile>* skipped = nullptr);
std::vector<ordered_json> load_constant_sets(const std::filesystem::path& dir);

// The text of include/sglab/constants.hpp for these (valid) sets; members in
// the declaration order of their struct; text fields escaped into comments.
std::string render_constants_header(const std::vector<ordered_json>& sets);

// Regenerates `header` from the sets in `dir` after checking that they are
// complete (validate_header_sets); writes nothing otherwise. Returns the
// number of sets.
std::size_t write_constants_header(const std::filesystem::path& dir,
                                   const std::filesystem::path& header);

// Writes `new_sets` (each with its destination file in `out_dir`) and the
// header generated from: the sets of `base_dir` (when given and not out_dir),
// replaced by those of out_dir with the same file name, replaced by new_sets.
// Everything is validated first and then written as one unit
// (io::write_files_atomic): all files or none. Returns the number of sets in
// the header.
// Files of base_dir and out_dir that are not constant sets are left alone and
// reported as load_constant_set_files does.
std::size_t write_sets_and_header(const std::vector<ConstantSetFile>& new_sets,
                                  const std::filesystem::path& out_dir,
                                  const std::optional<std::filesystem::path>& base_dir,
                                  const std::filesystem::path& header,
                                  std::vector<SkippedFile>* skipped = nullptr);

}  // namespace sglab::fit
