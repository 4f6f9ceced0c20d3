// fit/constants_schema.hpp — what a constant set (data/constants/*.json) may
// contain, in one place. A constants file is untrusted input: the header
// generated from it is compiled into the user's program, so every field that
// reaches C++ is checked here and every text field is escaped into comments.
//
// HOW TO ADD A PARAMETER STRUCT (a new `template <class S, ...> struct XParams`
// in include/sglab/params.hpp): add one line to kParamStructs in
// constants_schema.cpp — its name, its size parameters (the template
// parameters after S, in order) and its members in declaration order, each as
// `name` or `name[LENGTH]` with LENGTH written as in params.hpp (an integer, a
// size parameter, `P + k`, `P - k` or `P > k ? A : B`). tests/test_constants_io.cpp
// checks the table against params.hpp member by member.
//
// HOW TO ADD A REQUIRED SET (code that names `constants::SOME_SET`): add one
// line to kRequiredSets in constants_schema.cpp — the cpp_name and the
// canonical cpp_type the code was written against. The header is refused
// unless every required set is present with that type; a test scans the
// sources for `constants::NAME` and fails when a name is missing there.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/comment_text.hpp"
#include "common/json_input.hpp"

namespace sglab::fit {

using ordered_json = nlohmann::ordered_json;

// A constants file or set that is malformed or unsafe (bad input: exit 2).
// The message names the file and the key.
struct ConstantsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Limits on a constants file.
inline constexpr std::size_t kMaxConstantsFileBytes = 1 << 20;  // 1 MiB (a set is a few KB)
inline constexpr int kMaxJsonDepth = io::kMaxJsonDepth;         // nesting of objects and arrays
inline constexpr std::size_t kMaxArrayLength = 64;              // size parameters
// array members (sglab_tab's table: 32 cells × 7 cubics = 896)
inline constexpr std::size_t kMaxArrayMembers = 1024;
// cpp_name, target, variant, coefficient names
inline constexpr std::size_t kMaxIdentifierLength = 128;

// The format tag of a constant set: its top-level members "format" and
// "version" (written first by the fits).
inline constexpr std::string_view kConstantSetFormat = "sglab-constants";
inline constexpr int kConstantSetVersion = 1;

// Whether the text of a file in a folder of constant sets is a constant set,
// by its format tag: nullopt when it is (it is then parsed and validated as
// one, and refused when malformed), else a short reason for the message that
// names the skipped file. A JSON object with a "format" member is a constant
// set when that member is kConstantSetFormat; any other text (not JSON, not
// an object, no "format") is one only when it carries the tag string
// "sglab-constants", so that a damaged set is refused, never skipped.
std::optional<std::string> why_not_a_constant_set(std::string_view text);

struct ParamStruct {
  std::string_view name;                      // e.g. "Listing5Params"
  std::vector<std::string_view> size_params;  // e.g. {"NS", "NL"}: Listing5Params<double, NS, NL>
  std::vector<std::string_view> members;      // e.g. {"split", "cutoff", "small[NS]", "large[NL]"}
};
std::span<const ParamStruct> param_structs();

struct RequiredSet {
  std::string_view cpp_name;  // the name in namespace sglab::constants
  std::string_view cpp_type;  // canonical: "Name<double>" or "Name<double, 6, 7>"
};
std::span<const RequiredSet> required_sets();

// A cpp_type resolved against the table: canonical spelling and each member
// with its array length (0 for a scalar member).
struct ResolvedType {
  std::string canonical;
  std::vector<std::pair<std::string, std::size_t>> members;
};
// Throws ConstantsError (with `where` in front) for an unknown struct, a wrong
// number of size parameters, a malformed spelling, a size parameter outside
// [0, kMaxArrayLength] or an array length outside [1, kMaxArrayMembers].
ResolvedType resolve_cpp_type(std::string_view text, const std::string& where);

// Parses untrusted JSON text (at most kMaxConstantsFileBytes) with the one
// strict JSON parser, io::parse_json_strict (common/json_input.hpp).
// Throws ConstantsError naming `file` and the key path.
ordered_json parse_untrusted_json(std::string_view text, const std::string& file);

// Checks one set against the schema: the format tag (kConstantSetFormat,
// kConstantSetVersion); known top-level fields of the right types; target, variant and cpp_name
// identifiers; cpp_type known; every member of the struct given, no other coefficient, array
// lengths right, values finite; provenance an object whose well-known fields have the right type.
// Throws ConstantsError naming `file` and the key.
void validate_constant_set(const ordered_json& set, const std::string& file);

// Checks a complete collection for the header (each already validated):
// every required set present with its type, cpp_names unique.
// `files[i]` names where sets[i] came from. Throws ConstantsError.
void validate_header_sets(const std::vector<ordered_json>& sets,
                          const std::vector<std::string>& files);

// Text fields are escaped into the header's comments by the one escaping
// function that the shader exports use too (common/comment_text.hpp).
using io::comment_text;

// [A-Za-z_][A-Za-z0-9_]* and not a C++ keyword.
bool is_cpp_identifier(std::string_view s);

}  // namespace sglab::fit
