// envmap/map.cpp — reading, checking, writing and downsampling equirectangular
// maps; pixel geometry; the exact irradiance of a map (envmap.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <system_error>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfTestFile.h>
#include <openexr.h>

#include "envmap/envmap.hpp"
#include "envmap/radiance_hdr.hpp"

namespace sglab::envmap {

namespace {

using io::InputError;

const char* channel_name(std::size_t ch) { return ch == 0 ? "R" : ch == 1 ? "G" : "B"; }

// OpenEXRCore's message for the failure being handled (its error callback
// has no user pointer: the context's is the file handle).
thread_local std::string exr_core_message;
void keep_exr_core_message(exr_const_context_t, exr_result_t, const char* message) {
  exr_core_message = message ? message : "";
}

// Before any pixel buffer: the data window of the part Imf::InputFile reads
// (part 0) passes check_size, and every chunk of its full-resolution level is
// in the file: its offset table fits in the file, and OpenEXRCore finds each
// chunk's header where the table says and checks that the chunk ends within
// the file. A header declaring more pixels than the file holds is so refused
// in time proportional to its chunk count. Deep parts are left to
// Imf::InputFile, which refuses them.
void check_exr_layout(const std::string& name) {
  exr_core_message.clear();
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = &keep_exr_core_message;
  exr_context_t raw = nullptr;
  auto why = [](exr_result_t rv) {
    return exr_core_message.empty() ? std::string(exr_get_default_error_message(rv))
                                    : exr_core_message;
  };
  const exr_result_t opened = exr_start_read(&raw, name.c_str(), &init);
  std::unique_ptr<exr_context_t, void (*)(exr_context_t*)> ctxt(
      &raw, [](exr_context_t* c) { exr_finish(c); });
  if (opened != EXR_ERR_SUCCESS)
    throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, why(opened)));
  exr_storage_t storage{};
  if (exr_get_storage(raw, 0, &storage) != EXR_ERR_SUCCESS ||
      (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED))
    return;
  exr_attr_box2i_t dw{};
  if (const exr_result_t rv = exr_get_data_window(raw, 0, &dw); rv != EXR_ERR_SUCCESS)
    throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, why(rv)));
  const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
  const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
  if (w <= 0 || h <= 0) throw InputError(fmt::format("{}: empty data window", name));
  check_size(static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), name);
  const std::uint64_t file_size = std::filesystem::file_size(name);
  int32_t chunks = 0;
  if (const exr_result_t rv = exr_get_chunk_count(raw, 0, &chunks); rv != EXR_ERR_SUCCESS)
    throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, why(rv)));
  if (chunks <= 0 || static_cast<std::uint64_t>(chunks) * 8 > file_size)
    throw InputError(fmt::format(
        "{}: damaged OpenEXR file: {} x {} pixels in {} chunks, whose offset table alone needs "
        "more than the file's {} bytes",
        name, w, h, chunks, file_size));
  auto check_chunk = [&](exr_result_t rv, const std::string& which) {
    if (rv != EXR_ERR_SUCCESS)
      throw InputError(
          fmt::format("{}: damaged OpenEXR file: {} is missing ({})", name, which, why(rv)));
  };
  exr_chunk_info_t info{};
  if (storage == EXR_STORAGE_SCANLINE) {
    int32_t lines = 0;
    exr_get_scanlines_per_chunk(raw, 0, &lines);
    for (long long y = dw.min.y; y <= dw.max.y; y += std::max(lines, 1))
      check_chunk(exr_read_scanline_chunk_info(raw, 0, static_cast<int>(y), &info),
                  fmt::format("the chunk of scanline {}", y));
  } else {
    int32_t tw = 0, th = 0, lw = 0, lh = 0;
    if (const exr_result_t rv = exr_get_tile_sizes(raw, 0, 0, 0, &tw, &th);
        rv != EXR_ERR_SUCCESS || tw <= 0 || th <= 0)
      throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, why(rv)));
    if (const exr_result_t rv = exr_get_level_sizes(raw, 0, 0, 0, &lw, &lh); rv != EXR_ERR_SUCCESS)
      throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, why(rv)));
    for (int ty = 0; ty < (lh + th - 1) / th; ++ty)
      for (int tx = 0; tx < (lw + tw - 1) / tw; ++tx)
        check_chunk(exr_read_tile_chunk_info(raw, 0, tx, ty, 0, 0, &info),
                    fmt::format("tile ({}, {})", tx, ty));
  }
}

Map read_exr(const std::string& name) {
  check_exr_layout(name);
  Imf::InputFile file(name.c_str());
  const Imath::Box2i dw = file.header().dataWindow();
  const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
  const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
  if (w <= 0 || h <= 0) throw InputError(fmt::format("{}: empty data window", name));
  check_size(static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h), name);
  const Imf::ChannelList& channels = file.header().channels();
  for (std::size_t ch = 0; ch < 3; ++ch)
    if (!channels.findChannel(channel_name(ch)))
      throw InputError(fmt::format("{}: no {} channel (an RGB map needs channels R, G and B)", name,
                                   channel_name(ch)));
  Map map;
  map.width = static_cast<std::size_t>(w);
  map.height = static_cast<std::size_t>(h);
  map.rgb.assign(map.width * map.height * 3, 0.0f);
  Imf::FrameBuffer fb;
  const std::size_t xs = 3 * sizeof(float), ys = xs * map.width;
  // The slice base is the address of pixel (0, 0) of the display, which the
  // data window may not contain: offset from the first pixel we hold.
  char* first = reinterpret_cast<char*>(map.rgb.data());
  const std::ptrdiff_t offset =
      static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) +
      static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
  for (std::size_t ch = 0; ch < 3; ++ch)
    fb.insert(channel_name(ch),
              Imf::Slice(Imf::FLOAT, first - offset + ch * sizeof(float), xs, ys));
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return map;
}

}  // namespace

void check_size(std::uint64_t width, std::uint64_t height, const std::string& source) {
  if (width > kMaxPixels || height > kMaxPixels || width * height > kMaxPixels)
    throw InputError(fmt::format(
        "{}: {} x {} pixels, more than the {} (16384 x 8192) a map may have (docs/envmaps.md: the "
        "memory and time of the largest map)",
        source, width, height, kMaxPixels));
  if (width != 2 * height)
    throw InputError(fmt::format(
        "{}: {} x {} pixels is not a 2:1 equirectangular map (width must be twice the height)",
        source, width, height));
  if (height < kMinHeight)
    throw InputError(fmt::format("{}: {} x {} pixels, at least {} x {} needed", source, width,
                                 height, 2 * kMinHeight, kMinHeight));
}

void check_map(Map& map, const std::string& source) {
  check_size(map.width, map.height, source);
  double integral = 0;  // Σ ΔΩ (r + g + b)
  for (std::size_t j = 0; j < map.height; ++j) {
    const double om = pixel_solid_angle(map, j);
    for (std::size_t i = 0; i < map.width; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch) {
        const float v = map.at(i, j, ch);
        if (std::isnan(v))
          throw InputError(
              fmt::format("{}: pixel ({}, {}) channel {} is NaN", source, i, j, channel_name(ch)));
        if (std::isinf(v))
          throw InputError(fmt::format("{}: pixel ({}, {}) channel {} is infinite", source, i, j,
                                       channel_name(ch)));
        integral += om * std::max(0.0f, v);
      }
  }
  const double mean = integral / (3 * 4 * M_PI);
  if (!(mean > 0))
    throw InputError(fmt::format("{}: no pixel is positive (the map is dark)", source));
  // Lossy encoders leave tiny negative values around dark pixels (every one of
  // Blender's studio-light worlds has some, down to −1.8 % of its mean): those down to
  // −kNegativeTolerance × the mean radiance are taken as 0; anything more
  // negative is refused.
  const double floor = -kNegativeTolerance * mean;
  for (std::size_t j = 0; j < map.height; ++j)
    for (std::size_t i = 0; i < map.width; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch) {
        float& v = map.rgb[(j * map.width + i) * 3 + ch];
        if (v >= 0) continue;
        if (v < floor)
          throw InputError(fmt::format(
              "{}: pixel ({}, {}) channel {} is negative ({}, below {:.3g} = -{} x the mean "
              "radiance {:.4g})",
              source, i, j, channel_name(ch), v, floor, kNegativeTolerance, mean));
        v = 0;
      }
}

Map read_map(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    throw InputError(fmt::format("{}: no such file", name));
  if (!std::filesystem::is_regular_file(status))
    throw InputError(
        fmt::format("{}: not a regular file (it is {})", name, io::file_type_name(path)));
  Map map;
  try {
    if (Imf::isOpenExrFile(name.c_str()))
      map = read_exr(name);
    else if (is_radiance_hdr(path))
      map = read_radiance_hdr(path);
    else
      throw InputError(
          fmt::format("{}: not an HDR image (neither OpenEXR nor Radiance .hdr)", name));
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: unreadable OpenEXR file ({})", name, e.what()));
  }
  check_map(map, name);
  return map;
}

std::vector<std::filesystem::path> map_files(const std::filesystem::path& dir,
                                             std::string_view option) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const auto ext = e.path().extension().string();
    if (ext == ".exr" || ext == ".hdr") files.push_back(e.path());
  }
  if (ec) throw InputError(fmt::format("{} {}: {}", option, dir.string(), ec.message()));
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw InputError(fmt::format("{} {}: no .exr or .hdr maps", option, dir.string()));
  return files;
}

void write_exr(const std::filesystem::path& path, const Map& map) {
  std::string bytes;
  {
    Imf::Header header(static_cast<int>(map.width), static_cast<int>(map.height));
    header.compression() = Imf::ZIP_COMPRESSION;
    for (std::size_t ch = 0; ch < 3; ++ch)
      header.channels().insert(channel_name(ch), Imf::Channel(Imf::FLOAT));
    Imf::StdOSStream os;
    {
      Imf::OutputFile out(os, header);
      Imf::FrameBuffer fb;
      const std::size_t xs = 3 * sizeof(float), ys = xs * map.width;
      char* base = const_cast<char*>(reinterpret_cast<const char*>(map.rgb.data()));
      for (std::size_t ch = 0; ch < 3; ++ch)
        fb.insert(channel_name(ch), Imf::Slice(Imf::FLOAT, base + ch * sizeof(float), xs, ys));
      out.setFrameBuffer(fb);
      out.writePixels(static_cast<int>(map.height));
    }
    bytes = os.str();
  }
  io::write_file_atomic(path, bytes);
}

namespace {

// Row j of `rows` equal rows over θ ∈ [0, π] (a map's pixel rows, or its
// sub-pixel rows).
RowGeometry row_geometry(std::size_t rows, std::size_t j) {
  const double h = static_cast<double>(rows);
  const double theta = M_PI * (static_cast<double>(j) + 0.5) / h;
  const double t0 = M_PI * static_cast<double>(j) / h, t1 = M_PI * static_cast<double>(j + 1) / h;
  return {std::sin(theta), std::cos(theta),
          (t1 - t0) / 2 - (std::sin(2 * t1) - std::sin(2 * t0)) / 4,
          (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) / 2};
}

// Column i of `columns` equal columns over φ ∈ [0, 2π].
ColumnGeometry column_geometry(std::size_t columns, std::size_t i) {
  const double w = static_cast<double>(columns);
  const double phi = 2 * M_PI * (static_cast<double>(i) + 0.5) / w;
  const double p0 = 2 * M_PI * static_cast<double>(i) / w,
               p1 = 2 * M_PI * static_cast<double>(i + 1) / w;
  return {std::cos(phi), std::sin(phi), std::sin(p1) - std::sin(p0), std::cos(p1) - std::cos(p0),
          p1 - p0};
}

Vec3 direction(const RowGeometry& r, const ColumnGeometry& c) {
  return {r.sin_theta * c.cos_phi, -r.sin_theta * c.sin_phi, r.cos_theta};
}

Vec3 moment(const RowGeometry& r, const ColumnGeometry& c) {
  return {r.s2 * c.dsin, r.s2 * c.dcos, r.sc * c.dphi};
}

// A piece of an input pixel that an output pixel of downsample covers: the
// input row or column and its weight.
struct Piece {
  std::size_t index;
  double weight;
};

// For each of `out` output pixels along an axis of `in` input pixels, the
// input pixels it covers: input pixel i spans [i·out, (i+1)·out] and output
// pixel o spans [o·in, (o+1)·in], in exact integer units of 1/(in·out) of the
// axis; weight(i, lo, hi) weighs the overlap [lo, hi].
template <class Weight>
std::vector<std::vector<Piece>> pieces(std::size_t in, std::size_t out, Weight weight) {
  std::vector<std::vector<Piece>> r(out);
  for (std::size_t o = 0; o < out; ++o) {
    const std::uint64_t a = std::uint64_t{o} * in, b = a + in;
    for (std::uint64_t i = a / out; i * out < b; ++i) {
      const std::uint64_t lo = std::max(i * out, a), hi = std::min((i + 1) * out, b);
      if (hi > lo) r[o].push_back({static_cast<std::size_t>(i), weight(i, lo, hi)});
    }
  }
  return r;
}

}  // namespace

double pixel_solid_angle(const Map& map, std::size_t row) {
  const double h = static_cast<double>(map.height);
  const double t0 = M_PI * static_cast<double>(row) / h,
               t1 = M_PI * static_cast<double>(row + 1) / h;
  return 2 * M_PI / static_cast<double>(map.width) * (std::cos(t0) - std::cos(t1));
}

Vec3 pixel_direction(const Map& map, std::size_t i, std::size_t j) {
  return direction(row_geometry(map.height, j), column_geometry(map.width, i));
}

Vec3 pixel_moment(const Map& map, std::size_t i, std::size_t j) {
  return moment(row_geometry(map.height, j), column_geometry(map.width, i));
}

Map downsample(const Map& map, std::size_t width) {
  if (width < 2 * kMinHeight || width % 2 != 0)
    throw InputError(
        fmt::format("--width {}: must be even and at least {} (the result is width x width/2, 2:1)",
                    width, 2 * kMinHeight));
  if (width > map.width)
    throw InputError(fmt::format("--width {}: more than the map's width {} (downsample reduces)",
                                 width, map.width));
  Map out;
  out.width = width;
  out.height = width / 2;
  out.rgb.assign(out.width * out.height * 3, 0.0f);
  // Rows weigh the solid angle of the part of the row covered (a whole row
  // exactly pixel_solid_angle), columns the fraction of the column covered.
  const double H = static_cast<double>(map.height), h = static_cast<double>(out.height);
  const auto rows =
      pieces(map.height, out.height, [&](std::uint64_t j, std::uint64_t lo, std::uint64_t hi) {
        if (hi - lo == out.height) return pixel_solid_angle(map, static_cast<std::size_t>(j));
        return 2 * M_PI / static_cast<double>(map.width) *
               (std::cos(M_PI * static_cast<double>(lo) / (H * h)) -
                std::cos(M_PI * static_cast<double>(hi) / (H * h)));
      });
  const auto columns =
      pieces(map.width, out.width, [&](std::uint64_t, std::uint64_t lo, std::uint64_t hi) {
        return static_cast<double>(hi - lo) / static_cast<double>(out.width);
      });
  tbb::parallel_for(std::size_t{0}, out.height, [&](std::size_t oj) {
    for (std::size_t oi = 0; oi < out.width; ++oi) {
      double covered = 0;  // input columns covered, in pixels
      for (const Piece& c : columns[oi]) covered += c.weight;
      double total = 0;  // the output pixel's solid angle
      for (const Piece& r : rows[oj]) total += r.weight * covered;
      for (std::size_t ch = 0; ch < 3; ++ch) {
        double sum = 0;
        for (const Piece& r : rows[oj])
          for (const Piece& c : columns[oi])
            sum += r.weight * c.weight * map.at(c.index, r.index, ch);
        out.rgb[(oj * out.width + oi) * 3 + ch] = static_cast<float>(sum / total);
      }
    }
  });
  return out;
}

Map working_copy(const Map& map, std::size_t max_width) {
  if (map.width <= max_width) return map;
  return downsample(map, max_width - max_width % 2);
}

MapIrradiance::MapIrradiance(const Map& map) : map_(map) {
  const std::size_t W = map.width, H = map.height, S = kHorizonSubdivision;
  // Per-row and per-column factors of every pixel's centre and moment (memory
  // O(W + H) beside the map, whatever its size).
  for (std::size_t j = 0; j < H; ++j) rows_.push_back(row_geometry(H, j));
  for (std::size_t i = 0; i < W; ++i) columns_.push_back(column_geometry(W, i));
  dphi_ = 2 * M_PI / static_cast<double>(W);
  // A pixel lies within ρ = Δθ/2 + Δφ/2 of its centre ω_c (along the meridian,
  // then along the parallel, whose arc is at least the great circle's), so
  // n·ω > 0 on all of it when n·ω_c > sin ρ and n·ω < 0 when n·ω_c < −sin ρ.
  sin_rho_pixel_ = std::sin(M_PI / (2 * static_cast<double>(H)) + M_PI / static_cast<double>(W));
  // The pixels between: S × S sub-pixels, each with its own moment (the
  // closed form of pixel_moment, from per-sub-row and per-sub-column factors).
  for (std::size_t r = 0; r < H * S; ++r) sub_rows_.push_back(row_geometry(H * S, r));
  for (std::size_t c = 0; c < W * S; ++c) sub_columns_.push_back(column_geometry(W * S, c));
  sub_dphi_ = 2 * M_PI / static_cast<double>(W * S);
  // Blocks of kBlock × kBlock sub-pixels, bounded as the pixels are.
  const std::size_t BH = H * S / kBlock, BW = W * S / kBlock;
  for (std::size_t r = 0; r < BH; ++r) block_rows_.push_back(row_geometry(BH, r));
  for (std::size_t c = 0; c < BW; ++c) block_columns_.push_back(column_geometry(BW, c));
  block_dphi_ = 2 * M_PI / static_cast<double>(BW);
  sin_rho_block_ = std::sin(M_PI / (2 * static_cast<double>(BH)) + M_PI / static_cast<double>(BW));
  // Tiles: the same bound with the tile's extent (ρ = Δθ_tile/2 + Δφ_tile/2).
  for (std::size_t j0 = 0; j0 < H; j0 += kTile)
    for (std::size_t i0 = 0; i0 < W; i0 += kTile) {
      Tile t{};
      t.i0 = i0;
      t.j0 = j0;
      t.i1 = std::min(W, i0 + kTile);
      t.j1 = std::min(H, j0 + kTile);
      const double th0 = M_PI * static_cast<double>(t.j0) / static_cast<double>(H);
      const double th1 = M_PI * static_cast<double>(t.j1) / static_cast<double>(H);
      const double ph0 = 2 * M_PI * static_cast<double>(t.i0) / static_cast<double>(W);
      const double ph1 = 2 * M_PI * static_cast<double>(t.i1) / static_cast<double>(W);
      const double th = (th0 + th1) / 2, ph = (ph0 + ph1) / 2;
      t.centre = {std::sin(th) * std::cos(ph), -std::sin(th) * std::sin(ph), std::cos(th)};
      t.sin_rho = std::sin(std::min(M_PI / 2, (th1 - th0) / 2 + (ph1 - ph0) / 2));
      for (std::size_t j = t.j0; j < t.j1; ++j)
        for (std::size_t i = t.i0; i < t.i1; ++i) {
          const RowGeometry& row = rows_[j];
          const ColumnGeometry& column = columns_[i];
          const Vec3 m = {row.s2 * column.dsin, row.s2 * column.dcos, row.sc * dphi_};
          for (std::size_t ch = 0; ch < 3; ++ch)
            for (std::size_t d = 0; d < 3; ++d) t.moment[ch][d] += map.at(i, j, ch) * m[d];
        }
      tiles_.push_back(t);
    }
}

double MapIrradiance::pixel_weight(const Vec3& nv, std::size_t i, std::size_t j) const {
  const RowGeometry& r = rows_[j];
  const ColumnGeometry& c = columns_[i];
  const double nc = r.sin_theta * (nv[0] * c.cos_phi - nv[1] * c.sin_phi) + nv[2] * r.cos_theta;
  if (nc >= sin_rho_pixel_)
    return nv[0] * r.s2 * c.dsin + nv[1] * r.s2 * c.dcos + nv[2] * r.sc * dphi_;
  if (nc <= -sin_rho_pixel_) return 0;
  const std::size_t S = kHorizonSubdivision, K = S / kBlock;
  double w = 0;
  for (std::size_t ba = 0; ba < K; ++ba) {
    const RowGeometry& brow = block_rows_[j * K + ba];
    for (std::size_t bb = 0; bb < K; ++bb) {
      const ColumnGeometry& bcol = block_columns_[i * K + bb];
      const double bc =
          brow.sin_theta * (nv[0] * bcol.cos_phi - nv[1] * bcol.sin_phi) + nv[2] * brow.cos_theta;
      if (bc >= sin_rho_block_) {
        w += nv[0] * brow.s2 * bcol.dsin + nv[1] * brow.s2 * bcol.dcos +
             nv[2] * brow.sc * block_dphi_;
        continue;
      }
      if (bc <= -sin_rho_block_) continue;
      for (std::size_t a = ba * kBlock; a < (ba + 1) * kBlock; ++a) {
        const RowGeometry& row = sub_rows_[j * S + a];
        for (std::size_t b = bb * kBlock; b < (bb + 1) * kBlock; ++b) {
          const ColumnGeometry& col = sub_columns_[i * S + b];
          const double x =
              nv[0] * row.s2 * col.dsin + nv[1] * row.s2 * col.dcos + nv[2] * row.sc * sub_dphi_;
          if (x > 0) w += x;
        }
      }
    }
  }
  return w;
}

Vec3 MapIrradiance::at(const Vec3& nv) const {
  double r = 0, g = 0, b = 0;
  for (const Tile& t : tiles_) {
    const double nc = nv[0] * t.centre[0] + nv[1] * t.centre[1] + nv[2] * t.centre[2];
    if (nc <= -t.sin_rho) continue;
    if (nc >= t.sin_rho) {
      r += nv[0] * t.moment[0][0] + nv[1] * t.moment[0][1] + nv[2] * t.moment[0][2];
      g += nv[0] * t.moment[1][0] + nv[1] * t.moment[1][1] + nv[2] * t.moment[1][2];
      b += nv[0] * t.moment[2][0] + nv[1] * t.moment[2][1] + nv[2] * t.moment[2][2];
      continue;
    }
    for (std::size_t j = t.j0; j < t.j1; ++j)
      for (std::size_t i = t.i0; i < t.i1; ++i) {
        const double w = pixel_weight(nv, i, j);
        if (w <= 0) continue;
        const std::size_t p = j * map_.width + i;
        r += w * map_.rgb[3 * p];
        g += w * map_.rgb[3 * p + 1];
        b += w * map_.rgb[3 * p + 2];
      }
  }
  return {r, g, b};
}

std::vector<Vec3> MapIrradiance::at(const std::vector<Vec3>& normals) const {
  std::vector<Vec3> out(normals.size());
  tbb::parallel_for(std::size_t{0}, normals.size(),
                    [&](std::size_t k) { out[k] = at(normals[k]); });
  return out;
}

std::vector<Vec3> irradiance(const Map& map, const std::vector<Vec3>& normals) {
  return MapIrradiance(map).at(normals);
}

ErrorStats irradiance_error(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact) {
  double peak = 0, worst = 0, sq = 0;
  for (const auto& e : exact)
    for (double x : e) peak = std::max(peak, x);
  std::size_t count = 0;
  for (std::size_t i = 0; i < exact.size() && i < approx.size(); ++i)
    for (std::size_t ch = 0; ch < 3; ++ch) {
      const double d = std::abs(approx[i][ch] - exact[i][ch]);
      if (!std::isfinite(d))
        return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
      worst = std::max(worst, d);
      sq += d * d;
      ++count;
    }
  return {worst / peak,
          std::sqrt(sq / static_cast<double>(std::max<std::size_t>(count, 1))) / peak};
}

}  // namespace sglab::envmap
