// validate/kappa_range.cpp — see kappa_range.hpp.
#include "validate/kappa_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <boost/math/tools/minima.hpp>

#include "common/io.hpp"
#include "reference/reference.hpp"

namespace sglab::validate {

namespace {

constexpr float kFloatMin = std::numeric_limits<float>::denorm_min();

// |Ê − E|/E(1, κ) of one evaluation; +inf when Ê is not finite.
double peak_rel(double value, double reference, double peak) {
  if (!std::isfinite(value)) return std::numeric_limits<double>::infinity();
  return std::abs(value - reference) / peak;
}

// The cosines scanned at κ: uniform, then the layer t/√κ, float-exact, sorted, distinct.
std::vector<double> scan_cosines(double kappa, const KappaScanOptions& o) {
  std::vector<double> c;
  for (int i = 0; i < o.cosines; ++i) c.push_back(-1.0 + 2.0 * i / (o.cosines - 1));
  c.back() = 1.0;
  if (kappa > 0)
    for (int i = 0; i < o.layer; ++i) {
      const double t = o.layer == 1 ? 0.0 : -8.0 + 16.0 * i / (o.layer - 1);
      const double x = t / std::sqrt(kappa);
      if (std::abs(x) < 1) c.push_back(x);
    }
  for (double& x : c) x = static_cast<float>(x);
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  return c;
}

// The worst of one precision over the cosines at one κ, refined by Brent's method.
template <class Eval>
KappaWorst worst_at(double kappa, const std::vector<double>& cosines,
                    const std::vector<reference::ReferencePoint>& ref, double peak,
                    const Eval& eval, const reference::ReferenceEngine& engine, bool refine) {
  KappaWorst w;
  std::size_t at = 0;
  for (std::size_t j = 0; j < cosines.size(); ++j) {
    const double e = peak_rel(eval(cosines[j]), ref[j].irradiance, peak);
    if (!(e <= w.peak_rel)) w = {e, cosines[j]}, at = j;
  }
  if (!refine || !std::isfinite(w.peak_rel) || cosines.size() < 3) return w;
  const double a = cosines[at == 0 ? 0 : at - 1], b = cosines[std::min(at + 1, cosines.size() - 1)];
  const auto minus_error = [&](double c) {
    const double cf = static_cast<float>(c);
    const double e = peak_rel(eval(cf), engine.evaluate(kappa, cf).irradiance, peak);
    return std::isfinite(e) ? -e : -std::numeric_limits<double>::max();
  };
  std::uintmax_t iterations = 40;
  const auto [c, minus] = boost::math::tools::brent_find_minima(minus_error, a, b, 24, iterations);
  if (-minus > w.peak_rel) w = {-minus, static_cast<float>(c)};
  return w;
}

}  // namespace

std::string kappa_range_text(const ValidRange& v) {
  const auto end = [](float k) {
    return k == kFloatMax ? std::string("FLT_MAX") : fmt::format("{:.2g}", k);
  };
  return fmt::format("[{}, {}]", end(v.kappa_lo), end(v.kappa_hi));
}

double MethodScan::worst(std::size_t i) const { return std::max(f32[i].peak_rel, f64[i].peak_rel); }

std::vector<double> scan_kappas(int per_decade, std::span<const double> extra) {
  const double e_lo = std::log10(double(kFloatMin)), e_hi = std::log10(double(kFloatMax));
  const int n = static_cast<int>(std::ceil((e_hi - e_lo) * per_decade));
  // 0, and the ends of the fitted range [1e−3, 1e4] that every card's bound is taken on.
  std::vector<double> k = {0.0, double(float(1e-3)), double(float(1e4))};
  for (int i = 0; i <= n; ++i) {
    const float x = static_cast<float>(std::pow(10.0, e_lo + (e_hi - e_lo) * i / n));
    k.push_back(i == 0 ? kFloatMin : i == n ? kFloatMax : std::clamp(x, kFloatMin, kFloatMax));
  }
  for (double x : extra)
    if (x >= 0 && x <= kFloatMax) k.push_back(static_cast<float>(x));
  std::sort(k.begin(), k.end());
  k.erase(std::unique(k.begin(), k.end()), k.end());
  return k;
}

KappaScan scan_kappa_range(std::span<const Method> methods, const KappaScanOptions& o) {
  if (o.per_decade < 1 || o.per_decade > 1000)
    throw std::invalid_argument(
        fmt::format("per_decade must be in [1, 1000], got {}", o.per_decade));
  if (o.cosines < 2 || o.cosines > 100001)
    throw std::invalid_argument(fmt::format("cosines must be in [2, 100001], got {}", o.cosines));
  if (o.layer < 0 || o.layer > 100001)
    throw std::invalid_argument(fmt::format("layer must be in [0, 100001], got {}", o.layer));
  KappaScan scan;
  scan.kappas = scan_kappas(o.per_decade, o.extra_kappas);
  for (const Method& m : methods)
    scan.methods.push_back({std::string(m.id), std::vector<KappaWorst>(scan.kappas.size()),
                            std::vector<KappaWorst>(scan.kappas.size())});
  // A private engine: its cache is emptied after every κ, so memory stays at one κ's points.
  const reference::ReferenceEngine engine;
  std::optional<io::Progress> progress;
  if (o.progress) progress.emplace("range", scan.kappas.size());
  for (std::size_t i = 0; i < scan.kappas.size(); ++i) {
    const double kappa = scan.kappas[i];
    const std::vector<double> cosines = scan_cosines(kappa, o);
    std::vector<reference::Query> q;
    for (double c : cosines) q.push_back({kappa, c});
    const std::vector<reference::ReferencePoint> ref = engine.evaluate(q);
    const double peak = engine.evaluate(kappa, 1.0).irradiance;
    tbb::parallel_for(std::size_t{0}, methods.size(), [&](std::size_t m) {
      const Method& method = methods[m];
      const float kf = static_cast<float>(kappa);
      scan.methods[m].f32[i] = worst_at(
          kappa, cosines, ref, peak,
          [&](double c) { return double(method.f32(static_cast<float>(c), kf)); }, engine,
          o.refine);
      scan.methods[m].f64[i] = worst_at(
          kappa, cosines, ref, peak, [&](double c) { return method.f64(c, kappa); }, engine,
          o.refine);
    });
    engine.clear_cache();
    if (progress) progress->advance();
  }
  if (progress) progress->finish();
  return scan;
}

std::optional<KappaInterval> holds_on(const KappaScan& scan, const MethodScan& m, double bound,
                                      double from, double to) {
  const auto& k = scan.kappas;
  std::size_t first = k.size(), last = 0;
  for (std::size_t i = 0; i < k.size(); ++i)
    if (k[i] >= from && k[i] <= to) {
      if (!(m.worst(i) <= bound)) return std::nullopt;
      first = std::min(first, i);
      last = i;
    }
  if (first == k.size()) return std::nullopt;
  while (first > 0 && m.worst(first - 1) <= bound) --first;
  while (last + 1 < k.size() && m.worst(last + 1) <= bound) ++last;
  return KappaInterval{k[first], k[last]};
}

WorstPoint worst_over(const KappaScan& scan, const MethodScan& m, double lo, double hi) {
  WorstPoint w;
  for (std::size_t i = 0; i < scan.kappas.size(); ++i) {
    if (scan.kappas[i] < lo || scan.kappas[i] > hi) continue;
    for (const KappaWorst* x : {&m.f32[i], &m.f64[i]})
      if (!(x->peak_rel <= w.peak_rel)) w = {x->peak_rel, scan.kappas[i], x->cosine};
  }
  return w;
}

Table kappa_range_table(const KappaScan& scan, std::span<const Method> methods,
                        const KappaScanOptions& o) {
  Table t(fmt::format("Each irradiance method's stated bound (registry card: max peak_rel over "
                      "c, float and double) and the κ range it holds on, against the reference "
                      "engine on {} κ from 0 to FLT_MAX ({} per decade) × {} uniform cosines and "
                      "{} at c = t/√κ, |t| ≤ 8{}; `holds`: the bound holds at every scanned κ of "
                      "the stated range; `bound holds on`: the largest scanned range around "
                      "[1e-3, 1e4] where it does",
                      scan.kappas.size(), o.per_decade, o.cosines, o.layer,
                      o.refine ? ", the worst cosine refined by Brent's method" : ""),
          {{"method"},
           {"origin"},
           {"bound", 2},
           {"kappa_lo", 2},
           {"kappa_hi", 2},
           {"max_peak_rel", 3},
           {"at_kappa", 3},
           {"at_cosine", 3},
           {"holds"},
           {"holds_from", 3},
           {"holds_to", 3},
           {"max_peak_rel_anywhere", 3},
           {"anywhere_at_kappa", 3}});
  for (const Method& method : methods) {
    const auto it = std::find_if(scan.methods.begin(), scan.methods.end(),
                                 [&](const MethodScan& s) { return s.id == method.id; });
    if (it == scan.methods.end())
      throw std::invalid_argument(fmt::format("kappa_range_table: {} was not scanned", method.id));
    const ValidRange& v = method.valid;
    const WorstPoint in = worst_over(scan, *it, v.kappa_lo, v.kappa_hi);
    const WorstPoint all = worst_over(scan, *it, 0, kFloatMax);
    const auto extent = holds_on(scan, *it, v.max_peak_rel, 1e-3, 1e4);
    const double none = std::numeric_limits<double>::quiet_NaN();
    t.add_row({Table::text(method.id), Table::text(to_string(method.origin)),
               Table::real(v.max_peak_rel), Table::real(v.kappa_lo), Table::real(v.kappa_hi),
               Table::real(in.peak_rel), Table::real(in.kappa), Table::real(in.cosine),
               Table::text(in.peak_rel <= v.max_peak_rel ? "yes" : "NO"),
               Table::real(extent ? extent->lo : none), Table::real(extent ? extent->hi : none),
               Table::real(all.peak_rel), Table::real(all.kappa)});
  }
  return t;
}

}  // namespace sglab::validate
