#include "validate/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "common/args.hpp"
#include "common/io.hpp"
#include "common/json_input.hpp"
#include "validate/irradiance_table.hpp"
#include "validate/reference.hpp"

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
  if (!v.is_array())
    fail(source, key, fmt::format("expected an array of 3 numbers, got {}", type_name(v)));
  if (v.size() != 3) fail(source, key, fmt::format("expected 3 numbers, got {}", v.size()));
  Vec3 out;
  for (std::size_t i = 0; i < 3; ++i)
    out[i] = finite_number(source, fmt::format("{}[{}]", key, i), v[i]);
  return out;
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The cosine between a unit axis and a unit normal, kept in [−1, 1] against rounding.
double cosine(const Vec3& axis, const Vec3& normal) {
  return std::clamp(dot(axis, normal), -1.0, 1.0);
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

namespace {

// A light in units of the scene's largest amplitude; lights with the same
// sharpness and axis merged into one lobe (their amplitudes summed).
struct Lobe {
  double kappa;
  Vec3 axis;
  Vec3 amplitude;
};

std::vector<Lobe> lobes_of(const Scene& scene) {
  double largest = 0;
  for (const auto& l : scene.lights)
    for (double a : l.amplitude) largest = std::max(largest, a);
  if (!(largest > 0)) largest = 1;  // a dark scene (refused by parse_scene)
  std::vector<Lobe> lobes;
  lobes.reserve(scene.lights.size());
  for (const auto& l : scene.lights)
    lobes.push_back(
        {l.sharpness,
         l.axis,
         {l.amplitude[0] / largest, l.amplitude[1] / largest, l.amplitude[2] / largest}});
  const auto key = [](const Lobe& x) { return std::tie(x.kappa, x.axis[0], x.axis[1], x.axis[2]); };
  std::sort(lobes.begin(), lobes.end(),
            [&](const Lobe& a, const Lobe& b) { return key(a) < key(b); });
  std::vector<Lobe> merged;
  for (const Lobe& l : lobes) {
    if (!merged.empty() && key(merged.back()) == key(l)) {
      for (std::size_t ch = 0; ch < 3; ++ch) merged.back().amplitude[ch] += l.amplitude[ch];
      continue;
    }
    merged.push_back(l);
  }
  return merged;
}

double method_value(const Method& m, io::Precision precision, double cosine, double kappa) {
  return precision == io::Precision::float32
             ? static_cast<double>(m.f32(static_cast<float>(cosine), static_cast<float>(kappa)))
             : m.f64(cosine, kappa);
}

// The scene's RGB sums at every normal, exact (when `with_exact`) and with
// each method, in units of the largest amplitude: visit(j, exact, approx) is
// called once per normal j, from parallel tasks, approx[m] the sum of method m.
// The exact value is the irradiance table's (validate/irradiance_table.hpp:
// the reference quadrature to 1e−10 of each lobe's peak), one slice E(·, κ)
// per lobe. The normals are split into blocks of at most kSceneBlockNormals,
// summed in parallel; within a block one lobe and one method at a time over
// its normals (one function over many cosines), the cosines formed as they
// are used. Every sum adds the lobes in their order, so the result does not
// depend on the blocks.
template <class Visit>
void sum_over_normals(const Scene& scene, const std::vector<Vec3>& normals,
                      std::span<const Method> methods, io::Precision precision, bool with_exact,
                      Visit&& visit) {
  const std::vector<Lobe> lobes = lobes_of(scene);
  const std::size_t nm = methods.size();
  // E(·, κ) of each lobe (the irradiance table: the quadrature to 1e−10 of the peak).
  std::vector<IrradianceTable::Slice> exact_of;
  if (with_exact) {
    exact_of.reserve(lobes.size());
    for (const Lobe& l : lobes) exact_of.push_back(irradiance_table().slice(l.kappa));
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, normals.size(), kSceneBlockNormals),
      [&](const tbb::blocked_range<std::size_t>& r) {
        const std::size_t j0 = r.begin(), nb = r.size();
        if (nb > kSceneBlockNormals)  // the simple partitioner keeps blocks within the grain
          throw std::logic_error("sum_over_normals: a block larger than kSceneBlockNormals");
        std::array<double, kSceneBlockNormals> c{};
        std::array<Vec3, kSceneBlockNormals> exact{};
        std::vector<Vec3> approx(nb * nm, Vec3{0, 0, 0});
        for (std::size_t i = 0; i < lobes.size(); ++i) {
          const Lobe& l = lobes[i];
          for (std::size_t b = 0; b < nb; ++b) c[b] = cosine(l.axis, normals[j0 + b]);
          if (with_exact)
            for (std::size_t b = 0; b < nb; ++b) {
              const double e = exact_of[i](c[b]);
              for (std::size_t ch = 0; ch < 3; ++ch) exact[b][ch] += l.amplitude[ch] * e;
            }
          for (std::size_t m = 0; m < nm; ++m)
            for (std::size_t b = 0; b < nb; ++b) {
              const double v = method_value(methods[m], precision, c[b], l.kappa);
              for (std::size_t ch = 0; ch < 3; ++ch) approx[b * nm + m][ch] += l.amplitude[ch] * v;
            }
        }
        for (std::size_t b = 0; b < nb; ++b)
          visit(j0 + b, exact[b], std::span<const Vec3>(approx.data() + b * nm, nm));
      },
      tbb::simple_partitioner());
}

}  // namespace

std::vector<Vec3> scene_irradiance_reference(const Scene& scene, const std::vector<Vec3>& normals) {
  std::vector<Vec3> out(normals.size());
  sum_over_normals(
      scene, normals, {}, io::Precision::float64, true,
      [&](std::size_t j, const Vec3& exact, std::span<const Vec3>) { out[j] = exact; });
  return out;
}

std::vector<Vec3> scene_irradiance(const Scene& scene, const std::vector<Vec3>& normals,
                                   const Method& method, io::Precision precision) {
  std::vector<Vec3> out(normals.size());
  sum_over_normals(
      scene, normals, std::span<const Method>(&method, 1), precision, false,
      [&](std::size_t j, const Vec3&, std::span<const Vec3> approx) { out[j] = approx[0]; });
  return out;
}

std::vector<double> scene_errors(const Scene& scene, const std::vector<Vec3>& normals,
                                 std::span<const Method> methods, io::Precision precision) {
  // Per thread: the largest |Ê − E| of each method, then the largest exact value.
  const std::size_t peak = methods.size();
  tbb::combinable<std::vector<double>> partial(
      [&] { return std::vector<double>(methods.size() + 1, 0.0); });
  sum_over_normals(scene, normals, methods, precision, true,
                   [&](std::size_t, const Vec3& exact, std::span<const Vec3> approx) {
                     std::vector<double>& w = partial.local();
                     for (std::size_t ch = 0; ch < 3; ++ch) {
                       w[peak] = std::max(w[peak], exact[ch]);
                       for (std::size_t m = 0; m < methods.size(); ++m) {
                         const double d = std::abs(approx[m][ch] - exact[ch]);
                         w[m] = std::isfinite(d) ? std::max(w[m], d)
                                                 : std::numeric_limits<double>::infinity();
                       }
                     }
                   });
  std::vector<double> worst(methods.size() + 1, 0.0);
  partial.combine_each([&](const std::vector<double>& w) {
    for (std::size_t i = 0; i < worst.size(); ++i) worst[i] = std::max(worst[i], w[i]);
  });
  std::vector<double> out(methods.size());
  for (std::size_t m = 0; m < methods.size(); ++m) out[m] = worst[m] / worst[peak];
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
