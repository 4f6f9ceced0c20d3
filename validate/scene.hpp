// validate/scene.hpp — a scene of SG lights and the error each irradiance
// method makes on it (`sglab recommend --scene FILE`).
//
// Scene file (JSON):
//   {"lights": [{"axis": [x, y, z], "sharpness": κ, "amplitude": [r, g, b]}, …]}
// axis: three finite numbers with a nonzero length (normalized on reading);
// sharpness: a finite number ≥ 0; amplitude: three finite numbers ≥ 0. Every
// light needs all three keys and no others; at least one light; at least one
// positive amplitude.
//
// The scene's irradiance at a normal n, per channel ch:
//   E_ch(n) = Σ_lights amplitude_ch · E(axis·n, κ),
// exactly (the reference engine) or with a method's Ê in float or double.
// Error of a method: max over the normals and the three channels of
// |Ê_ch(n) − E_ch(n)| divided by the scene's largest exact irradiance
// max_{n, ch} E_ch(n) — per channel, relative to one scene-wide scale, so a
// dim channel is not judged by its own tiny peak.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <sglab/registry.hpp>

#include "sweep.hpp"

namespace sglab::validate {

using Vec3 = std::array<double, 3>;

struct SceneLight {
  Vec3 axis;  // unit length
  double sharpness = 0;
  Vec3 amplitude;
};

struct Scene {
  std::vector<SceneLight> lights;
  double kappa_min() const;
  double kappa_max() const;
};

// A malformed or invalid scene; the message names the line (JSON syntax) or
// the key (e.g. "lights[1].sharpness") and what was wrong.
struct SceneError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The largest scene file read (io::read_input_file), about 100,000 lights.
inline constexpr std::size_t kMaxSceneFileBytes = 16 << 20;

// Parses scene JSON (io::parse_json_strict); `source` (a file name) prefixes every message.
Scene parse_scene(std::string_view text, std::string_view source);

// n unit vectors spread over the sphere (Fibonacci lattice:
// z_i = 1 − (2i + 1)/n, azimuth i·π(3 − √5)).
std::vector<Vec3> fibonacci_normals(std::size_t n);

// Per-normal RGB irradiance of the scene, exact (reference engine, in parallel).
std::vector<Vec3> scene_irradiance_reference(const Scene& scene, const std::vector<Vec3>& normals);
// The same with a method's f32 (binary32: cosine and κ rounded to float, the
// per-light value in float, summed in double) or f64.
std::vector<Vec3> scene_irradiance(const Scene& scene, const std::vector<Vec3>& normals, const Method& method,
                                   FloatFormat precision);

// max_{n,ch} |approx − exact| / max_{n,ch} exact (+inf on a non-finite value).
double scene_relative_error(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact);

}  // namespace sglab::validate
