#include "common/comment_text.hpp"

#include <cstdint>

#include <fmt/format.h>

namespace sglab::io {

std::string comment_text(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      if (b < 0x20 || b == 0x7f || b == '\\' || (b == '?' && i > 0 && s[i - 1] == '?'))
        out += fmt::format("\\x{:02x}", b);
      else
        out += static_cast<char>(b);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no overlong forms, no surrogates, ≤ U+10FFFF)?
    const int len = b >= 0xf0 ? 4 : b >= 0xe0 ? 3 : b >= 0xc0 ? 2 : 0;
    char32_t cp = len == 4 ? b & 0x07 : len == 3 ? b & 0x0f : b & 0x1f;
    bool ok = len > 0 && b <= 0xf4 && b >= 0xc2 && i + static_cast<std::size_t>(len) <= s.size();
    for (int k = 1; ok && k < len; ++k) {
      const auto c = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      ok = (c & 0xc0) == 0x80;
      cp = (cp << 6) | (c & 0x3f);
    }
    ok = ok && !(len == 3 && cp < 0x800) && !(len == 4 && (cp < 0x10000 || cp > 0x10ffff)) &&
         !(cp >= 0xd800 && cp <= 0xdfff);
    if (!ok) {
      out += fmt::format("\\x{:02x}", b);
      ++i;
      continue;
    }
    const bool invisible = (cp >= 0x80 && cp <= 0x9f) || cp == 0x2028 || cp == 0x2029 ||
                           cp == 0x200e || cp == 0x200f || cp == 0x061c || cp == 0xfeff ||
                           (cp >= 0x202a && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069);
    if (invisible)
      out += fmt::format("\\u{{{:04x}}}", static_cast<std::uint32_t>(cp));
    else
      out.append(s.substr(i, static_cast<std::size_t>(len)));
    i += static_cast<std::size_t>(len);
  }
  return out;
}

}  // namespace sglab::io
