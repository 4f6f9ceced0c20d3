#include "validate/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "common/args.hpp"
#include "common/io.hpp"

namespace sglab::validate {

void SweepGrid::validate() const {
  constexpr double flt_max = std::numeric_limits<float>::max();
  if (!std::isfinite(kappa_lo) || !std::isfinite(kappa_hi))
    throw std::invalid_argument(
        fmt::format("κ bounds must be finite, got {}:{}", kappa_lo, kappa_hi));
  if (!(kappa_lo > 0))
    throw std::invalid_argument(fmt::format("κ lower bound must be > 0, got {}", kappa_lo));
  if (!(kappa_hi >= kappa_lo))
    throw std::invalid_argument(
        fmt::format("κ upper bound must be >= the lower bound, got {} < {}", kappa_hi, kappa_lo));
  if (static_cast<float>(kappa_lo) == 0.0f)
    throw std::invalid_argument(fmt::format(
        "κ lower bound {} rounds to 0 in float (inputs are rounded to float first)", kappa_lo));
  if (kappa_hi > flt_max)
    throw std::invalid_argument(fmt::format(
        "κ upper bound {} exceeds the largest float {} (inputs are rounded to float first)",
        kappa_hi, flt_max));
  if (kappa_count < 1)
    throw std::invalid_argument(fmt::format("κ count must be >= 1, got {}", kappa_count));
  if (kappa_count == 1 && kappa_lo != kappa_hi)
    throw std::invalid_argument(
        fmt::format("a κ count of 1 needs equal bounds, got {}:{}", kappa_lo, kappa_hi));
  if (cosine_count < 2)
    throw std::invalid_argument(fmt::format("cosine count must be >= 2, got {}", cosine_count));
  if (point_count() > kMaxPoints) {
    // every method, float and double
    const std::size_t entries = registered_sweep_methods().size() * 2;
    throw std::invalid_argument(
        fmt::format("the grid of {} κ × {} cosines = {} points exceeds the limit of {} points; it "
                    "would need about {:.3g} GB of memory for every method in float and double "
                    "(use fewer κ or cosines, or several smaller sweeps)",
                    kappa_count, cosine_count, point_count(), kMaxPoints,
                    static_cast<double>(sweep_memory_estimate(*this, entries)) / 1e9));
  }
}

std::uint64_t SweepGrid::point_count() const {
  if (kappa_count < 1 || cosine_count < 1) return 0;
  return static_cast<std::uint64_t>(kappa_count) * static_cast<std::uint64_t>(cosine_count);
}

std::uint64_t sweep_memory_estimate(const SweepGrid& grid, std::size_t entries) {
  const std::uint64_t points = grid.point_count();
  const std::uint64_t per_point = sizeof(reference::Query) + sizeof(reference::ReferencePoint) +
                                  entries * kSweepBytesPerPointEntry;
  return points * per_point;
}

std::vector<double> SweepGrid::kappas() const {
  return io::log_spaced(kappa_lo, kappa_hi, kappa_count);
}

std::vector<double> SweepGrid::cosines() const {
  std::vector<double> c;
  if (cosine_count < 2) return c;
  c.reserve(static_cast<std::size_t>(cosine_count));
  const int last = cosine_count - 1;
  for (int i = 0; i <= last; ++i)
    // the standard grid's expression (docs/quantities.md); ends exact
    c.push_back(-1.0 + 2.0 * i / last);
  return c;
}

std::vector<double> float_exact(std::span<const double> values) {
  std::vector<double> out;
  out.reserve(values.size());
  for (double v : values) out.push_back(static_cast<double>(static_cast<float>(v)));
  return out;
}

std::vector<SweepMethod> registered_sweep_methods() {
  std::vector<SweepMethod> out;
  for (const Method& m : irradiance_methods) out.push_back({Quantity::irradiance, m});
  for (const Method& m : hemispherical_methods) out.push_back({Quantity::hemispherical, m});
  for (const Method& m : normalized_methods) out.push_back({Quantity::normalized, m});
  return out;
}

double reference_value(const reference::ReferencePoint& point, Quantity q) {
  switch (q) {
    case Quantity::irradiance:
      return point.irradiance;
    case Quantity::hemispherical:
      return point.hemispherical;
    case Quantity::normalized:
      return point.normalized;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double SweepResult::reference_value(Quantity q, std::size_t k, std::size_t j) const {
  return validate::reference_value(reference[index(k, j)], q);
}

double SweepResult::peak_value(Quantity q, std::size_t k) const {
  return validate::reference_value(peak[k], q);
}

const SweepEntry* SweepResult::find(std::string_view method, Quantity q,
                                    const io::Evaluation& f) const {
  for (const SweepEntry& e : entries)
    if (e.method == method && e.quantity == q && e.precision == f) return &e;
  return nullptr;
}

namespace {

std::vector<reference::ReferencePoint> evaluate_reference(std::span<const reference::Query> queries,
                                                          reference::Quadrature quadrature,
                                                          bool progress) {
  // In chunks, so that the terminal shows progress; each chunk still runs in
  // parallel inside the engine.
  constexpr std::size_t chunk = 256;
  std::vector<reference::ReferencePoint> out;
  out.reserve(queries.size());
  std::optional<io::Progress> bar;
  if (progress) bar.emplace("sweep: reference", queries.size());
  for (std::size_t begin = 0; begin < queries.size(); begin += chunk) {
    const std::size_t n = std::min(chunk, queries.size() - begin);
    auto part = reference::reference_engine().evaluate(queries.subspan(begin, n), quadrature);
    out.insert(out.end(), part.begin(), part.end());
    if (bar) bar->advance(n);
  }
  if (bar) bar->finish();
  return out;
}

double evaluate(const Method& m, io::Precision p, double cosine, double kappa) {
  if (p == io::Precision::float32)
    return static_cast<double>(m.f32(static_cast<float>(cosine), static_cast<float>(kappa)));
  return m.f64(cosine, kappa);
}

}  // namespace

SweepEntry sweep_entry(const SweepResult& r, const SweepMethod& sm, const io::Evaluation& f,
                       std::span<const double> values, bool keep_points) {
  const std::size_t nk = r.kappas.size(), nc = r.cosines.size();
  if (values.size() != nk * nc)
    throw std::invalid_argument(
        fmt::format("sweep_entry: {} values for a {} x {} grid", values.size(), nk, nc));
  SweepEntry e;
  e.method = std::string(sm.method.id);
  e.quantity = sm.quantity;
  e.precision = f;
  if (keep_points) {
    e.values.resize(nk * nc);
    e.peak_rel.resize(nk * nc);
  }
  MetricAccumulator total;
  e.per_kappa.reserve(nk);
  for (std::size_t k = 0; k < nk; ++k) {
    MetricAccumulator row;
    const double peak = r.peak_value(sm.quantity, k);
    for (std::size_t j = 0; j < nc; ++j) {
      const double value = values[r.index(k, j)];
      const PointErrors p =
          row.add(r.kappas[k], r.cosines[j], value, r.reference_value(sm.quantity, k, j), peak);
      if (keep_points) {
        e.values[r.index(k, j)] = value;
        e.peak_rel[r.index(k, j)] = p.peak_rel;
      }
    }
    total.merge(row);
    e.per_kappa.push_back(row.summary());
  }
  e.summary = total.summary();
  return e;
}

SweepResult sweep(const SweepGrid& grid, std::span<const SweepMethod> methods,
                  const SweepOptions& options) {
  grid.validate();
  SweepResult r;
  r.grid = grid;
  r.kappas = float_exact(grid.kappas());
  r.cosines = float_exact(grid.cosines());
  const std::size_t nk = r.kappas.size(), nc = r.cosines.size();

  std::vector<reference::Query> queries;
  queries.reserve(nk * nc + nk);
  for (std::size_t k = 0; k < nk; ++k)
    for (std::size_t j = 0; j < nc; ++j) queries.push_back({r.kappas[k], r.cosines[j]});
  for (std::size_t k = 0; k < nk; ++k) queries.push_back({r.kappas[k], 1.0});
  auto ref = evaluate_reference(queries, options.reference, options.progress);
  r.peak.assign(ref.begin() + static_cast<std::ptrdiff_t>(nk * nc), ref.end());
  ref.resize(nk * nc);
  r.reference = std::move(ref);

  for (const SweepMethod& sm : methods) {
    for (io::Precision f : options.precisions) {
      std::vector<double> values(nk * nc);
      for (std::size_t k = 0; k < nk; ++k)
        for (std::size_t j = 0; j < nc; ++j)
          values[r.index(k, j)] = evaluate(sm.method, f, r.cosines[j], r.kappas[k]);
      r.entries.push_back(sweep_entry(r, sm, io::on_cpu(f), values, options.keep_points));
    }
  }
  return r;
}

Table summary_table(const SweepResult& result) {
  Table t(fmt::format(
              "Accuracy sweep: κ in [{}, {}] ({} values), {} cosines; peak_rel = |x̂ − x|/x(1, κ)",
              result.grid.kappa_lo, result.grid.kappa_hi, result.grid.kappa_count,
              result.grid.cosine_count),
          {{"method"},
           {"quantity"},
           {"precision"},
           {"max_peak_rel", 3},
           {"worst_kappa", 4},
           {"worst_cosine", 4},
           {"rms_peak_rel", 3},
           {"max_rel", 3},
           {"nonfinite"}});
  for (const SweepEntry& e : result.entries) {
    const MetricSummary& s = e.summary;
    t.add_row({Table::text(e.method), Table::text(to_string(e.quantity)),
               Table::text(to_string(e.precision)), Table::real(s.peak_rel.max),
               Table::real(s.peak_rel.worst_kappa), Table::real(s.peak_rel.worst_cosine),
               Table::real(s.peak_rel.rms), Table::real(s.rel.max), Table::count(s.nonfinite)});
  }
  return t;
}

Table per_kappa_table(const SweepResult& result) {
  Table t("Accuracy sweep per κ: max and RMS over the cosines", {{"method"},
                                                                 {"quantity"},
                                                                 {"precision"},
                                                                 {"kappa", 4},
                                                                 {"max_peak_rel", 3},
                                                                 {"worst_cosine", 4},
                                                                 {"rms_peak_rel", 3},
                                                                 {"max_rel", 3},
                                                                 {"nonfinite"}});
  for (const SweepEntry& e : result.entries) {
    for (std::size_t k = 0; k < e.per_kappa.size(); ++k) {
      const MetricSummary& s = e.per_kappa[k];
      t.add_row({Table::text(e.method), Table::text(to_string(e.quantity)),
                 Table::text(to_string(e.precision)), Table::real(result.kappas[k]),
                 Table::real(s.peak_rel.max), Table::real(s.peak_rel.worst_cosine),
                 Table::real(s.peak_rel.rms), Table::real(s.rel.max), Table::count(s.nonfinite)});
    }
  }
  return t;
}

Table points_table(const SweepResult& result) {
  Table t("Accuracy sweep, every point", {{"kappa"},
                                          {"cosine"},
                                          {"method"},
                                          {"quantity"},
                                          {"precision"},
                                          {"value"},
                                          {"reference"},
                                          {"peak_rel"}});
  for (const SweepEntry& e : result.entries) {
    if (e.values.empty()) continue;
    for (std::size_t k = 0; k < result.kappas.size(); ++k)
      for (std::size_t j = 0; j < result.cosines.size(); ++j) {
        const std::size_t i = result.index(k, j);
        t.add_row({Table::real(result.kappas[k]), Table::real(result.cosines[j]),
                   Table::text(e.method), Table::text(to_string(e.quantity)),
                   Table::text(to_string(e.precision)), Table::real(e.values[i]),
                   Table::real(result.reference_value(e.quantity, k, j)),
                   Table::real(e.peak_rel[i])});
      }
  }
  return t;
}

}  // namespace sglab::validate
