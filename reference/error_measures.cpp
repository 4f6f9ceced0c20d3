#include "reference/error_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sglab::reference {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

double abs_error(double value, double reference) {
  if (std::isnan(value) || std::isnan(reference)) return kNaN;
  if (value == reference) return 0;  // also equal infinities
  return std::abs(value - reference);
}

double peak_rel_error(double value, double reference, double peak) {
  const double e = abs_error(value, reference);
  if (std::isnan(e) || std::isnan(peak)) return kNaN;
  if (e == 0) return 0;
  const double p = std::abs(peak);
  if (p == 0) return kInf;
  if (std::isinf(p)) return std::isinf(e) ? kNaN : 0;  // inf/inf is undefined
  return e / p;
}

double rel_error(double value, double reference) {
  if (std::isnan(value) || std::isnan(reference)) return kNaN;
  if (value == reference) return 0;
  if (reference == 0) return kInf;
  if (std::isinf(reference))
    return std::isinf(value) ? kInf : 1;  // |x̂/±inf − 1| = 1; opposite infinities: inf
  return std::abs(value / reference - 1);
}

double max_peak_rel_error(std::span<const double> values, std::span<const double> references,
                          std::span<const double> peaks) {
  if (values.size() != references.size() || values.size() != peaks.size())
    throw std::invalid_argument(
        "max_peak_rel_error: values, references and peaks differ in length");
  double worst = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double e = peak_rel_error(values[i], references[i], peaks[i]);
    if (!std::isfinite(e)) return kInf;
    worst = std::max(worst, e);
  }
  return worst;
}

bool significant(double reference, double peak) {
  if (std::isnan(reference) || std::isnan(peak)) return false;
  return std::abs(reference) >= kSignificantFraction * std::abs(peak);
}

}  // namespace sglab::reference
