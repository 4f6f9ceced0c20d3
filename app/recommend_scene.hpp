// app/recommend_scene.hpp — the --scene mode of `sglab recommend` (recommend_scene.cpp).
#pragma once

#include <cstddef>
#include <string>

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

// Throws InputError (exit 2) on an unreadable or invalid scene.
void recommend_scene(const SceneRecommendArgs& args);

}  // namespace sglab::app
