// Environment-map input and its bounds (envmap/envmap.hpp, envmap/radiance_hdr.hpp):
// Radiance .hdr files made here byte by byte (every encoding, known values,
// every truncation), OpenEXR files declaring more than they hold, the OpenEXR
// variants that must still read, the area-averaging downsample at widths that
// do not divide the map, and the fit's memory bound.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include "envmap/envmap.hpp"
#include "envmap/radiance_hdr.hpp"
#include "tests/test_support.hpp"

namespace {

using namespace sglab;
using envmap::Map;
using envmap::Vec3;
using test::run_sglab;
using test::TempDir;
using Rgbe = std::array<std::uint8_t, 4>;

// ---- Radiance files made here -----------------------------------------------

// Ward's encoder ([Ward1991], setcolr): the largest channel's frexp exponent
// and mantissas truncated to 8 bits.
Rgbe rgbe_of(double r, double g, double b) {
  const double d = std::max({r, g, b});
  if (d <= 1e-32) return {0, 0, 0, 0};
  int e = 0;
  const double s = std::frexp(d, &e) * 256.0 / d;
  return {static_cast<std::uint8_t>(r * s), static_cast<std::uint8_t>(g * s),
          static_cast<std::uint8_t>(b * s), static_cast<std::uint8_t>(e + 128)};
}

enum class Encoding { flat, rle, repeats };

// One component of a scanline in the adaptive run-length encoding: runs of 3
// or more equal bytes as (128 + n, value), n ≤ 127; the rest as (n, n bytes),
// n ≤ 128.
void encode_component(std::string& out, const std::vector<std::uint8_t>& v) {
  std::size_t i = 0;
  while (i < v.size()) {
    std::size_t run = 1;
    while (i + run < v.size() && run < 127 && v[i + run] == v[i]) ++run;
    if (run >= 3) {
      out += static_cast<char>(128 + run);
      out += static_cast<char>(v[i]);
      i += run;
      continue;
    }
    std::size_t j = i;
    while (j < v.size() && j - i < 128 &&
           !(j + 2 < v.size() && v[j] == v[j + 1] && v[j] == v[j + 2]))
      ++j;
    out += static_cast<char>(j - i);
    for (; i < j; ++i) out += static_cast<char>(v[i]);
  }
}

// A Radiance picture of w × h RGBE pixels (rows from the top) in one encoding:
// flat, run-length encoded scanlines, or flat pixels with Radiance's old
// repeats (1, 1, 1, n), consecutive repeats counting n << 8, n << 16.
std::string hdr_file(std::size_t w, std::size_t h, const std::vector<Rgbe>& px, Encoding enc,
                     const std::string& header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n") {
  std::string s = header + "-Y " + std::to_string(h) + " +X " + std::to_string(w) + "\n";
  for (std::size_t j = 0; j < h; ++j) {
    const Rgbe* row = px.data() + j * w;
    if (enc == Encoding::rle) {
      s += {2, 2, static_cast<char>(w >> 8), static_cast<char>(w & 255)};
      for (std::size_t c = 0; c < 4; ++c) {
        std::vector<std::uint8_t> v(w);
        for (std::size_t i = 0; i < w; ++i) v[i] = row[i][c];
        encode_component(s, v);
      }
      continue;
    }
    for (std::size_t i = 0; i < w;) {
      s.append(reinterpret_cast<const char*>(row[i].data()), 4);
      std::size_t n = 0;
      while (enc == Encoding::repeats && i + 1 + n < w && row[i + 1 + n] == row[i]) ++n;
      for (std::size_t left = n; left > 0; left >>= 8)
        s += {1, 1, 1, static_cast<char>(left & 255)};
      i += 1 + n;
    }
  }
  return s;
}

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

// Pixels whose bytes vary in every channel, with runs (equal neighbours along
// rows) for the run-length encodings; no pixel starts (2, 2) or is (1, 1, 1, n).
std::vector<Rgbe> test_pixels(std::size_t w, std::size_t h) {
  std::vector<Rgbe> px(w * h);
  for (std::size_t j = 0; j < h; ++j)
    for (std::size_t i = 0; i < w; ++i) {
      const std::size_t k = i / 3;  // runs of 3 pixels
      px[j * w + i] = {static_cast<std::uint8_t>(40 + (k * 37 + j * 11) % 200),
                       static_cast<std::uint8_t>((k * 53 + j * 7) % 256),
                       static_cast<std::uint8_t>(i % 4 == 0 ? 0 : 9 + (j * 29) % 230),
                       static_cast<std::uint8_t>(120 + (k + j) % 20)};
    }
  return px;
}

double radiance_decode(std::uint8_t m, std::uint8_t e) {
  return e == 0 ? 0.0 : std::ldexp(m + 0.5, e - 136);
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// ---- RGBE values --------------------------------------------------------------

TEST(EnvmapInput, RgbeChannelIsRadiancesDecoding) {
  // Radiance's colr_color: (m + ½)·2^(e − 136); exponent 0 is black.
  EXPECT_EQ(envmap::rgbe_channel(128, 129), 1.00390625f);  // 128.5 / 128
  EXPECT_EQ(envmap::rgbe_channel(64, 129), 0.50390625f);
  EXPECT_EQ(envmap::rgbe_channel(0, 136), 0.5f);
  EXPECT_EQ(envmap::rgbe_channel(255, 0), 0.0f);
  EXPECT_EQ(envmap::rgbe_channel(0, 1), std::ldexp(1.0f, -136));  // subnormal, exact
  EXPECT_EQ(envmap::rgbe_channel(255, 255), std::ldexp(511.0f, 118));
  EXPECT_TRUE(std::isfinite(envmap::rgbe_channel(255, 255)));
  for (int e = 1; e < 256; ++e)
    for (int m = 0; m < 256; ++m)
      ASSERT_EQ(static_cast<double>(envmap::rgbe_channel(static_cast<std::uint8_t>(m),
                                                         static_cast<std::uint8_t>(e))),
                std::ldexp(2 * m + 1, e - 137))
          << "m " << m << " e " << e;
}

// A hand-made map of known bytes reads the same in every encoding, each value
// (m + ½)·2^(e − 136), rows from the top and columns from the left.
TEST(EnvmapInput, RadianceEncodingsReadTheirKnownValues) {
  TempDir dir("envmap-hdr-known");
  const std::size_t w = 32, h = 16;
  const std::vector<Rgbe> px = test_pixels(w, h);
  for (Encoding enc : {Encoding::flat, Encoding::rle, Encoding::repeats}) {
    const auto path = dir.path / "m.hdr";
    write_bytes(path, hdr_file(w, h, px, enc));
    const Map m = envmap::read_map(path);
    ASSERT_EQ(m.width, w);
    ASSERT_EQ(m.height, h);
    for (std::size_t j = 0; j < h; ++j)
      for (std::size_t i = 0; i < w; ++i)
        for (std::size_t ch = 0; ch < 3; ++ch)
          ASSERT_EQ(static_cast<double>(m.at(i, j, ch)),
                    radiance_decode(px[j * w + i][ch], px[j * w + i][3]))
              << "encoding " << static_cast<int>(enc) << " pixel " << i << ", " << j;
  }
  // The encodings differ: the run-length file is smaller than the flat one.
  EXPECT_LT(hdr_file(w, h, px, Encoding::rle).size(), hdr_file(w, h, px, Encoding::flat).size());
  // Without FORMAT (Radiance assumes RGBE) and with "#?RGBE".
  write_bytes(dir.path / "f.hdr", hdr_file(w, h, px, Encoding::rle, "#?RGBE\nEXPOSURE=2\n\n"));
  EXPECT_EQ(envmap::read_map(dir.path / "f.hdr").at(5, 3, 1),
            static_cast<float>(radiance_decode(px[3 * w + 5][1], px[3 * w + 5][3])));
}

// Old-style repeats count n << 8 after a first repeat (600 wide: one pixel and
// repeats of 87 and 2·256 fill each constant row).
TEST(EnvmapInput, RadianceRepeatsShiftByEightBits) {
  TempDir dir("envmap-hdr-shift");
  const std::size_t w = 600, h = 300;
  std::vector<Rgbe> px(w * h);
  for (std::size_t j = 0; j < h; ++j)
    for (std::size_t i = 0; i < w; ++i)
      px[j * w + i] = {static_cast<std::uint8_t>(100 + j % 50), 90, 80, 130};
  const std::string bytes = hdr_file(w, h, px, Encoding::repeats);
  EXPECT_LT(bytes.size(), 13 * h + 64);  // 12 bytes a row
  write_bytes(dir.path / "m.hdr", bytes);
  const Map m = envmap::read_map(dir.path / "m.hdr");
  for (std::size_t j = 0; j < h; j += 37)
    for (std::size_t i : {std::size_t{0}, std::size_t{87}, std::size_t{88}, w - 1})
      ASSERT_EQ(m.at(i, j, 0), static_cast<float>(radiance_decode(px[j * w][0], 130)))
          << i << ", " << j;
}

// Ward's truncating encoder loses half a mantissa step on average; decoding at
// the step's centre, as Radiance does, keeps the map's irradiance (a map of
// known lobes, its float values against its RGBE file).
TEST(EnvmapInput, RadianceDecodingKeepsTheIrradiance) {
  TempDir dir("envmap-hdr-bias");
  const std::vector<envmap::Lobe> lobes = {
      {{0.3, 0.4, std::sqrt(1 - 0.25)}, 40.0, {4.0, 3.5, 3.0}},
      {{-0.8, 0.0, -0.6}, 6.0, {0.5, 0.8, 1.2}},
      {{0.0, -1.0, 0.0}, 15.0, {1.5, 1.0, 0.5}},
  };
  Map truth = envmap::reconstruct(lobes, 128, 64);
  for (float& v : truth.rgb) v += 0.05f;  // no black pixel
  std::vector<Rgbe> px(truth.width * truth.height);
  for (std::size_t p = 0; p < px.size(); ++p)
    px[p] = rgbe_of(truth.rgb[3 * p], truth.rgb[3 * p + 1], truth.rgb[3 * p + 2]);
  write_bytes(dir.path / "m.hdr", hdr_file(truth.width, truth.height, px, Encoding::rle));
  const Map read = envmap::read_map(dir.path / "m.hdr");
  const auto normals = reference::fibonacci_normals(400);
  const auto err = envmap::irradiance_error(envmap::irradiance(read, normals),
                                            envmap::irradiance(truth, normals));
  std::printf("RGBE round trip: max irradiance error %.3g\n", err.max_rel);
  // Measured 9.5e-5; decoded as m·2^(e−136) (no ½) 3.2e-3.
  EXPECT_LT(err.max_rel, 5e-4);
}

// ---- damaged and oversized Radiance files -------------------------------------

// Every truncation of a file is refused as damaged, in each encoding (a
// decoder that reads past the end as zero bytes spins on the zero run counts
// of a cut run-length scanline, and fills a cut flat one with black).
TEST(EnvmapInput, EveryTruncatedRadianceFileIsDamaged) {
  TempDir dir("envmap-hdr-cut");
  const std::size_t w = 8, h = 4;  // the smallest map; run-length encoding from width 8
  const std::vector<Rgbe> px = test_pixels(w, h);
  for (Encoding enc : {Encoding::flat, Encoding::rle, Encoding::repeats}) {
    const std::string full = hdr_file(w, h, px, enc);
    const std::size_t header = full.find("+X 8\n") + 5;
    for (std::size_t n = header; n < full.size(); ++n) {
      write_bytes(dir.path / "cut.hdr", full.substr(0, n));
      try {
        envmap::read_map(dir.path / "cut.hdr");
        ADD_FAILURE() << "encoding " << static_cast<int>(enc) << " cut at " << n << " of "
                      << full.size() << " was read";
      } catch (const io::InputError& e) {
        ASSERT_NE(std::string(e.what()).find("damaged Radiance HDR file"), std::string::npos)
            << e.what();
      }
    }
  }
}

TEST(EnvmapInput, MalformedRadianceFilesNameTheirFault) {
  TempDir dir("envmap-hdr-bad");
  const std::size_t w = 16, h = 8;
  const std::vector<Rgbe> px = test_pixels(w, h);
  const std::string good = hdr_file(w, h, px, Encoding::rle);
  const std::size_t data = good.find("+X 16\n") + 6;
  struct Case {
    std::string name, bytes, says;
  };
  std::string run_past_end = good;  // scanline 0, R: a run of 127
  run_past_end[data + 4] = static_cast<char>(255);
  std::string length = good;  // scanline 0 declares 17 pixels
  length[data + 3] = 17;
  std::string repeat_first = hdr_file(w, h, px, Encoding::flat);
  repeat_first.replace(data, 4, std::string{1, 1, 1, 5});
  const std::vector<Case> cases = {
      {"run.hdr", run_past_end, "scanline 0 has a run of 127 past its end"},
      {"length.hdr", length, "scanline 0 declares 17 pixels, the width is 16"},
      {"repeat.hdr", repeat_first, "scanline 0 starts with a run-length repeat"},
      {"xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 8 +X 16\n", "FORMAT=32-bit_rle_xyze"},
      {"flip.hdr", "#?RADIANCE\n\n+Y 8 +X 16\n" + good.substr(data), "standard orientation"},
      {"cols.hdr", "#?RADIANCE\n\n+X 16 -Y 8\n" + good.substr(data), "standard orientation"},
      {"res.hdr", "#?RADIANCE\n\n-Y 8 +X 1x6\n" + good.substr(data), "resolution line"},
      {"noend.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "ends inside its header"},
      {"long.hdr", "#?RADIANCE\n" + std::string(envmap::kMaxHeaderBytes, 'x'),
       "no end of the header"},
      {"square.hdr", hdr_file(8, 8, test_pixels(8, 8), Encoding::rle), "not a 2:1"},
      {"huge.hdr", "#?RADIANCE\n\n-Y 16384 +X 32768\n", "more than the 134217728"},
  };
  for (const Case& c : cases) {
    write_bytes(dir.path / c.name, c.bytes);
    try {
      envmap::read_map(dir.path / c.name);
      ADD_FAILURE() << c.name << " was read";
    } catch (const io::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos)
          << c.name << ": " << e.what();
    }
  }
}

// A 1 KB file declaring 16384 × 8192 (1.5 GiB as float RGB) is refused as
// damaged without the map's memory ever being taken.
TEST(EnvmapInput, RadianceDeclaredSizeIsCheckedBeforeAllocation) {
  TempDir dir("envmap-hdr-big");
  std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n";
  bytes.resize(1024, static_cast<char>(77));
  write_bytes(dir.path / "big.hdr", bytes);
  const long before = peak_rss_kb();
  EXPECT_THROW(envmap::read_map(dir.path / "big.hdr"), io::InputError);
  EXPECT_LT(peak_rss_kb() - before, 64 * 1024) << "KB of peak memory taken";
}

// ---- OpenEXR ------------------------------------------------------------------

// An EXR header of w × h float RGB whose first `lines` scanlines are written
// (the rest missing, as a writer stopped early leaves them).
void write_partial_exr(const std::filesystem::path& p, int w, int h, int lines) {
  Imf::Header header(w, h);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
  Imf::OutputFile out(p.c_str(), header);
  std::vector<float> px(static_cast<std::size_t>(w) * static_cast<std::size_t>(lines) * 3, 1.0f);
  Imf::FrameBuffer fb;
  const std::size_t xs = 3 * sizeof(float), ys = xs * static_cast<std::size_t>(w);
  for (std::size_t c = 0; c < 3; ++c)
    fb.insert(std::string(1, "RGB"[c]),
              Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data() + c), xs, ys));
  out.setFrameBuffer(fb);
  out.writePixels(lines);
}

// A tiled EXR of w × h half RGB in square tiles of `tile` pixels whose first
// tile only is written.
void write_first_tile_exr(const std::filesystem::path& p, int w, int h, int tile) {
  Imf::Header hd(w, h);
  for (const char* c : {"R", "G", "B"}) hd.channels().insert(c, Imf::Channel(Imf::HALF));
  hd.setTileDescription(Imf::TileDescription(static_cast<unsigned>(tile),
                                             static_cast<unsigned>(tile), Imf::ONE_LEVEL));
  Imf::TiledOutputFile out(p.c_str(), hd);
  std::vector<half> px(static_cast<std::size_t>(tile * tile * 3), half(1.0f));
  Imf::FrameBuffer fb;
  for (std::size_t c = 0; c < 3; ++c)
    fb.insert(std::string(1, "RGB"[c]),
              Imf::Slice(Imf::HALF, reinterpret_cast<char*>(px.data() + c), 3 * sizeof(half),
                         3 * sizeof(half) * static_cast<std::size_t>(tile)));
  out.setFrameBuffer(fb);
  out.writeTile(0, 0);
}

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A 16384 × 8192 header over 16 written lines (7 KB), that file cut to 6 KB,
// and a tiled one with one tile written: refused as damaged before the map's
// 1.5 GiB is taken.
TEST(EnvmapInput, ExrDeclaredSizeIsCheckedBeforeAllocation) {
  TempDir dir("envmap-exr-big");
  const auto p = dir.path / "big.exr";
  write_partial_exr(p, 16384, 8192, 16);
  const std::string bytes = read_bytes(p);
  ASSERT_LT(bytes.size(), 16384u);
  write_bytes(dir.path / "cut.exr", bytes.substr(0, 6144));
  write_first_tile_exr(dir.path / "tiled.exr", 16384, 8192, 64);  // 1 of 32768 tiles
  const long before = peak_rss_kb();
  for (const char* name : {"big.exr", "cut.exr", "tiled.exr"}) {
    try {
      envmap::read_map(dir.path / name);
      ADD_FAILURE() << name << " was read";
    } catch (const io::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("damaged OpenEXR file"), std::string::npos) << e.what();
    }
  }
  EXPECT_LT(peak_rss_kb() - before, 64 * 1024) << "KB of peak memory taken";
}

// A tiled EXR whose tile description is patched to 1 × 1 tiles declares 512
// chunks, whose offset table alone is larger than the file: refused before
// the table is read (at 16384 × 8192 that table would be 1 GiB).
TEST(EnvmapInput, ExrChunkTableLargerThanTheFileIsRefused) {
  TempDir dir("envmap-exr-tiles");
  const auto p = dir.path / "tiled.exr";
  write_first_tile_exr(p, 32, 16, 32);  // the one tile
  std::string bytes = read_bytes(p);
  ASSERT_NO_THROW(envmap::read_map(p));
  // "tiles\0tiledesc\0", the size 9, then the tile width and height (uint32 LE).
  const std::size_t at = bytes.find(std::string("tiles\0tiledesc\0", 15));
  ASSERT_NE(at, std::string::npos);
  for (std::size_t k = 0; k < 8; ++k) bytes[at + 19 + k] = k % 4 == 0 ? 1 : 0;
  ASSERT_LT(bytes.size(), 512u * 8);
  write_bytes(p, bytes);
  try {
    envmap::read_map(p);
    ADD_FAILURE() << "read";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("offset table alone needs more than the file's"),
              std::string::npos)
        << e.what();
  }
}

// Every truncation of a small EXR is refused (InputError), never read.
TEST(EnvmapInput, TruncatedExrIsRefused) {
  TempDir dir("envmap-exr-cut");
  Map m = envmap::reconstruct({{{0, 0, 1}, 5.0, {1, 2, 3}}}, 32, 16);
  envmap::write_exr(dir.path / "m.exr", m);
  const std::string bytes = read_bytes(dir.path / "m.exr");
  for (std::size_t n = 1; n < bytes.size(); n += 7) {
    write_bytes(dir.path / "cut.exr", bytes.substr(0, n));
    EXPECT_THROW(envmap::read_map(dir.path / "cut.exr"), io::InputError) << "cut at " << n;
  }
}

// What the layout check must let through: tiled (one level and mipmaps),
// multi-part, an offset data window, half channels, other compressions.
TEST(EnvmapInput, ExrVariantsStillRead) {
  TempDir dir("envmap-exr-variants");
  const int w = 32, h = 16;
  const Map m = envmap::reconstruct({{{0.6, 0, 0.8}, 7.0, {1, 2, 3}}}, w, h);
  std::vector<float> px = m.rgb;
  std::vector<half> px_half(px.begin(), px.end());
  // The pixels as a frame buffer whose data window starts at (x0, y0).
  auto frame = [&](int x0, int y0, Imf::PixelType type) {
    Imf::FrameBuffer fb;
    const std::ptrdiff_t size = type == Imf::HALF ? sizeof(half) : sizeof(float);
    const std::ptrdiff_t xs = 3 * size, ys = xs * w;
    char* data = type == Imf::HALF ? reinterpret_cast<char*>(px_half.data())
                                   : reinterpret_cast<char*>(px.data());
    char* base = data - x0 * xs - y0 * ys;
    for (std::ptrdiff_t c = 0; c < 3; ++c)
      fb.insert(std::string(1, "RGB"[c]),
                Imf::Slice(type, base + c * size, static_cast<std::size_t>(xs),
                           static_cast<std::size_t>(ys)));
    return fb;
  };
  auto header = [&](Imf::Compression comp, Imf::PixelType type, int x0, int y0) {
    Imf::Header hd(Imath::Box2i({0, 0}, {w - 1, h - 1}),
                   Imath::Box2i({x0, y0}, {x0 + w - 1, y0 + h - 1}));
    hd.compression() = comp;
    for (const char* c : {"R", "G", "B"}) hd.channels().insert(c, Imf::Channel(type));
    return hd;
  };
  auto check = [&](const std::string& name, bool half) {
    SCOPED_TRACE(name);
    const Map r = envmap::read_map(dir.path / name);
    ASSERT_EQ(r.width, static_cast<std::size_t>(w));
    ASSERT_EQ(r.height, static_cast<std::size_t>(h));
    for (std::size_t k = 0; k < r.rgb.size(); ++k)
      ASSERT_NEAR(r.rgb[k], m.rgb[k], half ? 1e-3 * (1 + m.rgb[k]) : 0) << k;
  };
  for (auto [comp, type, name] : {std::tuple{Imf::NO_COMPRESSION, Imf::FLOAT, "none.exr"},
                                  std::tuple{Imf::PIZ_COMPRESSION, Imf::HALF, "piz_half.exr"},
                                  std::tuple{Imf::RLE_COMPRESSION, Imf::FLOAT, "rle.exr"},
                                  std::tuple{Imf::ZIPS_COMPRESSION, Imf::FLOAT, "zips.exr"}}) {
    {
      Imf::OutputFile out((dir.path / name).c_str(), header(comp, type, 5, -3));
      out.setFrameBuffer(frame(5, -3, type));
      out.writePixels(h);
    }
    check(name, type == Imf::HALF);
  }
  for (auto [mode, name] :
       {std::pair{Imf::ONE_LEVEL, "tiled.exr"}, std::pair{Imf::MIPMAP_LEVELS, "mipmap.exr"}}) {
    Imf::Header hd = header(Imf::ZIP_COMPRESSION, Imf::FLOAT, 0, 0);
    hd.setTileDescription(Imf::TileDescription(8, 4, mode));
    {
      Imf::TiledOutputFile out((dir.path / name).c_str(), hd);
      out.setFrameBuffer(frame(0, 0, Imf::FLOAT));
      out.writeTiles(0, out.numXTiles(0) - 1, 0, out.numYTiles(0) - 1, 0);
      for (int level = 1; level < out.numLevels(); ++level) {
        std::vector<float> small(static_cast<std::size_t>(out.levelWidth(level)) *
                                     static_cast<std::size_t>(out.levelHeight(level)) * 3,
                                 1.0f);
        Imf::FrameBuffer fb;
        const std::size_t xs = 3 * sizeof(float),
                          ys = xs * static_cast<std::size_t>(out.levelWidth(level));
        for (std::size_t c = 0; c < 3; ++c)
          fb.insert(std::string(1, "RGB"[c]),
                    Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(small.data() + c), xs, ys));
        out.setFrameBuffer(fb);
        out.writeTiles(0, out.numXTiles(level) - 1, 0, out.numYTiles(level) - 1, level);
      }
    }
    check(name, false);
  }
  {
    std::vector<Imf::Header> parts = {header(Imf::ZIP_COMPRESSION, Imf::FLOAT, 0, 0),
                                      header(Imf::ZIP_COMPRESSION, Imf::FLOAT, 0, 0)};
    for (int part = 0; part < 2; ++part) {
      parts[static_cast<std::size_t>(part)].setName(part == 0 ? "beauty" : "other");
      parts[static_cast<std::size_t>(part)].setType(Imf::SCANLINEIMAGE);
    }
    Imf::MultiPartOutputFile file((dir.path / "parts.exr").c_str(), parts.data(), 2);
    for (int part = 0; part < 2; ++part) {
      Imf::OutputPart out(file, part);
      out.setFrameBuffer(frame(0, 0, Imf::FLOAT));
      out.writePixels(h);
    }
  }
  check("parts.exr", false);
}

// ---- downsample and the working copy ------------------------------------------

// The solid angle of the region θ ∈ [t0, t1], φ ∈ [p0, p1].
double region_solid_angle(double t0, double t1, double p0, double p1) {
  return (p1 - p0) * (std::cos(t0) - std::cos(t1));
}

// One bright input pixel straddling output rows and columns (100 → 48 wide):
// each output pixel holds its radiance times the solid angle of their overlap
// over the output pixel's own, the overlap computed here in radians.
TEST(EnvmapInput, DownsampleToAnyEvenWidthAveragesByArea) {
  const std::size_t W = 100, H = 50, w = 48, h = 24, i0 = 37, j0 = 22;
  Map m;
  m.width = W;
  m.height = H;
  m.rgb.assign(W * H * 3, 0.0f);
  m.rgb[(j0 * W + i0) * 3 + 1] = 7.0f;
  const Map d = envmap::downsample(m, w);
  ASSERT_EQ(d.width, w);
  ASSERT_EQ(d.height, h);
  // θ of row boundary k of n rows, φ of column boundary k of n columns.
  auto theta = [](std::size_t k, std::size_t n) {
    return M_PI * static_cast<double>(k) / static_cast<double>(n);
  };
  auto phi = [](std::size_t k, std::size_t n) {
    return 2 * M_PI * static_cast<double>(k) / static_cast<double>(n);
  };
  const double t0 = theta(j0, H), t1 = theta(j0 + 1, H);
  const double p0 = phi(i0, W), p1 = phi(i0 + 1, W);
  int touched = 0;
  for (std::size_t oj = 0; oj < h; ++oj)
    for (std::size_t oi = 0; oi < w; ++oi) {
      const double a0 = theta(oj, h), a1 = theta(oj + 1, h);
      const double b0 = phi(oi, w), b1 = phi(oi + 1, w);
      const double lo_t = std::max(t0, a0), hi_t = std::min(t1, a1);
      const double lo_p = std::max(p0, b0), hi_p = std::min(p1, b1);
      const double overlap =
          hi_t > lo_t && hi_p > lo_p ? region_solid_angle(lo_t, hi_t, lo_p, hi_p) : 0;
      const double expected = 7.0 * overlap / region_solid_angle(a0, a1, b0, b1);
      touched += expected > 0;
      EXPECT_NEAR(d.at(oi, oj, 1), expected, 1e-6 * 7) << oi << ", " << oj;
      EXPECT_EQ(d.at(oi, oj, 0), 0.0f);
    }
  EXPECT_EQ(touched, 4);  // two rows by two columns
}

double integral(const Map& m) {
  double s = 0;
  for (std::size_t j = 0; j < m.height; ++j)
    for (std::size_t i = 0; i < m.width; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch) s += envmap::pixel_solid_angle(m, j) * m.at(i, j, ch);
  return s;
}

// A 2062 × 1031 map (no even divisor of 2062 in [8, 128]) is fitted on its
// 128 × 64 area average, which keeps its integral; so is every width.
TEST(EnvmapInput, WorkingCopyOfAnyWidthIs128Wide) {
  const std::vector<envmap::Lobe> lobes = {{{0.3, 0.4, std::sqrt(0.75)}, 40.0, {4, 3.5, 3}},
                                           {{-0.8, 0, -0.6}, 6.0, {0.5, 0.8, 1.2}}};
  for (std::size_t width : {2062, 1000, 130}) {
    const Map m = envmap::reconstruct(lobes, width, width / 2);
    const Map work = envmap::working_copy(m);
    EXPECT_EQ(work.width, 128u) << width;
    EXPECT_EQ(work.height, 64u) << width;
    EXPECT_NEAR(integral(work) / integral(m), 1.0, 1e-6) << width;
  }
}

TEST(EnvmapInput, DownsampleRefusesWidthsWithoutA21Result) {
  const Map m = envmap::reconstruct({{{0, 0, 1}, 5.0, {1, 1, 1}}}, 36, 18);
  for (std::size_t width : {9, 17, 6, 0}) {
    try {
      envmap::downsample(m, width);
      ADD_FAILURE() << width << " accepted";
    } catch (const io::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("must be even and at least 8"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(envmap::downsample(m, 38), io::InputError);
  EXPECT_EQ(envmap::downsample(m, 36).rgb, m.rgb);
  EXPECT_EQ(envmap::downsample(m, 10).height, 5u);
}

// ---- the fit's memory -------------------------------------------------------

// pixels × lobes is bounded before any fitting: a full 2062 × 1031 map with
// 256 lobes would hold about 122 GB; the 128 × 64 working copy holds 0.47 GB.
TEST(EnvmapInput, FitMemoryIsBoundedUpFront) {
  Map full;
  full.width = 2062;
  full.height = 1031;
  full.rgb.assign(full.width * full.height * 3, 1.0f);
  EXPECT_NEAR(envmap::fit_memory_bytes(full, 256), 2062.0 * 1031 * 256 * 224, 1);
  envmap::FitOptions o;
  o.lobes = 256;
  o.objective = envmap::Objective::radiance;
  try {
    envmap::fit(full, {}, o);
    ADD_FAILURE() << "a 2062 x 1031 fit with 256 lobes was attempted";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("would hold about 122 GB"), std::string::npos) << e.what();
  }
  EXPECT_THROW(envmap::fit_baseline(full, 256), io::InputError);
  const Map work = envmap::working_copy(full);
  EXPECT_NO_THROW(envmap::check_lobe_count(work, 256));
  EXPECT_LE(envmap::fit_memory_bytes(work, envmap::max_lobes(work)),
            static_cast<double>(envmap::kMaxFitBytes));
}

// ---- the command line ---------------------------------------------------------

// Damaged and oversized maps exit 2 naming the damage, at once, from every
// command that reads maps; a downsample to an odd width exits 2 and writes
// nothing.
TEST(EnvmapInputCli, DamagedMapsExitTwo) {
  TempDir dir("envmap-input-cli");
  const auto p = [&](const char* name) { return (dir.path / name).string(); };
  const std::vector<Rgbe> px = test_pixels(64, 32);
  const std::string rle = hdr_file(64, 32, px, Encoding::rle);
  const std::string flat = hdr_file(64, 32, px, Encoding::flat);
  write_bytes(p("cut55.hdr"), rle.substr(0, 55));
  write_bytes(p("half.hdr"), flat.substr(0, flat.size() / 2));
  std::string big = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n";
  big.resize(1024, static_cast<char>(77));
  write_bytes(p("big.hdr"), big);
  write_partial_exr(p("big.exr"), 16384, 8192, 16);
  write_bytes(p("good.hdr"), rle);
  std::filesystem::create_directory(p("maps"));
  write_bytes(p("maps/cut.hdr"), rle.substr(0, 55));
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases = {
      {{"envmap", "irradiance", p("cut55.hdr")}, "damaged Radiance HDR file"},
      {{"envmap", "fit", p("cut55.hdr"), "--lobes", "2", "--out", p("o.json")},
       "damaged Radiance HDR file"},
      {{"envmap", "baselines", "--maps", p("maps"), "--out", p("out"), "--quick"},
       "damaged Radiance HDR file"},
      {{"envmap", "irradiance", p("half.hdr")}, "damaged Radiance HDR file"},
      {{"envmap", "irradiance", p("big.hdr")}, "damaged Radiance HDR file"},
      {{"envmap", "irradiance", p("big.exr")}, "damaged OpenEXR file"},
      {{"envmap", "downsample", p("good.hdr"), p("o.exr"), "--width", "9"}, "must be even"},
      {{"envmap", "downsample", p("good.hdr"), p("o.exr"), "--width", "66"},
       "more than the map's width 64"},
  };
  for (const Case& c : cases) {
    const auto r = run_sglab(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args[1] << " " << c.args[2] << ": " << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args[2] << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(p("o.json")));
    EXPECT_FALSE(std::filesystem::exists(p("o.exr")));
  }
  // A width that does not divide the map's is area-averaged to a 2:1 map.
  const auto ok = run_sglab({"envmap", "downsample", p("good.hdr"), p("o.exr"), "--width", "24"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const Map d = envmap::read_map(p("o.exr"));
  EXPECT_EQ(d.width, 24u);
  EXPECT_EQ(d.height, 12u);
}

}  // namespace
