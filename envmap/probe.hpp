// envmap/probe.hpp — diffuse lighting probes of an environment map (spherical
// harmonics, ZH3, SG lobes, SH + lobes) behind one interface, and the dense
// error every envmap error is measured with.
//
// Every probe approximates the map's irradiance E(n) (envmap.hpp, irradiance)
// and is judged on it: max and RMS over normals and RGB of |E_probe − E_map|,
// relative to the largest E_map.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "envmap/envmap.hpp"

namespace sglab::envmap {

// ---- Dense error -------------------------------------------------------------

// Normals of the dense set (Fibonacci) every probe error is measured at.
inline constexpr std::size_t kDenseNormals = 20000;
// Normals (Fibonacci, other than the dense set) the probes' least squares fit.
inline constexpr std::size_t kFitNormals = 1024;

// The map's exact irradiance at the dense set, and the largest irradiance
// (max over the dense set and RGB, raised by a local maximization of each
// channel from its largest dense value).
struct DenseTruth {
  const MapIrradiance* field = nullptr;  // the exact irradiance at any normal
  std::vector<Vec3> normals, exact;
  double peak = 0;
  double spacing = 0;  // mean distance between neighbouring normals, √(4π/N) rad
};
DenseTruth dense_truth(const MapIrradiance& field, std::size_t normals = kDenseNormals);

struct DenseError {
  double max_rel = 0, rms_rel = 0;  // over the dense set and the local searches; RMS: dense set
  double dense_max_rel = 0;         // over the dense set alone
  Vec3 worst{0, 0, 1};              // the normal of max_rel
};

// A probe's irradiance at one normal (RGB, the map's units).
using IrradianceFn = std::function<Vec3(const Vec3&)>;

// The error of `approx` over the dense set, then a local maximization of
// |E_approx − E_map| (a pattern search on the sphere, steps from the set's
// spacing down to 1e−4 rad, the exact E_map at every step) from the `starts`
// worst dense normals at least 3 spacings apart. Deterministic.
DenseError dense_error(const DenseTruth& truth, const IrradianceFn& approx, std::size_t starts = 8);

// ---- Spherical harmonics -----------------------------------------------------

inline constexpr int kMaxShOrder = 4;
constexpr std::size_t sh_count(int order) {
  return static_cast<std::size_t>((order + 1) * (order + 1));
}

// Real orthonormal spherical harmonics Y_lm, l ≤ order, at the unit vector
// (x, y, z), index l² + l + m, m = −l … l: Y_l0 = K_l0 P̄_l^0(z),
// Y_l±m = √2 K_lm P̄_l^m(z) (Re, Im)(x + iy)^m, K_lm = √((2l+1)/4π · (l−m)!/(l+m)!),
// P̄_l^m = P_l^m / sin^m θ (no Condon–Shortley phase) by the usual recurrence.
// Templated on the scalar (Ceres Jets differentiate it).
template <class T>
void sh_basis(int order, const T& x, const T& y, const T& z, T* out) {
  T cm = T(1), sm = T(0);  // (x + iy)^m
  double pmm = 1;          // P̄_m^m = (2m − 1)!!
  for (int m = 0; m <= order; ++m) {
    if (m > 0) {
      const T c = cm * x - sm * y, s = cm * y + sm * x;
      cm = c;
      sm = s;
      pmm *= 2 * m - 1;
    }
    T p_prev = T(0), p = T(pmm);
    for (int l = m; l <= order; ++l) {
      if (l > m) {
        const T next = (T(2 * l - 1) * z * p - T(l + m - 1) * p_prev) / T(l - m);
        p_prev = p;
        p = next;
      }
      double ratio = 1;  // (l − m)!/(l + m)!
      for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
      const double K = std::sqrt((2 * l + 1) / (4 * M_PI) * ratio);
      if (m == 0) {
        out[l * l + l] = T(K) * p;
      } else {
        out[l * l + l + m] = T(std::sqrt(2.0) * K) * p * cm;
        out[l * l + l - m] = T(std::sqrt(2.0) * K) * p * sm;
      }
    }
  }
}

// Â_l: the clamped cosine's Funk–Hecke factor, E_lm = Â_l L_lm
// ([Ramamoorthi2001] eq. 8–9): π, 2π/3, π/4, 0, −π/24 for l = 0 … 4; 0 for odd
// l > 1; 2π (−1)^{l/2−1} / ((l + 2)(l − 1)) · l! / (2^l ((l/2)!)²) for even l ≥ 2.
double clamped_cosine_factor(int l);

// The radiance's SH coefficients L_lm, l ≤ order, per RGB: Σ_pixels L_p ∫ Y_lm dΩ
// over each pixel (3 × 3 Gauss–Legendre in θ and φ with the sin θ weight).
std::vector<Vec3> radiance_sh(const Map& map, int order);

// ---- Probes ------------------------------------------------------------------

enum class ProbeKind {
  sh,         // irradiance SH of `order`
  sh_nonneg,  // L1 irradiance SH with its gradient shortened so E ≥ 0 everywhere
  zh3,        // L1 SH + one zonal l = 2 term per channel along the L1 luminance direction
  lobes,      // SG lobes, E = Σ a_k E(μ_k·n, κ_k) (exact SG irradiance)
  hybrid,     // L2 irradiance SH + SG lobes
};

// Luminance weights of linear Rec. 709 RGB: the ZH3 axis.
inline constexpr std::array<double, 3> kLuminance{0.2126, 0.7152, 0.0722};

struct Probe {
  ProbeKind kind = ProbeKind::sh;
  int order = 2;            // SH order (sh: 0 … 4; sh_nonneg, zh3: 1; hybrid: 2)
  std::string fit;          // "projection" or "fit" (least squares at the fit normals) ...
  std::vector<Vec3> sh;     // irradiance SH coefficients E_lm, sh_count(order) × RGB
  Vec3 zonal{0, 0, 0};      // zh3: E's zonal l = 2 coefficient per channel
  std::vector<Lobe> lobes;  // lobes, hybrid
  // The runtime irradiance method the lobes were fitted with (the ladders'
  // Ê, envmap/fit.cpp) and are exported with (`sglab export --probe`).
  std::string method = "sglab_acc3";

  // The ZH3 axis: the L1 luminance direction of `sh` (not stored: derived).
  Vec3 zonal_axis() const;
  // Stored floats: 3 per SH coefficient, 3 for ZH3's zonal term, 7 per lobe
  // (axis 3, sharpness 1, RGB amplitude 3). Bytes: 4 per float (IEEE binary32).
  std::size_t floats() const;
  std::size_t bytes() const { return 4 * floats(); }
  std::string label() const;  // "SH L2", "ZH3", "4 SG", "SH L2 + 3 SG", ...
  nlohmann::ordered_json to_json() const;
  // Throws io::InputError naming the key (the caller names the file): a
  // missing or mistyped key, a coefficient count that does not match the
  // order, a non-finite number, a zero axis, a negative sharpness, a method
  // that is not a registered irradiance method.
  static Probe from_json(const nlohmann::ordered_json& j);
};

// The probe's irradiance (lobes through the exact SG irradiance table).
IrradianceFn probe_irradiance(const Probe& probe);
// The same with the lobes through the runtime's `method` in double, as the
// exported probe evaluates them.
IrradianceFn probe_irradiance_method(const Probe& probe);

// Projections: E_lm = Â_l L_lm of the map (the L2-best irradiance of that
// order over the sphere); the non-negative L1; ZH3 as [Roughton2024]: L1
// plus the l = 2 band's best zonal fit along the L1 luminance direction d,
// z = √(4π/5) Σ_m E_2m Y_2m(d).
Probe project_sh(const std::vector<Vec3>& radiance_sh, int order);
Probe project_sh_nonneg(const std::vector<Vec3>& radiance_sh);
Probe project_zh3(const std::vector<Vec3>& radiance_sh);

// The same families fitted on the irradiance objectives the lobes are fitted
// on: E_map at `normals` by linear least squares, or their minimax per channel
// by kLinearMinimaxRounds rounds of Lawson's iteration [Lawson1961] (ZH3: with
// the projection's axis).
enum class LinearFit { least_squares, minimax };
inline constexpr int kLinearMinimaxRounds = 50;
Probe fit_sh(const std::vector<Vec3>& normals, const std::vector<Vec3>& exact, int order,
             LinearFit how = LinearFit::least_squares);
Probe fit_zh3(const std::vector<Vec3>& normals, const std::vector<Vec3>& exact, const Vec3& axis,
              LinearFit how = LinearFit::least_squares);

// ---- Fits of lobes and hybrids (envmap/fit.cpp) -------------------------------

// envmap::fit at the given normals (`exact` the map's irradiance there).
FitReport fit_with_normals(const Map& work, const std::vector<Vec3>& normals,
                           const std::vector<Vec3>& exact, const FitOptions& options);

// Rounds of Lawson's minimax iteration [Lawson1961] after least squares, and
// the Ceres iterations of each (a round starts from the last one's solution).
inline constexpr int kMinimaxRounds = 8;
inline constexpr int kMinimaxIterations = 10;

struct LadderStep {
  Probe probe;
  std::string start;   // the candidate kept: "fresh", "warm", "restart r", "lobes", "kept n-1",
                       // "kept k-1",
                       // with " minimax" when its minimax refinement was kept
  double judged = 0;   // the judge's value of the probe
  double seconds = 0;  // wall time of the step, every candidate
};
// The error a ladder minimizes when it chooses among candidates (the dense max
// error on the full map, for `envmap baselines`).
using Judge = std::function<double(const Probe&)>;

// Lobe probes of 1 … max_lobes lobes on the irradiance objective (least
// squares at `normals`, derivatives of Ê by Ceres Jets through the runtime's
// template). At each count the candidates are a fresh fit (radiance stage,
// then the irradiance), the previous count's solution plus the best new lobe
// (at the largest residual) refined jointly, and the previous solution with a
// zero-amplitude lobe; the best of the first two (by the judge) is also
// refined toward the minimax at `normals` (`minimax_rounds` rounds of Lawson's
// iteration [Lawson1961], kMinimaxIterations Ceres iterations each; the round
// with the smallest max residual there), and that refinement is a candidate
// too. The one the judge rates lowest is kept, so the judged error never
// increases with the count. With `restarts` > 0 a second ladder runs whose
// steps also try that many fits started from lobes drawn from the map's light
// (quasi-random axes by luminance × solid angle [Roberts2018], log-uniform
// sharpness; the one with the smallest max residual at `normals` is a
// candidate, and it too is refined toward the minimax); each count keeps the
// better of the two ladders, so restarts never raise an error (they cost the
// second ladder and its restarts' fits). Deterministic.
std::vector<LadderStep> fit_lobe_ladder(const Map& work, const std::vector<Vec3>& normals,
                                        const std::vector<Vec3>& exact, std::size_t max_lobes,
                                        const Judge& judge, int max_iterations = 100,
                                        int minimax_rounds = kMinimaxRounds, int restarts = 0);
// The starting lobes of the ladder's restart `restart` at `lobes` lobes: axes
// drawn from the working copy's light (each pixel's luminance × solid angle)
// at points of the R2 sequence [Roberts2018], sharpness log-uniform on
// [1, min(κ_max, 256)], each carrying 1/lobes of the map's light.
std::vector<Lobe> restart_lobes(const Map& work, std::size_t lobes, std::size_t restart);
// The same ladder at the given increasing lobe counts only: a step from m to n
// lobes warm-starts with the n − m best new lobes, each at the largest
// residual the lobes before it leave.
std::vector<LadderStep> fit_lobe_ladder(const Map& work, const std::vector<Vec3>& normals,
                                        const std::vector<Vec3>& exact,
                                        const std::vector<std::size_t>& counts, const Judge& judge,
                                        int max_iterations = 100,
                                        int minimax_rounds = kMinimaxRounds, int restarts = 0);

// fit_lobe_ladder grown on demand: grow_to(n) fits the counts after those
// already fitted up to n and returns every step, so growing to 4 and then to 8
// gives exactly fit_lobe_ladder to 8 (deterministic) at the cost of 8 steps,
// not 12. The map, normals and irradiance are referenced, not copied.
class LobeLadder {
 public:
  LobeLadder(const Map& work, const std::vector<Vec3>& normals, const std::vector<Vec3>& exact,
             Judge judge, int max_iterations = 100, int minimax_rounds = kMinimaxRounds,
             int restarts = 0);
  const std::vector<LadderStep>& grow_to(std::size_t max_lobes);

 private:
  const Map& work_;
  const std::vector<Vec3>& normals_;
  const std::vector<Vec3>& exact_;
  Judge judge_;
  int max_iterations_, minimax_rounds_, restarts_;
  std::vector<LadderStep> plain_, restarted_, steps_;  // the two ladders, the better of each
};

// L2 SH + k lobes, k = 1 … max_lobes, fitted jointly: candidates the k-lobe
// probe of `lobe_ladder` with SH fitted to what it leaves, the (k − 1) hybrid
// plus the best new lobe (k = 1: the fitted L2 SH), and the (k − 1) hybrid
// with a zero lobe; each refined jointly, plus the minimax refinement of the
// best of the first two as in fit_lobe_ladder; the judge's lowest kept.
std::vector<LadderStep> fit_hybrid_ladder(const Map& work, const std::vector<Vec3>& normals,
                                          const std::vector<Vec3>& exact,
                                          const std::vector<LadderStep>& lobe_ladder,
                                          std::size_t max_lobes, const Judge& judge,
                                          int max_iterations = 100,
                                          int minimax_rounds = kMinimaxRounds);

}  // namespace sglab::envmap
