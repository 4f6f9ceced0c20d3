// reference/reference.cpp — the reference engine: validation, the cache, the
// parallel batch, and the double (Quadrature::standard) instantiation of the
// quadrature in reference_detail.hpp. The high-precision instantiation lives
// in reference_high.cpp (it is slow to compile; a separate unit builds in
// parallel).
#include "reference/reference.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "reference/reference_detail.hpp"

namespace sglab::reference {

namespace detail {

ReferencePoint compute_standard(double kappa, double cosine) {
  return to_reference_point(kappa, cosine, compute<double>(kappa, cosine));
}

}  // namespace detail

namespace {

void check_query(double kappa, double cosine) {
  if (!(std::isfinite(kappa) && kappa >= 0))
    throw std::invalid_argument(
        fmt::format("reference: kappa must be finite and >= 0, got {}", kappa));
  if (!(cosine >= -1 && cosine <= 1))
    throw std::invalid_argument(
        fmt::format("reference: cosine must be in [-1, 1], got {}", cosine));
}

}  // namespace

struct ReferenceEngine::Impl {
  // Cache key: the bit patterns of (κ, c) and the quadrature (the two modes give
  // different values for the same point).
  struct Key {
    std::uint64_t kappa, cosine;
    Quadrature quadrature;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept {
      std::uint64_t h = k.kappa * 0x9E3779B97F4A7C15ull;
      h ^= (k.cosine + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2));
      h ^= static_cast<std::uint64_t>(k.quadrature) + (h << 6) + (h >> 2);
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };

  std::shared_mutex mutex;
  std::unordered_map<Key, ReferencePoint, KeyHash> cache;

  ReferencePoint evaluate(double kappa, double cosine, Quadrature quadrature) {
    const Key key{std::bit_cast<std::uint64_t>(kappa), std::bit_cast<std::uint64_t>(cosine),
                  quadrature};
    {
      std::shared_lock lock(mutex);
      if (auto it = cache.find(key); it != cache.end()) return it->second;
    }
    // Computed outside the lock; two threads racing on the same new point
    // both compute it (identical results) and the first insert wins.
    const ReferencePoint p = quadrature == Quadrature::high
                                 ? detail::compute_high(kappa, cosine)
                                 : detail::compute_standard(kappa, cosine);
    std::unique_lock lock(mutex);
    cache.emplace(key, p);
    return p;
  }
};

ReferenceEngine::ReferenceEngine() : impl_(new Impl) {}
ReferenceEngine::~ReferenceEngine() { delete impl_; }

ReferencePoint ReferenceEngine::evaluate(double kappa, double cosine, Quadrature quadrature) const {
  check_query(kappa, cosine);
  return impl_->evaluate(kappa, cosine, quadrature);
}

std::vector<ReferencePoint> ReferenceEngine::evaluate(std::span<const Query> queries,
                                                      Quadrature quadrature) const {
  for (const Query& q : queries) check_query(q.kappa, q.cosine);  // fail before any work
  std::vector<ReferencePoint> out(queries.size());
  tbb::parallel_for(std::size_t{0}, queries.size(), [&](std::size_t i) {
    out[i] = impl_->evaluate(queries[i].kappa, queries[i].cosine, quadrature);
  });
  return out;
}

std::size_t ReferenceEngine::cache_size() const {
  std::shared_lock lock(impl_->mutex);
  return impl_->cache.size();
}

void ReferenceEngine::clear_cache() const {
  std::unique_lock lock(impl_->mutex);
  impl_->cache.clear();
}

const ReferenceEngine& reference_engine() {
  static const ReferenceEngine engine;
  return engine;
}

}  // namespace sglab::reference
