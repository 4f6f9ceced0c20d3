// tests/random_points.hpp — the random (κ, c) of the suites that test a
// method against the reference engine on points no fit used.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "reference/reference.hpp"

namespace sglab::test {

// `n` points, κ log-uniform over [1e-3, 1e4] and c uniform over [-1, 1] from
// a fixed seed, each rounded to float so that the float and double paths see
// the same inputs.
inline std::vector<reference::Query> random_points(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> lk(std::log(1e-3), std::log(1e4)), uc(-1.0, 1.0);
  std::vector<reference::Query> q;
  for (int i = 0; i < n; ++i)
    q.push_back({double(float(std::exp(lk(rng)))), double(float(uc(rng)))});
  return q;
}

}  // namespace sglab::test
