// sglab/batch.hpp — bulk evaluation: arrays of cosines and κ in, values out.
//
// The loop body is the inlined method, with no aliasing between inputs and
// output, so the compiler may vectorize it where the method's math allows.
#pragma once

#include <cstddef>

namespace sglab {

template <class T, class F>
void evaluate_batch(F f, const T* __restrict cosine, const T* __restrict kappa, T* __restrict out,
                    std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = f(cosine[i], kappa[i]);
}

}  // namespace sglab
