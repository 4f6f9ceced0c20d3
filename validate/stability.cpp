#include "validate/stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include <sglab/closed_forms.hpp>
#include <sglab/erf.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/irradiance.hpp>
#include <sglab/math.hpp>
#include <sglab/registry.hpp>
#include <sglab/sg.hpp>

#include "validate/reference.hpp"

namespace sglab::validate {

std::string_view to_string(FailureKind k) {
  switch (k) {
    case FailureKind::nan:
      return "nan";
    case FailureKind::inf:
      return "inf";
    case FailureKind::overflow:
      return "overflow";
    case FailureKind::negative:
      return "negative";
    case FailureKind::out_of_range:
      return "out_of_range";
    case FailureKind::inaccurate:
      return "inaccurate";
  }
  return "?";
}

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

const StabilityRow* StabilityReport::find(std::string_view function, FloatFormat f, bool valid_inputs) const {
  for (const StabilityRow& r : rows)
    if (r.function == function && r.precision == f && r.valid_inputs == valid_inputs) return &r;
  return nullptr;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Exact text of a value: shortest decimal in its own precision and hex.
template <class T> std::string show(T x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{} ({:a})", x, static_cast<double>(x));
}
template <class T> std::string show(const Vec3<T>& v) {
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

template <class T> FloatFormat format_of() {
  return sizeof(T) == sizeof(float) ? FloatFormat::binary32 : FloatFormat::binary64;
}

template <class T> bool valid_kappa(T k) { return std::isfinite(k) && k >= T(0); }
template <class T> bool valid_cosine(T c) { return c >= T(-1) && c <= T(1); }

template <class Describe> void note(FailureStats& f, double key, Describe&& describe, double error = -1) {
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
template <class T> bool beyond_max(long double x) {
  return std::isinf(x) || std::abs(x) > static_cast<long double>(std::numeric_limits<T>::max());
}

// Tolerance of the `inaccurate` check against an exact value: far looser than
// rounding (so only gross errors such as a lost term count).
constexpr long double kInaccurateRelative = 1e-4L;

}  // namespace

template <class T> long double inaccuracy(T y, long double exact) {
  // Relative wherever the exact value is a normal number of T; below, relative
  // to the smallest normal (a denormal result carries fewer bits by design).
  const long double scale = std::max(std::abs(exact), static_cast<long double>(std::numeric_limits<T>::min()));
  return std::abs(static_cast<long double>(y) - exact) / scale;
}
template <class T> bool is_inaccurate(T y, long double exact) { return inaccuracy(y, exact) > kInaccurateRelative; }
template long double inaccuracy<float>(float, long double);
template long double inaccuracy<double>(double, long double);
template bool is_inaccurate<float>(float, long double);
template bool is_inaccurate<double>(double, long double);

namespace {

// Runs one function over its inputs and fills a valid-input and an
// invalid-input row.
template <class T> class Probe {
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
      return is_valid ? static_cast<long double>(exact()) : std::numeric_limits<long double>::quiet_NaN();
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
    note(row.failures[static_cast<std::size_t>(kind)], key, [&] {
      if (kind == FailureKind::inaccurate)
        return fmt::format("{} -> {}, exact {:.17g}", describe(), show(y), static_cast<double>(x));
      return fmt::format("{} -> {}", describe(), show(y));
    }, static_cast<double>(error));
  }

  // An input the function refused by throwing (the reference engine's
  // argument check): right for invalid inputs, a failure (counted as `nan`,
  // no value) for valid ones.
  template <class Describe> void refused(bool is_valid, double key, Describe&& describe, const char* what) {
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

}  // namespace

std::vector<double> method_sharpness_constants() {
  // The sharpness of the SG each method multiplies the light by (κ = λ is
  // where the product with it has κ3 = 0 at c = −1), read from the constant
  // sets the methods use: the cosine lobe of wang2009 and its refit, the
  // diffuse lobe λd of vsgl2015 and its refits, Meder's cosine-fit λm, and the
  // clamped-cosine λ of tokuyoshi2022 and its refits.
  return {constants::cosine_lobe_published.lambda,
          constants::lambda_d_cosine_lobe_free_amplitude.lambda,
          constants::diffuse_lobe_published.lambda_d,
          constants::lambda_d_diffuse_lobe_irradiance.lambda_d,
          constants::lambda_d_diffuse_lobe_hemisphere_ls.lambda_d,
          constants::lambda_d_diffuse_lobe_sphere_ls.lambda_d,
          constants::meder2018_published.sharpness,
          constants::clamped_cosine_published.lambda,
          constants::clamped_cosine_float.lambda,
          constants::clamped_cosine_float_alpha_free.lambda,
          constants::clamped_cosine_double.lambda,
          constants::clamped_cosine_half.lambda};
}

namespace {

// The inputs of the stability sweep, in precision T: special values, a
// logarithmic ladder, and the methods' own sharpness constants (rounded to T
// as the methods round them).
template <class T> std::vector<T> probe_kappas() {
  const double list[] = {-1,   0,    1e-30, 1e-6, 1e-3, 1e-2, 0.1,  0.2,  0.3,  0.4,  0.5,  0.6,  0.7,
                         0.8,  1,    2,     5,    10,   20,   50,   88,   89,   100,  700,  710,  1e3,
                         1e4,  1e5,  1e6,   1e10, 1e15, 1e20, 1e30, 1e38, 1e100, 1e200, 1e300};
  std::vector<T> out;
  // Every binade of the subnormals, 2^e from the smallest subnormal up to the
  // smallest normal, and the largest subnormal.
  for (int e = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits;
       e < std::numeric_limits<T>::min_exponent; ++e)
    out.push_back(std::ldexp(T(1), e));
  out.push_back(std::numeric_limits<T>::min() - std::numeric_limits<T>::denorm_min());
  for (double v : list) {
    const T t = static_cast<T>(v);
    if (std::isfinite(t)) out.push_back(t);
  }
  for (double v : method_sharpness_constants()) out.push_back(static_cast<T>(v));
  out.push_back(std::numeric_limits<float>::max());
  if constexpr (sizeof(T) > sizeof(float)) out.push_back(std::numeric_limits<double>::max());
  out.push_back(std::numeric_limits<T>::infinity());
  out.push_back(std::numeric_limits<T>::quiet_NaN());
  return out;
}

template <class T> std::vector<T> probe_cosines() {
  const T one(1);
  return {T(-1) - T(0x1p-10),
          std::nextafter(-one, T(-2)),
          T(-1),
          std::nextafter(-one, T(0)),
          T(-0.5),
          T(-0.0),
          T(0),
          T(0.5),
          std::nextafter(one, T(0)),
          T(1),
          std::nextafter(one, T(2)),
          T(1) + T(0x1p-10),
          std::numeric_limits<T>::quiet_NaN()};
}

template <class T> struct AxisPair {
  const char* name;
  Vec3<T> a, b;
  bool valid;
};

template <class T> std::vector<AxisPair<T>> probe_axes() {
  using std::sqrt;
  const T z0(0), o(1);
  const Vec3<T> z{z0, z0, o}, x{o, z0, z0};
  const T d = sizeof(T) == sizeof(float) ? T(0x1p-12) : T(0x1p-26);
  const T s = T(0.70710678118654752440L);
  const T nan = std::numeric_limits<T>::quiet_NaN();
  return {
      {"same", z, z, true},
      {"orthogonal", z, x, true},
      {"opposite", z, Vec3<T>{z0, z0, -o}, true},
      {"nearly opposite", z, Vec3<T>{d, z0, -sqrt(o - d * d)}, true},
      {"45 degrees", z, Vec3<T>{s, z0, s}, true},
      {"generic", Vec3<T>{T(0.36), T(0.48), T(0.8)}, Vec3<T>{T(0.6), z0, T(-0.8)}, true},
      {"non-unit (2x)", z, Vec3<T>{z0, z0, T(2)}, false},
      {"non-unit opposite (2x)", z, Vec3<T>{z0, z0, T(-2)}, false},
      {"non-unit (0.5x) orthogonal", z, Vec3<T>{T(0.5), z0, z0}, false},
      {"zero axis", z, Vec3<T>{z0, z0, z0}, false},
      {"NaN axis", z, Vec3<T>{nan, z0, z0}, false},
  };
}

// Exact product quantities in long double (docs/quantities.md; [Tokuyoshi2022] Eq. 1-2):
// κ3 = |κ1 v1 + κ2 v2|, log-amplitude κ3 − κ1 − κ2 = −κ1κ2|v1 − v2|²/(κ3 + κ1 + κ2).
// |κ1v1 + κ2v2|² = (κ1 − κ2)(κ1|v1|² − κ2|v2|²) + κ1κ2|v1 + v2|², an identity
// that does not cancel for nearly opposite axes and nearly equal κ.
template <class T> long double exact_product_sharpness(const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
  using L = long double;
  const L a2 = L(a.x) * a.x + L(a.y) * a.y + L(a.z) * a.z, b2 = L(b.x) * b.x + L(b.y) * b.y + L(b.z) * b.z;
  const L sx = L(a.x) + b.x, sy = L(a.y) + b.y, sz = L(a.z) + b.z;
  const L s = (L(k1) - k2) * (L(k1) * a2 - L(k2) * b2) + L(k1) * k2 * (sx * sx + sy * sy + sz * sz);
  return std::sqrt(s > 0 ? s : L(0));
}
template <class T> long double exact_product_log_amplitude(const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
  using L = long double;
  const L dx = L(a.x) - b.x, dy = L(a.y) - b.y, dz = L(a.z) - b.z;
  const L den = exact_product_sharpness(a, k1, b, k2) + L(k1) + L(k2);
  return den > 0 ? -L(k1) * L(k2) * (dx * dx + dy * dy + dz * dz) / den : L(0);
}
template <class T> long double exact_normal_product_sharpness(T c, T k, T l) {
  using L = long double;
  const L s = (L(k) - l) * (L(k) - l) + 2 * L(k) * l * (1 + L(c));  // (κ − λ)² + 2κλ(1 + c)
  return std::sqrt(s > 0 ? s : L(0));
}
template <class T> long double exact_normal_product_log_amplitude(T c, T k, T l) {
  using L = long double;
  const L den = exact_normal_product_sharpness(c, k, l) + L(k) + L(l);
  return den > 0 ? -2 * (1 - L(c)) * L(k) * L(l) / den : L(0);
}

// Exact closed forms of docs/quantities.md in long double, for κ ≥ 0 (series near 0,
// where long double would cancel too).
using L = long double;
constexpr L kPiL = 3.141592653589793238462643383279502884L;
L exact_expm1_over_minus(L k) { return k == 0 ? L(1) : -std::expm1(-k) / k; }  // (1 − e^{−κ})/κ
L exact_sphere_integral(L k) { return 4 * kPiL * exact_expm1_over_minus(2 * k); }
L exact_upper_over_two_pi(L k) {  // (κ − 1 + e^{−κ})/κ²
  if (k < L(1e-2)) return L(1) / 2 - k / 6 + k * k / 24 - k * k * k / 120 + k * k * k * k / 720;
  return (k - 1 + std::exp(-k)) / (k * k);
}
L exact_lower_over_two_pi(L k) {  // e^{−κ}(1 − e^{−κ} − κe^{−κ})/κ²
  if (k < L(1e-2)) return std::exp(-k) * (L(1) / 2 - 2 * k / 6 + 3 * k * k / 24 - 4 * k * k * k / 120 + 5 * k * k * k * k / 720);
  const L e = std::exp(-k);
  return e * (1 - e - k * e) / (k * k);
}
template <class S> L exact_steepness2022(L k, const Steepness2022Params<S>& p) {
  return k * std::sqrt((L(0.5) * k + L(p.A)) / ((k + L(p.B)) * k + L(p.C)));
}
template <class S> L exact_steepness2024(L k, const Steepness2024Params<S>& p) {
  return k * std::sqrt(L(0.5) * ((k + L(p.A)) * k + L(p.B)) / (((k + L(p.C)) * k + L(p.D)) * k + L(p.E)));
}

template <class T> class Runner {
 public:
  std::vector<StabilityRow> rows;

  Runner() : kappas_(probe_kappas<T>()), cosines_(probe_cosines<T>()), axes_(probe_axes<T>()) {}

  // f(κ)
  template <class F, class Exact = std::nullptr_t>
  void kappa_only(const char* name, Origin origin, Range range, F f, Exact exact = nullptr) {
    Probe<T> p(name, origin, range);
    for (T k : kappas_)
      p.check(
          valid_kappa(k), static_cast<double>(k), f(k), [&] { return fmt::format("κ = {}", show(k)); },
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
  void cosine_kappa(const std::string& name, Origin origin, Range range, F f, Exact exact = nullptr) {
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
              valid_kappa(k1) && valid_kappa(k2) && valid_cosine(c), static_cast<double>(k1), f(c, k1, k2),
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
  template <class F> void axes_kappa(const char* name, Origin origin, Range range, F f) {
    Probe<T> p(name, origin, range);
    for (const AxisPair<T>& ax : axes_)
      for (T k : kappas_)
        p.check(ax.valid && valid_kappa(k), static_cast<double>(k), f(ax.a, ax.b, k), [&] {
          return fmt::format("{} axes ω = {}, v = {}, κ = {}", ax.name, show(ax.a), show(ax.b), show(k));
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
              ax.valid && valid_kappa(k1) && valid_kappa(k2), static_cast<double>(k1), f(ax.a, k1, ax.b, k2),
              [&] {
                return fmt::format("{} axes v1 = {}, κ1 = {}, v2 = {}, κ2 = {}", ax.name, show(ax.a), show(k1),
                                   show(ax.b), show(k2));
              },
              [&] {
                if constexpr (std::is_same_v<Exact, std::nullptr_t>)
                  return no_exact();
                else
                  return exact(ax.a, k1, ax.b, k2);
              });
    std::move(p).append_to(rows);
  }

  // A quantity of the reference engine (validate/reference.hpp) over (c, κ):
  // the engine runs in double at the probe's values (float probes converted
  // exactly) and its result is rounded to T. Invalid inputs must be refused.
  template <class Get, class Exact>
  void reference(const char* name, Range range, Get get, Exact exact) {
    Probe<T> p(name, Origin::sglab, range);
    for (T k : kappas_)
      for (T c : cosines_) {
        const bool valid = valid_kappa(k) && valid_cosine(c);
        const auto describe = [&] { return fmt::format("c = {}, κ = {}", show(c), show(k)); };
        ReferencePoint point;
        try {
          point = reference_engine().evaluate(static_cast<double>(k), static_cast<double>(c));
        } catch (const std::invalid_argument& e) {
          p.refused(valid, static_cast<double>(k), describe, e.what());
          continue;
        }
        p.check(valid, static_cast<double>(k), static_cast<T>(get(point)), describe, [&] { return exact(c, k); });
      }
    std::move(p).append_to(rows);
  }

  // Marks the rows of the probe just run as an approximation.
  void approximation() {
    rows[rows.size() - 1].approximation = true;
    rows[rows.size() - 2].approximation = true;
  }

  // f(x) over ±κ values and ±inf, NaN; valid when finite; located by x.
  template <class F> void real_line(const std::string& name, Origin origin, Range range, F f) {
    Probe<T> p(name, origin, range);
    std::vector<T> xs;
    for (T k : kappas_) {
      xs.push_back(k);
      if (!std::isnan(k) && k != T(0)) xs.push_back(-k);
    }
    for (T x : xs) p.check(std::isfinite(x), static_cast<double>(x), f(x), [&] { return fmt::format("x = {}", show(x)); });
    std::move(p).append_to(rows);
  }

  const std::vector<T>& kappas() const { return kappas_; }
  const std::vector<T>& cosines() const { return cosines_; }

 private:
  std::vector<T> kappas_;
  std::vector<T> cosines_;
  std::vector<AxisPair<T>> axes_;
};

// Every probe, in a fixed order, for precision T.
template <class T> std::vector<StabilityRow> run_all(std::vector<double>& kappas, std::vector<double>& cosines) {
  constexpr Origin own = Origin::sglab, pub = Origin::published;
  Runner<T> r;
  for (T k : r.kappas()) kappas.push_back(static_cast<double>(k));
  for (T c : r.cosines()) cosines.push_back(static_cast<double>(c));

  // SG primitives (sg.hpp).
  r.cosine_kappa(
      "sg_evaluate(c, κ)", own, kUnit, [](T c, T k) { return sg_evaluate(c, k); },
      [](T c, T k) { return std::exp(L(k) * (L(c) - 1)); });
  r.axes_kappa("sg_evaluate(ω, v, κ)", own, kUnit,
               [](const Vec3<T>& w, const Vec3<T>& v, T k) { return sg_evaluate(w, v, k); });
  r.kappa_only(
      "sphere_integral", own, kFourPi, [](T k) { return sphere_integral(k); },
      [](T k) { return exact_sphere_integral(k); });
  r.kappa_only("sphere_integral_approx", pub, kFourPi, [](T k) { return sphere_integral_approx(k); });
  r.approximation();
  r.kappa_only(
      "expm1_over_x(-κ)", own, kUnit, [](T k) { return expm1_over_x(-k); },
      [](T k) { return exact_expm1_over_minus(k); });
  r.axes_two_kappas(
      "sg_product.sharpness", own, kNonNegative,
      [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) { return sg_product(a, k1, b, k2).sharpness; },
      exact_product_sharpness<T>);
  r.axes_two_kappas("sg_product.log_amplitude", own, kNonPositive,
                    [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
                      return sg_product(a, k1, b, k2).log_amplitude;
                    },
                    exact_product_log_amplitude<T>);
  r.axes_two_kappas("sg_product.axis_length", own, kUnitLength, [](const Vec3<T>& a, T k1, const Vec3<T>& b, T k2) {
    return length(sg_product(a, k1, b, k2).axis);
  });
  r.cosine_two_kappas("sg_product_with_normal.sharpness", own, kNonNegative,
                      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).sharpness; },
                      exact_normal_product_sharpness<T>);
  r.cosine_two_kappas("sg_product_with_normal.log_amplitude", own, kNonPositive,
                      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).log_amplitude; },
                      exact_normal_product_log_amplitude<T>);
  r.cosine_two_kappas("sg_product_with_normal.cosine", own, kSigned,
                      [](T c, T k, T l) { return sg_product_with_normal(c, k, l).cosine; });
  r.cosine_two_kappas(
      "sg_inner_product", own, kFourPi, [](T c, T k1, T k2) { return sg_inner_product(c, k1, k2); },
      [](T c, T k1, T k2) {
        return std::exp(exact_normal_product_log_amplitude(c, k1, k2)) *
               exact_sphere_integral(exact_normal_product_sharpness(c, k1, k2));
      });
  r.cosine_two_kappas("sg_inner_product_iwasaki", pub, kFourPi,
                      [](T c, T k1, T k2) { return sg_inner_product_iwasaki(c, k1, k2); });
  r.approximation();

  // Closed forms (closed_forms.hpp).
  r.kappa_only(
      "irradiance_upper", own, kPi, [](T k) { return irradiance_upper(k); },
      [](T k) { return 2 * kPiL * exact_upper_over_two_pi(k); });
  r.kappa_only(
      "irradiance_lower", own, kPi, [](T k) { return irradiance_lower(k); },
      [](T k) { return 2 * kPiL * exact_lower_over_two_pi(k); });
  r.kappa_only(
      "irradiance_upper_over_two_pi", own, kHalf, [](T k) { return irradiance_upper_over_two_pi(k); },
      [](T k) { return exact_upper_over_two_pi(k); });
  r.kappa_only(
      "irradiance_lower_over_two_pi", own, kHalf, [](T k) { return irradiance_lower_over_two_pi(k); },
      [](T k) { return exact_lower_over_two_pi(k); });
  r.kappa_only(
      "hemispherical_upper", own, kTwoPi, [](T k) { return hemispherical_upper(k); },
      [](T k) { return 2 * kPiL * exact_expm1_over_minus(k); });
  r.kappa_only(
      "hemispherical_lower", own, kTwoPi, [](T k) { return hemispherical_lower(k); },
      [](T k) { return std::exp(-L(k)) * 2 * kPiL * exact_expm1_over_minus(k); });
  r.kappa_only(
      "hemispherical_equator", own, kTwoPi, [](T k) { return hemispherical_equator(k); },
      [](T k) { return exact_sphere_integral(k) / 2; });

  // The reference engine, exact at the poles and (H, s) on the horizon.
  const auto nan_l = std::numeric_limits<L>::quiet_NaN();
  r.reference(
      "reference/hemispherical", kTwoPi, [](const ReferencePoint& q) { return q.hemispherical; },
      [nan_l](T c, T k) {
        if (c == T(1)) return 2 * kPiL * exact_expm1_over_minus(k);
        if (c == T(-1)) return std::exp(-L(k)) * 2 * kPiL * exact_expm1_over_minus(k);
        if (c == T(0)) return exact_sphere_integral(k) / 2;
        return nan_l;
      });
  r.reference(
      "reference/irradiance", kPi, [](const ReferencePoint& q) { return q.irradiance; },
      [nan_l](T c, T k) {
        if (c == T(1)) return 2 * kPiL * exact_upper_over_two_pi(k);
        if (c == T(-1)) return 2 * kPiL * exact_lower_over_two_pi(k);
        return nan_l;
      });
  r.reference(
      "reference/normalized", kUnit, [](const ReferencePoint& q) { return q.normalized; },
      [nan_l](T c, T k) {
        if (c == T(1)) return L(1);
        if (c == T(-1)) return L(0);
        if (c != T(0)) return nan_l;
        // s(0, κ) = (S/2 − H(−1))/(H(1) − H(−1)) = ½ + O(κ); the difference
        // form loses ~ε_L/κ in long double, so below κ = 1e−6 take ½.
        if (L(k) < L(1e-6)) return L(0.5);
        const L h1 = exact_expm1_over_minus(k), hm1 = std::exp(-L(k)) * h1;
        return (exact_sphere_integral(k) / (4 * kPiL) - hm1) / (h1 - hm1);
      });

  // Steepness functions and erf-based pieces (hemispherical.hpp, irradiance.hpp).
  r.kappa_only(
      "steepness2022", own, kNonNegative, [](T k) { return steepness2022(k); },
      [](T k) { return exact_steepness2022(k, constants::steepness2022_published); });
  r.approximation();
  r.kappa_only(
      "steepness2024", own, kNonNegative, [](T k) { return steepness2024(k); },
      [](T k) { return exact_steepness2024(k, constants::steepness2024_published); });
  r.approximation();
  r.kappa_only("steepness_meder2018", pub, kNonNegative, [](T k) { return steepness_meder2018(k); });
  r.approximation();
  r.cosine_kappa("erf_ratio(t, c)", own, kSigned, [](T c, T t) { return erf_ratio(t, c); });
  r.cosine_kappa("lerp_factor_tokuyoshi2024", own, kUnit,
                 [](T c, T k) { return lerp_factor_tokuyoshi2024(c, k); });
  r.approximation();

  // erf variants.
  for (const ErfVariant& v : erf_variants) {
    const auto f = v;
    r.real_line(fmt::format("erf/{}", v.id), pub, kSigned, [f](T x) {
      if constexpr (sizeof(T) == sizeof(float))
        return f.f32(x);
      else
        return f.f64(x);
    });
    r.approximation();
  }

  // Every registered method.
  const auto call = [](const Method& m) {
    return [m](T c, T k) {
      if constexpr (sizeof(T) == sizeof(float))
        return m.f32(c, k);
      else
        return m.f64(c, k);
    };
  };
  // Each labelled with the registry's origin (Method::origin).
  for (const Method& m : normalized_methods) {
    r.cosine_kappa(fmt::format("normalized/{}", m.id), m.origin, kUnit, call(m));
    r.approximation();
  }
  for (const Method& m : hemispherical_methods) {
    r.cosine_kappa(fmt::format("hemispherical/{}", m.id), m.origin, kTwoPi, call(m));
    r.approximation();
  }
  for (const Method& m : irradiance_methods) {
    r.cosine_kappa(fmt::format("irradiance/{}", m.id), m.origin, kPi, call(m));
    r.approximation();
  }
  return std::move(r.rows);
}

std::string kappa_span(const FailureStats& f) {
  std::string s;
  if (!std::isnan(f.kappa_min)) {
    s = f.kappa_min == f.kappa_max ? fmt::format("κ = {:g}", f.kappa_min)
                                    : fmt::format("κ in [{:g}, {:g}]", f.kappa_min, f.kappa_max);
  }
  if (f.at_nan_kappa) s += s.empty() ? "κ = nan" : ", κ = nan";
  return s;
}

std::string findings(const StabilityRow& row) {
  std::string s;
  for (std::size_t i = 0; i < kFailureKinds; ++i) {
    const FailureStats& f = row.failures[i];
    if (f.count == 0) continue;
    if (!s.empty()) s += "; ";
    const auto kind = static_cast<FailureKind>(i);
    s += fmt::format("{} {}/{} ({}){}", to_string(kind), f.count, row.evaluations, kappa_span(f),
                     row.is_failure(kind) ? "" : " [not a failure]");
  }
  return s.empty() ? "none" : s;
}

// The first input of the most important kind found: failures first.
std::string first_failure(const StabilityRow& row) {
  for (std::size_t i = 0; i < kFailureKinds; ++i)
    if (row.failures[i].count && row.is_failure(static_cast<FailureKind>(i))) return row.failures[i].example;
  for (const FailureStats& f : row.failures)
    if (f.count) return f.example;
  return {};
}

// Why a row has outcomes: invalid inputs, outcomes that are not failures,
// and for published formulas on valid inputs why they are reported and not
// patched (sglab transcribes published methods as written; it fixes only
// transcription-level numerical defects that leave the function unchanged:
// wang2009's 0/0 and cancelling exponent, Hill's 0/0 at c = 0, and Meder's s,
// which is evaluated as the normalized logistic of [Meder2018]).
std::string why(const StabilityRow& row) {
  if (!row.valid_inputs) return "invalid input (outside finite κ ≥ 0, c in [-1, 1], unit axes, finite x)";
  if (row.failure_count() == 0) return "not a failure (overflow of an exact result beyond the largest finite value, "
                                       "or an approximation exceeding the exact range by its error)";
  const std::string_view f = row.function;
  const auto is = [&](std::string_view id) { return f == id || f.ends_with("/" + std::string(id)); };
  if (row.origin == Origin::sglab) return "sglab primitive or model failing on valid input: a bug";
  if (row.origin == Origin::refit) return "sglab refit of a published formula failing on valid input: a bug";
  if (f == "sphere_integral_approx" || is("punctual"))
    return "published approximation 2π/κ [Pettineo2016]: infinite at κ = 0 (and NaN where 0·inf) by construction";
  if (f == "sg_inner_product_iwasaki" || is("vsgl2015") || is("vsgl2015_refit"))
    return "published approximate product integral [Iwasaki2012]: 2π/(κ1 + κ2) is infinite at κ1 = κ2 = 0; "
           "transcribed as published (κ1κ2/(κ1 + κ2) formed without overflow)";
  if (f == "steepness_meder2018" || is("meder2018"))
    return "published t(κ) = √κ(a2κ² + a1κ)/(κ² + b1κ + b0) forms κ² (inf/inf for κ ≳ 1.8e19 in float, 1.3e154 in "
           "double); the published cosine fit a·G(λm) − b makes Ê a difference that goes negative; both kept as published";
  if (is("hill") || is("hill_exact"))
    return "Hill's published curve [Pettineo2016] is fitted for larger κ: 1/κ is infinite at κ = 0 and the curve goes "
           "negative below κ ≈ 0.5 (its c = 0 limit at large κ is fixed)";
  if (f.starts_with("erf/")) return "published erf approximation";
  return "published formula, transcribed as written";
}

bool any_outcome(const StabilityRow& row) {
  for (const FailureStats& f : row.failures)
    if (f.count) return true;
  return false;
}

}  // namespace

StabilityReport stability() {
  StabilityReport report;
  auto f = run_all<float>(report.kappas_float, report.cosines_float);
  auto d = run_all<double>(report.kappas_double, report.cosines_double);
  // Interleave: per function, float (valid, invalid) then double (valid, invalid).
  for (std::size_t i = 0; i + 1 < f.size() && i + 1 < d.size(); i += 2) {
    report.rows.push_back(std::move(f[i]));
    report.rows.push_back(std::move(f[i + 1]));
    report.rows.push_back(std::move(d[i]));
    report.rows.push_back(std::move(d[i + 1]));
  }
  return report;
}

std::vector<const StabilityRow*> own_failures_on_valid_inputs(const StabilityReport& report) {
  std::vector<const StabilityRow*> out;
  for (const StabilityRow& r : report.rows)
    if (r.origin != Origin::published && r.valid_inputs && r.failure_count() > 0) out.push_back(&r);
  return out;
}

Table stability_table(const StabilityReport& report) {
  std::vector<Column> cols = {{"function"}, {"origin"}, {"precision"}, {"inputs"}, {"evaluations"}};
  for (std::size_t i = 0; i < kFailureKinds; ++i) {
    const std::string k(to_string(static_cast<FailureKind>(i)));
    cols.push_back({k});
    cols.push_back({k + "_kappa_min", 3});
    cols.push_back({k + "_kappa_max", 3});
  }
  cols.push_back({"range"});
  cols.push_back({"approximation"});
  cols.push_back({"findings"});
  cols.push_back({"first_failure"});
  Table t("Stability: NaN / Inf / negative / out-of-range outputs over special inputs "
          "(valid inputs: finite κ ≥ 0, c in [-1, 1], unit axes, finite x)",
          std::move(cols));
  for (const StabilityRow& r : report.rows) {
    std::vector<Cell> row = {Table::text(r.function), Table::text(to_string(r.origin)),
                             Table::text(to_string(r.precision)), Table::text(r.valid_inputs ? "valid" : "invalid"),
                             Table::count(r.evaluations)};
    for (std::size_t i = 0; i < kFailureKinds; ++i) {
      const FailureStats& f = r.failures[i];
      const bool applies = i != static_cast<std::size_t>(FailureKind::negative) || r.sign_checked;
      row.push_back(applies ? Table::count(f.count) : Cell{});
      row.push_back(f.count && !std::isnan(f.kappa_min) ? Table::real(f.kappa_min) : Cell{});
      row.push_back(f.count && !std::isnan(f.kappa_max) ? Table::real(f.kappa_max) : Cell{});
    }
    row.push_back(Table::text(r.range));
    row.push_back(Cell{r.approximation});
    row.push_back(Table::text(findings(r)));
    row.push_back(Table::text(first_failure(r)));
    t.add_row(std::move(row));
  }
  return t;
}

Table stability_findings_table(const StabilityReport& report) {
  Table t("Stability findings (rows with any NaN / Inf / overflow / negative / out-of-range / inaccurate output)",
          {{"function"}, {"origin"}, {"precision"}, {"inputs"}, {"findings"}, {"first_failure"}, {"why"}});
  for (const StabilityRow& r : report.rows) {
    if (!any_outcome(r)) continue;
    t.add_row({Table::text(r.function), Table::text(to_string(r.origin)), Table::text(to_string(r.precision)),
               Table::text(r.valid_inputs ? "valid" : "invalid"), Table::text(findings(r)),
               Table::text(first_failure(r)), Table::text(why(r))});
  }
  return t;
}

namespace {

// What half does at one κ of the grid: "" (survived), or the first of nan, inf,
// negative, off (beyond the tolerance) over the cosines; and the largest
// finite |E_half − E_float|/E(1, κ).
struct HalfAtKappa {
  std::string failure;
  double diff = 0;
};
HalfAtKappa half_at_kappa(const SweepResult& r, const SweepEntry& f, const SweepEntry& h, std::size_t k,
                          double tolerance) {
  HalfAtKappa out;
  const double peak = r.peak_value(f.quantity, k);
  for (std::size_t j = 0; j < r.cosines.size(); ++j) {
    const double x = h.values[r.index(k, j)], y = f.values[r.index(k, j)];
    const double d = std::abs(x - y) / peak;
    std::string why = std::isnan(x) ? "nan" : std::isinf(x) ? "inf" : x < 0 ? "negative" : !(d <= tolerance) ? "off" : "";
    if (std::isfinite(d)) out.diff = std::max(out.diff, d);
    if (out.failure.empty()) out.failure = std::move(why);
  }
  return out;
}

}  // namespace

Table half_ranges_table(const SweepResult& r, double tolerance) {
  Table t(fmt::format("Half precision: κ range each method's half export survives on the device (every cosine finite, "
                      "non-negative and within {:g} of its float export, relative to E(1, κ))",
                      tolerance),
          {{"method"}, {"survives_kappa_lo", 4}, {"survives_kappa_hi", 4}, {"fails_below_kappa", 4}, {"below"},
           {"fails_above_kappa", 4}, {"above"}, {"max_diff_in_range", 3}, {"max_diff_grid", 3}});
  for (const SweepEntry& h : r.entries) {
    if (h.precision != FloatFormat::vulkan_half) continue;
    const SweepEntry* f = r.find(h.method, h.quantity, FloatFormat::vulkan);
    if (!f || f->values.size() != h.values.size()) continue;
    std::vector<HalfAtKappa> at;
    for (std::size_t k = 0; k < r.kappas.size(); ++k) at.push_back(half_at_kappa(r, *f, h, k, tolerance));
    // The largest run of survived κ (the first, on ties).
    std::size_t best_lo = 0, best_len = 0;
    for (std::size_t k = 0; k < at.size();) {
      std::size_t e = k;
      while (e < at.size() && at[e].failure.empty()) ++e;
      if (e - k > best_len) best_lo = k, best_len = e - k;
      k = e == k ? k + 1 : e;
    }
    double in_range = 0, grid = 0;
    for (std::size_t k = 0; k < at.size(); ++k) {
      grid = std::max(grid, at[k].diff);
      if (k >= best_lo && k < best_lo + best_len) in_range = std::max(in_range, at[k].diff);
    }
    const bool any = best_len > 0, below = any && best_lo > 0, above = any && best_lo + best_len < at.size();
    t.add_row({Table::text(h.method), Table::real(any ? r.kappas[best_lo] : kNaN),
               Table::real(any ? r.kappas[best_lo + best_len - 1] : kNaN),
               Table::real(below ? r.kappas[best_lo - 1] : kNaN), Table::text(below ? at[best_lo - 1].failure : "-"),
               Table::real(above ? r.kappas[best_lo + best_len] : kNaN),
               Table::text(above ? at[best_lo + best_len].failure : "-"), Table::real(any ? in_range : kNaN),
               Table::real(grid)});
  }
  return t;
}

}  // namespace sglab::validate
