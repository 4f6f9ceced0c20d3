// reference/scene.hpp — a scene of SG lights and its exact irradiance.
//
// Scene file (JSON):
//   {"lights": [{"axis": [x, y, z], "sharpness": κ, "amplitude": [r, g, b]}, …]}
// and optionally "provenance": an object, not read (how the scene was made,
// e.g. by `sglab envmap fit --out`).
// axis: three finite numbers with a nonzero length (normalized on reading);
// sharpness: a finite number ≥ 0; amplitude: three finite numbers ≥ 0. Every
// light needs all three keys and no others; at least one light; at least one
// positive amplitude.
//
// The scene's irradiance at a normal n, per channel ch:
//   E_ch(n) = Σ_lights amplitude_ch · E(axis·n, κ),
// exactly: the reference engine's E through the irradiance table
// (reference/irradiance_table.hpp: within 1e−10 of each light's peak E(1, κ)).
// Every sum is formed in units of the scene's largest amplitude
// (amplitude / max amplitude ∈ [0, 1]), which neither overflows (1e308-bright
// lights) nor underflows (1e−300-dim ones). Lights with the same sharpness and
// axis are one lobe (their amplitudes summed: E depends on κ and c only).
//
// The error each method makes on a scene is validate/scene_errors.hpp; the
// limits below bound that evaluation, one evaluation of the table and of each
// method per (distinct light, normal). The normals are summed in parallel
// (TBB) in blocks of at most kSceneBlockNormals, each holding its sums alone,
// so memory does not grow with the (light, normal) pairs beyond the scene and
// normals themselves.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace sglab::reference {

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

// Limits of a scene evaluation (docs/cli.md, "Choosing a method for a scene"),
// refused before any work: lights per scene, normals, and (light, normal)
// pairs, each pair one evaluation of every method (about 1 µs of one core
// for the registry in float) and of the irradiance table.
inline constexpr std::size_t kMaxSceneLights = 100000;
inline constexpr std::size_t kMaxSceneNormals = 1000000;
inline constexpr std::size_t kMaxScenePairs = 50000000;
inline constexpr std::size_t kSceneBlockNormals = 16;

// The largest scene file read (io::read_input_file), about 100,000 lights.
inline constexpr std::size_t kMaxSceneFileBytes = 16 << 20;

// Parses scene JSON (io::parse_json_strict); `source` (a file name) prefixes
// every message. A sharpness must be at most the largest float (every method
// is ranked in float), and a scene has at most kMaxSceneLights lights.
Scene parse_scene(std::string_view text, std::string_view source);

// Bytes a scene evaluation of `lights` lights at `normals` normals holds at
// most: the lights (with one slice of the irradiance table each) and the
// normals; each parallel task adds one block's sums (a few KB).
std::size_t scene_memory_bytes(std::size_t lights, std::size_t normals);

// Throws SceneError (naming the limit, the pair count and the memory) when
// `lights` × `normals` is beyond the limits above.
void check_scene_limits(std::size_t lights, std::size_t normals);

// n unit vectors spread over the sphere (Fibonacci lattice:
// z_i = 1 − (2i + 1)/n, azimuth i·π(3 − √5)).
std::vector<Vec3> fibonacci_normals(std::size_t n);

// A light in units of the scene's largest amplitude; lights with the same
// sharpness and axis merged into one lobe (their amplitudes summed).
struct SceneLobe {
  double kappa;
  Vec3 axis;
  Vec3 amplitude;
};

// The scene's lobes, sorted by (κ, axis): every sum over them adds them in
// this order.
std::vector<SceneLobe> scene_lobes(const Scene& scene);

// The cosine between a unit axis and a unit normal, kept in [−1, 1] against rounding.
inline double scene_cosine(const Vec3& axis, const Vec3& normal) {
  return std::clamp(axis[0] * normal[0] + axis[1] * normal[1] + axis[2] * normal[2], -1.0, 1.0);
}

// Per-normal RGB irradiance of the scene in units of its largest amplitude,
// exact (the reference E through the irradiance table, in parallel).
std::vector<Vec3> scene_irradiance_reference(const Scene& scene, const std::vector<Vec3>& normals);

}  // namespace sglab::reference
