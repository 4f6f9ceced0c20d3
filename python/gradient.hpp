// python/gradient.hpp — exact derivatives of the runtime's irradiance methods:
// each registry entry's own template (include/sglab/registry.hpp,
// with_irradiance_methods) instantiated with a Ceres Jet of two partials
// (forward-mode automatic differentiation), so dE/dκ and dE/dc are those of the
// code that computes E, branches and clamps included, not a difference quotient.
#pragma once

#include <cstddef>
#include <span>

namespace sglab::python {

// ∂E/∂κ and ∂E/∂c of irradiance method `index` (its position in
// sglab::irradiance_methods) at n points, in double: the derivatives of the
// template the runtime's f64 instantiates. (The Jet's own value is not
// returned: Ceres divides by multiplying with the reciprocal, so it may differ
// from f64 in the last bit; the caller takes E from the runtime.) Double only: the float
// instantiations are the runtime's own float code paths (sglab_mid's float log, the branch-free
// kernels), which a Jet of floats would not follow, and a float derivative would round the steps.
using GradientBatch = void (*)(const double* cosine, const double* kappa, double* d_kappa,
                               double* d_cosine, std::size_t n);

GradientBatch gradient_batch(std::size_t index);

}  // namespace sglab::python
