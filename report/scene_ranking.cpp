// report/scene_ranking.cpp — see scene_ranking.hpp.
#include "report/scene_ranking.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include <sglab/registry.hpp>

namespace sglab::report {

std::vector<MethodPoint> scene_points(const reference::Scene& scene,
                                      const std::vector<reference::Vec3>& normals,
                                      io::Precision precision) {
  const std::vector<double> errors =
      validate::scene_errors(scene, normals, irradiance_methods, precision);
  std::vector<MethodPoint> points;
  for (std::size_t i = 0; i < std::size(irradiance_methods); ++i) {
    MethodPoint p;
    p.method = std::string(irradiance_methods[i].id);
    p.origin = irradiance_methods[i].origin;
    p.max_peak_rel = errors[i];
    points.push_back(p);
  }
  mark_valid_range(points, scene.kappa_min(), scene.kappa_max());
  return points;
}

SceneRanking rank_scene(const std::vector<MethodPoint>& points, const reference::Scene& scene,
                        double budget, io::Precision precision) {
  SceneRanking r;
  r.recommendation = recommend(points, budget);
  r.kappa_lo = std::max(scene.kappa_min(), 1e-3);
  r.kappa_hi = std::max(scene.kappa_max(), r.kappa_lo);
  const auto range_errors = irradiance_errors(r.kappa_lo, r.kappa_hi, precision);
  for (const auto& p : points) {
    if (p.origin != Origin::sglab) continue;
    for (const auto& e : range_errors)
      if (e.method == p.method) {
        MethodPoint m = p;
        m.max_peak_rel = e.max_peak_rel;
        r.models_on_range.push_back(m);
      }
  }
  for (const auto& m : r.models_on_range)
    if (m.max_peak_rel <= budget && std::isfinite(m.cost) && m.in_valid_range &&
        (!r.sufficient || m.cost < r.sufficient->cost))
      r.sufficient = m;
  return r;
}

}  // namespace sglab::report
