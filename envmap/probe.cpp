// envmap/probe.cpp — the dense error, spherical harmonics, ZH3 and the probe
// interface (probe.hpp).
#include "envmap/probe.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "reference/irradiance_table.hpp"

namespace sglab::envmap {

namespace {

using io::InputError;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec3 normalized(const Vec3& v) {
  const double len = std::sqrt(dot(v, v));
  return {v[0] / len, v[1] / len, v[2] / len};
}

// Two unit tangents of the unit vector n.
std::pair<Vec3, Vec3> tangents(const Vec3& n) {
  const Vec3 a = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 t1 =
      normalized({a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0]});
  const Vec3 t2 = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2],
                   n[0] * t1[1] - n[1] * t1[0]};
  return {t1, t2};
}

// Local maximum of f on the sphere from n: a pattern search over 8 tangent
// directions, the step halved when none improves, from `step` down to 1e−4 rad.
std::pair<Vec3, double> local_max(const std::function<double(const Vec3&)>& f, Vec3 n,
                                  double step) {
  double best = f(n);
  int evaluations = 1;
  while (step > 1e-4 && evaluations < 400) {
    const auto [t1, t2] = tangents(n);
    Vec3 best_n = n;
    bool moved = false;
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4;
      const double u = std::cos(a) * step, v = std::sin(a) * step;
      const Vec3 c = normalized({n[0] + u * t1[0] + v * t2[0], n[1] + u * t1[1] + v * t2[1],
                                 n[2] + u * t1[2] + v * t2[2]});
      const double fc = f(c);
      ++evaluations;
      if (fc > best) {
        best = fc;
        best_n = c;
        moved = true;
      }
    }
    if (moved)
      n = best_n;
    else
      step /= 2;
  }
  return {n, best};
}

double y20(double t) { return std::sqrt(5 / (16 * M_PI)) * (3 * t * t - 1); }

}  // namespace

// ---- Dense error -------------------------------------------------------------

DenseTruth dense_truth(const MapIrradiance& field, std::size_t n) {
  DenseTruth t;
  t.field = &field;
  t.normals = reference::fibonacci_normals(n);
  t.exact = field.at(t.normals);
  t.spacing = std::sqrt(4 * M_PI / static_cast<double>(n));
  for (std::size_t ch = 0; ch < 3; ++ch) {
    std::size_t arg = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (t.exact[k][ch] > t.exact[arg][ch]) arg = k;
    const auto [where, value] =
        local_max([&](const Vec3& v) { return field.at(v)[ch]; }, t.normals[arg], t.spacing);
    (void)where;
    t.peak = std::max({t.peak, value, t.exact[arg][ch]});
  }
  return t;
}

DenseError dense_error(const DenseTruth& truth, const IrradianceFn& approx, std::size_t starts) {
  const std::size_t n = truth.normals.size();
  std::vector<double> d(n), sq(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    const Vec3 a = approx(truth.normals[k]);
    double worst = 0, s = 0;
    for (std::size_t ch = 0; ch < 3; ++ch) {
      const double e = std::abs(a[ch] - truth.exact[k][ch]);
      worst = std::max(worst, std::isfinite(e) ? e : HUGE_VAL);
      s += e * e;
    }
    d[k] = worst;
    sq[k] = s;
  });
  DenseError out;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return d[a] > d[b]; });
  double total = 0;
  for (double s : sq) total += s;
  out.rms_rel = std::sqrt(total / static_cast<double>(3 * n)) / truth.peak;
  out.dense_max_rel = d[order[0]] / truth.peak;
  out.max_rel = out.dense_max_rel;
  out.worst = truth.normals[order[0]];
  // Starts: the worst normals, each at least 3 spacings from those before.
  std::vector<std::size_t> chosen;
  const double min_cos = std::cos(3 * truth.spacing);
  for (std::size_t k : order) {
    if (chosen.size() >= starts) break;
    bool near = false;
    for (std::size_t c : chosen)
      if (dot(truth.normals[c], truth.normals[k]) > min_cos) near = true;
    if (!near) chosen.push_back(k);
  }
  std::vector<std::pair<Vec3, double>> found(chosen.size());
  const auto error_at = [&](const Vec3& v) {
    const Vec3 a = approx(v), e = truth.field->at(v);
    return std::max({std::abs(a[0] - e[0]), std::abs(a[1] - e[1]), std::abs(a[2] - e[2])});
  };
  tbb::parallel_for(std::size_t{0}, chosen.size(), [&](std::size_t c) {
    found[c] = local_max(error_at, truth.normals[chosen[c]], truth.spacing);
  });
  for (const auto& [v, e] : found)
    if (e / truth.peak > out.max_rel) {
      out.max_rel = e / truth.peak;
      out.worst = v;
    }
  return out;
}

// ---- Spherical harmonics -----------------------------------------------------

double clamped_cosine_factor(int l) {
  if (l == 0) return M_PI;
  if (l == 1) return 2 * M_PI / 3;
  if (l % 2 == 1) return 0;
  double f = 1;  // l! / (2^l ((l/2)!)²)
  for (int k = 1; k <= l; ++k) f *= k;
  double h = 1;
  for (int k = 1; k <= l / 2; ++k) h *= k;
  f /= std::pow(2.0, l) * h * h;
  const double sign = (l / 2 - 1) % 2 == 0 ? 1 : -1;
  return 2 * M_PI * sign / ((l + 2) * (l - 1)) * f;
}

std::vector<Vec3> radiance_sh(const Map& map, int order) {
  const std::size_t K = sh_count(order), W = map.width, H = map.height;
  constexpr std::array<double, 3> node{-0.7745966692414834, 0.0, 0.7745966692414834};
  constexpr std::array<double, 3> weight{5.0 / 9, 8.0 / 9, 5.0 / 9};
  std::vector<std::vector<Vec3>> rows(H, std::vector<Vec3>(K, Vec3{0, 0, 0}));
  tbb::parallel_for(std::size_t{0}, H, [&](std::size_t j) {
    const double t0 = M_PI * static_cast<double>(j) / static_cast<double>(H);
    const double dt = M_PI / static_cast<double>(H), dp = 2 * M_PI / static_cast<double>(W);
    std::array<double, sh_count(kMaxShOrder)> y{};
    for (std::size_t i = 0; i < W; ++i) {
      const double p0 = dp * static_cast<double>(i);
      for (std::size_t a = 0; a < 3; ++a) {
        const double th = t0 + dt * (1 + node[a]) / 2;
        const double wt = weight[a] * dt / 2 * std::sin(th);
        for (std::size_t b = 0; b < 3; ++b) {
          const double ph = p0 + dp * (1 + node[b]) / 2;
          const double w = wt * weight[b] * dp / 2;
          sh_basis(order, std::sin(th) * std::cos(ph), -std::sin(th) * std::sin(ph), std::cos(th),
                   y.data());
          for (std::size_t k = 0; k < K; ++k)
            for (std::size_t ch = 0; ch < 3; ++ch) rows[j][k][ch] += w * y[k] * map.at(i, j, ch);
        }
      }
    }
  });
  std::vector<Vec3> out(K, Vec3{0, 0, 0});
  for (const auto& r : rows)
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t ch = 0; ch < 3; ++ch) out[k][ch] += r[k][ch];
  return out;
}

// ---- Probes ------------------------------------------------------------------

Vec3 Probe::zonal_axis() const {
  Vec3 v{0, 0, 0};
  if (sh.size() < 4) return {0, 0, 1};
  for (std::size_t ch = 0; ch < 3; ++ch) {
    v[0] += kLuminance[ch] * sh[3][ch];  // Y_11 ∝ x
    v[1] += kLuminance[ch] * sh[1][ch];  // Y_1−1 ∝ y
    v[2] += kLuminance[ch] * sh[2][ch];  // Y_10 ∝ z
  }
  if (!(dot(v, v) > 0)) return {0, 0, 1};
  return normalized(v);
}

std::size_t Probe::floats() const {
  switch (kind) {
    case ProbeKind::sh:
      return 3 * sh_count(order);
    case ProbeKind::sh_nonneg:
      return 12;
    case ProbeKind::zh3:
      return 15;
    case ProbeKind::lobes:
      return 7 * lobes.size();
    case ProbeKind::hybrid:
      return 3 * sh_count(order) + 7 * lobes.size();
  }
  return 0;
}

std::string Probe::label() const {
  switch (kind) {
    case ProbeKind::sh:
      return fmt::format("SH L{}", order);
    case ProbeKind::sh_nonneg:
      return "SH L1 non-negative";
    case ProbeKind::zh3:
      return "ZH3";
    case ProbeKind::lobes:
      return fmt::format("{} SG", lobes.size());
    case ProbeKind::hybrid:
      return fmt::format("SH L{} + {} SG", order, lobes.size());
  }
  return "";
}

namespace {
const char* kind_name(ProbeKind k) {
  switch (k) {
    case ProbeKind::sh:
      return "sh";
    case ProbeKind::sh_nonneg:
      return "sh_nonneg";
    case ProbeKind::zh3:
      return "zh3";
    case ProbeKind::lobes:
      return "lobes";
    case ProbeKind::hybrid:
      return "hybrid";
  }
  return "";
}
}  // namespace

nlohmann::ordered_json Probe::to_json() const {
  nlohmann::ordered_json j;
  j["kind"] = kind_name(kind);
  j["label"] = label();
  if (kind != ProbeKind::lobes) j["sh_order"] = order;
  j["fit"] = fit;
  j["floats"] = floats();
  j["bytes"] = bytes();
  j["encoding"] = "IEEE binary32 per float";
  if (kind != ProbeKind::lobes) {
    j["sh_basis"] =
        "irradiance coefficients E_lm of real orthonormal SH, index l*l + l + m, no "
        "Condon-Shortley phase; RGB";
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const Vec3& c : sh) a.push_back({c[0], c[1], c[2]});
    j["sh"] = a;
  }
  if (kind == ProbeKind::zh3) {
    j["zonal"] = {zonal[0], zonal[1], zonal[2]};
    const Vec3 d = zonal_axis();
    j["zonal_axis"] = {d[0], d[1], d[2]};
  }
  if (kind == ProbeKind::lobes || kind == ProbeKind::hybrid) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const Lobe& l : lobes)
      a.push_back({{"axis", {l.axis[0], l.axis[1], l.axis[2]}},
                   {"sharpness", l.sharpness},
                   {"amplitude", {l.amplitude[0], l.amplitude[1], l.amplitude[2]}}});
    j["lobes"] = a;
    j["method"] = method;
  }
  return j;
}

Probe Probe::from_json(const nlohmann::ordered_json& j) {
  Probe p;
  auto vec3 = [](const nlohmann::ordered_json& v, const std::string& key) {
    if (!v.is_array() || v.size() != 3)
      throw InputError(fmt::format("probe: '{}' must be an array of 3 numbers", key));
    Vec3 out{};
    for (std::size_t d = 0; d < 3; ++d) {
      if (!v[d].is_number())
        throw InputError(fmt::format("probe: '{}' must be an array of 3 numbers", key));
      out[d] = v[d].get<double>();
      if (!std::isfinite(out[d])) throw InputError(fmt::format("probe: '{}' is not finite", key));
    }
    return out;
  };
  if (!j.is_object() || !j.contains("kind") || !j["kind"].is_string())
    throw InputError("probe: expected an object with a string 'kind'");
  const std::string kind = j["kind"].get<std::string>();
  bool known = false;
  for (ProbeKind k :
       {ProbeKind::sh, ProbeKind::sh_nonneg, ProbeKind::zh3, ProbeKind::lobes, ProbeKind::hybrid})
    if (kind == kind_name(k)) {
      p.kind = k;
      known = true;
    }
  if (!known)
    throw InputError(
        fmt::format("probe: 'kind' must be sh, sh_nonneg, zh3, lobes or hybrid, got '{}'", kind));
  if (j.contains("fit") && j["fit"].is_string()) p.fit = j["fit"].get<std::string>();
  if (p.kind != ProbeKind::lobes) {
    if (!j.contains("sh_order") || !j["sh_order"].is_number_integer())
      throw InputError("probe: 'sh_order' (an integer) is required");
    p.order = j["sh_order"].get<int>();
    if (p.order < 0 || p.order > kMaxShOrder)
      throw InputError(fmt::format("probe: 'sh_order' must be 0 … {}", kMaxShOrder));
    if ((p.kind == ProbeKind::sh_nonneg || p.kind == ProbeKind::zh3) && p.order != 1)
      throw InputError("probe: 'sh_order' must be 1 for sh_nonneg and zh3");
    if (p.kind == ProbeKind::hybrid && p.order != 2)
      throw InputError("probe: 'sh_order' must be 2 for hybrid");
    if (!j.contains("sh") || !j["sh"].is_array() || j["sh"].size() != sh_count(p.order))
      throw InputError(fmt::format("probe: 'sh' must hold {} RGB coefficients", sh_count(p.order)));
    for (const auto& c : j["sh"]) p.sh.push_back(vec3(c, "sh"));
  }
  if (p.kind == ProbeKind::zh3) {
    if (!j.contains("zonal")) throw InputError("probe: 'zonal' is required for zh3");
    p.zonal = vec3(j["zonal"], "zonal");
  }
  if (p.kind == ProbeKind::lobes || p.kind == ProbeKind::hybrid) {
    if (!j.contains("lobes") || !j["lobes"].is_array())
      throw InputError("probe: 'lobes' (an array) is required");
    for (const auto& l : j["lobes"]) {
      if (!l.is_object() || !l.contains("axis") || !l.contains("sharpness") ||
          !l.contains("amplitude") || !l["sharpness"].is_number())
        throw InputError("probe: each lobe needs 'axis', 'sharpness' and 'amplitude'");
      Lobe lobe;
      lobe.axis = vec3(l["axis"], "axis");
      const double len = std::sqrt(dot(lobe.axis, lobe.axis));
      if (!(len > 0)) throw InputError("probe: a lobe's 'axis' is zero");
      lobe.axis = normalized(lobe.axis);
      lobe.sharpness = l["sharpness"].get<double>();
      if (!(lobe.sharpness >= 0) || !std::isfinite(lobe.sharpness))
        throw InputError("probe: a lobe's 'sharpness' must be finite and >= 0");
      lobe.amplitude = vec3(l["amplitude"], "amplitude");
      p.lobes.push_back(lobe);
    }
    if (p.kind == ProbeKind::lobes && p.lobes.empty()) throw InputError("probe: 'lobes' is empty");
    if (j.contains("method")) {
      if (!j["method"].is_string()) throw InputError("probe: 'method' must be a string");
      p.method = j["method"].get<std::string>();
      if (!find_method(irradiance_methods, p.method))
        throw InputError(fmt::format(
            "probe: 'method' must be a registered irradiance method (`sglab methods`), got '{}'",
            p.method));
    }
  }
  return p;
}

IrradianceFn probe_irradiance(const Probe& probe) {
  std::vector<reference::IrradianceTable::Slice> slices;
  const auto& table = reference::irradiance_table();
  for (const Lobe& l : probe.lobes) slices.push_back(table.slice(l.sharpness));
  const Vec3 axis = probe.zonal_axis();
  return [probe, slices, axis](const Vec3& n) {
    Vec3 e{0, 0, 0};
    if (probe.kind != ProbeKind::lobes) {
      std::array<double, sh_count(kMaxShOrder)> y{};
      sh_basis(probe.order, n[0], n[1], n[2], y.data());
      for (std::size_t k = 0; k < probe.sh.size(); ++k)
        for (std::size_t ch = 0; ch < 3; ++ch) e[ch] += probe.sh[k][ch] * y[k];
    }
    if (probe.kind == ProbeKind::zh3) {
      const double z = y20(dot(axis, n));
      for (std::size_t ch = 0; ch < 3; ++ch) e[ch] += probe.zonal[ch] * z;
    }
    for (std::size_t k = 0; k < probe.lobes.size(); ++k) {
      const double c = std::clamp(dot(probe.lobes[k].axis, n), -1.0, 1.0);
      const double s = slices[k](c);
      for (std::size_t ch = 0; ch < 3; ++ch) e[ch] += probe.lobes[k].amplitude[ch] * s;
    }
    return e;
  };
}

IrradianceFn probe_irradiance_method(const Probe& probe) {
  const Method* method = find_method(irradiance_methods, probe.method);
  if (!method)
    throw std::logic_error(fmt::format("probe: unknown irradiance method '{}'", probe.method));
  Probe rest = probe;  // the SH and zonal terms, as probe_irradiance evaluates them
  rest.lobes.clear();
  const bool has_rest = probe.kind != ProbeKind::lobes;
  const IrradianceFn base = probe_irradiance(rest);
  return [probe, method, base, has_rest](const Vec3& n) {
    Vec3 e = has_rest ? base(n) : Vec3{0, 0, 0};
    for (const Lobe& l : probe.lobes) {
      const double s = method->f64(std::clamp(dot(l.axis, n), -1.0, 1.0), l.sharpness);
      for (std::size_t ch = 0; ch < 3; ++ch) e[ch] += l.amplitude[ch] * s;
    }
    return e;
  };
}

Probe project_sh(const std::vector<Vec3>& radiance, int order) {
  if (radiance.size() < sh_count(order))
    throw std::logic_error("project_sh: fewer radiance coefficients than the order needs");
  Probe p;
  p.kind = ProbeKind::sh;
  p.order = order;
  p.fit = "projection";
  for (int l = 0; l <= order; ++l)
    for (int m = -l; m <= l; ++m) {
      const Vec3& c = radiance[static_cast<std::size_t>(l * l + l + m)];
      const double a = clamped_cosine_factor(l);
      p.sh.push_back({a * c[0], a * c[1], a * c[2]});
    }
  return p;
}

Probe project_sh_nonneg(const std::vector<Vec3>& radiance) {
  Probe p = project_sh(radiance, 1);
  p.kind = ProbeKind::sh_nonneg;
  // E(n) = e0 Y_00 + g·Y_1(n) ≥ e0/√(4π) − |g|√(3/4π): non-negative when |g| ≤ e0/√3.
  for (std::size_t ch = 0; ch < 3; ++ch) {
    const double g = std::sqrt(p.sh[1][ch] * p.sh[1][ch] + p.sh[2][ch] * p.sh[2][ch] +
                               p.sh[3][ch] * p.sh[3][ch]);
    const double limit = std::max(0.0, p.sh[0][ch]) / std::sqrt(3.0);
    if (g > limit)
      for (std::size_t k = 1; k < 4; ++k) p.sh[k][ch] *= limit / g;
  }
  return p;
}

Probe project_zh3(const std::vector<Vec3>& radiance) {
  const Probe l2 = project_sh(radiance, 2);
  Probe p;
  p.kind = ProbeKind::zh3;
  p.order = 1;
  p.fit = "projection";
  p.sh.assign(l2.sh.begin(), l2.sh.begin() + 4);
  const Vec3 d = p.zonal_axis();
  std::array<double, sh_count(kMaxShOrder)> y{};
  sh_basis(2, d[0], d[1], d[2], y.data());
  for (std::size_t ch = 0; ch < 3; ++ch) {
    double z = 0;
    for (std::size_t k = 4; k < 9; ++k) z += l2.sh[k][ch] * y[k];
    p.zonal[ch] = std::sqrt(4 * M_PI / 5) * z;
  }
  return p;
}

namespace {
// Least squares of exact (N × 3) on the columns of basis (N × K), per channel.
std::vector<Vec3> least_squares(const Eigen::MatrixXd& basis, const std::vector<Vec3>& exact) {
  Eigen::MatrixXd b(static_cast<Eigen::Index>(exact.size()), 3);
  for (std::size_t k = 0; k < exact.size(); ++k)
    for (std::size_t ch = 0; ch < 3; ++ch)
      b(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(ch)) = exact[k][ch];
  const Eigen::MatrixXd x = basis.colPivHouseholderQr().solve(b);
  std::vector<Vec3> out(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index k = 0; k < x.rows(); ++k)
    out[static_cast<std::size_t>(k)] = {x(k, 0), x(k, 1), x(k, 2)};
  return out;
}

// The minimax of |basis x − exact| per channel by Lawson's iteration
// [Lawson1961]: weighted least squares with weights u_i ← u_i |r_i| / Σ u_j |r_j|
// from least squares (u = 1); per channel the round with the smallest max |r_i|.
std::vector<Vec3> lawson_minimax(const Eigen::MatrixXd& basis, const std::vector<Vec3>& exact,
                                 int rounds) {
  std::vector<Vec3> out = least_squares(basis, exact);
  const auto rows = static_cast<Eigen::Index>(exact.size());
  for (std::size_t ch = 0; ch < 3; ++ch) {
    Eigen::VectorXd b(rows), x(basis.cols());
    for (Eigen::Index k = 0; k < rows; ++k) b(k) = exact[static_cast<std::size_t>(k)][ch];
    for (Eigen::Index c = 0; c < x.size(); ++c) x(c) = out[static_cast<std::size_t>(c)][ch];
    Eigen::VectorXd r = basis * x - b, u = Eigen::VectorXd::Ones(rows);
    double best = r.cwiseAbs().maxCoeff();
    for (int round = 0; round < rounds; ++round) {
      u = u.cwiseProduct(r.cwiseAbs());
      const double total = u.sum();
      if (!(total > 0)) break;
      u *= static_cast<double>(rows) / total;
      const Eigen::VectorXd w = u.cwiseSqrt();
      x = (w.asDiagonal() * basis).colPivHouseholderQr().solve(w.cwiseProduct(b));
      r = basis * x - b;
      const double m = r.cwiseAbs().maxCoeff();
      if (m < best) {
        best = m;
        for (Eigen::Index c = 0; c < x.size(); ++c) out[static_cast<std::size_t>(c)][ch] = x(c);
      }
    }
  }
  return out;
}
}  // namespace

Probe fit_sh(const std::vector<Vec3>& normals, const std::vector<Vec3>& exact, int order,
             LinearFit how) {
  const std::size_t K = sh_count(order);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(normals.size()), static_cast<Eigen::Index>(K));
  std::array<double, sh_count(kMaxShOrder)> y{};
  for (std::size_t k = 0; k < normals.size(); ++k) {
    sh_basis(order, normals[k][0], normals[k][1], normals[k][2], y.data());
    for (std::size_t c = 0; c < K; ++c)
      a(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = y[c];
  }
  Probe p;
  p.kind = ProbeKind::sh;
  p.order = order;
  p.fit = how == LinearFit::minimax ? "minimax" : "fit";
  p.sh = how == LinearFit::minimax ? lawson_minimax(a, exact, kLinearMinimaxRounds)
                                   : least_squares(a, exact);
  return p;
}

Probe fit_zh3(const std::vector<Vec3>& normals, const std::vector<Vec3>& exact, const Vec3& axis,
              LinearFit how) {
  Eigen::MatrixXd a(static_cast<Eigen::Index>(normals.size()), 5);
  std::array<double, sh_count(kMaxShOrder)> y{};
  for (std::size_t k = 0; k < normals.size(); ++k) {
    sh_basis(1, normals[k][0], normals[k][1], normals[k][2], y.data());
    for (Eigen::Index c = 0; c < 4; ++c)
      a(static_cast<Eigen::Index>(k), c) = y[static_cast<std::size_t>(c)];
    a(static_cast<Eigen::Index>(k), 4) = y20(dot(axis, normals[k]));
  }
  const std::vector<Vec3> x = how == LinearFit::minimax
                                  ? lawson_minimax(a, exact, kLinearMinimaxRounds)
                                  : least_squares(a, exact);
  Probe p;
  p.kind = ProbeKind::zh3;
  p.order = 1;
  p.fit = how == LinearFit::minimax ? "minimax" : "fit";
  p.sh.assign(x.begin(), x.begin() + 4);
  p.zonal = x[4];
  // Evaluated along the axis its own L1 implies (zonal_axis), which the fit
  // moves by the sampling's tiny l = 1/l = 2 coupling only; the error is
  // measured on the probe as stored.
  return p;
}

}  // namespace sglab::envmap
