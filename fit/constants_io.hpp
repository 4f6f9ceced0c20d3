// fit/constants_io.hpp — the constant sets in data/constants/*.json and the
// runtime header include/sglab/constants.hpp generated from them.
//
// Each JSON file holds one constant set: target, variant, the C++ name and
// parameter type it becomes in the header, the functional form, the
// coefficients (at full double precision, in the member order of the
// parameter struct of include/sglab/params.hpp) and its provenance.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sglab::fit {

using ordered_json = nlohmann::ordered_json;

// The source tree's data/constants and include/sglab/constants.hpp.
std::filesystem::path default_constants_dir();
std::filesystem::path default_header_path();

// All constant sets in `dir`, sorted by file name. Throws std::runtime_error
// naming the file and the missing or malformed field.
std::vector<ordered_json> load_constant_sets(const std::filesystem::path& dir);

// Checks one set's required fields; throws std::runtime_error naming `where`.
void check_constant_set(const ordered_json& set, const std::string& where);

// The text of include/sglab/constants.hpp for these sets.
std::string render_constants_header(const std::vector<ordered_json>& sets);

// Regenerates the header from the JSON files (atomically).
void write_constants_header(const std::filesystem::path& dir, const std::filesystem::path& header);

}  // namespace sglab::fit
