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
        "{}: {} x {} pixels, more than the {} (16384 x 8192) a map may have (README, Environment "
        "maps: the memory and time of the largest map)",
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

double pixel_solid_angle(const Map& map, std::size_t row) {
  const double h = static_cast<double>(map.height);
  const double t0 = M_PI * static_cast<double>(row) / h,
               t1 = M_PI * static_cast<double>(row + 1) / h;
  return 2 * M_PI / static_cast<double>(map.width) * (std::cos(t0) - std::cos(t1));
}

Vec3 pixel_direction(const Map& map, std::size_t i, std::size_t j) {
  const double theta = M_PI * (static_cast<double>(j) + 0.5) / static_cast<double>(map.height);
  const double phi = 2 * M_PI * (static_cast<double>(i) + 0.5) / static_cast<double>(map.width);
  return {std::sin(theta) * std::cos(phi), -std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Vec3 pixel_moment(const Map& map, std::size_t i, std::size_t j) {
  const double h = static_cast<double>(map.height), w = static_cast<double>(map.width);
  const double t0 = M_PI * static_cast<double>(j) / h, t1 = M_PI * static_cast<double>(j + 1) / h;
  const double p0 = 2 * M_PI * static_cast<double>(i) / w,
               p1 = 2 * M_PI * static_cast<double>(i + 1) / w;
  const double s2 = (t1 - t0) / 2 - (std::sin(2 * t1) - std::sin(2 * t0)) / 4;  // ∫ sin²θ dθ
  // ∫ sinθ cosθ dθ
  const double sc = (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) / 2;
  return {s2 * (std::sin(p1) - std::sin(p0)), s2 * (std::cos(p1) - std::cos(p0)), sc * (p1 - p0)};
}

Map downsample(const Map& map, std::size_t width) {
  if (width < 2 * kMinHeight || width > map.width || map.width % width != 0)
    throw InputError(fmt::format("--width {}: must divide the map's width {} and be at least {}",
                                 width, map.width, 2 * kMinHeight));
  const std::size_t f = map.width / width;
  Map out;
  out.width = width;
  out.height = width / 2;
  out.rgb.assign(out.width * out.height * 3, 0.0f);
  std::vector<double> omega(map.height);
  for (std::size_t j = 0; j < map.height; ++j) omega[j] = pixel_solid_angle(map, j);
  tbb::parallel_for(std::size_t{0}, out.height, [&](std::size_t oj) {
    double total = 0;
    for (std::size_t b = 0; b < f; ++b) total += omega[oj * f + b] * static_cast<double>(f);
    for (std::size_t oi = 0; oi < out.width; ++oi)
      for (std::size_t ch = 0; ch < 3; ++ch) {
        double sum = 0;
        for (std::size_t b = 0; b < f; ++b)
          for (std::size_t a = 0; a < f; ++a)
            sum += omega[oj * f + b] * map.at(oi * f + a, oj * f + b, ch);
        out.rgb[(oj * out.width + oi) * 3 + ch] = static_cast<float>(sum / total);
      }
  });
  return out;
}

Map working_copy(const Map& map, std::size_t max_width) {
  if (map.width <= max_width) return map;
  for (std::size_t w = max_width - max_width % 2; w >= 2 * kMinHeight; w -= 2)
    if (map.width % w == 0) return downsample(map, w);
  return map;  // no divisor: fit at full resolution
}

std::vector<Vec3> irradiance(const Map& map, const std::vector<Vec3>& normals) {
  const std::size_t n = map.width * map.height, W = map.width, H = map.height,
                    S = kHorizonSubdivision;
  std::vector<Vec3> moment(n), centre(n);
  tbb::parallel_for(std::size_t{0}, H, [&](std::size_t j) {
    for (std::size_t i = 0; i < W; ++i) {
      moment[j * W + i] = pixel_moment(map, i, j);
      centre[j * W + i] = pixel_direction(map, i, j);
    }
  });
  // A pixel lies within ρ = Δθ/2 + Δφ/2 of its centre ω_c (along the meridian,
  // then along the parallel, whose arc is at least the great circle's), so
  // n·ω > 0 on all of it when n·ω_c > sin ρ and n·ω < 0 when n·ω_c < −sin ρ.
  const double sin_rho =
      std::sin(M_PI / (2 * static_cast<double>(H)) + M_PI / static_cast<double>(W));
  // The pixels between: S × S sub-pixels, each with its own moment
  // (the closed form of pixel_moment, from per-sub-row and per-sub-column factors).
  std::vector<double> s2(H * S), sc(H * S), dsin(W * S), dcos(W * S);
  for (std::size_t r = 0; r < H * S; ++r) {
    const double t0 = M_PI * static_cast<double>(r) / static_cast<double>(H * S);
    const double t1 = M_PI * static_cast<double>(r + 1) / static_cast<double>(H * S);
    s2[r] = (t1 - t0) / 2 - (std::sin(2 * t1) - std::sin(2 * t0)) / 4;
    sc[r] = (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) / 2;
  }
  for (std::size_t c = 0; c < W * S; ++c) {
    const double p0 = 2 * M_PI * static_cast<double>(c) / static_cast<double>(W * S);
    const double p1 = 2 * M_PI * static_cast<double>(c + 1) / static_cast<double>(W * S);
    dsin[c] = std::sin(p1) - std::sin(p0);
    dcos[c] = std::cos(p1) - std::cos(p0);
  }
  const double dphi_sub = 2 * M_PI / static_cast<double>(W * S);
  std::vector<Vec3> out(normals.size());
  tbb::parallel_for(std::size_t{0}, normals.size(), [&](std::size_t k) {
    const Vec3& nv = normals[k];
    double r = 0, g = 0, b = 0;
    for (std::size_t p = 0; p < n; ++p) {
      const Vec3& c = centre[p];
      const double nc = nv[0] * c[0] + nv[1] * c[1] + nv[2] * c[2];
      double w;
      if (nc >= sin_rho) {
        w = nv[0] * moment[p][0] + nv[1] * moment[p][1] + nv[2] * moment[p][2];
      } else if (nc <= -sin_rho) {
        continue;
      } else {
        w = 0;
        const std::size_t j = p / W, i = p % W;
        for (std::size_t a = 0; a < S; ++a) {
          const std::size_t row = j * S + a;
          for (std::size_t bb = 0; bb < S; ++bb) {
            const std::size_t col = i * S + bb;
            const double x = nv[0] * s2[row] * dsin[col] + nv[1] * s2[row] * dcos[col] +
                             nv[2] * sc[row] * dphi_sub;
            if (x > 0) w += x;
          }
        }
      }
      if (w <= 0) continue;
      r += w * map.rgb[3 * p];
      g += w * map.rgb[3 * p + 1];
      b += w * map.rgb[3 * p + 2];
    }
    out[k] = {r, g, b};
  });
  return out;
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
