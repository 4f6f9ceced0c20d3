// bench/method_cost.cpp — CPU cost of one registry method, outside any
// benchmark framework, for `perf stat` (task-clock: CPU time, so a loaded
// machine's waiting is not counted) and `valgrind --tool=callgrind`
// (instruction counts). Built as build/bench/method_cost (it needs only the
// header-only runtime):
//   build/bench/method_cost METHOD PASSES [batch|scalar|eval|setup]
// Workload: the distribution of cost/cpu_timing.hpp (κ log-uniform over
// [1e−3, 1e4], c uniform over [−1, 1], mt19937_64 seed 20261121) but 4096
// inputs, not 2^20, so that a callgrind run stays short. Modes: batch (the
// registry's batch32), scalar (f32 per element), eval (one light_setup32 per
// pass, then light_eval32 per cosine: the per-shading-point cost), setup
// (light_setup32 per κ: the per-light cost). Cost per evaluation =
// (run with PASSES − run with 0 passes) / (PASSES × 4096).
#include <cmath>
#include <cstdlib>
#include <random>
#include <sglab/sglab.hpp>
#include <string>
#include <vector>
int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: method_cost METHOD PASSES [batch|scalar|eval|setup]\n");
    return 2;
  }
  const auto* m = sglab::find_method(sglab::irradiance_methods, argv[1]);
  if (!m) {
    std::fprintf(stderr, "method_cost: unknown method '%s'\n", argv[1]);
    return 2;
  }
  const int passes = std::atoi(argv[2]);
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> lk(-3, 4), uc(-1, 1);
  const std::size_t n = 4096;
  std::vector<float> k(n), c(n), out(n);
  for (std::size_t i = 0; i < n; ++i) k[i] = float(std::pow(10.0, lk(rng))), c[i] = float(uc(rng));
  double s = 0;
  const std::string mode = argc > 3 ? argv[3] : "batch";
  if ((mode == "eval" || mode == "setup") && !m->light_setup32) {
    std::fprintf(stderr, "method_cost: %s has no per-light split\n", argv[1]);
    return 2;
  }
  float st[sglab::kLightStateFloats];
  for (int p = 0; p < passes; ++p) {
    if (mode == "eval") {
      m->light_setup32(k[p % n], st);
      for (std::size_t i = 0; i < n; ++i) out[i] = m->light_eval32(st, c[i]);
    } else if (mode == "setup") {
      for (std::size_t i = 0; i < n; ++i) {
        m->light_setup32(k[i], st);
        out[i] = st[0] + st[3];
      }
    } else if (mode == "scalar") {
      for (std::size_t i = 0; i < n; ++i) out[i] = m->f32(c[i], k[i]);
    } else
      m->batch32(c.data(), k.data(), out.data(), n);
    s += out[p % n];
  }
  std::printf("%g\n", s);
}
