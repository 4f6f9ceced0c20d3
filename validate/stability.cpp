#include "validate/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

// The stability table is split along its seams: the taxonomy and the
// `inaccurate` judgement (this file), the probe engine
// (validate/stability_probe.hpp), the input generators
// (stability_inputs.cpp), the exact forms (stability_exact.hpp), the catalogue
// of probed functions (stability_catalogue.cpp) and the report: prose and
// tables (stability_report.cpp).

namespace sglab::validate {

bool StabilityRow::is_failure(FailureKind k) const {
  switch (k) {
    case FailureKind::overflow:
      return false;
    case FailureKind::out_of_range:
      return !approximation;
    default:
      return true;
  }
}

std::size_t StabilityRow::failure_count() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < kFailureKinds; ++i)
    if (is_failure(static_cast<FailureKind>(i))) n += failures[i].count;
  return n;
}

const StabilityRow* StabilityReport::find(std::string_view function, io::Precision f,
                                          bool valid_inputs) const {
  for (const StabilityRow& r : rows)
    if (r.function == function && r.precision == f && r.valid_inputs == valid_inputs) return &r;
  return nullptr;
}

namespace {

// Tolerance of the `inaccurate` check against an exact value: far looser than
// rounding (so only gross errors such as a lost term count).
constexpr long double kInaccurateRelative = 1e-4L;

}  // namespace

template <class T>
long double inaccuracy(T y, long double exact) {
  // Relative wherever the exact value is a normal number of T; below, relative
  // to the smallest normal (a denormal result carries fewer bits by design).
  const long double scale =
      std::max(std::abs(exact), static_cast<long double>(std::numeric_limits<T>::min()));
  return std::abs(static_cast<long double>(y) - exact) / scale;
}
template <class T>
bool is_inaccurate(T y, long double exact) {
  return inaccuracy(y, exact) > kInaccurateRelative;
}
template long double inaccuracy<float>(float, long double);
template long double inaccuracy<double>(double, long double);
template bool is_inaccurate<float>(float, long double);
template bool is_inaccurate<double>(double, long double);

}  // namespace sglab::validate
