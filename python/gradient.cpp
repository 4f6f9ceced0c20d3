// python/gradient.cpp — the Jet instantiations of every irradiance method
// (python/gradient.hpp).
#include "python/gradient.hpp"

#include <array>
#include <stdexcept>

#include <ceres/jet.h>

#include <sglab/registry.hpp>

namespace sglab::python {
namespace {

template <class F>
void gradient_of(const double* cosine, const double* kappa, double* d_kappa, double* d_cosine,
                 std::size_t n) {
  using Jet = ceres::Jet<double, 2>;
  for (std::size_t i = 0; i < n; ++i) {
    const Jet e = F{}(Jet(cosine[i], 1), Jet(kappa[i], 0));
    d_kappa[i] = e.v[0];
    d_cosine[i] = e.v[1];
  }
}

// One entry per irradiance method, in registry order.
struct CollectGradients {
  template <class... M>
  constexpr std::array<GradientBatch, sizeof...(M)> operator()(const M&...) const {
    return {&gradient_of<typename M::Functor>...};
  }
};

constexpr auto kGradients = with_irradiance_methods(CollectGradients{});
static_assert(kGradients.size() == std::size(irradiance_methods));

}  // namespace

GradientBatch gradient_batch(std::size_t index) {
  if (index >= kGradients.size()) throw std::out_of_range("gradient_batch: no such method");
  return kGradients[index];
}

}  // namespace sglab::python
