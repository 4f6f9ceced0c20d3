// sglab/params.hpp — parameter sets of the fitted methods.
//
// Each struct is templated on its own scalar S so that a runtime function
// template<class T, class S> can run in precision T with constants stored in
// precision S: double constants rounded to float for the float path, Ceres
// Jets for the fitters. The published and refitted values themselves live in
// the generated header sglab/constants.hpp (from data/constants/*.json).
#pragma once

#include <cstddef>

namespace sglab {

// max(cos θ, 0) ≈ α (e^{λ cos θ} − 1) on the upper hemisphere
// ([Tokuyoshi2022] Listing 1).
template <class S>
struct ClampedCosineParams {
  S lambda;
  S alpha;
};

// Steepness of the erf-based normalized hemispherical integral,
// t(κ) = κ √((0.5κ + A) / ((κ + B)κ + C))  ([Tokuyoshi2022] Eq. 6, Listing 3).
template <class S>
struct Steepness2022Params {
  S A, B, C;
};

// Steepness of the 2024 clamped-cosine interpolation factor,
// t(κ) = κ √(0.5((κ + A)κ + B) / (((κ + C)κ + D)κ + E))
// (Tokuyoshi et al. 2024, supplementary Listing 7).
template <class S>
struct Steepness2024Params {
  S A, B, C, D, E;
};

// General rational steepness of sglab's model-order search:
// t(κ) = κ √(0.5 P(κ)/Q(κ)) with monic P = κ^M + p[M−1]κ^{M−1} + … + p[0] and
// Q = κ^{M+1} + q[M]κ^M + … + q[0], so that t → √(κ/2) as κ → ∞ for every
// order M ([Tokuyoshi2022] supplementary §1.2). M = 1 is the 2022 form (p0 = 2A, q1 = B, q0 = C),
// M = 2 the 2024 form (p1 = A, p0 = B, q2 = C, q1 = D, q0 = E). For M = 0, P = 1
// and p is unused.
template <class S, std::size_t M>
struct SteepnessRationalParams {
  S p[M > 0 ? M : 1];
  S q[M + 1];
};

// [Tokuyoshi2022] Listing 5 erf structure: x·P(x²) on |x| ≤ split (P has NS
// coefficients, lowest order first), 1 − 2^{−a·Q(a)} on split < a < cutoff
// (Q has NL coefficients, lowest order first), ±1 beyond.
template <class S, std::size_t NS, std::size_t NL>
struct Listing5Params {
  S split;
  S cutoff;
  S small[NS];
  S large[NL];
};

// Abramowitz–Stegun 7.1.25/7.1.26 structure:
// erf(x) ≈ 1 − (a1 t + a2 t² + … + aN t^N) e^{−x²}, t = 1/(1 + p x), x ≥ 0.
template <class S, std::size_t N>
struct AbramowitzStegunParams {
  S p;
  S a[N];
};

// A single SG standing in for the cosine lobe: a·G(ω; n, λ) (Wang et al. 2009).
template <class S>
struct CosineLobeParams {
  S lambda;
  S amplitude;
};

// Normalized SG standing in for cos⁺/π: G(ω; n, λd)/A(λd) ([Tokuyoshi2015] supplemental Eq. 1).
template <class S>
struct DiffuseLobeParams {
  S lambda_d;
};

// Stephen Hill's fitted irradiance curve ([Pettineo2016]): c1 = 1/(4 c0).
template <class S>
struct HillParams {
  S c0;
};

// Meder & Brüderlin 2018: logistic steepness
// t(κ) = √κ (a2 κ² + a1 κ) / (κ² + b1 κ + b0) and the cosine fit
// cos θ ≈ amplitude·e^{sharpness(cos θ − 1)} − offset on the upper hemisphere.
template <class S>
struct Meder2018Params {
  S a2, a1, b1, b0;
  S amplitude, sharpness, offset;
};

// The coefficients of sglab_fast (include/sglab/sglab_fast.hpp, docs/models.md#sglab_fast):
// Ê = E(1, κ)·max(0, A + B c + C ρ(V c + ½)) with
// A = Pa(κ̃)/Q(κ̃), B = Pb/Q, C = Pc/Q, V = Pv/Q, κ̃ = min(κ, kappa_max),
// numerators of degree 4 and one shared monic quartic Q = κ̃⁴ + q[3]κ̃³ + … + q[0]
// (coefficients lowest order first).
template <class S>
struct SglabFastParams {
  S a[5], b[5], c[5], v[5];
  S q[4];
  S kappa_max;
};

// The coefficients of sglab_lite (include/sglab/sglab_lite.hpp, docs/models.md#sglab_lite):
// Ê = max(0, A + B c + C ρ(V c + ½)) with A = Pa(κ̃)/((1 + κ̃)Q(κ̃)), B = Pb/((1 + κ̃)Q),
// C = Pc/((1 + κ̃)Q), V = Pv/Q,
// κ̃ = min(κ, kappa_max), numerators of degree 4 and one shared monic quartic
// Q = κ̃⁴ + q[3]κ̃³ + … + q[0] (coefficients lowest order first); E(1, κ) is folded into A, B, C.
template <class S>
struct SglabLiteParams {
  S a[5], b[5], c[5], v[5];
  S q[4];
  S kappa_max;
};

// The coefficients of sglab_min (include/sglab/sglab_min.hpp, docs/models.md#sglab_min):
// Ê = y·max(0, A(y) + B(y) c + G(y) c²), y = 1/(κ + s), with A(y) = a[0] + a[1]y + a[2]y²,
// B(y) = b[0] + b[1]y, G(y) = g[0] + g[1]y (coefficients lowest order first), s > 0.
template <class S>
struct SglabMinParams {
  S a[3], b[2], g[2];
  S s;
};

// The table of sglab_tab (include/sglab/sglab_tab.hpp, docs/models.md#sglab_tab): N equal
// cells of u = √κ/(1 + √κ) ∈ [0, 1]; on cell j, with local t = 2(uN − j) − 1 ∈ [−1, 1], each
// of the kSglabTabValues values A, B, D, G, H, s, v is a polynomial of degree D in t,
// coef[(j·7 + m)(D + 1) + i] the coefficient of t^i of value m (lowest order first).
inline constexpr std::size_t kSglabTabValues = 7;
template <class S, std::size_t N, std::size_t D>
struct SglabTabParams {
  S coef[N * 7 * (D + 1)];
};

// sglab's middle irradiance model (include/sglab/sglab_mid.hpp):
// Ê = E(1, κ)·max(0, A + B(c + √(c² + e^{S − V c²})) + D c²) with
// A = Pa(κ̃)/Q(κ̃), B = Pb/Q, D = Pd/Q, S = Ps/Q − ln(1 + κ̃), V = κ̃ Pv/Q, κ̃ = min(κ, kappa_max),
// numerators of degree 4 and one shared monic quartic Q = κ̃⁴ + q[3]κ̃³ + … + q[0]
// (coefficients lowest order first).
template <class S>
struct SglabMidParams {
  S a[5], b[5], d[5], s[5], v[5];
  S q[4];
  S kappa_max;
};

// sglab_acc `sglab_acc<N>` (sglab_acc.hpp): the steepness t(κ) of rational
// order M (SteepnessRationalParams) with its coefficients highest order first,
// steep = {P's κ^{M−1} … κ^0, Q's κ^M … κ^0}: t = κ√(0.5 P/Q),
// P = (…(κ + steep[0])κ + …)κ + steep[M−1], Q = (…(κ + steep[M])κ + …)κ + steep[2M];
// for M = 2 the 2024 form, steep = {A, B, C, D, E} (Steepness2024Params order);
// and N correction coefficients b_j(κ) = u(1 − u)³ P_j(u) that fade as
// κ → 0 and κ → ∞, u = t/(t + scale) ∈ [0, 1), P_j of degree D:
// P_j(u) = num[j(D+1)] + num[j(D+1)+1] u + … + num[j(D+1)+D] u^D; scale > 0.
template <class S, std::size_t N, std::size_t D, std::size_t M>
struct SglabAccParams {
  S steep[2 * M + 1];
  S num[N * (D + 1)];
  S scale;
};

}  // namespace sglab
