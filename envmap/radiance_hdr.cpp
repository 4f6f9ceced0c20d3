// envmap/radiance_hdr.cpp — the bounded Radiance picture reader
// (radiance_hdr.hpp). Scanlines are decoded as Radiance's freadcolrs and
// oldreadcolrs decode them and pixels as its colr_color converts them
// ([Ward1991], [RadianceFormat]), with every count checked against the bytes
// left in the file and the pixels left in the row.
#include "envmap/radiance_hdr.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace sglab::envmap {

namespace {

using io::InputError;

// Scanlines of this width may be run-length encoded ([RadianceFormat]; MINELEN
// and MAXELEN of Radiance's color.c).
constexpr std::size_t kMinEncodedWidth = 8, kMaxEncodedWidth = 0x7fff;

// Sequential reads through a 64 KiB buffer; get() is −1 at the end of the file.
class ByteReader {
 public:
  ByteReader(const std::filesystem::path& path, const std::string& name)
      : file_(std::fopen(path.c_str(), "rb"), &std::fclose), buffer_(std::size_t{1} << 16) {
    if (!file_) throw InputError(fmt::format("{}: cannot open ({})", name, std::strerror(errno)));
  }
  int get() {
    if (pos_ == end_ && !fill()) return -1;
    return buffer_[pos_++];
  }
  bool read(std::uint8_t* out, std::size_t n) {
    while (n > 0) {
      if (pos_ == end_ && !fill()) return false;
      const std::size_t k = std::min(n, end_ - pos_);
      std::memcpy(out, buffer_.data() + pos_, k);
      pos_ += k;
      out += k;
      n -= k;
    }
    return true;
  }
  long offset() const { return consumed_ - static_cast<long>(end_ - pos_); }
  bool seek(long offset) {
    pos_ = end_ = 0;
    consumed_ = offset;
    return std::fseek(file_.get(), offset, SEEK_SET) == 0;
  }

 private:
  bool fill() {
    end_ = std::fread(buffer_.data(), 1, buffer_.size(), file_.get());
    pos_ = 0;
    consumed_ += static_cast<long>(end_);
    return end_ > 0;
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<std::uint8_t> buffer_;
  std::size_t pos_ = 0, end_ = 0;
  long consumed_ = 0;  // bytes of the file taken into the buffer so far
};

InputError damaged(const std::string& name, std::string_view what) {
  return InputError(fmt::format("{}: damaged Radiance HDR file: {}", name, what));
}

struct Resolution {
  std::uint64_t width = 0, height = 0;
};

// A positive decimal count of at most 2^31 (larger sizes are refused by
// check_size anyway).
bool parse_count(std::string_view s, std::uint64_t& out) {
  if (s.empty() || s.front() < '0' || s.front() > '9') return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && out > 0 && out <= (1ull << 31);
}

// The header and the resolution line ([RadianceFormat]): reads up to the
// first scanline byte.
Resolution read_header(ByteReader& in, const std::string& name) {
  std::size_t total = 0;
  // One line without its '\n'; false at the end of the file.
  auto next_line = [&](std::string& line) {
    line.clear();
    for (;;) {
      const int c = in.get();
      if (c < 0) return false;
      if (++total > kMaxHeaderBytes)
        throw damaged(name,
                      fmt::format("no end of the header in its first {} bytes", kMaxHeaderBytes));
      if (c == '\n') return true;
      line.push_back(static_cast<char>(c));
    }
  };
  std::string line;
  if (!next_line(line) || line.rfind("#?", 0) != 0)
    throw InputError(fmt::format("{}: not a Radiance HDR file (no \"#?\" first line)", name));
  for (;;) {
    if (!next_line(line)) throw damaged(name, "the file ends inside its header");
    if (line.empty()) break;
    if (line.rfind("FORMAT=", 0) == 0) {
      std::string_view value = std::string_view(line).substr(7);
      const auto first = value.find_first_not_of(" \t"), last = value.find_last_not_of(" \t");
      value = first == std::string_view::npos ? "" : value.substr(first, last - first + 1);
      if (value != "32-bit_rle_rgbe")
        throw InputError(fmt::format(
            "{}: FORMAT={}: only 32-bit_rle_rgbe (RGB) Radiance pictures are read", name, value));
    }
  }
  if (!next_line(line)) throw damaged(name, "the file ends before its resolution line");
  std::vector<std::string_view> tokens;
  for (std::size_t p = 0; p < line.size();) {
    const std::size_t b = line.find_first_not_of(' ', p);
    if (b == std::string::npos) break;
    const std::size_t e = std::min(line.find(' ', b), line.size());
    tokens.push_back(std::string_view(line).substr(b, e - b));
    p = e;
  }
  Resolution r;
  auto axis = [](std::string_view t) {
    return t.size() == 2 && (t[0] == '-' || t[0] == '+') && (t[1] == 'X' || t[1] == 'Y');
  };
  if (tokens.size() != 4 || !axis(tokens[0]) || !axis(tokens[2]) || tokens[0][1] == tokens[2][1] ||
      !parse_count(tokens[1], r.height) || !parse_count(tokens[3], r.width))
    throw damaged(name, fmt::format("resolution line '{}' is not '-Y H +X W'", line.substr(0, 80)));
  if (tokens[0] != "-Y" || tokens[2] != "+X")
    throw InputError(fmt::format(
        "{}: resolution line '{}': only the standard orientation '-Y H +X W' (rows from the top, "
        "columns from the left) is read",
        name, line));
  return r;
}

// Scanline `row` of `width` pixels into rgbe[0 .. 4·width), as Radiance's
// freadcolrs reads it ([RadianceFormat]; radiance_hdr.hpp says how).
void read_scanline(ByteReader& in, std::size_t width, std::size_t row, std::uint8_t* rgbe,
                   const std::string& name) {
  auto bad = [&](std::string_view what) {
    return damaged(name, fmt::format("scanline {} {}", row, what));
  };
  auto cut = [&] { return bad("is cut short (the file ends before its last pixel)"); };
  bool have_first = false;  // the first flat pixel already read (the 4 bytes looked at)
  if (width >= kMinEncodedWidth && width <= kMaxEncodedWidth) {
    if (!in.read(rgbe, 4)) throw cut();
    if (rgbe[0] == 2 && rgbe[1] == 2 && (rgbe[2] & 0x80) == 0) {
      const std::size_t length = (std::size_t{rgbe[2]} << 8) | rgbe[3];
      if (length != width)
        throw bad(fmt::format("declares {} pixels, the width is {}", length, width));
      for (std::size_t c = 0; c < 4; ++c)
        for (std::size_t i = 0; i < width;) {
          const int code = in.get();
          if (code < 0) throw cut();
          const bool run = code > 128;
          const std::size_t n = static_cast<std::size_t>(run ? code - 128 : code);
          if (n > width - i)
            throw bad(
                fmt::format("has a run of {} past its end (component {}, pixel {})", n, c, i));
          int value = run ? in.get() : 0;
          for (std::size_t k = 0; k < n; ++k) {
            if (!run) value = in.get();
            if (value < 0) throw cut();
            rgbe[4 * (i + k) + c] = static_cast<std::uint8_t>(value);
          }
          i += n;
        }
      return;
    }
    have_first = true;
  }
  // Flat pixels; (1, 1, 1, n) repeats the previous one n << shift times,
  // shift growing by 8 over consecutive repeats (Radiance's oldreadcolrs),
  // never past the row's end.
  unsigned shift = 0;
  for (std::size_t i = 0; i < width;) {
    std::uint8_t* p = rgbe + 4 * i;
    if (have_first)
      have_first = false;
    else if (!in.read(p, 4))
      throw cut();
    if (p[0] != 1 || p[1] != 1 || p[2] != 1) {
      ++i;
      shift = 0;
      continue;
    }
    if (i == 0) throw bad("starts with a run-length repeat (1, 1, 1, n) before any pixel");
    const std::uint64_t n = p[3];
    const std::uint64_t want = n == 0 ? 0 : shift < 48 ? n << shift : width;
    const std::size_t count = static_cast<std::size_t>(std::min<std::uint64_t>(want, width - i));
    for (std::size_t k = 0; k < count; ++k) std::memcpy(p + 4 * k, p - 4, 4);
    i += count;
    shift += 8;
  }
}

}  // namespace

float rgbe_channel(std::uint8_t mantissa, std::uint8_t exponent) {
  static const std::array<double, 256> scale = [] {
    std::array<double, 256> s{};
    for (int e = 1; e < 256; ++e) s[static_cast<std::size_t>(e)] = std::ldexp(1.0, e - 136);
    return s;
  }();
  return static_cast<float>((mantissa + 0.5) * scale[exponent]);
}

bool is_radiance_hdr(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  char magic[2] = {0, 0};
  return f && std::fread(magic, 1, 2, f.get()) == 2 && magic[0] == '#' && magic[1] == '?';
}

Map read_radiance_hdr(const std::filesystem::path& path) {
  const std::string name = path.string();
  ByteReader in(path, name);
  const Resolution r = read_header(in, name);
  check_size(r.width, r.height, name);
  const std::size_t width = static_cast<std::size_t>(r.width),
                    height = static_cast<std::size_t>(r.height);
  // Pass 1: every scanline decoded into one row's buffer, so a file that
  // cannot hold the pixels it declares is refused before the map is allocated.
  const long data_start = in.offset();
  std::vector<std::uint8_t> scanline(4 * width);
  for (std::size_t j = 0; j < height; ++j) read_scanline(in, width, j, scanline.data(), name);
  // Pass 2: the same scanlines, into the map.
  if (!in.seek(data_start))
    throw InputError(fmt::format("{}: cannot read it again ({})", name, std::strerror(errno)));
  Map map;
  map.width = width;
  map.height = height;
  map.rgb.resize(width * height * 3);
  for (std::size_t j = 0; j < height; ++j) {
    read_scanline(in, width, j, scanline.data(), name);
    float* out = map.rgb.data() + j * width * 3;
    for (std::size_t i = 0; i < width; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch)
        out[3 * i + ch] = rgbe_channel(scanline[4 * i + ch], scanline[4 * i + 3]);
  }
  return map;
}

}  // namespace sglab::envmap
