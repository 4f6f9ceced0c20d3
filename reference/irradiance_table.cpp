// reference/irradiance_table.cpp — the irradiance table (irradiance_table.hpp):
// closed forms, the layout of the pieces, the build from the quadrature, the
// evaluation, and the check against the quadrature.
//
// Chebyshev interpolation in first-kind points with its coefficients by the
// discrete cosine transform ([Trefethen2019] ch. 3–4), summed by Clenshaw's
// recurrence [Clenshaw1955] (docs/references.md).
#include "reference/irradiance_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "common/io.hpp"
#include "sglab/closed_forms.hpp"

namespace sglab::reference {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kHorizonWidths = 8;  // a_max = min(1, 8/√κ)

// The pieces (irradiance_table.hpp): axis, κ range, nodes in κ and in a. The
// node counts are the smallest whose dense check (`sglab reference
// --check-table`) stays below 1e−13 of the peak.
struct Layout {
  IrradianceTable::Axis axis;
  double kappa_lo, kappa_hi;
  int kappa_nodes, cosine_nodes;
};
// The last piece of an axis runs to κ = ∞.
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
constexpr Layout kLayout[] = {
    {IrradianceTable::Axis::linear, 0, 1, 14, 12},
    {IrradianceTable::Axis::log, 1, 4, 19, 15},
    {IrradianceTable::Axis::log, 4, 16, 21, 23},
    {IrradianceTable::Axis::log, 16, 64, 20, 36},
    {IrradianceTable::Axis::log, 64, 256, 13, 37},
    {IrradianceTable::Axis::log, 256, 1024, 12, 37},
    {IrradianceTable::Axis::inverse, 1024, kUnbounded, 6, 37},
};

void check_kappa(double kappa) {
  if (!(std::isfinite(kappa) && kappa >= 0))
    throw std::invalid_argument(
        fmt::format("irradiance table: kappa must be finite and >= 0, got {}", kappa));
}

// Σ_{n<N} b_n T_n(y) by Clenshaw's recurrence.
double clenshaw(const double* b, int n, double y) {
  double b1 = 0, b2 = 0;
  const double y2 = 2 * y;
  for (int k = n - 1; k >= 1; --k) {
    const double b0 = std::fma(y2, b1, b[k] - b2);
    b2 = b1;
    b1 = b0;
  }
  return std::fma(y, b1, b[0] - b2);
}

// The coefficients b_k = (2 − δ_k0)/N Σ_j x_j cos(πk(j + ½)/N) of the
// interpolant through values x_j at the N first-kind points, in place, along
// one direction of an array: `lines` lines, line l starting at l·line_step,
// its N values `stride` apart.
void chebyshev_coefficients(std::vector<double>& v, int n, std::size_t stride, int lines,
                            std::size_t line_step) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int l = 0; l < lines; ++l) {
    double* line = v.data() + static_cast<std::size_t>(l) * line_step;
    for (int j = 0; j < n; ++j)
      x[static_cast<std::size_t>(j)] = line[static_cast<std::size_t>(j) * stride];
    for (int k = 0; k < n; ++k) {
      double s = 0;
      for (int j = 0; j < n; ++j)
        s += x[static_cast<std::size_t>(j)] * std::cos(std::numbers::pi * k * (j + 0.5) / n);
      line[static_cast<std::size_t>(k) * stride] = s * (k == 0 ? 1.0 : 2.0) / n;
    }
  }
}

// √max(κ, 1): the stored value is √max(κ, 1)·T/E(1, κ), O(1) at every κ.
double value_scale(double kappa) { return std::sqrt(std::max(kappa, 1.0)); }

}  // namespace

double irradiance_odd_slope(double kappa) {
  if (kappa < 1) {
    // ∫_{−1}^{1} t e^{κ(t−1)} dt = 2e^{−κ} Σ_{j≥0} κ^{2j+1}/((2j + 1)!(2j + 3)).
    double power = kappa, sum = 0;  // power = κ^{2j+1}/(2j+1)!
    for (int j = 0; j < 40 && power != 0; ++j) {
      sum += power / (2 * j + 3);
      power *= kappa * kappa / ((2 * j + 2) * (2 * j + 3));
    }
    return kTwoPi * 2 * std::exp(-kappa) * sum;
  }
  return kTwoPi / kappa * (1 - 1 / kappa + (1 + 1 / kappa) * std::exp(-2 * kappa));
}

double irradiance_table_cosine_range(double kappa) {
  return kappa <= kHorizonWidths * kHorizonWidths ? 1.0 : kHorizonWidths / std::sqrt(kappa);
}

// ---------------------------------------------------------------------------
// Pieces

double IrradianceTable::Piece::kappa_at(double y) const {
  const double u = (y + 1) / 2;  // 0 … 1
  switch (axis) {
    case Axis::linear:
      return kappa_lo + (kappa_hi - kappa_lo) * u;
    case Axis::log:
      return std::exp(std::log(kappa_lo) + (std::log(kappa_hi) - std::log(kappa_lo)) * u);
    case Axis::inverse:
      return u > 0 ? kappa_lo / u : kUnbounded;  // w = κ_lo/κ = (y + 1)/2
  }
  return kUnbounded;
}

double IrradianceTable::Piece::y_of_kappa(double kappa) const {
  double y = 0;
  switch (axis) {
    case Axis::linear:
      y = (2 * kappa - kappa_lo - kappa_hi) / (kappa_hi - kappa_lo);
      break;
    case Axis::log:
      y = (2 * std::log(kappa) - std::log(kappa_lo) - std::log(kappa_hi)) /
          (std::log(kappa_hi) - std::log(kappa_lo));
      break;
    case Axis::inverse:
      y = 2 * (kappa_lo / kappa) - 1;
      break;
  }
  return std::clamp(y, -1.0, 1.0);
}

double IrradianceTable::Piece::cosine_at(double kappa, double y) {
  return std::min(1.0, irradiance_table_cosine_range(kappa) * (y + 1) / 2);
}

const IrradianceTable::Piece& IrradianceTable::piece_of(double kappa) const {
  for (const Piece& p : pieces_)
    if (kappa <= p.kappa_hi) return p;
  return pieces_.back();
}

// ---------------------------------------------------------------------------
// Build

IrradianceTable::IrradianceTable() {
  // Every node of every piece, evaluated by the quadrature in one parallel batch.
  std::vector<Query> queries;
  for (const Layout& l : kLayout) {
    Piece p{l.axis, l.kappa_lo, l.kappa_hi, l.kappa_nodes, l.cosine_nodes, {}};
    for (int i = 0; i < p.kappa_nodes; ++i) {
      const double kappa = p.kappa_at(std::cos(std::numbers::pi * (i + 0.5) / p.kappa_nodes));
      for (int j = 0; j < p.cosine_nodes; ++j)
        queries.push_back({kappa, -Piece::cosine_at(kappa, std::cos(std::numbers::pi * (j + 0.5) /
                                                                    p.cosine_nodes))});
    }
    pieces_.push_back(std::move(p));
  }
  std::vector<ReferencePoint> ref;
  {
    // A private engine: the nodes do not stay in the process-wide cache. In
    // isolation: a caller inside a TBB task does not pick up other tasks
    // (which may want this table) while it waits.
    const ReferenceEngine engine;
    tbb::this_task_arena::isolate([&] { ref = engine.evaluate(queries); });
  }

  // Coefficients by the 2-D discrete cosine transform, one direction at a time:
  //   a_mn = (2 − δ_m0)(2 − δ_n0)/(N_κ N_a) Σ_ij v_ij cos(mθ_i) cos(nθ_j),
  // θ_i = π(i + ½)/N_κ, θ_j = π(j + ½)/N_a.
  std::size_t at = 0;
  for (Piece& p : pieces_) {
    const int nk = p.kappa_nodes, nc = p.cosine_nodes;
    std::vector<double> v(static_cast<std::size_t>(nk * nc));
    for (int i = 0; i < nk; ++i)
      for (int j = 0; j < nc; ++j, ++at) {
        const ReferencePoint& r = ref[at];
        v[static_cast<std::size_t>(i * nc + j)] =
            value_scale(r.kappa) * r.irradiance / irradiance_upper(r.kappa);
      }
    chebyshev_coefficients(v, nc, 1, nk, static_cast<std::size_t>(nc));  // along a
    chebyshev_coefficients(v, nk, static_cast<std::size_t>(nc), nc, 1);  // along κ
    p.coefficients = std::move(v);
  }
}

const IrradianceTable& irradiance_table() {
  static const IrradianceTable table;
  return table;
}

// ---------------------------------------------------------------------------
// Evaluation

IrradianceTable::Slice IrradianceTable::slice(double kappa) const {
  check_kappa(kappa);
  const Piece& p = piece_of(kappa);
  Slice s;
  s.kappa_ = kappa;
  s.n_ = p.cosine_nodes;
  s.a_max_ = irradiance_table_cosine_range(kappa);
  s.two_over_a_max_ = 2 / s.a_max_;
  s.scale_ = irradiance_upper(kappa) / value_scale(kappa);
  s.slope_ = irradiance_odd_slope(kappa);
  // b_n = Σ_m a_mn T_m(y_κ); T_{m+1} = 2y T_m − T_{m−1}, started from T_{−1} = y, T_0 = 1.
  const double y = p.y_of_kappa(kappa);
  double previous = y, tm = 1;
  const double* a = p.coefficients.data();
  for (int m = 0; m < p.kappa_nodes; ++m, a += s.n_) {
    for (int n = 0; n < s.n_; ++n) s.b_[static_cast<std::size_t>(n)] += a[n] * tm;
    const double next = std::fma(2 * y, tm, -previous);
    previous = tm;
    tm = next;
  }
  return s;
}

double IrradianceTable::Slice::operator()(double cosine) const {
  if (!(cosine >= -1 && cosine <= 1))
    throw std::invalid_argument(
        fmt::format("irradiance table: cosine must be in [-1, 1], got {}", cosine));
  const double a = std::abs(cosine);
  double shadow = 0;  // T(|c|, κ): 0 beyond a_max (irradiance_table.hpp)
  if (a <= a_max_) {
    const double y = std::min(1.0, std::fma(a, two_over_a_max_, -1.0));
    shadow = std::max(0.0, scale_ * clenshaw(b_.data(), n_, y));
  }
  return cosine > 0 ? std::fma(cosine, slope_, shadow) : shadow;
}

// ---------------------------------------------------------------------------
// Check

std::vector<Query> irradiance_table_check_points(int oversample) {
  if (oversample < 1 || oversample % 2 == 0)
    throw std::invalid_argument(
        fmt::format("irradiance table check: oversample must be odd and >= 1, got {}", oversample));
  std::vector<Query> out;
  for (const IrradianceTable::Piece& p : irradiance_table().pieces()) {
    const int nk = oversample * p.kappa_nodes, nc = oversample * p.cosine_nodes;
    for (int i = 0; i <= nk; ++i) {
      double kappa = p.kappa_at(std::cos(std::numbers::pi * i / nk));
      if (!std::isfinite(kappa)) kappa = std::numeric_limits<double>::max();  // w = 0
      std::vector<double> as;
      for (int j = 0; j <= nc; ++j)
        as.push_back(IrradianceTable::Piece::cosine_at(kappa, std::cos(std::numbers::pi * j / nc)));
      // Beyond a_max, where the shadow side is dropped.
      const double a_max = irradiance_table_cosine_range(kappa);
      for (double f : {1.001, 1.01, 1.1, 1.5, 2.0, 4.0})
        if (a_max * f < 1) as.push_back(a_max * f);
      for (double a : as) {
        out.push_back({kappa, a});
        if (a != 0) out.push_back({kappa, -a});
      }
    }
  }
  return out;
}

IrradianceTableCheck check_irradiance_table(std::span<const Query> points, bool progress) {
  const IrradianceTable& table = irradiance_table();
  const ReferenceEngine engine;  // nothing cached across calls, nothing left in the shared cache
  IrradianceTableCheck out;
  out.points = points.size();
  std::optional<io::Progress> bar;
  if (progress) bar.emplace("irradiance table check", points.size());
  constexpr std::size_t kChunk = 8192;
  for (std::size_t begin = 0; begin < points.size(); begin += kChunk) {
    const auto chunk = points.subspan(begin, std::min(kChunk, points.size() - begin));
    const auto ref = engine.evaluate(chunk);
    engine.clear_cache();
    for (std::size_t i = 0; i < chunk.size(); ++i) {
      const double e = table.irradiance(chunk[i].kappa, chunk[i].cosine);
      const double err = std::abs(e - ref[i].irradiance) / irradiance_upper(chunk[i].kappa);
      if (!(err <= out.max_error)) {  // NaN is the worst
        out.max_error = std::isnan(err) ? kUnbounded : err;
        out.worst_kappa = chunk[i].kappa;
        out.worst_cosine = chunk[i].cosine;
      }
    }
    if (bar) bar->advance(chunk.size());
  }
  if (bar) bar->finish();
  return out;
}

}  // namespace sglab::reference
