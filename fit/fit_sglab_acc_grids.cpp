// The training grids of the sglab-acc fits and their weights w(κ).
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_acc.hpp>

#include "fit/fit_sglab_acc_family.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit {

namespace acc {

std::vector<double> training_kappas(double lo, double hi, int count) {
  std::vector<double> k = log_midpoints(lo, hi, count);
  k.push_back(lo);
  const double a = std::log(lo), b = std::log(hi);
  const double da = std::log(std::max(lo, 0.5)), db = std::log(std::min(hi, 200.0));
  if (db > da) {
    const int dense = 2 * int(std::ceil(count * (db - da) / (b - a)));
    for (int i = 0; i < dense; ++i) k.push_back(std::exp(da + (db - da) * (i + 0.25) / dense));
  }
  k.push_back(hi);
  std::sort(k.begin(), k.end());
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

std::vector<reference::Query> training_grid(double lo, double hi) {
  std::vector<reference::Query> q;
  const int uniform = 24, zcount = 16;
  for (double k : training_kappas(lo, hi, 40)) {
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    q.push_back({k, 0.0});
    for (int j = 0; j < uniform; ++j) q.push_back({k, -1 + 2 * (j + 0.5) / uniform});
    for (int j = 0; j < zcount; ++j) {
      const double c = 0.2 * (j + 0.5) / t;  // z = 0.1 … 3.1
      if (c < 1) q.push_back({k, c}), q.push_back({k, -c});
    }
  }
  return q;
}

namespace {

// Dense training grid of the certificate (and of the LP's exchange): κ as
// training_kappas with twice the count, per κ c = 0, 64 cosines at half-step
// offsets of a uniform grid and c = ±z_k/t(κ), z_k = 0.05 … 3.15 (32), sorted
// by c (the exchange adds a peak's neighbours in c). Never a measuring grid.
constexpr int kDenseKappas = 80;

}  // namespace

std::vector<SglabAccSample> weighted(std::vector<SglabAccSample> samples, double target) {
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    double base = 0;
    for (; end < samples.size() && samples[end].kappa == samples[i].kappa; ++end)
      base = std::max(base, error_tokuyoshi2024_float(samples[end].kappa, samples[end].cosine,
                                                      samples[end].irradiance));
    for (; i < end; ++i) samples[i].weight = std::min(target, std::max(base, 8e-7));
  }
  return samples;
}

Grids grids_for(const FitSpec& spec) {
  Grids g;
  auto& engine = reference::reference_engine();
  for (const auto& r : engine.evaluate(training_grid(spec.kappa_lo, spec.kappa_hi)))
    g.train.push_back({r.kappa, r.cosine, r.irradiance});
  for (const auto& r : engine.evaluate(sglab_acc_dense_grid(spec.kappa_lo, spec.kappa_hi)))
    g.dense.push_back({r.kappa, r.cosine, r.irradiance});
  g.measuring = measuring_grids(spec);
  return g;
}

}  // namespace acc

std::vector<reference::Query> sglab_acc_dense_grid(double lo, double hi) {
  std::vector<reference::Query> q;
  const int uniform = acc::kDenseUniform, zcount = 32;
  for (double k : acc::training_kappas(lo, hi, acc::kDenseKappas)) {
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    std::vector<double> c{0.0};
    for (int j = 0; j < uniform; ++j) c.push_back(-1 + 2 * (j + 0.5) / uniform);
    for (int j = 0; j < zcount; ++j)
      if (const double x = 0.1 * (j + 0.5) / t; x < 1) c.push_back(x), c.push_back(-x);
    std::sort(c.begin(), c.end());
    for (double x : c) q.push_back({k, x});
  }
  return q;
}

}  // namespace sglab::fit
