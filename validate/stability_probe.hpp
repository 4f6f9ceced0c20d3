// validate/stability_probe.hpp — the probe engine of the stability table
// (validate/stability.hpp): the documented output ranges, the check of one
// output (Probe: NaN, Inf, overflow, negative, out of range, inaccurate) and
// the Runner that sweeps a function over the probe inputs of precision T
// (generated in stability_inputs.cpp) into a valid-input and an invalid-input row.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/math.hpp>

#include "reference/reference.hpp"
#include "validate/stability.hpp"

namespace sglab::validate::stability_detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Exact text of a value: shortest decimal in its own precision and hex.
template <class T>
std::string show(T x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{} ({:a})", x, static_cast<double>(x));
}
template <class T>
std::string show(const Vec3<T>& v) {
  return fmt::format("({}, {}, {})", show(v.x), show(v.y), show(v.z));
}

// The documented output range [lo, hi]. A bound that is not a small integer
// (π, 2π, 4π) cannot be met exactly in floating point: allow `ulps` units of
// the evaluated precision's epsilon relative to it.
struct Range {
  double lo;
  double hi;
  const char* text;
  double ulps = 0;
};
constexpr Range kNonNegative{0, kInf, "[0, inf)"};
constexpr Range kNonPositive{-kInf, 0, "(-inf, 0]"};
constexpr Range kUnit{0, 1, "[0, 1]"};
constexpr Range kSigned{-1, 1, "[-1, 1]"};
constexpr Range kHalf{0, 0.5, "[0, 1/2]"};
constexpr Range kPi{0, 3.141592653589793, "[0, π]", 4};
constexpr Range kTwoPi{0, 6.283185307179586, "[0, 2π]", 4};
constexpr Range kFourPi{0, 12.566370614359172, "[0, 4π]", 4};
constexpr Range kUnitLength{1, 1, "|axis| = 1", 8};

template <class T>
io::Precision format_of() {
  return sizeof(T) == sizeof(float) ? io::Precision::float32 : io::Precision::float64;
}

template <class T>
bool valid_kappa(T k) {
  return std::isfinite(k) && k >= T(0);
}
template <class T>
bool valid_cosine(T c) {
  return c >= T(-1) && c <= T(1);
}

template <class Describe>
void note(FailureStats& f, double key, Describe&& describe, double error = -1) {
  if (f.count == 0 || error > f.example_error) {
    f.example = describe();
    f.example_error = error;
  }
  ++f.count;
  if (std::isnan(key)) {
    f.at_nan_kappa = true;
    return;
  }
  if (std::isnan(f.kappa_min) || key < f.kappa_min) f.kappa_min = key;
  if (std::isnan(f.kappa_max) || key > f.kappa_max) f.kappa_max = key;
}

// For probes without an exact value.
constexpr auto no_exact = [] { return std::numeric_limits<long double>::quiet_NaN(); };

// |x| beyond the largest finite T (x computed in long double, whose range
// exceeds double's).
template <class T>
bool beyond_max(long double x) {
  return std::isinf(x) || std::abs(x) > static_cast<long double>(std::numeric_limits<T>::max());
}

// ---------------------------------------------------------------------------
// The inputs of the stability sweep, in precision T (float or double;
// stability_inputs.cpp): special values, a logarithmic ladder, and the
// methods' own sharpness constants (rounded to T as the methods round them).
template <class T>
std::vector<T> probe_kappas();
// Cosines at, just inside and just outside ±1, ±0, ±1/2 and NaN.
template <class T>
std::vector<T> probe_cosines();

template <class T>
struct AxisPair {
  const char* name;
  Vec3<T> a, b;
  bool valid;
};

// Unit, nearly opposite, non-unit, zero and NaN axis pairs.
template <class T>
std::vector<AxisPair<T>> probe_axes();

// ---------------------------------------------------------------------------
// Runs one function over its inputs and fills a valid-input and an
// invalid-input row.
template <class T>
class Probe {
 public:
  Probe(std::string name, Origin origin, Range range) : range_(range) {
    for (StabilityRow* r : {&valid_, &invalid_}) {
      r->function = name;
      r->origin = origin;
      r->precision = format_of<T>();
      r->range = range.text;
      r->sign_checked = range.lo >= 0;
    }
    valid_.valid_inputs = true;
    invalid_.valid_inputs = false;
  }

  // `key` is the κ (or x) the failure is located by; `describe()` gives the
  // exact inputs, called only on failure.
  // `exact()` is the exact result in long double (NaN when unknown): it tells
  // an overflow of the exact result from a spurious infinity, and flags
  // finite outputs far from it.
  template <class Describe, class Exact = std::remove_const_t<decltype(no_exact)>>
  void check(bool is_valid, double key, T y, Describe&& describe, Exact exact = {}) {
    StabilityRow& row = is_valid ? valid_ : invalid_;
    ++row.evaluations;
    // The exact value is defined for valid inputs only.
    const auto exact_value = [&]() -> long double {
      return is_valid ? static_cast<long double>(exact())
                      : std::numeric_limits<long double>::quiet_NaN();
    };
    FailureKind kind;
    long double error = -1;
    long double x = std::numeric_limits<long double>::quiet_NaN();
    if (std::isnan(y)) {
      kind = FailureKind::nan;
    } else if (std::isinf(y)) {
      kind = beyond_max<T>(exact_value()) ? FailureKind::overflow : FailureKind::inf;
    } else if (row.sign_checked && y < T(0)) {
      kind = FailureKind::negative;
    } else if (outside(static_cast<double>(y))) {
      kind = FailureKind::out_of_range;
    } else {
      x = exact_value();
      if (std::isnan(x) || beyond_max<T>(x)) return;
      if (!is_inaccurate(y, x)) return;
      kind = FailureKind::inaccurate;
      error = inaccuracy(y, x);
    }
    note(
        row.failures[static_cast<std::size_t>(kind)], key,
        [&] {
          if (kind == FailureKind::inaccurate)
            return fmt::format("{} -> {}, exact {:.17g}", describe(), show(y),
                               static_cast<double>(x));
          return fmt::format("{} -> {}", describe(), show(y));
        },
        static_cast<double>(error));
  }

  // An input the function refused by throwing (the reference engine's
  // argument check): right for invalid inputs, a failure (counted as `nan`,
  // no value) for valid ones.
  template <class Describe>
  void refused(bool is_valid, double key, Describe&& describe, const char* what) {
    StabilityRow& row = is_valid ? valid_ : invalid_;
    ++row.evaluations;
    if (!is_valid) return;
    note(row.failures[static_cast<std::size_t>(FailureKind::nan)], key,
         [&] { return fmt::format("{} -> refused: {}", describe(), what); });
  }

  void append_to(std::vector<StabilityRow>& rows) && {
    rows.push_back(std::move(valid_));
    rows.push_back(std::move(invalid_));
  }

 private:
  bool outside(double y) const {
    const double eps = std::numeric_limits<T>::epsilon();
    const double lo = range_.lo - range_.ulps * eps * std::abs(range_.lo);
    const double hi = range_.hi + range_.ulps * eps * std::abs(range_.hi);
    return y < lo || y > hi;
  }

  Range range_;
  StabilityRow valid_, invalid_;
};

template <class T>
class Runner {
 public:
  std::vector<StabilityRow> rows;

  Runner() : kappas_(probe_kappas<T>()), cosines_(probe_cosines<T>()), axes_(probe_axes<T>()) {}

  // f(κ)
  template <class F, class Exact = std::nullptr_t>
  void kappa_only(const char* name, Origin origin, Range range, F f, Exact exact = nullptr) {
    Probe<T> p(name, origin, range);
    for (T k : kappas_)
      p.check(
          valid_kappa(k), static_cast<double>(k), f(k),
          [&] { return fmt::format("κ = {}", show(k)); },
          [&] {
            if constexpr (std::is_same_v<Exact, std::nullptr_t>)
              return no_exact();
            else
              return exact(k);
          });
    std::move(p).append_to(rows);
  }

  // f(c, κ)
  template <class F, class Exact = std::nullptr_t>
  void cosine_kappa(const std::string& name, Origin origin, Range range, F f,
                    Exact exact = nullptr) {
    Probe<T> p(name, origin, range);
    for (T k : kappas_)
      for (T c : cosines_)
        p.check(
            valid_kappa(k) && valid_cosine(c), static_cast<double>(k), f(c, k),
            [&] { return fmt::format("c = {}, κ = {}", show(c), show(k)); },
            [&] {
              if constexpr (std::is_same_v<Exact, std::nullptr_t>)
                return no_exact();
              else
                return exact(c, k);
            });
    std::move(p).append_to(rows);
  }

  // f(c, κ1, κ2), located by κ1
  // `exact(c, κ1, κ2)` (long double, optional): the exact result.
  template <class F, class Exact = std::nullptr_t>
  void cosine_two_kappas(const char* name, Origin origin, Range range, F f, Exact exact = nullptr) {
    Probe<T> p(name, origin, range);
    for (T k1 : kappas_)
      for (T k2 : kappas_)
        for (T c : cosines_)
          p.check(
              valid_kappa(k1) && valid_kappa(k2) && valid_cosine(c), static_cast<double>(k1),
              f(c, k1, k2),
              [&] { return fmt::format("c = {}, κ1 = {}, κ2 = {}", show(c), show(k1), show(k2)); },
              [&] {
                if constexpr (std::is_same_v<Exact, std::nullptr_t>)
                  return no_exact();
                else
                  return exact(c, k1, k2);
              });
    std::move(p).append_to(rows);
  }

  // f(ω, v, κ) over the axis pairs
  template <class F>
  void axes_kappa(const char* name, Origin origin, Range range, F f) {
    Probe<T> p(name, origin, range);
    for (const AxisPair<T>& ax : axes_)
      for (T k : kappas_)
        p.check(ax.valid && valid_kappa(k), static_cast<double>(k), f(ax.a, ax.b, k), [&] {
          return fmt::format("{} axes ω = {}, v = {}, κ = {}", ax.name, show(ax.a), show(ax.b),
                             show(k));
        });
    std::move(p).append_to(rows);
  }

  // f(v1, κ1, v2, κ2), located by κ1
  template <class F, class Exact = std::nullptr_t>
  void axes_two_kappas(const char* name, Origin origin, Range range, F f, Exact exact = nullptr) {
    Probe<T> p(name, origin, range);
    for (const AxisPair<T>& ax : axes_)
      for (T k1 : kappas_)
        for (T k2 : kappas_)
          p.check(
              ax.valid && valid_kappa(k1) && valid_kappa(k2), static_cast<double>(k1),
              f(ax.a, k1, ax.b, k2),
              [&] {
                return fmt::format("{} axes v1 = {}, κ1 = {}, v2 = {}, κ2 = {}", ax.name,
                                   show(ax.a), show(k1), show(ax.b), show(k2));
              },
              [&] {
                if constexpr (std::is_same_v<Exact, std::nullptr_t>)
                  return no_exact();
                else
                  return exact(ax.a, k1, ax.b, k2);
              });
    std::move(p).append_to(rows);
  }

  // A quantity of the reference engine (reference/reference.hpp) over (c, κ):
  // the engine runs in double at the probe's values (float probes converted
  // exactly) and its result is rounded to T. Invalid inputs must be refused.
  template <class Get, class Exact>
  void reference(const char* name, Range range, Get get, Exact exact) {
    Probe<T> p(name, Origin::sglab, range);
    for (T k : kappas_)
      for (T c : cosines_) {
        const bool valid = valid_kappa(k) && valid_cosine(c);
        const auto describe = [&] { return fmt::format("c = {}, κ = {}", show(c), show(k)); };
        reference::ReferencePoint point;
        try {
          point = reference::reference_engine().evaluate(static_cast<double>(k),
                                                         static_cast<double>(c));
        } catch (const std::invalid_argument& e) {
          p.refused(valid, static_cast<double>(k), describe, e.what());
          continue;
        }
        p.check(valid, static_cast<double>(k), static_cast<T>(get(point)), describe,
                [&] { return exact(c, k); });
      }
    std::move(p).append_to(rows);
  }

  // Marks the rows of the probe just run as an approximation.
  void approximation() {
    rows[rows.size() - 1].approximation = true;
    rows[rows.size() - 2].approximation = true;
  }

  // f(x) over ±κ values and ±inf, NaN; valid when finite; located by x.
  template <class F>
  void real_line(const std::string& name, Origin origin, Range range, F f) {
    Probe<T> p(name, origin, range);
    std::vector<T> xs;
    for (T k : kappas_) {
      xs.push_back(k);
      if (!std::isnan(k) && k != T(0)) xs.push_back(-k);
    }
    for (T x : xs)
      p.check(std::isfinite(x), static_cast<double>(x), f(x),
              [&] { return fmt::format("x = {}", show(x)); });
    std::move(p).append_to(rows);
  }

  const std::vector<T>& kappas() const { return kappas_; }
  const std::vector<T>& cosines() const { return cosines_; }

 private:
  std::vector<T> kappas_;
  std::vector<T> cosines_;
  std::vector<AxisPair<T>> axes_;
};

}  // namespace sglab::validate::stability_detail
