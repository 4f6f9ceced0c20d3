// cost/cpu_timing.cpp — see cost.hpp.
#include "cost/cpu_timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

#include <sglab/erf.hpp>
#include <sglab/registry.hpp>

namespace sglab::cost {

std::string cost_input_description(std::size_t n) {
  return fmt::format(
      "{} inputs: kappa log-uniform in [1e-3, 1e4], cosine uniform in [-1, 1] (erf: x uniform in "
      "[0, 4]); std::mt19937_64 seed {}, drawn in double and rounded to float; light_eval: {} "
      "lights (the first kappa) x {} cosines each",
      n, kCostSeed, kCostLights, n / kCostLights);
}

std::string CostCase::name() const {
  return fmt::format("{}/{}/{}/{}", to_string(kind), method, to_string(precision), to_string(mode));
}

std::shared_ptr<CostWorkload> make_cost_workload(std::uint64_t seed, std::size_t n) {
  auto w = std::make_shared<CostWorkload>();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double e_lo = -3.0, e_hi = 4.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double kappa = std::pow(10.0, e_lo + (e_hi - e_lo) * unit(rng));
    const double cosine = -1.0 + 2.0 * unit(rng);
    const double x = 4.0 * unit(rng);
    // Round to float first so both precisions see the same inputs.
    w->kappa32.push_back(static_cast<float>(kappa));
    w->cosine32.push_back(static_cast<float>(cosine));
    w->x32.push_back(static_cast<float>(x));
    w->kappa64.push_back(w->kappa32.back());
    w->cosine64.push_back(w->cosine32.back());
    w->x64.push_back(w->x32.back());
  }
  w->out32.assign(n, 0.0f);
  w->out64.assign(n, 0.0);
  return w;
}

namespace {

// Keeps the compiler from discarding or hoisting the stores into `p`.
inline void clobber(const void* p) { asm volatile("" : : "r"(p) : "memory"); }

template <class Erf, class T>
void erf_batch(const T* __restrict x, T* __restrict out, std::size_t n) {
  const Erf f{};
  for (std::size_t i = 0; i < n; ++i) out[i] = f(x[i]);
}

using ErfBatch32 = void (*)(const float*, float*, std::size_t);
using ErfBatch64 = void (*)(const double*, double*, std::size_t);

// The inlined loop for each registered erf variant (nullptr if unknown).
std::pair<ErfBatch32, ErfBatch64> erf_batch_for(std::string_view id) {
  if (id == "listing5") return {&erf_batch<ErfListing5, float>, &erf_batch<ErfListing5, double>};
  if (id == "as7125") return {&erf_batch<ErfAS7125, float>, &erf_batch<ErfAS7125, double>};
  if (id == "std") return {&erf_batch<ErfStd, float>, &erf_batch<ErfStd, double>};
  return {nullptr, nullptr};
}

void add_method_cases(std::vector<CostCase>& out, CostKind kind, const Method& m,
                      const std::shared_ptr<CostWorkload>& w) {
  const std::size_t n = w->cosine32.size();
  const auto make = [&](io::Precision f, CostMode mode, std::function<void()> run) {
    CostCase c;
    c.kind = kind;
    c.method = std::string(m.id);
    c.refit = m.origin == Origin::refit;
    c.precision = f;
    c.mode = mode;
    c.evaluations = n;
    c.run = std::move(run);
    out.push_back(std::move(c));
  };
  // The function pointers are copied into the closures: calls stay indirect.
  float (*f32)(float, float) = m.f32;
  double (*f64)(double, double) = m.f64;
  auto b32 = m.batch32;
  auto b64 = m.batch64;
  make(io::Precision::float32, CostMode::scalar, [w, f32, n] {
    const float* c = w->cosine32.data();
    const float* k = w->kappa32.data();
    float* o = w->out32.data();
    for (std::size_t i = 0; i < n; ++i) o[i] = f32(c[i], k[i]);
    clobber(o);
  });
  make(io::Precision::float32, CostMode::batch, [w, b32, n] {
    b32(w->cosine32.data(), w->kappa32.data(), w->out32.data(), n);
    clobber(w->out32.data());
  });
  make(io::Precision::float64, CostMode::scalar, [w, f64, n] {
    const double* c = w->cosine64.data();
    const double* k = w->kappa64.data();
    double* o = w->out64.data();
    for (std::size_t i = 0; i < n; ++i) o[i] = f64(c[i], k[i]);
    clobber(o);
  });
  make(io::Precision::float64, CostMode::batch, [w, b64, n] {
    b64(w->cosine64.data(), w->kappa64.data(), w->out64.data(), n);
    clobber(w->out64.data());
  });
  if (m.light_setup32 && m.light_eval32 && n >= kCostLights) {
    auto setup = m.light_setup32;
    auto eval = m.light_eval32;
    // Setup: once per κ of the inputs, into a small ring of states.
    auto ring = std::make_shared<std::vector<float>>(64 * kLightStateFloats);
    make(io::Precision::float32, CostMode::light_setup, [w, setup, ring, n] {
      const float* k = w->kappa32.data();
      float* s = ring->data();
      for (std::size_t i = 0; i < n; ++i) setup(k[i], s + (i % 64) * kLightStateFloats);
      clobber(s);
    });
    // Eval: kCostLights lights, each at a contiguous block of the cosines.
    auto states = std::make_shared<std::vector<float>>(kCostLights * kLightStateFloats);
    for (std::size_t j = 0; j < kCostLights; ++j)
      setup(w->kappa32[j], states->data() + j * kLightStateFloats);
    make(io::Precision::float32, CostMode::light_eval, [w, eval, states, n] {
      const float* c = w->cosine32.data();
      float* o = w->out32.data();
      const std::size_t block = n / kCostLights;
      for (std::size_t j = 0; j < kCostLights; ++j) {
        const float* s = states->data() + j * kLightStateFloats;
        for (std::size_t i = j * block; i < (j + 1) * block; ++i) o[i] = eval(s, c[i]);
      }
      clobber(o);
    });
    out.back().evaluations = (n / kCostLights) * kCostLights;
  }
}

void add_erf_cases(std::vector<CostCase>& out, const ErfVariant& v,
                   const std::shared_ptr<CostWorkload>& w) {
  const std::size_t n = w->x32.size();
  const auto make = [&](io::Precision f, CostMode mode, std::function<void()> run) {
    CostCase c;
    c.kind = CostKind::erf;
    c.method = std::string(v.id);
    c.precision = f;
    c.mode = mode;
    c.evaluations = n;
    c.run = std::move(run);
    out.push_back(std::move(c));
  };
  float (*f32)(float) = v.f32;
  double (*f64)(double) = v.f64;
  const auto [b32, b64] = erf_batch_for(v.id);
  make(io::Precision::float32, CostMode::scalar, [w, f32, n] {
    const float* x = w->x32.data();
    float* o = w->out32.data();
    for (std::size_t i = 0; i < n; ++i) o[i] = f32(x[i]);
    clobber(o);
  });
  if (b32)
    make(io::Precision::float32, CostMode::batch, [w, b32 = b32, n] {
      b32(w->x32.data(), w->out32.data(), n);
      clobber(w->out32.data());
    });
  make(io::Precision::float64, CostMode::scalar, [w, f64, n] {
    const double* x = w->x64.data();
    double* o = w->out64.data();
    for (std::size_t i = 0; i < n; ++i) o[i] = f64(x[i]);
    clobber(o);
  });
  if (b64)
    make(io::Precision::float64, CostMode::batch, [w, b64 = b64, n] {
      b64(w->x64.data(), w->out64.data(), n);
      clobber(w->out64.data());
    });
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

template <class T>
bool contains(const std::vector<T>& v, T x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

std::vector<CostCase> cost_cases(const std::shared_ptr<CostWorkload>& workload) {
  std::vector<CostCase> out;
  for (const Method& m : irradiance_methods)
    add_method_cases(out, CostKind::irradiance, m, workload);
  for (const Method& m : hemispherical_methods)
    add_method_cases(out, CostKind::hemispherical, m, workload);
  for (const ErfVariant& v : erf_variants) add_erf_cases(out, v, workload);
  return out;
}

double time_case(const CostCase& c, int repetitions, double min_time) {
  if (repetitions < 1)
    throw std::invalid_argument(fmt::format("repetitions must be >= 1, got {}", repetitions));
  using clock = std::chrono::steady_clock;
  c.run();  // warm-up (caches, page faults)
  std::vector<double> ns;
  for (int r = 0; r < repetitions; ++r) {
    std::size_t passes = 0;
    const auto start = clock::now();
    auto now = start;
    do {
      c.run();
      ++passes;
      now = clock::now();
    } while (std::chrono::duration<double>(now - start).count() < min_time);
    const double elapsed_ns = std::chrono::duration<double, std::nano>(now - start).count();
    ns.push_back(elapsed_ns / static_cast<double>(passes * c.evaluations));
  }
  return median(std::move(ns));
}

std::vector<Cost> measure_costs(const CostOptions& options) {
  if (options.repetitions < 1)
    throw std::invalid_argument(
        fmt::format("repetitions must be >= 1, got {}", options.repetitions));
  std::regex filter;
  if (!options.filter.empty()) filter = std::regex(options.filter);  // throws std::regex_error
  const auto workload = make_cost_workload();
  std::vector<CostCase> selected;
  for (CostCase& c : cost_cases(workload)) {
    if (!contains(options.kinds, c.kind) || !contains(options.precisions, c.precision) ||
        !contains(options.modes, c.mode))
      continue;
    if (!options.filter.empty() && !std::regex_search(c.name(), filter)) continue;
    selected.push_back(std::move(c));
  }
  // Warm-up (~0.05 s on the first case) so the first case measured does not
  // pay for clock-frequency ramp-up and cold caches.
  if (!selected.empty()) time_case(selected.front(), 1, 0.05);
  std::vector<Cost> out;
  for (const CostCase& c : selected)
    out.push_back(
        Cost{static_cast<const CostOf&>(c), time_case(c, options.repetitions, options.min_time)});
  return out;
}

}  // namespace sglab::cost
