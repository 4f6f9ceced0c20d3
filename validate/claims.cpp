#include "validate/claims.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/minima.hpp>

#include <sglab/constants.hpp>
#include <sglab/erf.hpp>
#include <sglab/hemispherical.hpp>
#include <sglab/registry.hpp>
#include <sglab/sg.hpp>

#include "reference/reference.hpp"

namespace sglab::validate {

namespace {

const char* verdict(bool holds) { return holds ? "holds" : "does not hold"; }
// "holds", else "holds in part" when the weaker reading `in_part` holds.
const char* verdict(bool holds, bool in_part) {
  return holds ? "holds" : in_part ? "holds in part" : "does not hold";
}

// ∫_a^b f of a smooth f: adaptive 31-point Gauss-Kronrod (Boost.Math).
template <class F>
double integrate(F f, double a, double b) {
  return boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, a, b);
}

// The minimum of a unimodal f on [a, b]: Brent's method (Boost.Math), to
// its best resolution (√ε of double relative).
template <class F>
double minimum_point(F f, double a, double b) {
  return boost::math::tools::brent_find_minima(f, a, b, std::numeric_limits<double>::digits).first;
}

double gauss(double x, double mu, double lambda) {
  return std::exp(-(x - mu) * (x - mu) / (lambda * lambda));
}
double circ_gauss(double phi, double mu, double lambda) {
  return std::exp(2.0 * (std::cos(phi - mu) - 1.0) / (lambda * lambda));
}

// ---- [Xu2011] and [AS1964] --------------------------------------------------

Claim claim_as7125() {
  const double err = as7125_max_abs_error();
  return {"as7125_bound",
          "A&S 7.1.25 erf approximation (p = 0.47047, a1..a3) has |error| <= 2.5e-5",
          "[AS1964] 7.1.25, quoted in [Xu2011] supplemental §3",
          "max |erf_as7125(x) - erf(x)| in double over 2,000,001 evenly spaced x in [0, 6] (odd "
          "function; erf_as = 1 beyond)",
          fmt::format("max |error| = {:.4g}", err),
          verdict(err <= 2.5e-5)};
}

std::vector<Claim> claims_circular() {
  std::vector<Claim> out;
  // Pointwise: gc(φ; 0, λ) vs g(φ; 0, λ) for λ ∈ [0.01, π/6], φ ∈ [−π, π].
  double max_abs = 0, max_abs_lambda = 0, max_rel_sig = 0, max_rel_sig_lambda = 0;
  double max_rel_all = 0;
  double max_int = 0, max_int_lambda = 0;
  const int n_lambda = 200;
  for (int i = 0; i < n_lambda; ++i) {
    const double lambda = 0.01 + (std::numbers::pi / 6 - 0.01) * i / (n_lambda - 1);
    const int n_phi = 20001;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = -std::numbers::pi + 2 * std::numbers::pi * j / (n_phi - 1);
      const double gc = circ_gauss(phi, 0, lambda), g = gauss(phi, 0, lambda);
      const double a = std::abs(gc - g);
      if (a > max_abs) max_abs = a, max_abs_lambda = lambda;
      if (gc >= 1e-2) {
        const double r = std::abs(g / gc - 1);
        if (r > max_rel_sig) max_rel_sig = r, max_rel_sig_lambda = lambda;
      }
      if (gc > 0 && g > 0) max_rel_all = std::max(max_rel_all, std::abs(g / gc - 1));
    }
    // Integral over [−π, π]: trapezoid on the periodic integrand (spectrally accurate).
    const int n_int = 40000;
    double sum = 0;
    for (int j = 0; j < n_int; ++j)
      sum += circ_gauss(-std::numbers::pi + 2 * std::numbers::pi * j / n_int, 0, lambda);
    const double exact = sum * 2 * std::numbers::pi / n_int;
    const double approx =
        std::sqrt(std::numbers::pi) * lambda * std::erf(std::numbers::pi / lambda);
    const double r = std::abs(approx / exact - 1);
    if (r > max_int) max_int = r, max_int_lambda = lambda;
  }
  out.push_back(
      {"circular_gaussian_pointwise",
       "circular Gaussian gc(φ;μ,λ) = exp(2(cos(φ-μ)-1)/λ²) ≈ Gaussian exp(-(φ-μ)²/λ²) with "
       "relative error < 1.3% for φ in [-π, π], λ < π/6",
       "[Xu2011] supplemental §1 (definitions §2, §5)",
       "2nd-order Taylor cos x - 1 ≈ -x²/2; 200 λ in [0.01, π/6] × 20,001 φ in [-π, π]; error "
       "relative to the peak (= 1): max |gc - g|; also |g/gc - 1| where gc >= 1e-2 and everywhere",
       fmt::format("max |gc - g| (peak-relative) = {:.3g} (at λ = {:.3f}); |g/gc - 1| where gc >= "
                   "1e-2: {:.3g} (λ = {:.3f}); pointwise relative over all φ: {:.3g}",
                   max_abs, max_abs_lambda, max_rel_sig, max_rel_sig_lambda, max_rel_all),
       max_abs < 0.013 ? (max_rel_sig < 0.013 ? "holds" : "holds in part") : "does not hold"});
  out.back().measured += max_abs < 0.013 && max_rel_sig >= 0.013
                             ? " — holds as an error relative to the peak, not as a pointwise "
                               "relative error in the tails"
                             : "";
  out.push_back(
      {"circular_gaussian_integral",
       "integral of a circular Gaussian over [-π, π] ≈ the Gaussian's integral, relative error < "
       "1.9% for λ < π/6",
       "[Xu2011] supplemental §4",
       "exact ∫_{-π}^{π} gc dφ (= 2π e^{-a} I0(a), a = 2/λ², by periodic trapezoid, 40,000 nodes) "
       "vs √π·λ·erf(π/λ) (= √π·λ to 1e-16 for λ <= π/6); 200 λ in [0.01, π/6]",
       fmt::format("max relative error = {:.4g} (at λ = {:.4f})", max_int, max_int_lambda),
       verdict(max_int < 0.019)});

  const double e1 = gaussian_product_max_rel_error(20000, 12345u, false);
  out.push_back({"gaussian_product",
                 "product of two 1D Gaussians is a Gaussian: g1·g2 = b·g3(x; μ3, λ3)",
                 "[Xu2011] supplemental §2",
                 "closed form λ3² = λ1²λ2²/(λ1²+λ2²), μ3 = (μ1λ2² + μ2λ1²)/(λ1²+λ2²), b = "
                 "exp(-(μ1-μ2)²/(λ1²+λ2²)); 20,000 random (μi ∈ [-2,2], λi ∈ [0.1,2], x ∈ [-3,3])",
                 fmt::format("max |g1 g2 - b g3| / (g1 g2) = {:.3g}", e1), verdict(e1 < 1e-10)});
  const double e2 = gaussian_product_max_rel_error(20000, 54321u, true);
  out.push_back(
      {"circular_gaussian_product",
       "product of two circular Gaussians is a circular Gaussian: gc1·gc2 = b·gc3(φ; μ3, λ3)",
       "[Xu2011] supplemental §5",
       "with ai = 2/λi², A = |a1 e^{iμ1} + a2 e^{iμ2}|: μ3 = arg(a1 e^{iμ1} + a2 e^{iμ2}), λ3 = "
       "√(2/A), b = exp(A - a1 - a2); 20,000 random (μi ∈ [-π,π], λi ∈ [0.1,2], φ ∈ [-π,π])",
       fmt::format("max |gc1 gc2 - b gc3| / (gc1 gc2) = {:.3g}", e2), verdict(e2 < 1e-10)});
  return out;
}

// ---- [Tokuyoshi2015] --------------------------------------------------------

std::vector<Claim> claims_lambda_d() {
  // Least squares of max(u,0)/π − G(λ)/S(λ), over the sphere and over the upper hemisphere.
  auto objective = [](double lambda, bool sphere) {
    const double s = sphere_integral(lambda);
    auto sq = [&](double u) {
      const double d = std::max(u, 0.0) / std::numbers::pi - std::exp(lambda * (u - 1)) / s;
      return d * d;
    };
    double v = integrate(sq, 0.0, 1.0);
    if (sphere) v += integrate(sq, -1.0, 0.0);
    return 2 * std::numbers::pi * v;
  };
  const double ls_sphere = minimum_point([&](double l) { return objective(l, true); }, 0.5, 10);
  const double ls_hemi = minimum_point([&](double l) { return objective(l, false); }, 0.5, 10);
  const double c_sphere = constants::lambda_d_diffuse_lobe_sphere_ls.lambda_d;
  const double c_hemi = constants::lambda_d_diffuse_lobe_hemisphere_ls.lambda_d;
  const double obj2 = objective(2.0, true), objls = objective(ls_sphere, true);
  const bool near = std::abs(c_sphere - 2) / 2 < 0.05 && std::abs(c_hemi - 2) / 2 < 0.05;
  const bool rough = std::abs(c_sphere - 2) / 2 < 0.25 && std::abs(c_hemi - 2) / 2 < 0.25;
  std::vector<Claim> out;
  out.push_back(
      {"lambda_d_least_squares",
       "diffuse lobe max(cos,0)/π ≈ G(ω; n, λd)/A(λd) with λd ≈ 2 obtained by least squares",
       "[Tokuyoshi2015] supplemental Eq. 1",
       "least squares of max(u,0)/π - G(λd)/S(λd) (normalized lobe) over the sphere and over the "
       "upper hemisphere; refitted constants (data/constants) and an independent Gauss-Kronrod + "
       "Brent recomputation (Boost.Math); '≈ 2' read as within 5%",
       fmt::format("sphere LS λd = {:.4f} (recomputed {:.4f}), hemisphere LS λd = {:.4f} "
                   "(recomputed {:.4f}); sphere objective at λd = 2 is {:.3f}× its minimum",
                   c_sphere, ls_sphere, c_hemi, ls_hemi, obj2 / objls),
       verdict(near, rough)});
  const double a2 = sphere_integral(2.0);
  out.push_back({"lambda_d_A_pi", "A(λd) ≈ π for λd = 2 (Iwasaki et al.'s approximation)",
                 "[Tokuyoshi2015] supplemental §3.2 (after Eq. 7)",
                 "A(2) = S(2) = 2π(1 - e^{-4})/2 vs π",
                 fmt::format("A(2) = {:.6f}, π = {:.6f}, relative error {:.3g}", a2,
                             std::numbers::pi, a2 / std::numbers::pi - 1),
                 verdict(std::abs(a2 / std::numbers::pi - 1) < 0.02)});
  return out;
}

// ---- [Pettineo2016] ---------------------------------------------------------

Claim claim_wang_lobe_energy() {
  const double lam = constants::cosine_lobe_published.lambda,
               amp = constants::cosine_lobe_published.amplitude;
  const double energy = amp * 2 * std::numbers::pi * (1 - std::exp(-2 * lam)) / lam;
  return {"wang_lobe_energy",
          "Wang et al.'s cosine-lobe SG (λ = 2.133, a = 1.17) keeps the area under the curve "
          "'somewhat consistent' with the clamped cosine",
          "[Pettineo2016] (Error Analysis)",
          "∫_{S²} 1.17·e^{2.133(cos-1)} dω = 1.17·2π(1-e^{-4.266})/2.133 vs ∫ max(cos,0) dω = π; "
          "'somewhat consistent' read as within 10%",
          fmt::format("lobe energy {:.4f} vs π = {:.4f}: {:+.2f}%", energy, std::numbers::pi,
                      100 * (energy / std::numbers::pi - 1)),
          std::abs(energy / std::numbers::pi - 1) < 0.10 ? "holds" : "does not hold"};
}

// The κ = 4 charts of [Pettineo2016]: θ ∈ [0, π], 361 points, with the
// reference irradiance there and its peak E(1, κ).
struct Kappa4Chart {
  double kappa = 4;
  int n = 361;
  std::vector<reference::Query> q;
  std::vector<double> theta;
  std::vector<reference::ReferencePoint> ref;
  double peak = 0;
};
Kappa4Chart kappa4_chart() {
  Kappa4Chart c;
  for (int i = 0; i < c.n; ++i) {
    c.theta.push_back(std::numbers::pi * i / (c.n - 1));
    c.q.push_back({c.kappa, std::clamp(std::cos(c.theta.back()), -1.0, 1.0)});
  }
  c.ref = reference::reference_engine().evaluate(c.q);
  c.peak = reference::reference_engine().evaluate(c.kappa, 1.0).irradiance;
  return c;
}

const Method* registered_irradiance(const char* id) {
  const Method* m = find_method(irradiance_methods, id);
  if (!m) throw std::logic_error(fmt::format("claims: method '{}' not registered", id));
  return m;
}

Claim claim_mjp_inner_product_back(const Kappa4Chart& c) {
  const Method* m = registered_irradiance("wang2009");
  double max_err = 0, max_theta = 0, back_min_diff = std::numeric_limits<double>::infinity(),
         back_max = 0, front_max = 0;
  for (int i = 0; i < c.n; ++i) {
    const double d = m->f64(c.q[i].cosine, c.kappa) - c.ref[i].irradiance;
    if (std::abs(d) > max_err) max_err = std::abs(d), max_theta = c.theta[i];
    if (c.theta[i] > std::numbers::pi / 2) {
      back_min_diff = std::min(back_min_diff, d);
      back_max = std::max(back_max, std::abs(d));
    } else {
      front_max = std::max(front_max, std::abs(d));
    }
  }
  const bool stronger = back_min_diff > 0;
  const bool biggest_back = max_theta > std::numbers::pi / 2;
  return {"mjp_inner_product_back",
          "κ = 4 chart: the SG inner product (wang2009) is not hugely off; its biggest difference "
          "is on the side facing away from the light, where it has a stronger tail",
          "[Pettineo2016] (Error Analysis chart)",
          "Ê - E over θ ∈ [0, π] (361 points) at κ = 4: sign of Ê - E for θ > π/2 and where |Ê - "
          "E| is largest",
          fmt::format("max |Ê-E| = {:.4f} ({:.2f}% of E(1)) at θ = {:.1f}°; max on back side "
                      "{:.4f}, front side {:.4f}; min (Ê-E) for θ > 90° = {:.3g}",
                      max_err, 100 * max_err / c.peak, max_theta * 180 / std::numbers::pi, back_max,
                      front_max, back_min_diff),
          verdict(stronger && biggest_back, stronger || biggest_back)};
}

// The chart's points by θ: all, the side facing away from the light (θ > π/2), the front.
enum class Side { all, back, front };

// The max |Ê − E| of the method `id` (double) over the chart's points on `side`.
double max_abs_error(const Kappa4Chart& c, const char* id, Side side = Side::all) {
  const Method* m = registered_irradiance(id);
  double out = 0;
  for (int i = 0; i < c.n; ++i) {
    const bool back = c.theta[i] > std::numbers::pi / 2;
    if (side == Side::all || back == (side == Side::back))
      out = std::max(out, std::abs(m->f64(c.q[i].cosine, c.kappa) - c.ref[i].irradiance));
  }
  return out;
}

Claim claim_mjp_punctual(const Kappa4Chart& c) {
  const double back_max = max_abs_error(c, "punctual", Side::back),
               front_max = max_abs_error(c, "punctual", Side::front);
  return {"mjp_punctual",
          "κ = 4 chart: pulling the cosine out (punctual) introduces quite a bit of error, "
          "particularly where θ > π/2",
          "[Pettineo2016] (A Cheaper Approximation)",
          "max |Ê - E| / E(1) for θ > π/2 and θ <= π/2 at κ = 4; 'quite a bit' read as > 5% of the "
          "peak",
          fmt::format("max peak_rel: θ > 90°: {:.2f}%, θ <= 90°: {:.2f}%", 100 * back_max / c.peak,
                      100 * front_max / c.peak),
          verdict(back_max / c.peak > 0.05 && back_max > front_max,
                  back_max / c.peak > 0.05 || front_max / c.peak > 0.05)};
}

Claim claim_mjp_hill_close(const Kappa4Chart& c) {
  const double hill_max = max_abs_error(c, "hill"), wang_max = max_abs_error(c, "wang2009");
  return {"mjp_hill_close",
          "κ = 4 chart: Stephen Hill's fitted curve is 'very close' to the ground truth (closer "
          "than the inner product)",
          "[Pettineo2016] (A More Accurate Approximation)",
          "max |Ê - E| / E(1) over θ ∈ [0, π] at κ = 4; 'very close' read as <= 1% of the peak "
          "(invisible on the chart)",
          fmt::format("hill max peak_rel = {:.3f}% (wang2009: {:.3f}%)", 100 * hill_max / c.peak,
                      100 * wang_max / c.peak),
          verdict(hill_max / c.peak <= 0.01 && hill_max < wang_max, hill_max < wang_max)};
}

std::vector<Claim> claims_mjp() {
  const Kappa4Chart chart = kappa4_chart();
  return {claim_wang_lobe_energy(), claim_mjp_inner_product_back(chart), claim_mjp_punctual(chart),
          claim_mjp_hill_close(chart)};
}

// ---- [Tokuyoshi2022] --------------------------------------------------------

Claim claim_numerical_vs_approximation() {
  const auto p = constants::clamped_cosine_published;
  const float lf = static_cast<float>(p.lambda), af = static_cast<float>(p.alpha);
  double approx = 0, numerical = 0;
  const int n = 1'000'001;
  for (int i = 0; i < n; ++i) {
    const float uf = static_cast<float>(static_cast<double>(i) / (n - 1));
    const double u = uf;
    // the model in (near) exact arithmetic
    const double exact_model = p.alpha * std::expm1(p.lambda * u);
    approx = std::max(approx, std::abs(exact_model - u));
    const float fl = af * (std::exp(lf * uf) - 1.0f);  // as Listing 1 evaluates it, in float
    numerical = std::max(numerical, std::abs(static_cast<double>(fl) - exact_model));
  }
  const double ratio = numerical / approx;
  // α·ε_float: rounding of exp with a 1-ulp error (GPU-style exp)
  const double model = p.alpha * 0x1p-23;
  return {"float_numerical_vs_approximation",
          "with the published λ, α the maximum numerical (float rounding) error of α(e^{λ cos}-1) "
          "is almost the same as the maximum approximation error",
          "[Tokuyoshi2022] supplementary §1.1, Fig. 1",
          "u ∈ [0, 1], 1,000,001 float points: approximation error |α·expm1(λu) - u| in double; "
          "numerical error |float α(expf(λu) - 1) - α·expm1(λu)| with glibc expf; 'almost the "
          "same' read as a ratio within [0.8, 1.25] (holds in part within [0.25, 4])",
          fmt::format("max approximation error {:.4g}, max numerical error {:.4g} (ratio {:.3f}): "
                      "a correctly rounded expf errs by <= 0.5 ulp, so the numerical error is "
                      "α·2^-24, half the approximation error; with a 1-ulp exp (GPU-style) it is "
                      "α·ε_float = {:.4g}, equal to the approximation error (how λ was balanced)",
                      approx, numerical, ratio, model),
          verdict(ratio >= 0.8 && ratio <= 1.25, ratio >= 0.25 && ratio <= 4)};
}

std::vector<Claim> claims_steepness(const OptimalSteepnessFn& optimal_steepness) {
  std::vector<Claim> out;
  const std::vector<double> big = {1e2, 1e3, 1e4, 1e5};
  if (!optimal_steepness) {
    out.push_back({"tstar_asymptote", "t*(κ) → √(κ/2) as κ → ∞",
                   "[Tokuyoshi2022] supplementary §1.2", "needs fit::optimal_steepness",
                   "not measured", "not checked"});
    return out;
  }
  const auto ts = optimal_steepness(big);
  std::string m;
  std::vector<double> dev;
  for (std::size_t i = 0; i < big.size(); ++i) {
    const double r = ts[i] / std::sqrt(big[i] / 2);
    dev.push_back(std::abs(r - 1));
    m += fmt::format("{}κ = {:g}: t*/√(κ/2) = {:.4f}", i ? "; " : "", big[i], r);
  }
  const bool decreasing = std::is_sorted(dev.rbegin(), dev.rend());
  out.push_back({"tstar_asymptote",
                 "the optimal steepness t*(κ) of the normalized hemispherical integral approaches "
                 "√(κ/2) as κ → ∞",
                 "[Tokuyoshi2022] supplementary §1.2, Fig. 2",
                 "fit::optimal_steepness (minimax of erf-model s̃ - s over 201 cosines) at κ = "
                 "1e2..1e5; holds if |t*/√(κ/2) - 1| shrinks with κ and is < 2% at κ = 1e5",
                 m, verdict(decreasing && dev.back() < 0.02, dev.back() < 0.05)});

  // Eq. 6 close to the dots, and itself → √(κ/2).
  std::vector<double> ks;
  for (int i = 0; i < 21; ++i) ks.push_back(std::pow(10.0, -2 + 5.0 * i / 20));
  const auto t_opt = optimal_steepness(ks);
  double worst = 0, worst_k = 0, worst_ge1 = 0;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const double r = std::abs(steepness2022(ks[i]) / t_opt[i] - 1);
    if (r > worst) worst = r, worst_k = ks[i];
    if (ks[i] >= 1) worst_ge1 = std::max(worst_ge1, r);
  }
  const double t_asym = steepness2022(1e8) / std::sqrt(1e8 / 2);
  out.push_back(
      {"eq6_close_to_tstar",
       "the fitted t(κ) (Eq. 6, published A, B, C) is close to the numerically optimal t*(κ) and "
       "also approaches √(κ/2)",
       "[Tokuyoshi2022] supplementary §1.2, Fig. 2",
       "max |t(κ)/t*(κ) - 1| over 21 log-spaced κ in [1e-2, 1e3]; t(1e8)/√(1e8/2); 'close' read as "
       "within 10%",
       fmt::format(
           "max |t/t* - 1| = {:.3g} at κ = {:.3g} ({:.3g} over κ >= 1); t(1e8)/√(5e7) = {:.6f}",
           worst, worst_k, worst_ge1, t_asym),
       worst < 0.10 && std::abs(t_asym - 1) < 1e-3 ? "holds" : "holds in part"});
  return out;
}

// ---- [TokuyoshiHarada2017] --------------------------------------------------

std::vector<Claim> claims_fresnel() {
  std::vector<Claim> out;
  // Schlick (Eq. 1) monotone and Eq. 2's cos θh_max.
  {
    bool mono = true;
    double cos_identity = 0;
    for (int k = 0; k <= 20; ++k) {
      const double f0 = k / 20.0;
      double prev = -1;
      for (int i = 0; i <= 2000; ++i) {
        const double th = std::numbers::pi / 2 * i / 2000;
        const double f = f0 + (1 - f0) * std::pow(1 - std::cos(th), 5);
        if (f < prev - 1e-15) mono = false;
        prev = f;
      }
    }
    for (int i = 0; i <= 2000; ++i) {
      const double c = static_cast<double>(i) / 2000;
      const double a = std::cos(0.5 * std::acos(c) + std::numbers::pi / 4);
      const double b = std::sqrt((1 - std::sqrt(1 - c * c)) / 2);
      cos_identity = std::max(cos_identity, std::abs(a - b));
    }
    out.push_back({"schlick_monotone",
                   "Schlick F(cos θh) is monotonically increasing in θh ∈ [0, π/2], so F_max = "
                   "F(cos θh_max) with cos θh_max = √((1 - √(1 - (ωi·n)²))/2)",
                   "[TokuyoshiHarada2017] supplemental §1 Eq. 1-2",
                   "F0 ∈ {0, 0.05, …, 1} × 2001 θh; identity cos(½ arccos c + π/4) = "
                   "√((1-√(1-c²))/2) at 2001 c ∈ [0, 1]",
                   fmt::format("monotone: {}; max identity difference {:.2g}", mono ? "yes" : "no",
                               cos_identity),
                   verdict(mono && cos_identity < 1e-12)});
  }
  // Dielectric Fresnel: monotone inside [2-√3, 2+√3], quasiconvex outside; Eq. 6.
  const double lo = 2 - std::sqrt(3.0), hi = 2 + std::sqrt(3.0);
  int inside = 0, inside_mono = 0, outside = 0, outside_nonmono = 0, outside_qc = 0;
  double eq6_err = 0;
  std::vector<double> etas;
  for (int i = 0; i <= 200; ++i)
    etas.push_back(std::pow(10.0, -1.3 + 2.6 * i / 200));  // [0.05, 20]
  for (double e : {lo, hi, lo * 1.01, hi * 0.99, lo * 0.99, hi * 1.01}) etas.push_back(e);
  double first_fail_above = std::numeric_limits<double>::infinity(), last_fail_below = 0;
  for (double eta : etas) {
    if (std::abs(eta - 1) < 1e-9) continue;
    const FresnelShape s = fresnel_shape(eta, 2001, 91);
    eq6_err = std::max(eq6_err, s.eq6_max_error);
    if (eta >= lo && eta <= hi) {
      ++inside;
      inside_mono += s.monotone_increasing;
    } else {
      ++outside;
      outside_nonmono += !s.monotone_increasing;
      outside_qc += s.quasiconvex;
    }
    if (!s.monotone_increasing) {
      if (eta > 1) first_fail_above = std::min(first_fail_above, eta);
      if (eta < 1) last_fail_below = std::max(last_fail_below, eta);
    }
  }
  out.push_back({"fresnel_monotone_quasiconvex",
                 "unpolarized dielectric Fresnel F(cos θh) is monotonically increasing in θh ∈ [0, "
                 "π/2] if 2-√3 <= η <= 2+√3, otherwise quasiconvex",
                 "[TokuyoshiHarada2017] supplemental §1 Eq. 3-5",
                 fmt::format("{} η log-spaced in [0.05, 20] plus η = (2±√3)(1, 0.99, 1.01); 2001 "
                             "θh; monotone = non-decreasing, quasiconvex = non-increasing then "
                             "non-decreasing (tolerance 1e-12); complex sqrt for TIR",
                             etas.size()),
                 fmt::format("inside: {}/{} monotone; outside: {}/{} not monotone, {}/{} "
                             "quasiconvex; monotonicity fails for η <= {:.4f} and η >= {:.4f} "
                             "(2-√3 = {:.4f}, 2+√3 = {:.4f})",
                             inside_mono, inside, outside_nonmono, outside, outside_qc, outside,
                             last_fail_below, first_fail_above, lo, hi),
                 inside_mono == inside && outside_qc == outside
                     ? (outside_nonmono == outside ? "holds" : "holds in part")
                     : "does not hold"});
  out.push_back({"fresnel_eq6_max",
                 "the maximum Fresnel factor over half vectors is F_max(ωi) = max(F(1), F(cos "
                 "θh_max(ωi))), θh_max = ½ arccos(ωi·n) + π/4",
                 "[TokuyoshiHarada2017] supplemental §1 Eq. 6",
                 "for each η above and 91 θi ∈ [0, π/2]: brute-force max of F over 2001 θh ∈ [0, "
                 "θh_max] vs Eq. 6",
                 fmt::format("max |Eq. 6 - brute force| = {:.3g}", eq6_err),
                 verdict(eq6_err < 1e-12)});
  return out;
}

}  // namespace

// ---- public helpers ------------------------------------------------------------

double as7125_max_abs_error(int points) {
  double m = 0;
  for (int i = 0; i < points; ++i) {
    const double x = 6.0 * i / (points - 1);
    m = std::max(m, std::abs(erf_abramowitz_stegun(x) - std::erf(x)));
  }
  return m;
}

double fresnel_dielectric(double cos_theta, double eta) {
  using C = std::complex<double>;
  const double c = std::clamp(cos_theta, 0.0, 1.0);
  const double s2 = 1 - c * c;
  const C g = std::sqrt(C(eta * eta - s2, 0));
  const double e2 = eta * eta;
  const double fs = std::norm((c - g) / (c + g));
  const double fp = std::norm((g - e2 * c) / (g + e2 * c));
  return 0.5 * (fs + fp);
}

FresnelShape fresnel_shape(double eta, int theta_points, int incidence_points) {
  FresnelShape r;
  std::vector<double> f(theta_points);
  for (int i = 0; i < theta_points; ++i)
    f[i] = fresnel_dielectric(std::cos(std::numbers::pi / 2 * i / (theta_points - 1)), eta);
  const double tol = 1e-12;
  r.monotone_increasing = true;
  for (int i = 1; i < theta_points; ++i)
    if (f[i] < f[i - 1] - tol) r.monotone_increasing = false;
  const auto imin = static_cast<int>(std::min_element(f.begin(), f.end()) - f.begin());
  r.quasiconvex = true;
  for (int i = 1; i <= imin; ++i)
    if (f[i] > f[i - 1] + tol) r.quasiconvex = false;
  for (int i = imin + 1; i < theta_points; ++i)
    if (f[i] < f[i - 1] - tol) r.quasiconvex = false;
  // Eq. 6 against brute force.
  const int n_i = std::max(2, incidence_points);
  for (int k = 0; k < n_i; ++k) {
    const double ti = std::numbers::pi / 2 * k / (n_i - 1);
    const double ci = std::cos(ti);
    const double th_max = 0.5 * std::acos(std::clamp(ci, -1.0, 1.0)) + std::numbers::pi / 4;
    double brute = 0;
    for (int i = 0; i < theta_points; ++i)
      brute = std::max(brute, fresnel_dielectric(std::cos(th_max * i / (theta_points - 1)), eta));
    const double cmax = std::sqrt((1 - std::sqrt(std::max(0.0, 1 - ci * ci))) / 2);
    const double eq6 = std::max(fresnel_dielectric(1.0, eta), fresnel_dielectric(cmax, eta));
    r.eq6_max_error = std::max(r.eq6_max_error, std::abs(eq6 - brute));
  }
  return r;
}

GaussianProduct gaussian_product(double mu1, double lambda1, double mu2, double lambda2) {
  const double l1 = lambda1 * lambda1, l2 = lambda2 * lambda2, s = l1 + l2;
  return {std::exp(-(mu1 - mu2) * (mu1 - mu2) / s), (mu1 * l2 + mu2 * l1) / s,
          std::sqrt(l1 * l2 / s)};
}

GaussianProduct circular_gaussian_product(double mu1, double lambda1, double mu2, double lambda2) {
  const double a1 = 2 / (lambda1 * lambda1), a2 = 2 / (lambda2 * lambda2);
  const double x = a1 * std::cos(mu1) + a2 * std::cos(mu2),
               y = a1 * std::sin(mu1) + a2 * std::sin(mu2);
  const double a = std::hypot(x, y);
  return {std::exp(a - a1 - a2), std::atan2(y, x), std::sqrt(2 / a)};
}

double gaussian_product_max_rel_error(int trials, unsigned seed, bool circular) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> mu_d(circular ? -std::numbers::pi : -2.0,
                                              circular ? std::numbers::pi : 2.0),
      lam_d(0.1, 2.0), x_d(circular ? -std::numbers::pi : -3.0, circular ? std::numbers::pi : 3.0);
  double worst = 0;
  for (int t = 0; t < trials; ++t) {
    const double m1 = mu_d(rng), l1 = lam_d(rng), m2 = mu_d(rng), l2 = lam_d(rng), x = x_d(rng);
    double lhs, rhs;
    if (circular) {
      const auto p = circular_gaussian_product(m1, l1, m2, l2);
      lhs = circ_gauss(x, m1, l1) * circ_gauss(x, m2, l2);
      rhs = p.b * circ_gauss(x, p.mu, p.lambda);
    } else {
      const auto p = gaussian_product(m1, l1, m2, l2);
      lhs = gauss(x, m1, l1) * gauss(x, m2, l2);
      rhs = p.b * gauss(x, p.mu, p.lambda);
    }
    if (lhs < 1e-300) continue;
    worst = std::max(worst, std::abs(lhs - rhs) / lhs);
  }
  return worst;
}

std::vector<Claim> check_claims(const OptimalSteepnessFn& optimal_steepness) {
  std::vector<Claim> all;
  auto add = [&](std::vector<Claim> v) { all.insert(all.end(), v.begin(), v.end()); };
  all.push_back(claim_numerical_vs_approximation());
  add(claims_steepness(optimal_steepness));
  add(claims_mjp());
  all.push_back(claim_as7125());
  add(claims_circular());
  add(claims_fresnel());
  add(claims_lambda_d());
  return all;
}

Table claims_table(const std::vector<Claim>& claims) {
  Table t("Seed claims checked numerically",
          {Column("id"), Column("claim"), Column("source"), Column("tested_as"), Column("measured"),
           Column("verdict")});
  for (const Claim& c : claims)
    t.add_row({Table::text(c.id), Table::text(c.claim), Table::text(c.source),
               Table::text(c.tested_as), Table::text(c.measured), Table::text(c.verdict)});
  return t;
}

}  // namespace sglab::validate
