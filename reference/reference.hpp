// reference/reference.hpp — the reference engine: H(c, κ), E(c, κ) and s(c, κ)
// of docs/quantities.md by Boost.Math quadrature. Shared by fit/, envmap/ and validate/: there is
// exactly one reference engine in sglab.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace sglab::reference {

// One reference point. Values are in double; the error estimates and L1
// norms are those the quadrature returned (condition number = l1/|value|).
struct ReferencePoint {
  double kappa = 0;
  double cosine = 0;
  double hemispherical = 0;  // H(c, κ)
  double irradiance = 0;     // E(c, κ)
  double normalized = 0;     // s(c, κ) = (H − H(−1,κ)) / (H(1,κ) − H(−1,κ))
  double hemispherical_error = 0;
  double irradiance_error = 0;
  double hemispherical_l1 = 0;
  double irradiance_l1 = 0;
};

// The quadrature's arithmetic: double, or 50-digit cpp_bin_float (reference_high.cpp).
enum class Quadrature { standard, high };

struct Query {
  double kappa;
  double cosine;
};

// Thread-safe. Repeated queries of the same (κ, c) bit patterns are served
// from an in-memory cache.
class ReferenceEngine {
 public:
  ReferenceEngine();
  ~ReferenceEngine();
  ReferenceEngine(const ReferenceEngine&) = delete;
  ReferenceEngine& operator=(const ReferenceEngine&) = delete;

  // Requires finite κ ≥ 0 and c ∈ [−1, 1]; throws std::invalid_argument otherwise.
  ReferencePoint evaluate(double kappa, double cosine,
                          Quadrature quadrature = Quadrature::standard) const;

  // Evaluates many points in parallel on all cores (TBB), results in query order.
  std::vector<ReferencePoint> evaluate(std::span<const Query> queries,
                                       Quadrature quadrature = Quadrature::standard) const;

  // Number of cached points (each (κ, c, quadrature) counts once).
  std::size_t cache_size() const;

  // Empties the cache (logically const: it changes no result; thread-safe).
  // An addition to the original interface, for long sweeps that want the
  // memory back and for benchmarks that must not be served from the cache.
  void clear_cache() const;

 private:
  struct Impl;
  Impl* impl_;
};

// The process-wide engine (one cache for all users in a process).
const ReferenceEngine& reference_engine();

}  // namespace sglab::reference
