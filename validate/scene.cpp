#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io.hpp"
#include "json_input.hpp"
#include "reference.hpp"

namespace sglab::validate {

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
  if (!v.is_array()) fail(source, key, fmt::format("expected an array of 3 numbers, got {}", type_name(v)));
  if (v.size() != 3) fail(source, key, fmt::format("expected 3 numbers, got {}", v.size()));
  Vec3 out;
  for (std::size_t i = 0; i < 3; ++i) out[i] = finite_number(source, fmt::format("{}[{}]", key, i), v[i]);
  return out;
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The cosine between a unit axis and a unit normal, kept in [−1, 1] against rounding.
double cosine(const Vec3& axis, const Vec3& normal) { return std::clamp(dot(axis, normal), -1.0, 1.0); }

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
  if (!doc.is_object()) fail(source, "(top level)", fmt::format("expected an object, got {}", type_name(doc)));
  for (const auto& [key, value] : doc.items())
    if (key != "lights") fail(source, key, "unknown key (expected only \"lights\")");
  if (!doc.contains("lights")) fail(source, "lights", "missing key");
  const json& lights = doc["lights"];
  if (!lights.is_array()) fail(source, "lights", fmt::format("expected an array, got {}", type_name(lights)));
  if (lights.empty()) fail(source, "lights", "no lights");
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
    light.sharpness = finite_number(source, at + ".sharpness", l["sharpness"]) + 0.0;  // -0 is 0 (κ in [0, 0], not [-0, 0])
    if (light.sharpness < 0) fail(source, at + ".sharpness", fmt::format("must be >= 0, got {}", light.sharpness));
    light.amplitude = vector3(source, at + ".amplitude", l["amplitude"]);
    for (std::size_t ch = 0; ch < 3; ++ch) {
      if (light.amplitude[ch] < 0)
        fail(source, fmt::format("{}.amplitude[{}]", at, ch), fmt::format("must be >= 0, got {}", light.amplitude[ch]));
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

std::vector<Vec3> scene_irradiance_reference(const Scene& scene, const std::vector<Vec3>& normals) {
  std::vector<Query> queries;
  queries.reserve(scene.lights.size() * normals.size());
  for (const auto& n : normals)
    for (const auto& l : scene.lights) queries.push_back({l.sharpness, cosine(l.axis, n)});
  const auto ref = reference_engine().evaluate(queries);
  std::vector<Vec3> out(normals.size(), Vec3{0, 0, 0});
  std::size_t q = 0;
  for (std::size_t i = 0; i < normals.size(); ++i)
    for (const auto& l : scene.lights) {
      const double e = ref[q++].irradiance;
      for (std::size_t ch = 0; ch < 3; ++ch) out[i][ch] += l.amplitude[ch] * e;
    }
  return out;
}

std::vector<Vec3> scene_irradiance(const Scene& scene, const std::vector<Vec3>& normals, const Method& method,
                                   FloatFormat precision) {
  std::vector<Vec3> out(normals.size(), Vec3{0, 0, 0});
  for (std::size_t i = 0; i < normals.size(); ++i)
    for (const auto& l : scene.lights) {
      const double c = cosine(l.axis, normals[i]);
      const double e = precision == FloatFormat::binary32
                           ? static_cast<double>(method.f32(static_cast<float>(c), static_cast<float>(l.sharpness)))
                           : method.f64(c, l.sharpness);
      for (std::size_t ch = 0; ch < 3; ++ch) out[i][ch] += l.amplitude[ch] * e;
    }
  return out;
}

double scene_relative_error(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact) {
  double peak = 0, worst = 0;
  for (const auto& e : exact)
    for (double x : e) peak = std::max(peak, x);
  for (std::size_t i = 0; i < exact.size() && i < approx.size(); ++i)
    for (std::size_t ch = 0; ch < 3; ++ch) {
      const double d = std::abs(approx[i][ch] - exact[i][ch]);
      if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, d);
    }
  return worst / peak;
}

}  // namespace sglab::validate
