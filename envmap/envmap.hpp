// envmap/envmap.hpp — HDR environment maps as SG lighting (`sglab envmap`).
//
// Direction convention (docs/envmaps.md; every envmap command uses it):
// a map is an equirectangular (latitude-longitude) image of width W = 2H,
// +z is up. Pixel (i, j), column i from the left and row j from the top
// (0-based), covers the polar angles θ ∈ [πj/H, π(j+1)/H] from +z (row 0
// touches the zenith, row H−1 the nadir) and the azimuths φ ∈ [2πi/W,
// 2π(i+1)/W], with the direction
//   ω(θ, φ) = (sin θ cos φ, −sin θ sin φ, cos θ);
// its centre is θ = π(j + ½)/H, φ = 2π(i + ½)/W. So the image's left edge
// looks along +x, a quarter of the way across along −y, the centre along −x.
// The pixel's solid angle is ΔΩ_j = (2π/W)(cos(πj/H) − cos(π(j+1)/H)); the
// W·H solid angles sum to 4π.
//
// Radiance is the pixel value (float RGB), constant over the pixel.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "common/io.hpp"
#include "common/vocabulary.hpp"
#include "reference/scene.hpp"

namespace sglab::envmap {

using Vec3 = reference::Vec3;

// An equirectangular RGB radiance map, rows from the top, RGB interleaved.
struct Map {
  std::size_t width = 0, height = 0;
  std::vector<float> rgb;  // width·height·3
  float at(std::size_t i, std::size_t j, std::size_t ch) const {
    return rgb[(j * width + i) * 3 + ch];
  }
};

// Largest map read: 2^27 pixels (16384 × 8192), and the smallest: 8 × 4. The
// largest holds 1.5 GiB as float RGB, and every envmap command keeps at most
// one such map (plus O(W + H) and its 128-wide working copy): docs/envmaps.md
// gives the memory and time measured at that size.
inline constexpr std::size_t kMaxPixels = std::size_t{1} << 27;
inline constexpr std::size_t kMinHeight = 4;

// Reads an OpenEXR file (channels R, G, B; half or float; the data window) or
// a Radiance .hdr file (envmap/radiance_hdr.hpp: RGBE decoded as Radiance
// does, (m + ½)·2^(e−136)), chosen by the file's contents, not its name. The
// size the file declares is checked (check_size) and found in the file (every
// OpenEXR chunk present within it; every .hdr scanline decoded once) before
// any pixel buffer is allocated. Throws io::InputError naming the file and
// the problem: missing or not a regular file, neither OpenEXR nor Radiance
// HDR, unreadable or damaged (cut short, a chunk or scanline missing), no
// R/G/B channels, a size check_size refuses, a NaN, infinite or negative value
// (naming the pixel and channel; see check_map for the tiny negatives of lossy
// encoders), no positive value.
Map read_map(const std::filesystem::path& path);

// The maps in the folder `dir`: its .exr and .hdr files, sorted. Throws
// io::InputError "OPTION DIR: …" (`option`: what named the folder) when the
// folder cannot be listed or holds no map.
std::vector<std::filesystem::path> map_files(const std::filesystem::path& dir,
                                             std::string_view option);

// A W × H map must be 2:1 (W = 2H), at least 8 × 4 and at most kMaxPixels;
// throws io::InputError naming `source` and the size otherwise.
void check_size(std::uint64_t width, std::uint64_t height, const std::string& source);

// Checks the rules above on a map in memory (`source` names it in messages),
// and sets the tiny negative values lossy encoders leave (down to
// −kNegativeTolerance × the map's mean radiance) to 0.
inline constexpr double kNegativeTolerance = 0.05;
void check_map(Map& map, const std::string& source);

// The map as a ZIP-compressed float RGB OpenEXR file, written atomically
// (io::write_file_atomic: a temporary renamed into place).
void write_exr(const std::filesystem::path& path, const Map& map);

// Area average to `width` × width/2 (width even, 8 … W): each output pixel is
// the solid-angle weighted mean of the input pixels it overlaps, each weighed
// by the solid angle of the overlap (whole pixels when width divides W, parts
// of the pixels on its edges otherwise), so every pixel's radiance times its
// solid angle — the map's integral — is kept. Throws io::InputError for an
// odd width, one below 8 or one above W.
Map downsample(const Map& map, std::size_t width);

// A copy at the fitting resolution: the map itself when W ≤ max_width, else
// its downsample to max_width (rounded down to even), whatever W is.
Map working_copy(const Map& map, std::size_t max_width = 128);

// Pixel geometry (the convention above).
double pixel_solid_angle(const Map& map, std::size_t row);
Vec3 pixel_direction(const Map& map, std::size_t i, std::size_t j);
// ∫ ω dΩ over the pixel (exact): the pixel's clamped-cosine weight for a
// normal n is n · moment whenever the whole pixel is above n's horizon.
Vec3 pixel_moment(const Map& map, std::size_t i, std::size_t j);

// The map's diffuse irradiance E(n) = ∫ L(ω) max(ω·n, 0) dω at each normal,
// RGB, for radiance constant over each pixel: a pixel wholly above n's
// horizon contributes L · n·m (m = ∫ω dΩ over the pixel, closed form), one
// wholly below nothing, and one the horizon cuts is split into
// kHorizonSubdivision² sub-pixels, each contributing L · max(n·m_sub, 0). In
// parallel over normals (TBB), deterministic. The reference every envmap
// error is measured against.
inline constexpr std::size_t kHorizonSubdivision = 16;
std::vector<Vec3> irradiance(const Map& map, const std::vector<Vec3>& normals);

// The pixel geometry above as a row factor times a column factor, so that the
// per-pixel values are products of per-row and per-column ones.
struct RowGeometry {
  double sin_theta, cos_theta;  // at the pixel centre
  double s2, sc;                // ∫ sin²θ dθ and ∫ sinθ cosθ dθ over the row
};
struct ColumnGeometry {
  double cos_phi, sin_phi;  // at the pixel centre
  double dsin, dcos, dphi;  // sin φ1 − sin φ0, cos φ1 − cos φ0, φ1 − φ0
};

// The same exact irradiance at any normal, one normal at a time (the dense
// error's local search asks for normals it chooses). Pixels are grouped in
// kTile × kTile tiles: a tile wholly above n's horizon contributes
// n · Σ_p L_p m_p (its moments summed once, per channel), one wholly below
// nothing, and only the tiles the horizon cuts are visited pixel by pixel,
// as irradiance() above does — the same sum, in another order. Keeps a
// reference to `map`.
class MapIrradiance {
 public:
  static constexpr std::size_t kTile = 8;
  explicit MapIrradiance(const Map& map);
  Vec3 at(const Vec3& normal) const;
  std::vector<Vec3> at(const std::vector<Vec3>& normals) const;  // in parallel (TBB)

 private:
  struct Tile {
    std::size_t i0, j0, i1, j1;  // pixel columns [i0, i1), rows [j0, j1)
    Vec3 centre;                 // unit
    double sin_rho;              // every pixel of the tile is within ρ of the centre
    std::array<Vec3, 3> moment;  // per channel, Σ_p L_p m_p
  };
  // A pixel the horizon cuts is visited in kBlock × kBlock blocks of
  // sub-pixels, with the same bound as the tiles: a block wholly above the
  // horizon contributes n · its moment (the sum of its sub-pixels' n · m), one
  // below nothing, and only the blocks the horizon cuts sub-pixel by sub-pixel.
  static constexpr std::size_t kBlock = 4;
  static_assert(kHorizonSubdivision % kBlock == 0);
  double pixel_weight(const Vec3& n, std::size_t i, std::size_t j) const;
  const Map& map_;
  std::vector<Tile> tiles_;
  double sin_rho_pixel_ = 0, sin_rho_block_ = 0;
  std::vector<RowGeometry> rows_, block_rows_, sub_rows_;  // per row, block row, sub-row
  std::vector<ColumnGeometry> columns_, block_columns_, sub_columns_;
  double sub_dphi_ = 0, block_dphi_ = 0, dphi_ = 0;
};

// ---- SG fits ------------------------------------------------------------------

struct Lobe {
  Vec3 axis;         // unit
  double sharpness;  // κ
  Vec3 amplitude;    // RGB ≥ 0, in the map's radiance units
};

enum class Objective { radiance, irradiance };
constexpr std::array<io::EnumName<Objective>, 2> names_of(Objective) {
  return {{{Objective::radiance, "radiance"}, {Objective::irradiance, "irradiance"}}};
}

// The BakingLab baseline ([BakingLab], SG.cpp GenerateUniformSGs / SolveNNLS):
// N axes on BakingLab's spherical Fibonacci spiral (z_k = (2k + 1)/N − 1,
// φ_k = kπ(3 − √5), our +z up), one shared sharpness
// κ = N ln(0.65) / (min_k h_k·a_0 − 1) with h_k the normalized half vector
// of a_k and a_0, and non-negative least-squares amplitudes per channel
// against the radiance of every pixel of the working copy, weighted by its
// solid angle (BakingLab samples uniformly; every pixel weighted by ΔΩ is the
// same integral). NNLS by Ceres with lower bounds 0 (a linear problem).
std::vector<Lobe> fit_baseline(const Map& work, std::size_t lobes);

struct FitOptions {
  std::size_t lobes = 12;
  Objective objective = Objective::irradiance;
  std::size_t fit_normals = 1024;  // irradiance objective: Fibonacci normals fitted at
  int max_iterations = 200;
};

struct FitReport {
  std::vector<Lobe> lobes;
  int iterations = 0;         // Ceres iterations, all stages
  bool converged = false;     // the last stage's termination was CONVERGENCE
  std::size_t nonfinite = 0;  // non-finite residual evaluations seen (0 in a sound fit)
};

// Largest lobe count a map supports: one lobe per 32 pixels of the working
// copy, at most 256.
std::size_t max_lobes(const Map& work);

// The memory a fit holds grows with pixels × lobes: Ceres' Jacobian of the
// radiance stage (3 residuals × 7 parameters × 8 bytes per pixel and lobe)
// and its workspace, 224 bytes per pixel and lobe in all (the slope of the
// peak resident size of `envmap fit data/envmaps/city.exr --objective
// radiance` from 8 to 32 lobes: 32.0 MB and 75.1 MB). A fit may hold at most
// kMaxFitBytes, so that `envmap baselines`' two fits at a time stay within
// 2 GiB beside the largest map; a 128 × 64 working copy with 256 lobes needs
// 0.47 GB.
inline constexpr std::size_t kFitBytesPerPixelLobe = 224;
inline constexpr std::size_t kMaxFitBytes = std::size_t{1} << 30;
double fit_memory_bytes(const Map& work, std::size_t lobes);

// Throws io::InputError for 0 lobes, more than max_lobes(work) (naming the
// limit) or a fit needing more than kMaxFitBytes (naming the memory needed),
// before any fitting.
void check_lobe_count(const Map& work, std::size_t lobes);

// Fibonacci normals every envmap error is measured at by default (a set
// other than the 1024 the irradiance objective is fitted at).
inline constexpr std::size_t kEvalNormals = 2000;

// The SG fit of the working copy `work` (the map at fitting resolution) with
// Ceres, every parameter jointly (axis on the unit sphere, sharpness in
// [1e-2, (H/π)²] — a lobe no narrower than a pixel —, amplitudes ≥ 0):
// - radiance: Σ_pixels ΔΩ ‖L − Σ_k G_k(ω)‖² from the baseline's lobes;
// - irradiance: Σ_normals ‖E_map(n) − Σ_k a_k Ê(a_k·n, κ_k)‖² at
//   `fit_normals` Fibonacci normals, Ê = sglab_acc3 (peak-relative error
//   ≤ 3.2e-5 of the exact SG irradiance) with its derivatives by central
//   differences, from the radiance fit. `exact` is the map's irradiance at
//   those normals (from the full map, not the working copy).
// Single-threaded Ceres (the same input gives the same bytes); run fits in
// parallel over maps or lobe counts. Throws io::InputError as
// check_lobe_count does.
FitReport fit(const Map& work, const std::vector<Vec3>& exact_at_fit_normals,
              const FitOptions& options);

// The lobes as a scene (reference/scene.hpp) and their exact irradiance at the
// normals (reference engine), RGB in the map's units.
reference::Scene to_scene(const std::vector<Lobe>& lobes);
std::vector<Vec3> lobes_irradiance_exact(const std::vector<Lobe>& lobes,
                                         const std::vector<Vec3>& normals);

// Max and RMS over normals and channels of |approx − exact|, divided by the
// largest exact irradiance (max over normals and channels).
struct ErrorStats {
  double max_rel = 0, rms_rel = 0;
};
ErrorStats irradiance_error(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact);

// The reconstruction Σ_k G_k(ω) at every pixel centre of a map of the given
// size (for figures).
Map reconstruct(const std::vector<Lobe>& lobes, std::size_t width, std::size_t height);

}  // namespace sglab::envmap
