// reference/reference_high.cpp — Quadrature::high: the same quadrature as
// Quadrature::standard (reference_detail.hpp), run in 50-digit binary floating
// point (boost::multiprecision::cpp_bin_float_50 without expression
// templates). About 1000x slower than double; meant to spot-check it.
//
// (__float128 would be faster, but Boost's float128 wrapper does not compile
// in the strict ISO mode this project builds in: CMAKE_CXX_EXTENSIONS OFF.)
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "reference/reference_detail.hpp"

namespace sglab::reference::detail {

using HighReal = boost::multiprecision::number<boost::multiprecision::cpp_bin_float<50>,
                                               boost::multiprecision::et_off>;

ReferencePoint compute_high(double kappa, double cosine) {
  return to_reference_point(kappa, cosine, compute<HighReal>(kappa, cosine));
}

}  // namespace sglab::reference::detail
