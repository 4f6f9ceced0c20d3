// common/json_input.hpp — the one reader of JSON input files (constant sets,
// scenes, the cost table): bounded in size, strict in syntax, and every
// refusal is bad input (io::InputError, exit 2) naming the file and the key.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace sglab::io {

// Nesting of objects and arrays allowed in a JSON input.
inline constexpr int kMaxJsonDepth = 64;

// Parses untrusted JSON text: at most kMaxJsonDepth levels (checked while
// parsing, so a 100000-deep file is refused, not a stack overflow), no
// duplicate keys, numbers finite and not silently 0 (a decimal beyond the
// largest double or nonzero below the smallest is refused, as
// io::parse_decimal says), valid UTF-8. Messages quote input escaped
// and shortened (io::quote_escaped), so a 100,000-digit number or a
// control byte cannot flood or garble them. Throws InputError
// "SOURCE: malformed JSON: key 'a.b[2]': why" (or the line and column).
nlohmann::ordered_json parse_json_strict(std::string_view text, std::string_view source);

// read_input_file(path, max_bytes, what) (io.hpp) then parse_json_strict.
nlohmann::ordered_json read_json_file(const std::filesystem::path& path, std::size_t max_bytes,
                                      std::string_view what);

}  // namespace sglab::io
