#include "reference/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "common/args.hpp"
#include "common/io.hpp"
#include "common/json_input.hpp"
#include "reference/irradiance_table.hpp"

namespace sglab::reference {

namespace {

using json = nlohmann::ordered_json;

std::string type_name(const json& v) { return v.type_name(); }

[[noreturn]] void fail(std::string_view source, const std::string& key, const std::string& what) {
  throw SceneError(fmt::format("{}: {}: {}", source, key, what));
}

double finite_number(std::string_view source, const std::string& key, const json& v) {
  if (!v.is_number()) fail(source, key, fmt::format("expected a number, got {}", type_name(v)));
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(source, key, "not a finite number");
  return x;
}

Vec3 vector3(std::string_view source, const std::string& key, const json& v) {
  if (!v.is_array())
    fail(source, key, fmt::format("expected an array of 3 numbers, got {}", type_name(v)));
  if (v.size() != 3) fail(source, key, fmt::format("expected 3 numbers, got {}", v.size()));
  Vec3 out;
  for (std::size_t i = 0; i < 3; ++i)
    out[i] = finite_number(source, fmt::format("{}[{}]", key, i), v[i]);
  return out;
}

}  // namespace

double Scene::kappa_min() const {
  double k = std::numeric_limits<double>::infinity();
  for (const auto& l : lights) k = std::min(k, l.sharpness);
  return k;
}

double Scene::kappa_max() const {
  double k = 0;
  for (const auto& l : lights) k = std::max(k, l.sharpness);
  return k;
}

Scene parse_scene(std::string_view text, std::string_view source) {
  json doc;
  try {
    doc = io::parse_json_strict(text, source);  // names the key or the line and column
  } catch (const io::InputError& e) {
    throw SceneError(e.what());
  }
  if (!doc.is_object())
    fail(source, "(top level)", fmt::format("expected an object, got {}", type_name(doc)));
  for (const auto& [key, value] : doc.items())
    if (key != "lights" && key != "provenance")
      fail(source, key, "unknown key (expected \"lights\" and optionally \"provenance\")");
  if (doc.contains("provenance") && !doc["provenance"].is_object())
    fail(source, "provenance",
         fmt::format("expected an object, got {}", type_name(doc["provenance"])));
  if (!doc.contains("lights")) fail(source, "lights", "missing key");
  const json& lights = doc["lights"];
  if (!lights.is_array())
    fail(source, "lights", fmt::format("expected an array, got {}", type_name(lights)));
  if (lights.empty()) fail(source, "lights", "no lights");
  try {
    check_scene_limits(lights.size(), 0);  // before the lights are copied
  } catch (const SceneError& e) {
    fail(source, "lights", e.what());
  }
  Scene scene;
  double total_amplitude = 0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const std::string at = fmt::format("lights[{}]", i);
    const json& l = lights[i];
    if (!l.is_object()) fail(source, at, fmt::format("expected an object, got {}", type_name(l)));
    for (const auto& [key, value] : l.items())
      if (key != "axis" && key != "sharpness" && key != "amplitude")
        fail(source, at + "." + key, "unknown key (expected axis, sharpness, amplitude)");
    for (const char* key : {"axis", "sharpness", "amplitude"})
      if (!l.contains(key)) fail(source, at + "." + key, "missing key");
    SceneLight light;
    light.axis = vector3(source, at + ".axis", l["axis"]);
    const double length = std::hypot(light.axis[0], light.axis[1], light.axis[2]);
    if (!(length > 1e-12) || !std::isfinite(length))
      fail(source, at + ".axis", fmt::format("cannot be normalized (length {})", length));
    for (double& x : light.axis) x /= length;
    // -0 is 0 (κ in [0, 0], not [-0, 0])
    light.sharpness = finite_number(source, at + ".sharpness", l["sharpness"]) + 0.0;
    if (light.sharpness < 0)
      fail(source, at + ".sharpness", fmt::format("must be >= 0, got {}", light.sharpness));
    // Every method is ranked in float (and sglab's models over the κ range):
    // κ must be a finite float in both precisions.
    if (light.sharpness > io::kFloatFormat.max_finite)
      fail(source, at + ".sharpness",
           fmt::format("must be at most the largest finite float ({:.9g}), got {}",
                       io::kFloatFormat.max_finite, light.sharpness));
    light.amplitude = vector3(source, at + ".amplitude", l["amplitude"]);
    for (std::size_t ch = 0; ch < 3; ++ch) {
      if (light.amplitude[ch] < 0)
        fail(source, fmt::format("{}.amplitude[{}]", at, ch),
             fmt::format("must be >= 0, got {}", light.amplitude[ch]));
      total_amplitude += light.amplitude[ch];
    }
    scene.lights.push_back(light);
  }
  if (!(total_amplitude > 0)) fail(source, "lights", "every amplitude is 0 (the scene is dark)");
  return scene;
}

std::vector<Vec3> fibonacci_normals(std::size_t n) {
  std::vector<Vec3> out;
  out.reserve(n);
  const double golden_angle = M_PI * (3 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1 - (2.0 * static_cast<double>(i) + 1) / static_cast<double>(n);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = golden_angle * static_cast<double>(i);
    out.push_back({r * std::cos(phi), r * std::sin(phi), z});
  }
  return out;
}

std::size_t scene_memory_bytes(std::size_t lights, std::size_t normals) {
  return lights * (2 * sizeof(SceneLight) + sizeof(IrradianceTable::Slice)) +
         normals * sizeof(Vec3);
}

void check_scene_limits(std::size_t lights, std::size_t normals) {
  const double mb = static_cast<double>(scene_memory_bytes(lights, normals)) / 1e6;
  if (normals > kMaxSceneNormals)
    throw SceneError(fmt::format("{} normals, at most {} (it would hold {:.0f} MB)", normals,
                                 kMaxSceneNormals, mb));
  if (lights > kMaxSceneLights)
    throw SceneError(fmt::format("{} lights, at most {} (it would hold {:.0f} MB)", lights,
                                 kMaxSceneLights, mb));
  if (lights > kMaxScenePairs / std::max<std::size_t>(normals, 1))
    throw SceneError(fmt::format(
        "{} lights x {} normals = {} (light, normal) pairs, at most {} (it would hold {:.0f} MB); "
        "use fewer normals",
        lights, normals, static_cast<double>(lights) * static_cast<double>(normals), kMaxScenePairs,
        mb));
}

std::vector<SceneLobe> scene_lobes(const Scene& scene) {
  double largest = 0;
  for (const auto& l : scene.lights)
    for (double a : l.amplitude) largest = std::max(largest, a);
  if (!(largest > 0)) largest = 1;  // a dark scene (refused by parse_scene)
  std::vector<SceneLobe> lobes;
  lobes.reserve(scene.lights.size());
  for (const auto& l : scene.lights)
    lobes.push_back(
        {l.sharpness,
         l.axis,
         {l.amplitude[0] / largest, l.amplitude[1] / largest, l.amplitude[2] / largest}});
  const auto key = [](const SceneLobe& x) {
    return std::tie(x.kappa, x.axis[0], x.axis[1], x.axis[2]);
  };
  std::sort(lobes.begin(), lobes.end(),
            [&](const SceneLobe& a, const SceneLobe& b) { return key(a) < key(b); });
  std::vector<SceneLobe> merged;
  for (const SceneLobe& l : lobes) {
    if (!merged.empty() && key(merged.back()) == key(l)) {
      for (std::size_t ch = 0; ch < 3; ++ch) merged.back().amplitude[ch] += l.amplitude[ch];
      continue;
    }
    merged.push_back(l);
  }
  return merged;
}

// Blocks of at most kSceneBlockNormals normals, summed in parallel; within a
// block one lobe at a time over its normals (one slice E(·, κ) over many
// cosines). Every sum adds the lobes in their order, so the result does not
// depend on the blocks.
std::vector<Vec3> scene_irradiance_reference(const Scene& scene, const std::vector<Vec3>& normals) {
  const std::vector<SceneLobe> lobes = scene_lobes(scene);
  // E(·, κ) of each lobe (the irradiance table: the quadrature to 1e−10 of the peak).
  std::vector<IrradianceTable::Slice> exact_of;
  exact_of.reserve(lobes.size());
  for (const SceneLobe& l : lobes) exact_of.push_back(irradiance_table().slice(l.kappa));
  std::vector<Vec3> out(normals.size(), Vec3{0, 0, 0});
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, normals.size(), kSceneBlockNormals),
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = 0; i < lobes.size(); ++i) {
          const SceneLobe& l = lobes[i];
          for (std::size_t j = r.begin(); j < r.end(); ++j) {
            const double e = exact_of[i](scene_cosine(l.axis, normals[j]));
            for (std::size_t ch = 0; ch < 3; ++ch) out[j][ch] += l.amplitude[ch] * e;
          }
        }
      },
      tbb::simple_partitioner());
  return out;
}

}  // namespace sglab::reference
