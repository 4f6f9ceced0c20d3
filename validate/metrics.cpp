#include "validate/metrics.hpp"

#include <cmath>

namespace sglab::validate {

PointErrors compare(double value, double reference, double peak) {
  PointErrors p;
  if (!std::isfinite(value)) {
    p.status = PointStatus::nonfinite_output;
    return p;
  }
  if (!std::isfinite(reference) || !std::isfinite(peak)) {
    p.status = PointStatus::invalid_reference;
    return p;
  }
  p.abs = reference::abs_error(value, reference);
  p.peak_rel = reference::peak_rel_error(value, reference, peak);
  p.significant = reference::significant(reference, peak);
  if (p.significant) p.rel = reference::rel_error(value, reference);
  return p;
}

void ErrorAccumulator::add(double kappa, double cosine, double error) {
  if (std::isnan(error)) {
    ++skipped_;
    return;
  }
  if (error > max_) {
    max_ = error;
    kappa_ = kappa;
    cosine_ = cosine;
  }
  // Neumaier's compensated summation of error².
  const double x = error * error;
  const double t = sum_ + x;
  if (std::abs(sum_) >= std::abs(x))
    compensation_ += (sum_ - t) + x;
  else
    compensation_ += (x - t) + sum_;
  sum_ = t;
  ++count_;
}

void ErrorAccumulator::merge(const ErrorAccumulator& other) {
  if (other.count_ > 0 && other.max_ > max_) {
    max_ = other.max_;
    kappa_ = other.kappa_;
    cosine_ = other.cosine_;
  }
  const double t = sum_ + other.sum_;
  if (std::abs(sum_) >= std::abs(other.sum_))
    compensation_ += (sum_ - t) + other.sum_;
  else
    compensation_ += (other.sum_ - t) + sum_;
  sum_ = t;
  compensation_ += other.compensation_;
  count_ += other.count_;
  skipped_ += other.skipped_;
}

ErrorStats ErrorAccumulator::stats() const {
  ErrorStats s;
  s.count = count_;
  if (count_ == 0) return s;
  s.max = max_;
  s.worst_kappa = kappa_;
  s.worst_cosine = cosine_;
  s.rms = std::sqrt((sum_ + compensation_) / static_cast<double>(count_));
  return s;
}

PointErrors MetricAccumulator::add(double kappa, double cosine, double value, double reference,
                                   double peak) {
  const PointErrors p = compare(value, reference, peak);
  ++points_;
  switch (p.status) {
    case PointStatus::nonfinite_output:
      if (nonfinite_ == 0) {
        first_nonfinite_kappa_ = kappa;
        first_nonfinite_cosine_ = cosine;
      }
      ++nonfinite_;
      break;
    case PointStatus::invalid_reference:
      ++invalid_reference_;
      break;
    case PointStatus::ok:
      peak_rel_.add(kappa, cosine, p.peak_rel);
      abs_.add(kappa, cosine, p.abs);
      if (p.significant) rel_.add(kappa, cosine, p.rel);
      break;
  }
  return p;
}

void MetricAccumulator::merge(const MetricAccumulator& other) {
  peak_rel_.merge(other.peak_rel_);
  rel_.merge(other.rel_);
  abs_.merge(other.abs_);
  points_ += other.points_;
  if (nonfinite_ == 0 && other.nonfinite_ > 0) {
    first_nonfinite_kappa_ = other.first_nonfinite_kappa_;
    first_nonfinite_cosine_ = other.first_nonfinite_cosine_;
  }
  nonfinite_ += other.nonfinite_;
  invalid_reference_ += other.invalid_reference_;
}

MetricSummary MetricAccumulator::summary() const {
  MetricSummary s;
  s.peak_rel = peak_rel_.stats();
  s.rel = rel_.stats();
  s.abs = abs_.stats();
  s.points = points_;
  s.nonfinite = nonfinite_;
  s.invalid_reference = invalid_reference_;
  s.first_nonfinite_kappa = first_nonfinite_kappa_;
  s.first_nonfinite_cosine = first_nonfinite_cosine_;
  return s;
}

}  // namespace sglab::validate
