// validate/metrics.hpp — a method judged against the reference over a table:
// each point classified and measured by the metrics of docs/quantities.md
// (reference/error_measures.hpp), and their summaries (max, where, RMS, counts).
//
// The accumulators classify before they measure: a non-finite method output
// is counted in `nonfinite` and excluded from max and RMS (it would otherwise
// swamp both); a non-finite reference or peak is counted in
// `invalid_reference` and excluded too (that is a reference-engine problem,
// not the method's). Neither is ever silently dropped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "reference/error_measures.hpp"

namespace sglab::validate {

// What a comparison found at one point.
enum class PointStatus : std::uint8_t {
  ok,                 // finite output against a finite reference and peak
  nonfinite_output,   // x̂ is NaN or ±inf: counted, excluded from max/RMS
  invalid_reference,  // x or x(1, κ) is NaN or ±inf: counted, excluded
};

// All metrics of docs/quantities.md at one point; NaN where a metric does not apply
// (rel outside the significant region, every metric unless status == ok).
struct PointErrors {
  PointStatus status = PointStatus::ok;
  double abs = std::numeric_limits<double>::quiet_NaN();
  double peak_rel = std::numeric_limits<double>::quiet_NaN();
  double rel = std::numeric_limits<double>::quiet_NaN();
  bool significant = false;
};

PointErrors compare(double value, double reference, double peak);

// Summary of one metric over a set of points.
struct ErrorStats {
  double max = std::numeric_limits<double>::quiet_NaN();  // NaN when no point entered
  double worst_kappa = std::numeric_limits<double>::quiet_NaN();
  double worst_cosine = std::numeric_limits<double>::quiet_NaN();
  double rms = std::numeric_limits<double>::quiet_NaN();
  std::size_t count = 0;  // points that entered max and RMS
};

// Max (first occurrence wins ties, so the result does not depend on
// anything but the order of `add`), where it occurs, and the RMS with a
// compensated sum of squares. NaN errors are ignored and counted in
// `skipped` (use the classification in MetricAccumulator to count them as
// what they are).
class ErrorAccumulator {
 public:
  void add(double kappa, double cosine, double error);
  // Appends `other` as if its points had been added after this one's.
  void merge(const ErrorAccumulator& other);
  ErrorStats stats() const;
  std::size_t skipped() const { return skipped_; }

 private:
  double max_ = -1;
  double kappa_ = std::numeric_limits<double>::quiet_NaN();
  double cosine_ = std::numeric_limits<double>::quiet_NaN();
  double sum_ = 0, compensation_ = 0;  // Neumaier sum of error²
  std::size_t count_ = 0;
  std::size_t skipped_ = 0;
};

// Every summary (docs/quantities.md) of a method against a reference over a table:
// peak_rel, rel (significant points only) and abs, plus the counts.
struct MetricSummary {
  ErrorStats peak_rel;
  ErrorStats rel;
  ErrorStats abs;
  std::size_t points = 0;             // every point added
  std::size_t nonfinite = 0;          // non-finite method outputs
  std::size_t invalid_reference = 0;  // non-finite reference or peak
  // Where the first non-finite output occurred (NaN when none).
  double first_nonfinite_kappa = std::numeric_limits<double>::quiet_NaN();
  double first_nonfinite_cosine = std::numeric_limits<double>::quiet_NaN();
};

class MetricAccumulator {
 public:
  // Classifies and accumulates one point; returns what it measured.
  PointErrors add(double kappa, double cosine, double value, double reference, double peak);
  void merge(const MetricAccumulator& other);
  MetricSummary summary() const;

 private:
  ErrorAccumulator peak_rel_, rel_, abs_;
  std::size_t points_ = 0, nonfinite_ = 0, invalid_reference_ = 0;
  double first_nonfinite_kappa_ = std::numeric_limits<double>::quiet_NaN();
  double first_nonfinite_cosine_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace sglab::validate
