// reference/reference_detail.hpp — the quadrature behind the reference engine
// (reference/reference.hpp), written once as a template over the real type
// `Real` it runs in: double for Quadrature::standard (reference.cpp), 50-digit
// boost::multiprecision::cpp_bin_float for Quadrature::high
// (reference_high.cpp). Internal to reference/; include reference.hpp instead.
//
// Everything here follows docs/quantities.md and deliberately uses nothing from the
// runtime headers (include/sglab/): this is the independent truth.
//
// The 1-D forms (docs/quantities.md), u = ω·n, r = √(1−c²), ρ = √(1−u²):
//   H = 2π ∫₀¹ e^{κ(cu−1)} I0(κrρ) du,   E = 2π ∫₀¹ u e^{κ(cu−1)} I0(κrρ) du.
// With the scaled Bessel function I0e(x) = I0(x)e^{−x} the integrand is
//   e^{κ(cu + rρ − 1)} I0e(κrρ),
// and with u = cos θ, ρ = sin θ, c = cos θc, r = sin θc (du = −ρ dθ) it is
//   H = 2π ∫₀^{π/2} e^{κ(cos(θ−θc) − 1)} I0e(κ r sin θ) sin θ dθ,
// because cu + rρ = cos(θ − θc). We integrate in this angle, measured from
// the peak of the exponent, rather than in u: the integrand is then a
// Gaussian-like bump of width 1/√κ in every case (in u the width collapses to
// ~1/κ as c → 1, next to the square-root behaviour of ρ at u = 1), and the
// exponents of docs/quantities.md become exact trigonometric identities:
//   c ≥ 0, offset t = θ − θc:   cu + rρ − 1 = cos t − 1 = −2 sin²(t/2)
//         (the same quantity as −½((u−c)² + (ρ−r)²)),
//   c < 0, ψ = π/2 − θ (so u = sin ψ, ρ = cos ψ), β = asin|c|, m = r = cos β:
//         cu + rρ − r = cos(ψ + β) − cos β = −2 sin(ψ/2 + β) sin(ψ/2)
//         (the same quantity as cu − r u²/(1+ρ)),
//   peak factor e^{κ(r − 1)} with r − 1 = −c²/(1 + r).
// Every factor is computed without cancellation; θc, α = π/2 − θc and β come
// from atan2 of (r, c) so each is accurate relative to itself.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/policies/policy.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/bessel.hpp>
#include <boost/math/special_functions/expm1.hpp>

#include "reference/reference.hpp"

namespace sglab::reference::detail {

// ---------------------------------------------------------------------------
// Per-type settings.

// The type the peak factor e^{κ(m−1)} is formed in. Its exponent reaches −745
// where H is still a (denormal) double, and a relative error ε in it would be
// an absolute error 745ε ≈ 1.7e−13 in log H — above the 1e−13 budget. So the
// double engine forms it in long double (ε = 5.4e−20); wider types use
// themselves.
template <class Real>
struct Wide {
  using type = Real;
};
template <>
struct Wide<double> {
  using type = long double;
};

template <class Real>
struct Settings {
  // Gauss–Kronrod order, and the relative tolerance on the summed
  // |Kronrod − Gauss| estimate. That estimate is pessimistic for these
  // smooth integrands (the Kronrod value is far better than it): in double
  // the measured error is ~1e−15 (see tests/test_reference.cpp). The high
  // mode aims at ~1e−30, far below what it has to check.
  static constexpr bool is_double = std::is_same_v<Real, double>;
  static constexpr unsigned order = is_double ? 31 : 61;
  static Real tolerance() { return is_double ? Real(1e-14) : Real(1e-30); }
};

// ---------------------------------------------------------------------------
// Scaled modified Bessel function I0(x)·e^{−x}, x ≥ 0.
//
// boost::math::cyl_bessel_i(0, x) overflows double for x > ~713, and the
// reference needs x = κrρ up to 1e6. From x = x_asym on we use the Hankel
// asymptotic series (Abramowitz & Stegun 9.7.1)
//   I0(x)e^{−x} = (2πx)^{−1/2} Σ_k a_k x^{−k},  a_k = a_{k−1}(2k−1)²/(8k),
// all terms positive, summed until they no longer change the sum. Its
// smallest term is ~e^{−2x}, so x_asym = max(50, 0.6·ln(1/ε)) keeps that
// below ε (e^{−100} in double; about e^{−139} for 50 digits).
// Below x_asym: in double, Boost's I0 (a minimax rational approximation,
// ~1 ulp) times e^{−x}; in the high-precision type, the power series
// Σ (x²/4)^k/(k!)² (all terms positive) times e^{−x}, which is faster there
// than Boost's generic-precision Bessel code and independent of it.
template <class Real>
Real scaled_bessel_i0(const Real& x) {
  using std::exp;
  using std::log;
  using std::sqrt;
  const Real eps = std::numeric_limits<Real>::epsilon();
  static const Real x_asym = std::max(Real(50), Real(-0.6 * log(eps)));
  if (x < x_asym) {
    if constexpr (std::is_same_v<Real, double>) {
      // Do not promote double to long double inside Boost: the 53-bit
      // approximation is accurate to ~1 ulp and much faster.
      using Pol = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
      return boost::math::cyl_bessel_i(0, x, Pol()) * exp(-x);
    } else {
      const Real q = x * x / 4;
      Real term = 1, sum = 1;
      for (int k = 1; k < 1000; ++k) {
        term *= q / Real(k * k);
        sum += term;
        if (term < eps * sum / 8) break;
      }
      return sum * exp(-x);
    }
  }
  Real term = 1, sum = 1;
  for (int k = 1; k < 1000; ++k) {
    term *= Real((2 * k - 1) * (2 * k - 1)) / (Real(8 * k) * x);
    sum += term;
    if (term < eps * sum / 8) break;
  }
  // √(2π)·√x rather than √(2πx): 2πx overflows for x > max/2π (κ near the
  // largest finite double), the product of the roots does not.
  return sum / (sqrt(2 * boost::math::constants::pi<Real>()) * sqrt(x));
}

// I0(x) − 1 = Σ_{k≥1} (x²/4)^k / (k!)², without cancellation (used for x ≤ 1).
template <class Real>
Real bessel_i0_minus_one(const Real& x) {
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real q = x * x / 4;
  Real term = q, sum = q;
  for (int k = 2; k < 200 && term > eps * sum / 8; ++k) {
    term *= q / Real(k * k);
    sum += term;
  }
  return sum;
}

// ---------------------------------------------------------------------------
// H and E are integrated together, on the same nodes, as a pair handed to
// Boost's Gauss–Kronrod (which accepts any value type with +, −, scaling by
// Real and an abs()). The E component is pre-multiplied by `gamma` ≈ H/E so
// that abs() = max(|h|, |γe|) weighs both relative errors alike.
template <class Real>
struct Pair {
  Real h{0}, e{0};
  Pair() = default;
  Pair(const Real& a, const Real& b) : h(a), e(b) {}
  template <class T, std::enable_if_t<std::is_arithmetic_v<T> || std::is_same_v<T, Real>, int> = 0>
  Pair(const T& v) : h(v), e(v) {}  // K(0) and static_cast<K>(Real) in Boost
  Pair& operator+=(const Pair& o) {
    h += o.h;
    e += o.e;
    return *this;
  }
  friend Pair operator+(Pair a, const Pair& b) { return a += b; }
  friend Pair operator-(const Pair& a, const Pair& b) { return {a.h - b.h, a.e - b.e}; }
  friend Pair operator-(const Pair& a) { return {-a.h, -a.e}; }
  friend Pair operator*(const Pair& a, const Real& s) { return {a.h * s, a.e * s}; }
  friend Pair operator*(const Real& s, const Pair& a) { return {a.h * s, a.e * s}; }
  friend Real abs(const Pair& a) {
    using std::abs;
    return std::max(Real(abs(a.h)), Real(abs(a.e)));
  }
};

// ---------------------------------------------------------------------------
// Globally adaptive Gauss–Kronrod over a list of segments (QUADPACK QAG
// style): every segment is integrated with Boost's Kronrod rule, and the
// segment with the largest error estimate is bisected until the summed
// estimate is ≤ tolerance·|total| (or `max_bisections` is reached).
//
// Boost 1.74's adaptive gauss_kronrod::integrate does not multiply the
// |Kronrod − Gauss| estimate of a subinterval by its half-width (the value
// and the L1 norm are), so on an interval of width w its estimate is w/2
// times too large and narrow peaks are refined to the maximum depth. Each
// segment is therefore mapped to [−1, 1] here and Boost is called with
// max_depth = 0 (one Kronrod rule, for which its estimate is right).
template <class Real, class K>
struct Segment {
  Real a, b;
  int side;  // which integrand (see `compute`)
  K value;
  Real error;
};

template <class Real, class K, class F>
Segment<Real, K> kronrod_segment(const F& f, int side, const Real& a, const Real& b) {
  using boost::math::quadrature::gauss_kronrod;
  const Real mid = (a + b) / 2, half = (b - a) / 2;
  auto g = [&](const Real& x) -> K { return f(side, mid + half * x); };
  Real error = 0;
  const K value = gauss_kronrod<Real, Settings<Real>::order>::integrate(g, Real(-1), Real(1), 0,
                                                                        Real(0), &error);
  return {a, b, side, value * half, error * half};
}

template <class Real, class K>
class AdaptiveQuadrature {
 public:
  // Integrand f(side, s); segments are added with `add` before `run`.
  template <class F>
  void add(const F& f, int side, const Real& a, const Real& b) {
    if (b > a) segments_.push_back(kronrod_segment<Real, K>(f, side, a, b));
  }
  // Splits [0, L] geometrically at w, 2w, 4w, ... (an integrand peaked at 0
  // that decays on the scale w), so that each segment sees a function that is
  // smooth on its own length.
  template <class F>
  void add_from_peak(const F& f, int side, const Real& L, const Real& w) {
    Real a = 0, b = w > 0 ? std::min(w, L) : L;
    while (a < L) {
      add(f, side, a, b);
      a = b;
      b = std::min(Real(2 * b), L);
    }
  }
  template <class F>
  void run(const F& f, const Real& tolerance, int max_bisections = 400) {
    using std::abs;
    for (int i = 0; i < max_bisections; ++i) {
      K total = 0;
      Real error = 0;
      std::size_t worst = 0;
      for (std::size_t j = 0; j < segments_.size(); ++j) {
        total += segments_[j].value;
        error += segments_[j].error;
        if (segments_[j].error > segments_[worst].error) worst = j;
      }
      if (segments_.empty() || !(error > tolerance * Real(abs(total)))) return;
      const Segment<Real, K> s = segments_[worst];
      const Real mid = (s.a + s.b) / 2;
      segments_[worst] = kronrod_segment<Real, K>(f, s.side, s.a, mid);
      segments_.push_back(kronrod_segment<Real, K>(f, s.side, mid, s.b));
    }
  }
  K value() const {
    K total = 0;
    for (const auto& s : segments_) total += s.value;
    return total;
  }
  Real error() const {
    Real e = 0;
    for (const auto& s : segments_) e += s.error;
    return e;
  }
  std::size_t size() const { return segments_.size(); }

 private:
  std::vector<Segment<Real, K>> segments_;
};

// What the template computes. Values are in the wide type W (long double for
// the double engine) so that a denormal result is rounded to double once.
template <class Real>
struct RawPoint {
  using W = typename Wide<Real>::type;
  W hemispherical = 0, irradiance = 0, normalized = 0;
  W hemispherical_error = 0, irradiance_error = 0;
  std::size_t segments = 0;  // Kronrod segments used (a diagnostic)
};

// H(−1, κ) and H(1,κ) − H(−1,κ) for κ > 0 (closed forms of docs/quantities.md), with
// 1 − e^{−κ} = −expm1(−κ) so that nothing cancels:
//   H(1) = 2π(1−e^{−κ})/κ, H(−1) = e^{−κ}H(1), H(1) − H(−1) = 2π(1−e^{−κ})²/κ.
// Used only to normalise s; H and E themselves always come from quadrature.
template <class W>
W hemispherical_at_minus_one(const W& kappa) {
  using std::exp;
  return 2 * boost::math::constants::pi<W>() * exp(-kappa) * (-boost::math::expm1(-kappa)) / kappa;
}
template <class W>
W hemispherical_span(const W& kappa) {
  const W m = boost::math::expm1(-kappa);
  return 2 * boost::math::constants::pi<W>() * (m / kappa) * m;
}

// The integrand of (H(c) − H(−1))/2π in u = ω·n, without cancellation.
// With δ = 1 + c ≥ 0 (so cu = −u + δu) and x = κrρ:
//   e^{κ(cu−1)} I0(x) − e^{−κ(1+u)} = e^{−κ(1+u)} [expm1(κδu)·I0(x) + (I0(x) − 1)],
// a sum of non-negative terms, each computed to relative ε: unlike the
// difference of the two integrands (or of H(c) and H(−1)), it stays accurate
// relative to itself as c → −1, where both vanish linearly in δ.
// Returned without the factor e^{−κ}; e^{x − κu} is formed as one exponential
// so that I0(x) cannot overflow.
template <class Real>
Real difference_integrand(const Real& kappa, const Real& delta, const Real& r, const Real& u,
                          const Real& rho) {
  using boost::math::expm1;
  using std::exp;
  const Real x = kappa * r * rho;
  const Real grow = expm1(kappa * delta * u);  // ≥ 0
  if (x <= 1) {
    const Real i0m1 = bessel_i0_minus_one(x);
    return exp(-kappa * u) * (grow * (1 + i0m1) + i0m1);
  }
  // I0(x) − 1 = I0e(x)e^x − 1 loses at most a factor I0(1)/(I0(1) − 1) < 4.
  const Real i0e = scaled_bessel_i0(x), ex = exp(x - kappa * u), e0 = exp(-kappa * u);
  return grow * ex * i0e + (ex * i0e - e0);
}

// s(c, κ) for 0 < κ ≤ 1, where H(c) − H(−1) cancels (both → 2π, the
// difference is O(κ), and O(δ) near c = −1). The difference is taken under
// the integral sign (difference_integrand), in u:
//   (H(c) − H(−1)) / 2π = e^{−κ} ∫₀¹ d(u) du,
// and with H(1) − H(−1) = 2πκ·(expm1(−κ)/κ)²:
//   s = e^{−κ} ∫₀¹ (d/κ) du / (expm1(−κ)/κ)².
// d/κ is analytic in u (I0 is even, so I0(κrρ) is a power series in 1 − u²)
// and accurate relative to itself for every c, so s is accurate relative to s.
template <class Real>
Real normalized_small_kappa(const Real& kappa, const Real& c, const Real& r) {
  using boost::math::expm1;
  using std::exp;
  using std::sqrt;
  const Real delta = 1 + c;
  auto d = [&](int, const Real& u) {
    const Real rho = sqrt(std::max(Real(0), (1 - u) * (1 + u)));
    return difference_integrand(kappa, delta, r, u, rho) / kappa;
  };
  AdaptiveQuadrature<Real, Real> quad;
  quad.add(d, 0, Real(0), Real(1));
  quad.run(d, Settings<Real>::tolerance());
  const Real q = expm1(-kappa) / kappa;
  return exp(-kappa) * quad.value() / (q * q);
}

// s(c, κ) for κ > 1 and c < 0 where H(c) < 2 H(−1), so that (H(c) − H(−1))
// would lose more than a bit: the same difference integrand, in the angle
// ψ = asin u above the horizon (u = sin ψ, du = cos ψ dψ), split
// geometrically from ψ = 0 on the scale 1/(κ + 1) of e^{−κu}:
//   (H(c) − H(−1)) / 2π = e^{−κ} ∫₀^{π/2} d(sin ψ) cos ψ dψ,
//   s = e^{−κ} κ ∫ … dψ / expm1(−κ)²   (formed in the wide type W).
template <class Real>
typename Wide<Real>::type normalized_by_difference(const Real& kappa, const Real& c,
                                                   const Real& r) {
  using W = typename Wide<Real>::type;
  using boost::math::expm1;
  using std::cos;
  using std::exp;
  using std::sin;
  const Real delta = 1 + c;
  auto d = [&](int, const Real& psi) {
    const Real rho = cos(psi), u = sin(psi);
    return difference_integrand(kappa, delta, r, u, rho) * rho;
  };
  AdaptiveQuadrature<Real, Real> quad;
  quad.add_from_peak(d, 0, Real(boost::math::constants::half_pi<Real>()), Real(1 / (kappa + 1)));
  quad.run(d, Settings<Real>::tolerance());
  const W kw = W(kappa), m = expm1(-kw);
  return exp(-kw) * kw * W(quad.value()) / (m * m);
}

// The integrand of H/(2π·peak factor) at one point as f(side, s), with s ≥ 0
// the angular offset from the peak, returned together with γ·u·f for E
// (compute() below). kscale: see compute().
template <class Real>
struct PointIntegrand {
  enum Side { toward_horizon = 0, toward_pole = 1, boundary_layer = 2 };
  Real kappa, r, kscale;
  Real gamma = 1;  // ≈ H/E, so that both components weigh alike in abs(Pair)
  Real theta_c = 0, alpha = 0, beta = 0;

  Pair<Real> operator()(int side, const Real& s) const {
    using std::cos;
    using std::exp;
    using std::sin;
    Real rho, u, exponent;
    if (side == boundary_layer) {
      // c < 0, ψ = s: u = sin ψ, ρ = cos ψ,
      // κ(cu + rρ − r) = −2κ sin(ψ/2 + β) sin(ψ/2).
      u = sin(s);
      rho = cos(s);
      exponent = -(kappa * sin(s / 2 + beta)) * (2 * sin(s / 2));  // no −2κ: it overflows
    } else {
      // c ≥ 0, t = ±s: κ(cu + rρ − 1) = −2κ sin²(t/2). θ = θc + t and
      // ψ = π/2 − θ = α − t are both formed from accurate parts, and ρ = sin θ,
      // u = sin ψ each from the one that is accurate where that factor is
      // small (ρ near the pole, u near the horizon).
      const Real t = side == toward_horizon ? s : Real(-s);
      rho = sin(std::max(Real(0), Real(theta_c + t)));
      u = sin(std::max(Real(0), Real(alpha - t)));
      const Real h = sin(s / 2);
      exponent = -(kappa * h) * (2 * h);
    }
    rho = std::min(rho, Real(1));
    u = std::min(u, Real(1));
    const Real value = exp(exponent) * scaled_bessel_i0(Real(kappa * r * rho)) * (rho * kscale);
    return Pair<Real>(value, gamma * u * value);
  }
};

// The segments of the quadrature, placed from the peak (filling γ and the
// angles of `f`), and log_peak = κ(m − 1), m = max over u of cu + rρ. T is the
// truncation exponent and gauss_cut the offset where the Gaussian reaches it
// (compute()). Returns false when the peak factor underflows: H = E = s = 0.
template <class Real>
bool place_segments(AdaptiveQuadrature<Real, Pair<Real>>& quad, PointIntegrand<Real>& f,
                    double kappa_in, double cosine_in, const Real& c, const Real& T,
                    const Real& gauss_cut, typename Wide<Real>::type& log_peak) {
  using W = typename Wide<Real>::type;
  using std::asin;
  using std::atan2;
  using std::min;
  using std::sqrt;
  using I = PointIntegrand<Real>;
  const Real pi = boost::math::constants::pi<Real>();
  const Real kappa = f.kappa, r = f.r;
  if (!(c < 0)) {
    // c ≥ 0: the peak is at θ = θc inside the hemisphere; m = 1, no factor.
    f.theta_c = atan2(r, c);  // angle of v from n
    f.alpha = atan2(c, r);    // π/2 − θc, angle of v above the horizon
    f.gamma = 1 / std::max(c, Real(Real(0.5) / (1 + sqrt(kappa))));
    const Real w = 1 / sqrt(kappa);  // Gaussian width in the angle
    quad.add_from_peak(f, I::toward_horizon, min(f.alpha, gauss_cut), w);
    quad.add_from_peak(f, I::toward_pole, min(f.theta_c, gauss_cut), w);
    return true;
  }
  // c < 0: the peak is on the horizon u = 0 with m = r; peak factor
  // e^{κ(r−1)}, r − 1 = −c²/(1+r), formed in the wide type.
  const W cw = cosine_in, kw = kappa_in;
  const W rw = sqrt((1 - cw) * (1 + cw));
  log_peak = -kw * (cw * cw) / (1 + rw);
  // Below e^{−750}, even 2π·(π/2)·peak rounds to 0 in double: H = E = 0 and
  // s = 0 (s ≤ H/(H(1)−H(−1)) < e^{−740}); skip the quadrature.
  if (log_peak < W(-750)) return false;
  f.beta = atan2(-c, r);  // θc − π/2 = asin|c|
  // (Any finite weight will do: capped where 2κ|c| would overflow; there
  // the peak factor is 0 anyway.)
  f.gamma = std::min(Real(2 * (1 + kappa * -c + sqrt(kappa))), std::numeric_limits<Real>::max());
  // Exponent ≈ −κ(ψ|c| + ψ²r/2): boundary layer of width 1/(κ|c|) or 1/√(κr).
  const Real w = 1 / (kappa * -c + sqrt(kappa * r));
  // −2κ sin(ψ/2+β) sin(ψ/2) decreases in ψ and is ≤ −2κ·max(sin β,
  // sin(ψ/2))·sin(ψ/2): cut where either bound reaches −T.
  Real cut = min(Real(pi / 2), gauss_cut);
  if (T / 2 / kappa / -c < 1) cut = min(cut, Real(2 * asin(T / 2 / kappa / -c)));
  quad.add_from_peak(f, I::boundary_layer, cut, w);
  return true;
}

// s = (H − H(−1)) / (H(1) − H(−1)), docs/quantities.md, from H at the point.
template <class Real>
typename Wide<Real>::type normalized_from(double kappa_in, double cosine_in, const Real& kappa,
                                          const Real& c, const Real& r,
                                          const typename Wide<Real>::type& hemispherical) {
  using W = typename Wide<Real>::type;
  W normalized;
  if (kappa < std::numeric_limits<Real>::epsilon() * std::numeric_limits<Real>::epsilon()) {
    // s = (1+c)/2 + O(κ): exact to far below ε, and no denormal κ below.
    normalized = (1 + W(cosine_in)) / 2;
  } else if (kappa <= 1) {
    normalized = W(normalized_small_kappa(kappa, c, r));
  } else {
    // κ > 1: the denominator H(1) − H(−1) ≥ 0.63·H(1) does not cancel. The
    // numerator H(c) − H(−1) loses at most a bit while H(c) ≥ 2H(−1); below
    // that (c < 0, towards c = −1) it is integrated as one non-negative
    // difference instead, so that s stays accurate relative to itself.
    const W kw = kappa_in;
    const W h_minus = hemispherical_at_minus_one(kw);
    if (c < 0 && hemispherical < 2 * h_minus)
      normalized = normalized_by_difference(kappa, c, r);
    else
      normalized = (hemispherical - h_minus) / hemispherical_span(kw);
  }
  return std::clamp(normalized, W(0), W(1));
}

// H, E, s at one point, docs/quantities.md. Requires finite κ ≥ 0 and c ∈ [−1, 1]
// (checked by the caller). Never NaN: where H underflows double the result is
// 0 or a denormal.
template <class Real>
RawPoint<Real> compute(double kappa_in, double cosine_in) {
  using W = typename Wide<Real>::type;
  using std::asin;
  using std::exp;
  using std::log;
  using std::sqrt;
  const Real pi = boost::math::constants::pi<Real>();
  const Real kappa = kappa_in, c = cosine_in;
  RawPoint<Real> out;

  // κ = 0: G ≡ 1, so H = 2π, E = π and s = (1 + c)/2 (the limits of docs/quantities.md), exactly.
  if (kappa == 0) {
    out.hemispherical = 2 * boost::math::constants::pi<W>();
    out.irradiance = boost::math::constants::pi<W>();
    out.normalized = (1 + W(cosine_in)) / 2;
    return out;
  }

  const Real r = sqrt((1 - c) * (1 + c));  // no cancellation near |c| = 1
  // Truncation: where the exponent (relative to the peak) is below −T the
  // integrand is < e^{−T} (I0e ≤ 1, ρ ≤ 1), so the neglected mass is
  // < e^{−T}·π/2, while the integral is ≳ κ^{−3/2}/(1+κ|c|) wherever it
  // matters; T = ln(1/ε) + 2 ln(1+κ) + 10 leaves that far below ε relative.
  const Real T = -log(std::numeric_limits<Real>::epsilon()) + 2 * log(1 + kappa) + 10;
  // Offset s where −2κ sin²(s/2) reaches −T (π if it never does).
  // (T/2/κ, not T/(2κ): 2κ overflows for κ > max/2.)
  const Real gauss_cut = (T / 2 / kappa < 1) ? Real(2 * asin(sqrt(T / 2 / kappa))) : pi;
  // The integrals below are ~1/κ: for large κ they would reach the denormals
  // (κ > 4.5e307 in double). The integrand is multiplied by kscale = 2^e ≤ κ
  // (exactly, a power of two, so nothing else changes) and the result divided
  // by it in the wide type.
  int kexp = 0;
  std::frexp(kappa_in, &kexp);
  const double kscale_d = kappa_in > 1 ? std::ldexp(1.0, kexp - 1) : 1.0;

  PointIntegrand<Real> f{kappa, r, Real(kscale_d)};
  W log_peak = 0;
  AdaptiveQuadrature<Real, Pair<Real>> quad;
  if (!place_segments(quad, f, kappa_in, cosine_in, c, T, gauss_cut, log_peak)) return out;
  quad.run(f, Settings<Real>::tolerance());
  const Pair<Real> q = quad.value();
  const Real q_error = quad.error();
  out.segments = quad.size();

  // H = 2π·e^{log_peak}·q.h, E = 2π·e^{log_peak}·q.e/γ. The combined error
  // estimate bounds |Δh| and γ|Δe| alike.
  const W scale = 2 * boost::math::constants::pi<W>() * exp(log_peak);
  // (Divided by kscale, see above.)
  const W kscale_w = W(kscale_d);
  out.hemispherical = scale * W(q.h) / kscale_w;
  out.irradiance = scale * W(q.e / f.gamma) / kscale_w;
  out.hemispherical_error = scale * W(q_error) / kscale_w;
  out.irradiance_error = scale * W(q_error / f.gamma) / kscale_w;
  out.normalized = normalized_from(kappa_in, cosine_in, kappa, c, r, out.hemispherical);
  return out;
}

// RawPoint → ReferencePoint (rounding to double once). Both integrands are
// nonnegative at every node (exponentials, I0e ≥ 0, ρ ≥ 0, u ≥ 0), so the L1
// norm the quadrature would report equals its value: condition number 1.
template <class Real>
ReferencePoint to_reference_point(double kappa, double cosine, const RawPoint<Real>& raw) {
  ReferencePoint p;
  p.kappa = kappa;
  p.cosine = cosine;
  p.hemispherical = static_cast<double>(raw.hemispherical);
  p.irradiance = static_cast<double>(raw.irradiance);
  p.normalized = static_cast<double>(raw.normalized);
  p.hemispherical_error = static_cast<double>(raw.hemispherical_error);
  p.irradiance_error = static_cast<double>(raw.irradiance_error);
  p.hemispherical_l1 = p.hemispherical;
  p.irradiance_l1 = p.irradiance;
  return p;
}

// The two instantiations (reference.cpp and reference_high.cpp).
ReferencePoint compute_standard(double kappa, double cosine);  // Real = double
ReferencePoint compute_high(double kappa, double cosine);      // Real = 50-digit cpp_bin_float

}  // namespace sglab::reference::detail
