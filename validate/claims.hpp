// validate/claims.hpp — every quantitative claim of the cited sources (docs/references.md)
// (/work/shared/seeds) checked numerically: `sglab claims`.
//
// Each claim records what the seed says, how sglab tests it (the
// interpretation, stated explicitly where the OCR'd text lost the equations),
// the measured numbers and a verdict: "holds", "does not hold" or "holds in part".
//
// validate/ does not link fit/, so the one quantity that needs the fitter
// (the per-κ optimal steepness t*(κ) of [Tokuyoshi2022] supplementary Fig. 2) is passed in.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "validate/table.hpp"

namespace sglab::validate {

struct Claim {
  std::string id;         // short key, e.g. "as7125_bound"
  std::string claim;      // what the seed says
  std::string source;     // seed and section
  std::string tested_as;  // the interpretation / procedure
  std::string measured;   // the numbers
  std::string verdict;    // "holds" | "does not hold" | "holds in part"
};

// t*(κ) for each κ (fit::optimal_steepness("steepness2022", κs)).
using OptimalSteepnessFn = std::function<std::vector<double>(const std::vector<double>&)>;

// Runs every check. `optimal_steepness` may be empty: the t* claims are then
// reported as not checked ("holds in part" is never invented; verdict "not checked").
std::vector<Claim> check_claims(const OptimalSteepnessFn& optimal_steepness);

// claim, source, tested_as, measured, verdict.
Table claims_table(const std::vector<Claim>& claims);

// ---- the individual checks, exposed for tests --------------------------------

// max |erf_as7125(x) − erf(x)| over a dense grid of x ∈ [0, 6] in double.
double as7125_max_abs_error(int points = 2'000'001);

// Unpolarized dielectric Fresnel factor ([TokuyoshiHarada2017] supplemental Eq. 3–5) at cos θh for
// the relative index η (complex square root: total internal reflection gives 1).
double fresnel_dielectric(double cos_theta, double eta);

struct FresnelShape {
  bool monotone_increasing = false;  // non-decreasing in θh ∈ [0, π/2] (tolerance 1e−12)
  bool quasiconvex = false;          // non-increasing then non-decreasing
  double eq6_max_error = 0;  // max over θi of |Eq. 6 − brute-force max over θh ∈ [0, θh_max(θi)]|
};
FresnelShape fresnel_shape(double eta, int theta_points = 2001, int incidence_points = 401);

// 1-D Gaussian g(x; μ, λ) = exp(−(x − μ)²/λ²) and circular Gaussian
// gc(φ; μ, λ) = exp(2(cos(φ − μ) − 1)/λ²) ([Xu2011] supplemental §2, §5).
struct GaussianProduct {
  double b, mu, lambda;  // g1·g2 = b·g(·; μ, λ)
};
GaussianProduct gaussian_product(double mu1, double lambda1, double mu2, double lambda2);
GaussianProduct circular_gaussian_product(double mu1, double lambda1, double mu2, double lambda2);

// Max relative difference |g1 g2 − b g3| / max(g1 g2, tiny) over random
// parameters and points (fixed seed); values where g1·g2 < 1e−300 are skipped.
double gaussian_product_max_rel_error(int trials, unsigned seed, bool circular);

}  // namespace sglab::validate
