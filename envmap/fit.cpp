// envmap/fit.cpp — SG mixtures fitted to an environment map with Ceres: the
// BakingLab fixed-axis NNLS baseline, the joint radiance fit and the joint
// irradiance fit (envmap.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <fmt/format.h>

#include <sglab/registry.hpp>

#include "envmap/envmap.hpp"
#include "envmap/probe.hpp"

namespace sglab::envmap {

namespace {

using io::InputError;

double dot3(const double* a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The map in fitting units: radiance divided by its solid-angle mean `scale`
// (so amplitudes are O(1)), with the per-row weight √ΔΩ and pixel directions.
struct Samples {
  std::size_t width = 0, height = 0;
  double scale = 1;
  std::vector<double> weight;  // per row, √ΔΩ
  std::vector<Vec3> dir;       // per pixel
  std::vector<double> value;   // per pixel × 3, radiance / scale
};

Samples samples_of(const Map& map) {
  Samples s;
  s.width = map.width;
  s.height = map.height;
  double total = 0;
  for (std::size_t j = 0; j < map.height; ++j) {
    const double om = pixel_solid_angle(map, j);
    s.weight.push_back(std::sqrt(om));
    for (std::size_t i = 0; i < map.width; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch) total += om * map.at(i, j, ch);
  }
  s.scale = total / (3 * 4 * M_PI);
  if (!(s.scale > 0)) s.scale = 1;
  s.dir.resize(map.width * map.height);
  s.value.resize(map.width * map.height * 3);
  for (std::size_t j = 0; j < map.height; ++j)
    for (std::size_t i = 0; i < map.width; ++i) {
      s.dir[j * map.width + i] = pixel_direction(map, i, j);
      for (std::size_t ch = 0; ch < 3; ++ch)
        s.value[(j * map.width + i) * 3 + ch] = map.at(i, j, ch) / s.scale;
    }
  return s;
}

// Lobe parameters as Ceres blocks: axis[3] (on the unit sphere), kappa[1], amp[3].
struct Params {
  std::vector<std::array<double, 3>> axis;
  std::vector<double> kappa;
  std::vector<std::array<double, 3>> amp;
  std::size_t size() const { return kappa.size(); }
};

// Radiance residuals of one row: √ΔΩ_j (Σ_k a_k G_k(ω) − L(ω)), 3 per pixel.
class RowCost final : public ceres::CostFunction {
 public:
  RowCost(const Samples& s, std::size_t row, std::size_t lobes) : s_(s), row_(row), lobes_(lobes) {
    set_num_residuals(static_cast<int>(3 * s.width));
    for (std::size_t k = 0; k < lobes; ++k) {
      mutable_parameter_block_sizes()->push_back(3);
      mutable_parameter_block_sizes()->push_back(1);
      mutable_parameter_block_sizes()->push_back(3);
    }
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    const double w = s_.weight[row_];
    const std::size_t W = s_.width;
    for (std::size_t i = 0; i < W; ++i)
      for (std::size_t ch = 0; ch < 3; ++ch) r[3 * i + ch] = -w * s_.value[(row_ * W + i) * 3 + ch];
    if (jac)
      for (std::size_t k = 0; k < 3 * lobes_; ++k)
        if (jac[k]) std::fill(jac[k], jac[k] + 3 * W * (k % 3 == 1 ? 1 : 3), 0.0);
    for (std::size_t k = 0; k < lobes_; ++k) {
      const double* mu = p[3 * k];
      const double kappa = p[3 * k + 1][0];
      const double* a = p[3 * k + 2];
      for (std::size_t i = 0; i < W; ++i) {
        const Vec3& om = s_.dir[row_ * W + i];
        const double c = dot3(mu, om);
        const double g = std::exp(kappa * (c - 1));
        for (std::size_t ch = 0; ch < 3; ++ch) r[3 * i + ch] += w * a[ch] * g;
        if (!jac) continue;
        for (std::size_t ch = 0; ch < 3; ++ch) {
          const std::size_t ri = 3 * i + ch;
          if (double* J = jac[3 * k])
            for (std::size_t d = 0; d < 3; ++d) J[ri * 3 + d] = w * a[ch] * kappa * g * om[d];
          if (double* J = jac[3 * k + 1]) J[ri] = w * a[ch] * (c - 1) * g;
          if (double* J = jac[3 * k + 2]) J[ri * 3 + ch] = w * g;
        }
      }
    }
    return true;
  }

 private:
  const Samples& s_;
  std::size_t row_, lobes_;
};

// The SG irradiance Ê(c, κ) of a unit-amplitude lobe (sglab_acc3, double) and
// its partial derivatives: the registry's own template instantiated with a
// Ceres Jet of two partials (forward-mode automatic differentiation), so the
// derivatives are those of the code that computes Ê, branches included.
const Method& accurate_method() {
  static const Method* m = find_method(irradiance_methods, "sglab_acc3");
  if (!m) throw std::logic_error("sglab_acc3 is not registered");
  return *m;
}

struct IrrValue {
  double e, de_dc, de_dk;
};

using Gradient = void (*)(double c, double kappa, double* de_dc, double* de_dk);

template <class F>
void gradient_of(double c, double kappa, double* de_dc, double* de_dk) {
  using Jet = ceres::Jet<double, 2>;
  const Jet e = F{}(Jet(c, 0), Jet(kappa, 1));
  *de_dc = e.v[0];
  *de_dk = e.v[1];
}

struct CollectGradients {
  template <class... M>
  constexpr std::array<Gradient, sizeof...(M)> operator()(const M&...) const {
    return {&gradient_of<typename M::Functor>...};
  }
};

Gradient accurate_gradient() {
  static constexpr auto kGradients = with_irradiance_methods(CollectGradients{});
  static const Gradient g = [] {
    for (std::size_t i = 0; i < std::size(irradiance_methods); ++i)
      if (irradiance_methods[i].id == "sglab_acc3") return kGradients[i];
    throw std::logic_error("sglab_acc3 is not registered");
  }();
  return g;
}

IrrValue sg_irradiance_d(double c, double kappa) {
  c = std::clamp(c, -1.0, 1.0);
  IrrValue v;
  v.e = accurate_method().f64(c, kappa);
  accurate_gradient()(c, kappa, &v.de_dc, &v.de_dk);
  return v;
}

// Irradiance residuals of a chunk of normals:
// (Σ_k a_k Ê(a_k·n, κ_k) [+ Σ_lm c_lm Y_lm(n)] − E(n)) / π, the SH block (order
// sh_order ≥ 0, 3 per coefficient) after the lobes' blocks; each multiplied by
// its `scale` (3 per normal, all normals; none: 1) when given.
class NormalsCost final : public ceres::CostFunction {
 public:
  NormalsCost(const std::vector<Vec3>& normals, const std::vector<Vec3>& target, std::size_t first,
              std::size_t count, std::size_t lobes, int sh_order = -1,
              const std::vector<double>* scale = nullptr)
      : normals_(normals),
        target_(target),
        first_(first),
        count_(count),
        lobes_(lobes),
        sh_order_(sh_order),
        scale_(scale) {
    set_num_residuals(static_cast<int>(3 * count));
    for (std::size_t k = 0; k < lobes; ++k) {
      mutable_parameter_block_sizes()->push_back(3);
      mutable_parameter_block_sizes()->push_back(1);
      mutable_parameter_block_sizes()->push_back(3);
    }
    if (sh_order >= 0)
      mutable_parameter_block_sizes()->push_back(static_cast<int>(3 * sh_count(sh_order)));
  }
  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    const double inv_pi = 1 / M_PI;
    for (std::size_t m = 0; m < count_; ++m)
      for (std::size_t ch = 0; ch < 3; ++ch) r[3 * m + ch] = -target_[first_ + m][ch] * inv_pi;
    if (jac)
      for (std::size_t k = 0; k < 3 * lobes_; ++k)
        if (jac[k]) std::fill(jac[k], jac[k] + 3 * count_ * (k % 3 == 1 ? 1 : 3), 0.0);
    for (std::size_t k = 0; k < lobes_; ++k) {
      const double* mu = p[3 * k];
      const double kappa = p[3 * k + 1][0];
      const double* a = p[3 * k + 2];
      for (std::size_t m = 0; m < count_; ++m) {
        const Vec3& n = normals_[first_ + m];
        const IrrValue v = sg_irradiance_d(dot3(mu, n), kappa);
        for (std::size_t ch = 0; ch < 3; ++ch) r[3 * m + ch] += a[ch] * v.e * inv_pi;
        if (!jac) continue;
        for (std::size_t ch = 0; ch < 3; ++ch) {
          const std::size_t ri = 3 * m + ch;
          if (double* J = jac[3 * k])
            for (std::size_t d = 0; d < 3; ++d) J[ri * 3 + d] = a[ch] * v.de_dc * n[d] * inv_pi;
          if (double* J = jac[3 * k + 1]) J[ri] = a[ch] * v.de_dk * inv_pi;
          if (double* J = jac[3 * k + 2]) J[ri * 3 + ch] = v.e * inv_pi;
        }
      }
    }
    if (sh_order_ >= 0) {
      const std::size_t K = sh_count(sh_order_);
      const double* c = p[3 * lobes_];
      double* J = jac ? jac[3 * lobes_] : nullptr;
      if (J) std::fill(J, J + 3 * count_ * 3 * K, 0.0);
      std::array<double, sh_count(kMaxShOrder)> y{};
      for (std::size_t m = 0; m < count_; ++m) {
        const Vec3& n = normals_[first_ + m];
        sh_basis(sh_order_, n[0], n[1], n[2], y.data());
        for (std::size_t q = 0; q < K; ++q)
          for (std::size_t ch = 0; ch < 3; ++ch) {
            r[3 * m + ch] += c[3 * q + ch] * y[q] * inv_pi;
            if (J) J[(3 * m + ch) * 3 * K + 3 * q + ch] = y[q] * inv_pi;
          }
      }
    }
    if (scale_) {
      const auto& sizes = parameter_block_sizes();
      for (std::size_t i = 0; i < 3 * count_; ++i) {
        const double w = (*scale_)[3 * first_ + i];
        r[i] *= w;
        if (!jac) continue;
        for (std::size_t b = 0; b < sizes.size(); ++b)
          if (double* J = jac[b]) {
            const auto cols = static_cast<std::size_t>(sizes[b]);
            for (std::size_t d = 0; d < cols; ++d) J[i * cols + d] *= w;
          }
      }
    }
    return true;
  }

 private:
  const std::vector<Vec3>& normals_;
  const std::vector<Vec3>& target_;
  std::size_t first_, count_, lobes_;
  int sh_order_;
  const std::vector<double>* scale_;
};

// The sharpest lobe: standard deviation 1/√κ no smaller than one pixel
// (π/H) of the working copy, so that a lobe sampled at pixel centres keeps its
// integral (a Gaussian sampled at its own σ sums to its integral within 1e−8).
double kappa_max(const Samples& s) {
  const double h = static_cast<double>(s.height) / M_PI;
  return h * h;
}
constexpr double kKappaMin = 1e-2;
constexpr std::size_t kCoarseWidth = 64;

void configure(ceres::Problem& problem, Params& p, double kmax, bool fix_shape) {
  for (std::size_t k = 0; k < p.size(); ++k) {
    problem.SetManifold(p.axis[k].data(), new ceres::SphereManifold<3>());
    problem.SetParameterLowerBound(&p.kappa[k], 0, kKappaMin);
    problem.SetParameterUpperBound(&p.kappa[k], 0, kmax);
    for (int ch = 0; ch < 3; ++ch) problem.SetParameterLowerBound(p.amp[k].data(), ch, 0.0);
    if (fix_shape) {
      problem.SetParameterBlockConstant(p.axis[k].data());
      problem.SetParameterBlockConstant(&p.kappa[k]);
    }
  }
}

struct SolveOutcome {
  int iterations = 0;
  bool converged = false;
};

SolveOutcome solve(ceres::Problem& problem, int max_iterations) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  o.num_threads = 1;  // deterministic: the same input gives the same bytes
  o.max_num_iterations = max_iterations;
  o.function_tolerance = 1e-10;
  o.gradient_tolerance = 1e-12;
  o.parameter_tolerance = 1e-10;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &problem, &summary);
  return {static_cast<int>(summary.iterations.size()),
          summary.termination_type == ceres::CONVERGENCE};
}

// BakingLab's spiral and shared sharpness (fit_baseline's comment).
Params baseline_params(std::size_t n, double kmax) {
  Params p;
  const double inc = M_PI * (3 - std::sqrt(5.0)), off = 2.0 / static_cast<double>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double z = static_cast<double>(k) * off - 1 + off / 2;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = static_cast<double>(k) * inc;
    p.axis.push_back({std::cos(phi) * r, std::sin(phi) * r, z});
  }
  double min_dp = n > 1 ? 1.0 : 0.0;  // one lobe: as if its neighbour were 90° away
  for (std::size_t k = 1; k < n; ++k) {
    std::array<double, 3> h{p.axis[k][0] + p.axis[0][0], p.axis[k][1] + p.axis[0][1],
                            p.axis[k][2] + p.axis[0][2]};
    const double len = std::hypot(h[0], h[1], h[2]);
    if (len > 0)
      min_dp =
          std::min(min_dp, (h[0] * p.axis[0][0] + h[1] * p.axis[0][1] + h[2] * p.axis[0][2]) / len);
  }
  const double kappa =
      std::clamp(std::log(0.65) * static_cast<double>(n) / (min_dp - 1), kKappaMin, kmax);
  p.kappa.assign(n, kappa);
  p.amp.assign(n, {0.0, 0.0, 0.0});
  return p;
}

void add_radiance_residuals(ceres::Problem& problem, const Samples& s, Params& p) {
  std::vector<double*> blocks;
  for (std::size_t k = 0; k < p.size(); ++k) {
    blocks.push_back(p.axis[k].data());
    blocks.push_back(&p.kappa[k]);
    blocks.push_back(p.amp[k].data());
  }
  for (std::size_t j = 0; j < s.height; ++j)
    problem.AddResidualBlock(new RowCost(s, j, p.size()), nullptr, blocks);
}

// Radiance NNLS with fixed axes and sharpness: amplitudes ≥ 0 (the baseline, and
// the start of the joint fit).
void solve_amplitudes(const Samples& s, Params& p) {
  for (auto& a : p.amp) a = {0.1, 0.1, 0.1};
  ceres::Problem problem;
  add_radiance_residuals(problem, s, p);
  configure(problem, p, kappa_max(s), /*fix_shape=*/true);
  solve(problem, 100);
}

std::vector<Lobe> lobes_of(const Params& p, double scale) {
  std::vector<Lobe> out;
  for (std::size_t k = 0; k < p.size(); ++k) {
    Lobe l;
    const double len = std::hypot(p.axis[k][0], p.axis[k][1], p.axis[k][2]);
    for (std::size_t d = 0; d < 3; ++d) l.axis[d] = p.axis[k][d] / len;
    l.sharpness = p.kappa[k];
    for (std::size_t ch = 0; ch < 3; ++ch) l.amplitude[ch] = std::max(0.0, p.amp[k][ch]) * scale;
    out.push_back(l);
  }
  return out;
}

// Every parameter of p (and the SH block `sh`, 3 per coefficient of order 2,
// when given) jointly on the irradiance at the normals.
SolveOutcome refine_irradiance(Params& p, std::vector<double>* sh, const std::vector<Vec3>& normals,
                               const std::vector<Vec3>& target, double kmax, int max_iterations,
                               const std::vector<double>* scale = nullptr) {
  ceres::Problem problem;
  std::vector<double*> blocks;
  for (std::size_t k = 0; k < p.size(); ++k) {
    blocks.push_back(p.axis[k].data());
    blocks.push_back(&p.kappa[k]);
    blocks.push_back(p.amp[k].data());
  }
  if (sh) blocks.push_back(sh->data());
  const std::size_t chunk = 64;
  for (std::size_t m = 0; m < normals.size(); m += chunk)
    problem.AddResidualBlock(
        new NormalsCost(normals, target, m, std::min(chunk, normals.size() - m), p.size(),
                        sh ? 2 : -1, scale),
        nullptr, blocks);
  configure(problem, p, kmax, false);
  return solve(problem, max_iterations);
}

// The residuals of p (and `sh`) at every normal, 3 per normal, unscaled.
std::vector<double> irradiance_residuals(const Params& p, std::vector<double>* sh,
                                         const std::vector<Vec3>& normals,
                                         const std::vector<Vec3>& target) {
  std::vector<const double*> blocks;
  for (std::size_t k = 0; k < p.size(); ++k) {
    blocks.push_back(p.axis[k].data());
    blocks.push_back(&p.kappa[k]);
    blocks.push_back(p.amp[k].data());
  }
  if (sh) blocks.push_back(sh->data());
  std::vector<double> r(3 * normals.size());
  const NormalsCost cost(normals, target, 0, normals.size(), p.size(), sh ? 2 : -1);
  cost.Evaluate(blocks.data(), r.data(), nullptr);
  return r;
}

double max_abs(const std::vector<double>& r) {
  double m = 0;
  for (double x : r) m = std::max(m, std::abs(x));
  return m;
}

// The minimax of the residuals at the normals by Lawson's iteration
// [Lawson1961]: weighted least squares with weights u_i ← u_i |r_i| / Σ u_j |r_j|
// from the least-squares solution p (u = 1), each round refining every
// parameter from the last; p (and `sh`) become the round with the smallest max
// |r_i| (p itself when no round improves on it). Deterministic.
void minimax_irradiance(Params& p, std::vector<double>* sh, const std::vector<Vec3>& normals,
                        const std::vector<Vec3>& target, double kmax, int rounds,
                        int max_iterations) {
  std::vector<double> r = irradiance_residuals(p, sh, normals, target);
  Params best = p;
  std::vector<double> best_sh = sh ? *sh : std::vector<double>{};
  double best_max = max_abs(r);
  std::vector<double> u(r.size(), 1.0), scale(r.size());
  for (int round = 0; round < rounds; ++round) {
    double total = 0;
    for (std::size_t i = 0; i < u.size(); ++i) total += u[i] *= std::abs(r[i]);
    if (!(total > 0)) break;
    const double mean = total / static_cast<double>(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) {
      u[i] /= mean;
      scale[i] = std::sqrt(u[i]);
    }
    refine_irradiance(p, sh, normals, target, kmax, max_iterations, &scale);
    r = irradiance_residuals(p, sh, normals, target);
    const double m = max_abs(r);
    if (m < best_max) {
      best_max = m;
      best = p;
      if (sh) best_sh = *sh;
    }
  }
  p = best;
  if (sh) *sh = best_sh;
}

Params params_of(const std::vector<Lobe>& lobes, double scale) {
  Params p;
  for (const Lobe& l : lobes) {
    p.axis.push_back({l.axis[0], l.axis[1], l.axis[2]});
    p.kappa.push_back(l.sharpness);
    p.amp.push_back({l.amplitude[0] / scale, l.amplitude[1] / scale, l.amplitude[2] / scale});
  }
  return p;
}

// The irradiance's scale: its mean over the normals divided by π (the mean radiance).
double irradiance_scale(const std::vector<Vec3>& exact) {
  double total = 0;
  for (const Vec3& e : exact) total += e[0] + e[1] + e[2];
  const double s = total / (3 * M_PI * static_cast<double>(std::max<std::size_t>(exact.size(), 1)));
  return s > 0 ? s : 1;
}

// The best new lobe for a probe whose irradiance at the normals is `current`:
// at the normal where E_map − E_probe (luminance) is largest, κ = 16, its
// amplitude the residual there divided by Ê(1, 16).
Lobe new_lobe(const std::vector<Vec3>& normals, const std::vector<Vec3>& exact,
              const std::vector<Vec3>& current) {
  std::size_t arg = 0;
  double best = -HUGE_VAL;
  for (std::size_t m = 0; m < normals.size(); ++m) {
    double r = 0;
    for (std::size_t ch = 0; ch < 3; ++ch) r += kLuminance[ch] * (exact[m][ch] - current[m][ch]);
    if (r > best) {
      best = r;
      arg = m;
    }
  }
  const double kappa = 16, peak = accurate_method().f64(1.0, kappa);
  Lobe l;
  l.axis = normals[arg];
  l.sharpness = kappa;
  for (std::size_t ch = 0; ch < 3; ++ch)
    l.amplitude[ch] = std::max(1e-6, exact[arg][ch] - current[arg][ch]) / peak;
  return l;
}

// The start of the ladder's restart `r` at n lobes: the axes drawn from the
// working copy's light (each pixel's luminance × solid angle, by the inverse of
// its cumulative sum) at the points r·n + 1 … r·n + n of the 2-D R2 sequence
// [Roberts2018], the second coordinate setting κ log-uniform on
// [1, min(kmax, 256)]; each lobe carries 1/n of the map's light,
// a = 2κ/n in fitting units (∫ a e^{κ(μ·ω − 1)} dω ≈ 2πa/κ against 4π).
// Deterministic.
Params restart_params(const Samples& s, std::size_t n, std::size_t r, double kmax) {
  std::vector<double> cdf(s.dir.size());
  double total = 0;
  for (std::size_t q = 0; q < s.dir.size(); ++q) {
    const double w = s.weight[q / s.width];
    const double* v = &s.value[3 * q];
    total += w * w * (kLuminance[0] * v[0] + kLuminance[1] * v[1] + kLuminance[2] * v[2]);
    cdf[q] = total;
  }
  const double g = 1.32471795724474602596;  // the plastic number, R2's constant
  const double a1 = 1 / g, a2 = 1 / (g * g);
  const double kappa_hi = std::min(kmax, 256.0);
  Params p;
  for (std::size_t k = 0; k < n; ++k) {
    const double q = static_cast<double>(r * n + k + 1);
    const double u = std::fmod(0.5 + a1 * q, 1.0), v = std::fmod(0.5 + a2 * q, 1.0);
    const std::size_t at = std::min<std::size_t>(
        std::lower_bound(cdf.begin(), cdf.end(), u * total) - cdf.begin(), cdf.size() - 1);
    const Vec3& d = s.dir[at];
    const double kappa = std::exp(v * std::log(kappa_hi));
    const double a = 2 * kappa / static_cast<double>(n);
    p.axis.push_back({d[0], d[1], d[2]});
    p.kappa.push_back(kappa);
    p.amp.push_back({a, a, a});
  }
  return p;
}

std::vector<Vec3> evaluate(const Probe& probe, const std::vector<Vec3>& normals) {
  const IrradianceFn f = probe_irradiance(probe);
  std::vector<Vec3> out;
  for (const Vec3& n : normals) out.push_back(f(n));
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void check_lobe_count(const Map& work, std::size_t lobes) {
  if (lobes == 0) throw InputError("--lobes 0: at least one lobe is needed");
  if (lobes > max_lobes(work))
    throw InputError(fmt::format(
        "--lobes {}: more than the map supports (at most {} for a {} x {} working copy: one lobe "
        "per 32 pixels, at most 256)",
        lobes, max_lobes(work), work.width, work.height));
  const double bytes = fit_memory_bytes(work, lobes);
  if (bytes > static_cast<double>(kMaxFitBytes))
    throw InputError(fmt::format(
        "--lobes {} on a {} x {} map: the fit would hold about {:.3g} GB ({} bytes per pixel "
        "and lobe), more than the {:.3g} GB a fit may hold; fit its working copy (at most 128 x "
        "64)",
        lobes, work.width, work.height, bytes / 1e9, kFitBytesPerPixelLobe,
        static_cast<double>(kMaxFitBytes) / 1e9));
}

double fit_memory_bytes(const Map& work, std::size_t lobes) {
  return static_cast<double>(work.width) * static_cast<double>(work.height) *
         static_cast<double>(lobes) * static_cast<double>(kFitBytesPerPixelLobe);
}

std::size_t max_lobes(const Map& work) {
  return std::min<std::size_t>(256, work.width * work.height / 32);
}

std::vector<Lobe> fit_baseline(const Map& work, std::size_t lobes) {
  check_lobe_count(work, lobes);
  const Samples s = samples_of(work);
  Params p = baseline_params(lobes, kappa_max(s));
  solve_amplitudes(s, p);
  return lobes_of(p, s.scale);
}

FitReport fit(const Map& work, const std::vector<Vec3>& exact_at_fit_normals,
              const FitOptions& options) {
  return fit_with_normals(work, reference::fibonacci_normals(options.fit_normals),
                          exact_at_fit_normals, options);
}

FitReport fit_with_normals(const Map& work, const std::vector<Vec3>& normals,
                           const std::vector<Vec3>& exact_at_fit_normals,
                           const FitOptions& options) {
  check_lobe_count(work, options.lobes);
  const Samples s = samples_of(work);
  const double kmax = kappa_max(s);
  // The radiance stage: on the working copy for the radiance objective; as the
  // start of the irradiance objective, on a 64 × 32 copy (4× fewer residuals
  // for a 128 × 64 map; the irradiance stage refines every parameter anyway).
  const bool coarse = options.objective == Objective::irradiance && work.width > kCoarseWidth &&
                      options.lobes <= kCoarseWidth * kCoarseWidth / 64;
  const Samples rs = coarse ? samples_of(downsample(work, kCoarseWidth)) : s;
  Params p = baseline_params(options.lobes, kappa_max(rs));
  solve_amplitudes(rs, p);
  FitReport report;
  {
    ceres::Problem problem;
    add_radiance_residuals(problem, rs, p);
    configure(problem, p, kappa_max(rs), false);
    const SolveOutcome o = solve(problem, options.max_iterations);
    report.iterations += o.iterations;
    report.converged = o.converged;
  }
  for (auto& a : p.amp)
    for (double& x : a) x *= rs.scale / s.scale;  // the same units as the working copy's
  if (options.objective == Objective::irradiance) {
    if (exact_at_fit_normals.size() != normals.size())
      throw std::logic_error("envmap::fit: the exact irradiance is not given at the fit normals");
    std::vector<Vec3> target(normals.size());
    for (std::size_t m = 0; m < normals.size(); ++m)
      for (std::size_t ch = 0; ch < 3; ++ch) target[m][ch] = exact_at_fit_normals[m][ch] / s.scale;
    const SolveOutcome o =
        refine_irradiance(p, nullptr, normals, target, kmax, options.max_iterations);
    report.iterations += o.iterations;
    report.converged = o.converged;
  }
  report.lobes = lobes_of(p, s.scale);
  return report;
}

reference::Scene to_scene(const std::vector<Lobe>& lobes) {
  reference::Scene scene;
  for (const Lobe& l : lobes) scene.lights.push_back({l.axis, l.sharpness, l.amplitude});
  return scene;
}

std::vector<Vec3> lobes_irradiance_exact(const std::vector<Lobe>& lobes,
                                         const std::vector<Vec3>& normals) {
  double largest = 0;
  for (const Lobe& l : lobes)
    for (double a : l.amplitude) largest = std::max(largest, a);
  if (!(largest > 0)) return std::vector<Vec3>(normals.size(), Vec3{0, 0, 0});
  std::vector<Vec3> e = reference::scene_irradiance_reference(to_scene(lobes), normals);
  for (auto& v : e)
    for (double& x : v) x *= largest;
  return e;
}

Map reconstruct(const std::vector<Lobe>& lobes, std::size_t width, std::size_t height) {
  Map m;
  m.width = width;
  m.height = height;
  m.rgb.assign(width * height * 3, 0.0f);
  for (std::size_t j = 0; j < height; ++j)
    for (std::size_t i = 0; i < width; ++i) {
      const Vec3 om = pixel_direction(m, i, j);
      for (const Lobe& l : lobes) {
        const double g =
            std::exp(l.sharpness * (l.axis[0] * om[0] + l.axis[1] * om[1] + l.axis[2] * om[2] - 1));
        for (std::size_t ch = 0; ch < 3; ++ch)
          m.rgb[(j * width + i) * 3 + ch] += static_cast<float>(l.amplitude[ch] * g);
      }
    }
  return m;
}

namespace {

// The previous step's probe with `lobe` at zero amplitude: never worse than that step.
LadderStep with_zero_lobe(const Probe& previous, Lobe lobe, const std::string& start) {
  LadderStep step;
  step.probe = previous;
  lobe.amplitude = {0, 0, 0};
  step.probe.lobes.push_back(lobe);
  step.start = start;
  return step;
}

using Refine = std::function<LadderStep(const LadderStep&)>;

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Judges every candidate; with `refine`, the best of the fresh and grown fits
// and the restart (each new, not the previous step kept) refined and judged
// too; appends the best of all (the first of equals) to `ladder`, with the
// step's wall time since t0.
void keep_best(std::vector<LadderStep>& candidates, const Judge& judge,
               std::chrono::steady_clock::time_point t0, std::vector<LadderStep>& ladder,
               const std::function<LadderStep(const LadderStep&)>& refine) {
  for (auto& c : candidates) c.judged = judge(c.probe);
  if (refine) {
    const std::size_t none = candidates.size();
    std::size_t fresh = none, restart = none;
    for (std::size_t k = 0; k < none; ++k) {
      if (starts_with(candidates[k].start, "kept")) continue;
      std::size_t& best = starts_with(candidates[k].start, "restart") ? restart : fresh;
      if (best == none || candidates[k].judged < candidates[best].judged) best = k;
    }
    for (const std::size_t k : {fresh, restart}) {
      if (k == none) continue;
      LadderStep r = refine(candidates[k]);
      r.start = candidates[k].start + " minimax";
      r.judged = judge(r.probe);
      candidates.push_back(r);
    }
  }
  std::size_t best = 0;
  for (std::size_t k = 1; k < candidates.size(); ++k)
    if (candidates[k].judged < candidates[best].judged) best = k;
  ladder.push_back(candidates[best]);
  ladder.back().seconds = seconds_since(t0);
}

}  // namespace

std::vector<Lobe> restart_lobes(const Map& work, std::size_t lobes, std::size_t restart) {
  const Samples s = samples_of(work);
  return lobes_of(restart_params(s, lobes, restart, kappa_max(s)), s.scale);
}

std::vector<LadderStep> fit_lobe_ladder(const Map& work, const std::vector<Vec3>& fit_normals,
                                        const std::vector<Vec3>& exact, std::size_t max_lobes,
                                        const Judge& judge, int max_iterations, int minimax_rounds,
                                        int restarts) {
  std::vector<std::size_t> counts(max_lobes);
  for (std::size_t n = 0; n < max_lobes; ++n) counts[n] = n + 1;
  check_lobe_count(work, max_lobes);
  return fit_lobe_ladder(work, fit_normals, exact, counts, judge, max_iterations, minimax_rounds,
                         restarts);
}

namespace {

// One ladder (fit_lobe_ladder), with `restarts` restarts at each step: the
// steps of `counts` appended to `ladder` (each larger than its last count).
void lobe_ladder_path(std::vector<LadderStep>& ladder, const Map& work,
                      const std::vector<Vec3>& fit_normals, const std::vector<Vec3>& exact,
                      const std::vector<std::size_t>& counts, const Judge& judge,
                      int max_iterations, int minimax_rounds, int restarts) {
  const double scale = irradiance_scale(exact);
  const Samples samples = samples_of(work);
  const double kmax = kappa_max(samples);
  std::vector<Vec3> target(exact.size());
  for (std::size_t m = 0; m < exact.size(); ++m)
    for (std::size_t ch = 0; ch < 3; ++ch) target[m][ch] = exact[m][ch] / scale;
  // The minimax refinement of a candidate (keep_best).
  const Refine refine = minimax_rounds <= 0 ? Refine{} : Refine{[&](const LadderStep& from) {
    LadderStep c = from;
    Params p = params_of(c.probe.lobes, scale);
    minimax_irradiance(p, nullptr, fit_normals, target, kmax, minimax_rounds, kMinimaxIterations);
    c.probe.lobes = lobes_of(p, scale);
    return c;
  }};
  for (const std::size_t n : counts) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<LadderStep> candidates;
    // A fresh fit: radiance stage, then the irradiance.
    FitOptions o;
    o.lobes = n;
    o.objective = Objective::irradiance;
    o.max_iterations = max_iterations;
    {
      LadderStep c;
      c.probe.kind = ProbeKind::lobes;
      c.probe.fit = "fit";
      c.probe.lobes = fit_with_normals(work, fit_normals, exact, o).lobes;
      c.start = "fresh";
      candidates.push_back(c);
    }
    // Restarts from the map's light, each fitted like the warm start; the one
    // with the smallest max residual at the normals is a candidate.
    {
      Params best;
      double best_max = HUGE_VAL;
      int best_r = 0;
      for (int r = 0; r < restarts; ++r) {
        Params p = restart_params(samples, n, static_cast<std::size_t>(r), kmax);
        refine_irradiance(p, nullptr, fit_normals, target, kmax, max_iterations);
        const double m = max_abs(irradiance_residuals(p, nullptr, fit_normals, target));
        if (m < best_max) {
          best_max = m;
          best = p;
          best_r = r;
        }
      }
      if (best.size() == n) {
        LadderStep c;
        c.probe.kind = ProbeKind::lobes;
        c.probe.fit = "fit";
        c.probe.lobes = lobes_of(best, scale);
        c.start = fmt::format("restart {}", best_r + 1);
        candidates.push_back(c);
      }
    }
    if (!ladder.empty()) {
      // Warm: the previous count's solution plus the best new lobes (each at
      // the largest residual the lobes before it leave), then every parameter.
      const Probe& prev = ladder.back().probe;
      Probe grown = prev;
      while (grown.lobes.size() < n)
        grown.lobes.push_back(new_lobe(fit_normals, exact, evaluate(grown, fit_normals)));
      Params p = params_of(grown.lobes, scale);
      refine_irradiance(p, nullptr, fit_normals, target, kmax, max_iterations);
      LadderStep c;
      c.probe.kind = ProbeKind::lobes;
      c.probe.fit = "fit";
      c.probe.lobes = lobes_of(p, scale);
      c.start = "warm";
      candidates.push_back(c);
      LadderStep kept = with_zero_lobe(prev, prev.lobes.back(), "kept n-1");
      while (kept.probe.lobes.size() < n) kept.probe.lobes.push_back(kept.probe.lobes.back());
      candidates.push_back(kept);
    }
    keep_best(candidates, judge, t0, ladder, refine);
  }
}

// The better of two ladders at each count (the first of equals), each step's
// seconds the sum of both.
std::vector<LadderStep> better_of(const std::vector<LadderStep>& a,
                                  const std::vector<LadderStep>& b) {
  std::vector<LadderStep> out = a;
  for (std::size_t k = 0; k < out.size() && k < b.size(); ++k) {
    if (b[k].judged < a[k].judged) out[k] = b[k];
    out[k].seconds = a[k].seconds + b[k].seconds;
  }
  return out;
}

}  // namespace

std::vector<LadderStep> fit_lobe_ladder(const Map& work, const std::vector<Vec3>& fit_normals,
                                        const std::vector<Vec3>& exact,
                                        const std::vector<std::size_t>& counts, const Judge& judge,
                                        int max_iterations, int minimax_rounds, int restarts) {
  for (std::size_t k = 0; k < counts.size(); ++k)
    if (counts[k] == 0 || (k > 0 && counts[k] <= counts[k - 1]))
      throw std::logic_error("fit_lobe_ladder: lobe counts must increase from 1 or more");
  if (!counts.empty()) check_lobe_count(work, counts.back());
  std::vector<LadderStep> ladder;
  lobe_ladder_path(ladder, work, fit_normals, exact, counts, judge, max_iterations, minimax_rounds,
                   0);
  if (restarts <= 0) return ladder;
  // A second ladder with restarts; at each count the better of the two, so
  // neither ladder's error is exceeded and both being non-increasing, the
  // result is too.
  std::vector<LadderStep> other;
  lobe_ladder_path(other, work, fit_normals, exact, counts, judge, max_iterations, minimax_rounds,
                   restarts);
  return better_of(ladder, other);
}

LobeLadder::LobeLadder(const Map& work, const std::vector<Vec3>& normals,
                       const std::vector<Vec3>& exact, Judge judge, int max_iterations,
                       int minimax_rounds, int restarts)
    : work_(work),
      normals_(normals),
      exact_(exact),
      judge_(std::move(judge)),
      max_iterations_(max_iterations),
      minimax_rounds_(minimax_rounds),
      restarts_(restarts) {}

const std::vector<LadderStep>& LobeLadder::grow_to(std::size_t max_lobes) {
  if (max_lobes <= plain_.size()) return steps_;
  check_lobe_count(work_, max_lobes);
  std::vector<std::size_t> counts;
  for (std::size_t n = plain_.size() + 1; n <= max_lobes; ++n) counts.push_back(n);
  lobe_ladder_path(plain_, work_, normals_, exact_, counts, judge_, max_iterations_,
                   minimax_rounds_, 0);
  if (restarts_ > 0) {
    lobe_ladder_path(restarted_, work_, normals_, exact_, counts, judge_, max_iterations_,
                     minimax_rounds_, restarts_);
    steps_ = better_of(plain_, restarted_);
  } else {
    steps_ = plain_;
  }
  return steps_;
}

std::vector<LadderStep> fit_hybrid_ladder(const Map& work, const std::vector<Vec3>& fit_normals,
                                          const std::vector<Vec3>& exact,
                                          const std::vector<LadderStep>& lobe_ladder,
                                          std::size_t max_lobes, const Judge& judge,
                                          int max_iterations, int minimax_rounds) {
  const double scale = irradiance_scale(exact);
  const double kmax = kappa_max(samples_of(work));
  std::vector<Vec3> target(exact.size());
  for (std::size_t m = 0; m < exact.size(); ++m)
    for (std::size_t ch = 0; ch < 3; ++ch) target[m][ch] = exact[m][ch] / scale;
  const Probe sh_fit = fit_sh(fit_normals, exact, 2);
  // The SH block of lobes plus SH fitted to what the lobes leave, then all jointly.
  const auto joint = [&](std::vector<Lobe> lobes, const std::string& start) {
    Probe only;
    only.kind = ProbeKind::lobes;
    only.lobes = lobes;
    const auto e = evaluate(only, fit_normals);
    std::vector<Vec3> rest(exact.size());
    for (std::size_t m = 0; m < exact.size(); ++m)
      for (std::size_t ch = 0; ch < 3; ++ch) rest[m][ch] = exact[m][ch] - e[m][ch];
    const Probe sh = fit_sh(fit_normals, rest, 2);
    std::vector<double> block;
    for (const Vec3& c : sh.sh)
      for (double x : c) block.push_back(x / scale);
    Params p = params_of(lobes, scale);
    refine_irradiance(p, &block, fit_normals, target, kmax, max_iterations);
    LadderStep c;
    c.probe.kind = ProbeKind::hybrid;
    c.probe.order = 2;
    c.probe.fit = "fit";
    c.probe.lobes = lobes_of(p, scale);
    for (std::size_t q = 0; q < sh_count(2); ++q)
      c.probe.sh.push_back(
          {block[3 * q] * scale, block[3 * q + 1] * scale, block[3 * q + 2] * scale});
    c.start = start;
    return c;
  };
  // The minimax refinement of a candidate, lobes and SH jointly (keep_best).
  const Refine refine = minimax_rounds <= 0 ? Refine{} : Refine{[&](const LadderStep& from) {
    LadderStep c = from;
    Params p = params_of(c.probe.lobes, scale);
    std::vector<double> block;
    for (const Vec3& q : c.probe.sh)
      for (double x : q) block.push_back(x / scale);
    minimax_irradiance(p, &block, fit_normals, target, kmax, minimax_rounds, kMinimaxIterations);
    c.probe.lobes = lobes_of(p, scale);
    for (std::size_t q = 0; q < sh_count(2); ++q)
      c.probe.sh[q] = {block[3 * q] * scale, block[3 * q + 1] * scale, block[3 * q + 2] * scale};
    return c;
  }};
  std::vector<LadderStep> ladder;
  for (std::size_t k = 1; k <= max_lobes; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<LadderStep> candidates;
    if (k <= lobe_ladder.size())
      candidates.push_back(joint(lobe_ladder[k - 1].probe.lobes, "lobes"));
    Probe prev;
    if (ladder.empty()) {
      prev = sh_fit;
      prev.kind = ProbeKind::hybrid;
    } else {
      prev = ladder.back().probe;
    }
    std::vector<Lobe> lobes = prev.lobes;
    lobes.push_back(new_lobe(fit_normals, exact, evaluate(prev, fit_normals)));
    candidates.push_back(joint(lobes, "warm"));
    candidates.push_back(with_zero_lobe(
        prev, new_lobe(fit_normals, exact, evaluate(prev, fit_normals)), "kept k-1"));
    keep_best(candidates, judge, t0, ladder, refine);
  }
  return ladder;
}

}  // namespace sglab::envmap
