// envmap/radiance_hdr.hpp — the Radiance picture (.hdr, RGBE) reader behind
// envmap::read_map ([Ward1991], [RadianceFormat]; docs/references.md).
//
// Bounded whatever the file holds: the header is read up to kMaxHeaderBytes,
// the declared size is checked by check_size (2:1, at least 8 × 4, at most
// kMaxPixels) and then by decoding every scanline into one scanline buffer
// (every run and count checked against the bytes left and the row width)
// before the map's pixel buffer is allocated; a second pass decodes into it.
// So a file that cannot hold its declared pixels is refused in time
// proportional to its own size, and memory never exceeds the map it holds.
#pragma once

#include <cstdint>
#include <filesystem>

#include "envmap/envmap.hpp"

namespace sglab::envmap {

// The longest header read (Radiance headers hold one line per program that
// touched the picture: a few hundred bytes in practice).
inline constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;

// True when the file starts with the Radiance signature "#?" (the first header
// line, "#?RADIANCE" from Radiance's own programs, "#?RGBE" from others).
bool is_radiance_hdr(const std::filesystem::path& path);

// Reads a Radiance picture: header lines up to an empty line (FORMAT must be
// 32-bit_rle_rgbe when given; EXPOSURE and the other lines are ignored, so
// values are as stored, as Radiance's pvalue prints them without -o), the
// resolution line "-Y H +X W" (rows from the top, columns from the left; the
// other seven orientations are refused), then H scanlines, each as Radiance's
// freadcolrs reads it: widths 8 … 32767 may use the adaptive run-length
// encoding (2, 2, W/256, W%256, then each of R, G, B, E as runs: a code
// 129 … 255 repeats the next byte code − 128 times, a code 0 … 128 copies that
// many bytes), and any scanline may be flat RGBE pixels, where (1, 1, 1, n)
// repeats the previous pixel n << s times, s growing by 8 over consecutive
// repeats. Bytes after the last scanline are ignored. Throws io::InputError
// naming the file: not a Radiance picture, a format other than RGBE, another
// orientation, a size check_size refuses, or "damaged" with the scanline
// (cut short, a run past the row's end, a scanline length other than W, a
// repeat before any pixel).
Map read_radiance_hdr(const std::filesystem::path& path);

// One RGBE channel as Radiance decodes it ([Ward1991], colr_color):
// (m + ½)·2^(e − 136), and 0 when e = 0. Exact in float for every m and e:
// (2m + 1)·2^(e − 137) has 9 significant bits, an exponent in [−136, 118],
// and is finite (at most 255.5·2^119 ≈ 1.7e38).
float rgbe_channel(std::uint8_t mantissa, std::uint8_t exponent);

}  // namespace sglab::envmap
