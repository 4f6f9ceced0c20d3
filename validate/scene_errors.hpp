// validate/scene_errors.hpp — the error each irradiance method makes on a
// scene of SG lights (reference/scene.hpp; `sglab recommend --scene FILE`).
//
// A method's scene irradiance at a normal n, per channel ch:
//   Ê_ch(n) = Σ_lights amplitude_ch · Ê(axis·n, κ), in float or double,
// in units of the scene's largest amplitude, like the exact
// reference::scene_irradiance_reference.
// Error of a method: max over the normals and the three channels of
// |Ê_ch(n) − E_ch(n)| divided by the scene's largest exact irradiance
// max_{n, ch} E_ch(n) — per channel, relative to one scene-wide scale, so a
// dim channel is not judged by its own tiny peak. The error is a ratio, so it
// does not depend on the amplitudes' unit.
//
// Work and memory: one table evaluation and one evaluation of each method
// per (distinct light, normal), within the limits of reference/scene.hpp
// (reference::check_scene_limits); the normals summed in parallel in blocks
// of at most reference::kSceneBlockNormals.
#pragma once

#include <span>
#include <vector>

#include <sglab/registry.hpp>

#include "common/vocabulary.hpp"
#include "reference/scene.hpp"

namespace sglab::validate {

// One method's value Ê(cosine, κ) as every scene sum here takes it: f32
// (cosine and κ rounded to binary32, the value widened to double) or f64.
double method_value(const Method& m, io::Precision precision, double cosine, double kappa);

// Per-normal RGB irradiance of the scene with a method's f32 (binary32:
// cosine and κ rounded to float, the per-light value in float, summed in
// double) or f64, in units of the scene's largest amplitude.
std::vector<reference::Vec3> scene_irradiance(const reference::Scene& scene,
                                              const std::vector<reference::Vec3>& normals,
                                              const Method& method, io::Precision precision);

// max_{n,ch} |approx − exact| / max_{n,ch} exact (+inf on a non-finite value).
double scene_relative_error(const std::vector<reference::Vec3>& approx,
                            const std::vector<reference::Vec3>& exact);

// The scene error of each method (as scene_relative_error of scene_irradiance
// against reference::scene_irradiance_reference), in one streamed pass: memory
// bounded as stated above, whatever the light and normal counts.
std::vector<double> scene_errors(const reference::Scene& scene,
                                 const std::vector<reference::Vec3>& normals,
                                 std::span<const Method> methods, io::Precision precision);

}  // namespace sglab::validate
