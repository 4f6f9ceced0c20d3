// common/comment_text.hpp — untrusted text made safe for a `//` comment of
// generated source: the one escaping function for every generated file that
// carries text from input (the constants header include/sglab/constants.hpp,
// and every GLSL, HLSL and C++ export of `sglab export`).
#pragma once

#include <string>
#include <string_view>

namespace sglab::io {

// `text` made safe for one line of a // comment: no control character, no
// NUL, no line or paragraph separator, no bidirectional override, never a
// trailing '\' (which would splice the next line into the comment) nor a "??/"
// trigraph (the same splice in C++ before C++17); those, every '\' and the second
// '?' of "??" become \xNN or \u{NNNN} escapes, ill-formed UTF-8 bytes become
// \xNN. Other UTF-8 text is kept as is.
std::string comment_text(std::string_view text);

}  // namespace sglab::io
