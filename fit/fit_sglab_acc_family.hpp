// fit/fit_sglab_acc_family.hpp — what the parts of the sglab-acc fitter
// share (fit/fit_sglab_acc.cpp: the ladder, the model order and their
// reports; fit/fit_sglab_acc_grids.cpp: the training grids and weights;
// fit/fit_sglab_acc_starts.cpp: per-κ optima and start values;
// fit/fit_sglab_acc_member.cpp: the certified fit of one member): the
// family's members, the bridge from a member to the templated code, the
// parameter packing and what a member's fit returns.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/sglab.hpp>
#include <sglab/sglab_acc.hpp>

#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit::acc {

struct Member {
  std::size_t n, d;   // correction terms, degree of the P_j
  std::size_t m = 2;  // order of the rational steepness t(κ) (2: the 2024 form)
  bool operator==(const Member&) const = default;
};

// The number of steepness coefficients of order m: P has m, Q m + 1 (params.hpp).
constexpr std::size_t steep_count(std::size_t m) { return 2 * m + 1; }

// The family, cheapest first (by the operations counted in `operations`):
// the one list of the members that are instantiated (with_member below).
constexpr Member kFamily[] = {{1, 2},    {1, 3}, {2, 2}, {2, 3},    {2, 5}, {3, 3},   {3, 4},
                              {3, 4, 3}, {4, 4}, {3, 6}, {3, 6, 3}, {4, 6}, {4, 6, 3}};

template <std::size_t V>
using Size = std::integral_constant<std::size_t, V>;

// f(Size<N>{}, Size<D>{}, Size<M>{}) for the member m = {N, D, M} of kFamily: the one bridge
// from a runtime member to the templated code (a fold over kFamily's indices).
template <class F>
auto with_member(Member m, F&& f) {
  using R = decltype(f(Size<kFamily[0].n>{}, Size<kFamily[0].d>{}, Size<kFamily[0].m>{}));
  return [&]<std::size_t... I>(std::index_sequence<I...>)->R {
    std::optional<R> r;
    ((m == kFamily[I] &&
      (r.emplace(f(Size<kFamily[I].n>{}, Size<kFamily[I].d>{}, Size<kFamily[I].m>{})), true)) ||
     ...);
    if (!r)
      throw std::invalid_argument(
          fmt::format("sglab-acc: no member N={} D={} M={}", m.n, m.d, m.m));
    return std::move(*r);
  }
  (std::make_index_sequence<std::size(kFamily)>{});
}

// f(Size<N>{}) for the number of terms N of a member of kFamily.
template <class F>
auto with_terms(std::size_t n, F&& f) {
  const Member* m =
      std::find_if(std::begin(kFamily), std::end(kFamily), [n](Member e) { return e.n == n; });
  if (m == std::end(kFamily))
    throw std::invalid_argument(fmt::format("sglab-acc: no member with N={}", n));
  return with_member(*m, [&](auto terms, auto, auto) { return f(terms); });
}
// The shipped ladder: id suffix and member.
struct Rung {
  const char* variant;
  Member member;
  double target;  // T of the weight w(κ): the max peak_rel error aimed at
};
constexpr Rung kLadder[] = {{"acc1", {1, 3}, 2.4e-4},
                            {"acc2", {2, 5}, 3.2e-5},
                            {"acc3", {3, 6, 3}, 1e-5},
                            {"acc4", {4, 6, 3}, 5e-6}};

// The search space of every solve below, a box (Ceres keeps each trial point
// inside it): log coefficients (names starting with "log") in [−200, 50],
// linear ones in [−1e6, 1e6]; the fits land far inside (|log| ≤ 46, |num| < 1).
// On the box the model and its derivatives are finite for every κ > 0 and
// c ∈ [−1, 1]: every coefficient is ≤ e^50 ≈ 5e21, and every denominator of
// t(κ) and b_j(κ) is ≥ min(κ³, 1) (κ < 1: the monic κ^k term plus positive
// ones; κ ≥ 1: 1 plus positive terms in 1/κ), so no intermediate overflows.
// Unbounded, a trust-region step once reached log B = 1024: e^1024 = inf, and
// the residual was NaN (Ceres rejected the step and logged it).
constexpr double kLogLower = -200, kLogUpper = 50, kLinearBound = 1e6;
void bound(Parameters& p);

// Parameters: log steep[2M + 1], num[N(D+1)], then log scale: the steepness
// coefficients and the scale stay positive by construction (t(κ) real,
// b_j(κ) finite for every κ ≥ 0).
template <class T, std::size_t N, std::size_t D, std::size_t M>
SglabAccParams<T, N, D, M> unpack(T const* const* p) {
  using std::exp;
  constexpr std::size_t K = steep_count(M);
  SglabAccParams<T, N, D, M> q{};
  for (std::size_t i = 0; i < K; ++i) q.steep[i] = exp(p[i][0]);
  for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[K + i][0];
  q.scale = exp(p[K + N * (D + 1)][0]);
  return q;
}

// The peak_rel error divided by the sample's weight (SglabAccSample::weight).
template <std::size_t N, std::size_t D, std::size_t M>
struct PeakRelResidual {
  double kappa, cosine, reference, peak, weight;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    const SglabAccParams<T, N, D, M> q = unpack<T, N, D, M>(p);
    r[0] = (irradiance_sglab_acc(T(cosine), T(kappa), q) - T(reference)) / T(peak * weight);
    return true;
  }
};

// The certificate of a member's fit, on the dense training
// grid (sglab_acc_dense_grid), in the units of the fit's objective, peak_rel/w(κ):
// achieved ≥ lower_bound ≥ per_kappa_floor.
struct Certificate {
  double achieved = 0;  // max at the final coefficients (double), every row
  // LP optimum at the fitted steepness t(κ) and scale s: the best member with those
  double lower_bound = 0;
  // max over κ of the optimum with b_j(κ) free at each κ, t(κ) as fitted
  double per_kappa_floor = 0;
  double per_kappa_floor_peak_rel = 0;  // the same without the weight w(κ) (plain max peak_rel)
  std::size_t rows = 0, kappas = 0, working_rows = 0;
  int rounds = 0;
  bool converged = false;  // the LP's exchange closed the gap (lp_minimax.hpp)
};

struct MemberFit {
  Member member;
  Certificate certificate;
  std::vector<double> values;  // steep[2M + 1], num, scale (itself, not its log)
  double train = 0;  // the fit objective: max of peak_rel/w(κ) on the training grid (double)
  Measured standard, held_out;
  // float scalar ns/eval over tokuyoshi2024's, from the cost table (member_cost)
  std::optional<double> cost;
  double floor = 0;  // max over κ of the per-κ optimum at the refitted 2024 t(κ) (0: not computed)
  bool converged = false;
};

template <std::size_t N, std::size_t D, std::size_t M>
SglabAccParams<double, N, D, M> params_of(const std::vector<double>& v) {
  constexpr std::size_t K = steep_count(M);
  SglabAccParams<double, N, D, M> p{};
  for (std::size_t i = 0; i < K; ++i) p.steep[i] = v[i];
  for (std::size_t i = 0; i < N * (D + 1); ++i) p.num[i] = v[K + i];
  p.scale = v[K + N * (D + 1)];
  return p;
}

// Stage 1 — per κ, b_0 … b_{N−1} free at the refitted 2024 steepness t(κ):
// minimax of the peak_rel error over that κ's training cosines. Linear in the
// b_j, so the optimum is unique and smooth in κ (a good start for stage 2);
// its max over κ is the family's floor at that steepness.
template <std::size_t N>
struct PerKappaResidual {
  double t, cosine, reference, peak, lower, upper;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    using std::erfc;
    SglabAccLight<T, N> l;
    l.t = T(t);
    l.half_erfc_t = T(0.5) * erfc(l.t);
    l.tail_scale = T(0.5) * inv_sqrt_pi_v<T>() / l.t;
    l.t2 = l.t * l.t;
    l.lower = T(lower);
    l.upper = T(upper);
    for (std::size_t j = 0; j < N; ++j) l.b[j] = p[j][0];
    r[0] = (sglab_acc_eval(l, T(cosine)) - T(reference)) / T(peak);
    return true;
  }
};

struct KappaOptimum {
  double kappa, t, error;
  std::vector<double> b;
};

// Per-κ optima for N terms (computed once per N).
struct Floors {
  std::map<std::size_t, std::vector<KappaOptimum>> by_terms;
  const std::vector<KappaOptimum>& get(std::size_t n, const std::vector<SglabAccSample>& train);
  double floor(std::size_t n, const std::vector<SglabAccSample>& train);
};

// Dense training grid of the certificate (sglab_acc_dense_grid): its uniform cosines per κ.
inline constexpr int kDenseUniform = 64;

// The grids of one sglab-acc run: training (Ceres), dense training (the LP
// and the certificate), and two measuring grids no fit uses.
struct Grids {
  std::vector<SglabAccSample> train, dense;
  MeasuringGrids measuring;
};

// fit/fit_sglab_acc_grids.cpp
// κ log-spaced at half-step offsets over [lo, hi] plus the ends, and twice as
// dense where the 2024 form's residual lives (κ ∈ [0.5, 200], clipped to the range).
std::vector<double> training_kappas(double lo, double hi, int count);
// The training grid of the Ceres fits: κ as training_kappas (40), per κ c = 0,
// 24 cosines at half-step offsets and c = ±z_k/t(κ), z_k = 0.1 … 3.1.
std::vector<reference::Query> training_grid(double lo, double hi);
// The training samples weighted for target T: w(κ) = min(T, max(e₂₀₂₄(κ), 8e−7)),
// e₂₀₂₄(κ) the float error of tokuyoshi2024 at κ, max over the κ's samples
// (the samples come grouped by κ, as training_grid makes them).
std::vector<SglabAccSample> weighted(std::vector<SglabAccSample> samples, double target);
Grids grids_for(const FitSpec& spec);

// fit/fit_sglab_acc_starts.cpp
// The values (steep, num, scale) of member `from` embedded in member `to`
// (no fewer terms, no lower degree or steepness order): the added terms and
// degrees 0, the steepness raised (raise_steepness_order). The same function.
std::vector<double> embed(Member from, const std::vector<double>& values, Member to);
// Start values for member m: the latest earlier fit nested in it (no more
// terms, no higher degree or steepness order) embedded (embed: the same function, so the fit
// starts at that member's error), else the staged start from the per-κ optima.
std::vector<double> start_for(Member m, const std::vector<MemberFit>& earlier, Floors& floors,
                              const std::vector<SglabAccSample>& train);
// The committed set `variant` over [lo, hi] as start values, if it exists
// with the member's number of terms and no higher degree or steepness order
// (embedded: the same function). The flag says whether it has the member's
// shape exactly (a polish) or was embedded.
std::optional<std::pair<std::vector<double>, bool>> committed(const std::string& variant, Member m,
                                                              double lo, double hi);

// fit/fit_sglab_acc_member.cpp
// Member (N, D) from `start`: Ceres (fit_coefficients) on the training grid,
// then the LP on the dense grid at its t(κ) and s, alternating with Ceres
// polishes; measured on the standard and held-out grids, and certified.
MemberFit fit_any(Member m, const std::vector<double>& start,
                  const std::vector<SglabAccSample>& train,
                  const std::vector<SglabAccSample>& dense, const MeasuringGrids& measuring,
                  bool polish_only = false);

}  // namespace sglab::fit::acc
