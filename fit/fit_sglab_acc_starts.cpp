// Start values of the sglab-acc fits: the per-κ optima (stage 1), the
// staged start from them (stage 2), and the embedding of a lower member or of
// a committed set.
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

#include "fit/fit_sglab_acc_family.hpp"
#include "fit/minimax.hpp"
#include "fit/model_family.hpp"
#include "fit/targets.hpp"
#include "reference/reference.hpp"

namespace sglab::fit::acc {

namespace {

template <std::size_t N>
std::vector<KappaOptimum> per_kappa_optima(const std::vector<SglabAccSample>& samples) {
  std::vector<KappaOptimum> out;
  std::vector<double> b;
  for (std::size_t i = 0; i < samples.size();) {
    std::size_t end = i;
    while (end < samples.size() && samples[end].kappa == samples[i].kappa) ++end;
    const double k = samples[i].kappa;
    const double t = steepness2024(k, constants::steepness2024_irradiance);
    Parameters params;
    for (std::size_t j = 0; j < N; ++j)
      params.names.push_back(fmt::format("b{}", j)), params.values.push_back(0.0);
    bound(params);
    Residuals residuals;
    for (std::size_t s = i; s < end; ++s)
      residuals.push_back(make_residual(
          PerKappaResidual<N>{t, samples[s].cosine, samples[s].irradiance, irradiance_upper(k),
                              irradiance_lower_over_two_pi(k), irradiance_upper_over_two_pi(k)},
          params.size()));
    FitOptions options;
    options.lawson_iterations = 10;
    options.penalty_decades = 6;
    options.solver_iterations = 50;
    const FitResult f = fit(residuals, params, options);
    b = f.values;
    out.push_back({k, t, f.max_abs, b});
    i = end;
  }
  return out;
}

// Stage 2a — t(κ): the 2024 rational form (log coefficients) by least squares on log t − log t*.
struct LogSteepnessResidual {
  double kappa, log_t, weight;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    using std::exp;
    using std::log;
    const Steepness2024Params<T> s{exp(p[0][0]), exp(p[1][0]), exp(p[2][0]), exp(p[3][0]),
                                   exp(p[4][0])};
    r[0] = T(weight) * (log(steepness2024(T(kappa), s)) - T(log_t));
    return true;
  }
};

// Stage 2b — b_j(κ) = u(1 − u)³ P_j(u), u = t/(t + s) (log scale), least
// squares on the per-κ optima (at their steepness t) weighted by the
// sensitivity of peak_rel to f, (Ē(1) − Ē(−1))/Ē(1).
template <std::size_t N, std::size_t D>
struct FadeResidual {
  double t, weight;
  std::size_t j;
  double target;
  template <class T>
  bool operator()(T const* const* p, T* r) const {
    using std::exp;
    SglabAccParams<T, N, D, 2> q{};  // the fade alone: the steepness is unused
    for (std::size_t i = 0; i < N * (D + 1); ++i) q.num[i] = p[i][0];
    q.scale = exp(p[N * (D + 1)][0]);
    T b[N];
    detail::sglab_acc_fade(T(t), q, b);
    r[0] = T(weight) * (b[j] - T(target));
    return true;
  }
};

// The steepness coefficients steep (params.hpp order, highest first) of order
// m(steep) raised to order `to`: P and Q both multiplied by (κ + 1) per step,
// so t(κ) is the same function (a start for a higher order that begins at the
// lower one's error). Every coefficient stays positive.
std::vector<double> raise_steepness_order(const std::vector<double>& steep, std::size_t to) {
  std::size_t m = (steep.size() - 1) / 2;
  std::vector<double> p{1.0}, q{1.0};  // monic, highest first
  p.insert(p.end(), steep.begin(), steep.begin() + long(m));
  q.insert(q.end(), steep.begin() + long(m), steep.end());
  const auto times_kappa_plus_one = [](std::vector<double>& c) {
    c.push_back(0.0);
    for (std::size_t i = c.size() - 1; i > 0; --i) c[i] += c[i - 1];
  };
  for (; m < to; ++m) times_kappa_plus_one(p), times_kappa_plus_one(q);
  std::vector<double> out(p.begin() + 1, p.end());
  out.insert(out.end(), q.begin() + 1, q.end());
  return out;
}

// Start values (steep[2M + 1], num, scale) for member (N, D, M) from the per-κ optima.
template <std::size_t N, std::size_t D, std::size_t M>
std::vector<double> staged_start(const std::vector<KappaOptimum>& optima) {
  FitOptions ls;
  ls.norm = Norm::least_squares;
  ls.solver_iterations = 200;
  Parameters steep;
  const auto& s0 = constants::steepness2024_irradiance;
  steep.names = {"logA", "logB", "logC", "logD", "logE"};
  steep.values = {std::log(s0.A), std::log(s0.B), std::log(s0.C), std::log(s0.D), std::log(s0.E)};
  bound(steep);
  Residuals rs;
  for (const auto& o : optima) {
    const double w =
        1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    rs.push_back(make_residual(LogSteepnessResidual{o.kappa, std::log(o.t), w}, 5));
  }
  const FitResult ft = fit(rs, steep, ls);
  Parameters fade;
  for (std::size_t i = 0; i < N * (D + 1); ++i)
    fade.names.push_back(fmt::format("num{}", i)), fade.values.push_back(0.0);
  fade.names.push_back("log_scale");
  // u = 1/2 at t = 2 (κ ≈ 8), the middle of the 2024 form's residual
  fade.values.push_back(std::log(2.0));
  bound(fade);
  Residuals rr;
  for (const auto& o : optima) {
    const double w =
        1 - irradiance_lower_over_two_pi(o.kappa) / irradiance_upper_over_two_pi(o.kappa);
    for (std::size_t j = 0; j < N; ++j)
      rr.push_back(make_residual(FadeResidual<N, D>{o.t, w, j, o.b[j]}, fade.size()));
  }
  // Polynomials first (linear, scale fixed), then everything.
  Parameters num_only = fade;
  num_only.fixed.assign(fade.size(), false);
  num_only.fixed.back() = true;
  fade.values = fit(rr, num_only, ls).values;
  const FitResult fr = fit(rr, fade, ls);
  std::vector<double> out;
  for (double v : ft.values) out.push_back(std::exp(v));
  out = raise_steepness_order(out, M);
  out.insert(out.end(), fr.values.begin(), fr.values.begin() + N * (D + 1));
  out.push_back(std::exp(fr.values.back()));
  return out;
}

}  // namespace

const std::vector<KappaOptimum>& Floors::get(std::size_t n,
                                             const std::vector<SglabAccSample>& train) {
  auto it = by_terms.find(n);
  if (it != by_terms.end()) return it->second;
  std::vector<KappaOptimum> o =
      with_terms(n, [&](auto N) { return per_kappa_optima<decltype(N)::value>(train); });
  return by_terms.emplace(n, std::move(o)).first->second;
}

double Floors::floor(std::size_t n, const std::vector<SglabAccSample>& train) {
  double m = 0;
  for (const auto& o : get(n, train)) m = std::max(m, o.error);
  return m;
}

namespace {

std::vector<double> staged_start_any(Member m, Floors& floors,
                                     const std::vector<SglabAccSample>& train) {
  const auto& optima = floors.get(m.n, train);
  return with_member(m,
                     [&](auto N, auto D, auto M) { return staged_start<N(), D(), M()>(optima); });
}

}  // namespace

std::vector<double> embed(Member from, const std::vector<double>& values, Member to) {
  const std::size_t kf = steep_count(from.m), kt = steep_count(to.m);
  std::vector<double> v =
      raise_steepness_order(std::vector<double>(values.begin(), values.begin() + long(kf)), to.m);
  v.resize(kt + to.n * (to.d + 1), 0.0);
  for (std::size_t j = 0; j < from.n; ++j)
    for (std::size_t k = 0; k <= from.d; ++k)
      v[kt + j * (to.d + 1) + k] = values[kf + j * (from.d + 1) + k];
  v.push_back(values.back());  // scale
  return v;
}

std::vector<double> start_for(Member m, const std::vector<MemberFit>& earlier, Floors& floors,
                              const std::vector<SglabAccSample>& train) {
  for (auto it = earlier.rbegin(); it != earlier.rend(); ++it) {
    const Member e = it->member;
    if (e.n > m.n || e.d > m.d || e.m > m.m) continue;
    return embed(e, it->values, m);
  }
  return staged_start_any(m, floors, train);
}

std::optional<std::pair<std::vector<double>, bool>> committed(const std::string& variant, Member m,
                                                              double lo, double hi) {
  const auto c = committed_coefficients("sglab-acc", variant, lo, hi);
  if (!c) return std::nullopt;
  try {
    std::vector<double> v = c->at("steep").get<std::vector<double>>();
    const auto num = c->at("num").get<std::vector<double>>();
    if (!c->contains("scale") || v.size() % 2 != 1 || num.size() % m.n != 0) return std::nullopt;
    const Member own{m.n, num.size() / m.n - 1, (v.size() - 1) / 2};
    if (own.d > m.d || own.m > m.m || own.m < 1) return std::nullopt;
    v.insert(v.end(), num.begin(), num.end());
    v.push_back(c->at("scale").get<double>());
    return std::pair{embed(own, v, m), own == m};
  } catch (const std::exception&) {
    return std::nullopt;  // another shape: fit from the lower member
  }
}

}  // namespace sglab::fit::acc
