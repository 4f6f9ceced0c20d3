#include "validate/scene_errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "reference/irradiance_table.hpp"

namespace sglab::validate {

double method_value(const Method& m, io::Precision precision, double cosine, double kappa) {
  return precision == io::Precision::float32
             ? static_cast<double>(m.f32(static_cast<float>(cosine), static_cast<float>(kappa)))
             : m.f64(cosine, kappa);
}

namespace {

// The scene's RGB sums at every normal, exact (when `with_exact`) and with
// each method, in units of the largest amplitude: visit(j, exact, approx) is
// called once per normal j, from parallel tasks, approx[m] the sum of method m.
// The exact value is the irradiance table's (reference/irradiance_table.hpp:
// the reference quadrature to 1e−10 of each lobe's peak), one slice E(·, κ)
// per lobe. The normals are split into blocks of at most reference::kSceneBlockNormals,
// summed in parallel; within a block one lobe and one method at a time over
// its normals (one function over many cosines), the cosines formed as they
// are used. Every sum adds the lobes in their order, so the result does not
// depend on the blocks.
template <class Visit>
void sum_over_normals(const reference::Scene& scene, const std::vector<reference::Vec3>& normals,
                      std::span<const Method> methods, io::Precision precision, bool with_exact,
                      Visit&& visit) {
  const std::vector<reference::SceneLobe> lobes = reference::scene_lobes(scene);
  const std::size_t nm = methods.size();
  // E(·, κ) of each lobe (the irradiance table: the quadrature to 1e−10 of the peak).
  std::vector<reference::IrradianceTable::Slice> exact_of;
  if (with_exact) {
    exact_of.reserve(lobes.size());
    for (const reference::SceneLobe& l : lobes)
      exact_of.push_back(reference::irradiance_table().slice(l.kappa));
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, normals.size(), reference::kSceneBlockNormals),
      [&](const tbb::blocked_range<std::size_t>& r) {
        const std::size_t j0 = r.begin(), nb = r.size();
        if (nb >
            reference::kSceneBlockNormals)  // the simple partitioner keeps blocks within the grain
          throw std::logic_error("sum_over_normals: a block larger than kSceneBlockNormals");
        std::array<double, reference::kSceneBlockNormals> c{};
        std::array<reference::Vec3, reference::kSceneBlockNormals> exact{};
        std::vector<reference::Vec3> approx(nb * nm, reference::Vec3{0, 0, 0});
        for (std::size_t i = 0; i < lobes.size(); ++i) {
          const reference::SceneLobe& l = lobes[i];
          for (std::size_t b = 0; b < nb; ++b)
            c[b] = reference::scene_cosine(l.axis, normals[j0 + b]);
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
          visit(j0 + b, exact[b], std::span<const reference::Vec3>(approx.data() + b * nm, nm));
      },
      tbb::simple_partitioner());
}

}  // namespace

std::vector<reference::Vec3> scene_irradiance(const reference::Scene& scene,
                                              const std::vector<reference::Vec3>& normals,
                                              const Method& method, io::Precision precision) {
  std::vector<reference::Vec3> out(normals.size());
  sum_over_normals(scene, normals, std::span<const Method>(&method, 1), precision, false,
                   [&](std::size_t j, const reference::Vec3&,
                       std::span<const reference::Vec3> approx) { out[j] = approx[0]; });
  return out;
}

std::vector<double> scene_errors(const reference::Scene& scene,
                                 const std::vector<reference::Vec3>& normals,
                                 std::span<const Method> methods, io::Precision precision) {
  // Per thread: the largest |Ê − E| of each method, then the largest exact value.
  const std::size_t peak = methods.size();
  tbb::combinable<std::vector<double>> partial(
      [&] { return std::vector<double>(methods.size() + 1, 0.0); });
  sum_over_normals(
      scene, normals, methods, precision, true,
      [&](std::size_t, const reference::Vec3& exact, std::span<const reference::Vec3> approx) {
        std::vector<double>& w = partial.local();
        for (std::size_t ch = 0; ch < 3; ++ch) {
          w[peak] = std::max(w[peak], exact[ch]);
          for (std::size_t m = 0; m < methods.size(); ++m) {
            const double d = std::abs(approx[m][ch] - exact[ch]);
            w[m] = std::isfinite(d) ? std::max(w[m], d) : std::numeric_limits<double>::infinity();
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

double scene_relative_error(const std::vector<reference::Vec3>& approx,
                            const std::vector<reference::Vec3>& exact) {
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
