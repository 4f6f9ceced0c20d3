// app/recommend_scene.hpp — the --scene mode of `sglab recommend` (recommend_scene.cpp).
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "app/costs_option.hpp"
#include "validate/sweep.hpp"

namespace sglab::app {

struct SceneRecommendArgs {
  std::string scene;  // path of the scene JSON
  double budget = 0;
  io::Precision precision = io::Precision::float32;
  std::size_t normals = 4096;
  bool json = false;
  CostsOption costs;  // the cost table (or live timing), as for `recommend --kappa`
};

// x as a JSON number, or null where x is not finite (JSON has no inf or NaN):
// the answers of `sglab recommend`, both modes.
nlohmann::ordered_json json_number(double x);

// Throws InputError (exit 2) on an unreadable or invalid scene.
void recommend_scene(const SceneRecommendArgs& args);

}  // namespace sglab::app
