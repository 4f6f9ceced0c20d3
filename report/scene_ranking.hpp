// report/scene_ranking.hpp — `sglab recommend --scene`: every irradiance
// method judged on a scene's lights (validate/scene_errors.hpp) and ranked as
// `recommend --kappa` ranks them on a κ range (pareto.hpp), plus sglab's own
// models over the scene's κ range.
#pragma once

#include <optional>
#include <vector>

#include "report/pareto.hpp"
#include "validate/scene_errors.hpp"
#include "validate/sweep.hpp"

namespace sglab::report {

// Every irradiance method of the registry with its scene error in
// max_peak_rel (validate::scene_errors at `normals`) and in_valid_range set
// when every light's κ lies in the method's valid range (registry card); cost
// left 0 for the caller's cost source.
std::vector<MethodPoint> scene_points(const reference::Scene& scene,
                                      const std::vector<reference::Vec3>& normals,
                                      io::Precision precision);

struct SceneRanking {
  Recommendation recommendation;  // recommend(points, budget)
  // sglab's models (origin sglab) with their max peak_rel over the scene's κ
  // range [kappa_lo, kappa_hi] (irradiance_errors) and their scene cost.
  double kappa_lo = 0, kappa_hi = 0;
  std::vector<MethodPoint> models_on_range;
  // the cheapest of them meeting the budget on the range, in its valid range
  std::optional<MethodPoint> sufficient;
};

// `points` with costs filled. κ = 0 lights: the range starts at 1e-3.
SceneRanking rank_scene(const std::vector<MethodPoint>& points, const reference::Scene& scene,
                        double budget, io::Precision precision);

}  // namespace sglab::report
