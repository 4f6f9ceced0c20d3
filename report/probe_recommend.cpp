// report/probe_recommend.cpp — the cheapest probe meeting a budget
// (probe_recommend.hpp).
#include "report/probe_recommend.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace sglab::report {

namespace {

bool meets(const ProbeCandidate& c, double budget) { return c.error.max_rel <= budget; }

// Indices of the candidates meeting the budget, cheapest first: fewest floats,
// or least cost when the candidates are costed (ties: smaller error, then the
// order tried).
std::vector<std::size_t> ranking(const std::vector<ProbeCandidate>& tried, double budget,
                                 bool by_cost) {
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < tried.size(); ++k)
    if (meets(tried[k], budget)) idx.push_back(k);
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    if (by_cost) {
      const double ca = tried[a].cost.value(), cb = tried[b].cost.value();
      if (ca != cb) return ca < cb;
    } else {
      const auto fa = tried[a].probe.floats(), fb = tried[b].probe.floats();
      if (fa != fb) return fa < fb;
    }
    return tried[a].error.max_rel < tried[b].error.max_rel;
  });
  return idx;
}

// The choice and the runner-up: another label, not the choice's function.
std::pair<std::optional<std::size_t>, std::optional<std::size_t>> pick(
    const std::vector<ProbeCandidate>& tried, double budget, bool by_cost = false) {
  const auto idx = ranking(tried, budget, by_cost);
  if (idx.empty()) return {std::nullopt, std::nullopt};
  const envmap::Probe& first = tried[idx[0]].probe;
  for (std::size_t k : idx)
    if (tried[k].probe.label() != first.label() && !same_probe_function(tried[k].probe, first))
      return {idx[0], k};
  return {idx[0], std::nullopt};
}

// Floats a candidate may have and still be the choice or the runner-up.
std::size_t float_bound(const std::vector<ProbeCandidate>& tried, double budget) {
  const auto [choice, runner_up] = pick(tried, budget);
  if (runner_up) return tried[*runner_up].probe.floats();
  return static_cast<std::size_t>(-1);
}

std::vector<envmap::Lobe> nonzero_lobes(const envmap::Probe& p) {
  std::vector<envmap::Lobe> out;
  for (const envmap::Lobe& l : p.lobes)
    if (l.amplitude[0] != 0 || l.amplitude[1] != 0 || l.amplitude[2] != 0) out.push_back(l);
  return out;
}

// The candidates both measures share: the map's exact irradiance, the error
// of a probe, and the SH and ZH3 families.
// The map's dense truth, after telling `note` that it is being computed.
envmap::DenseTruth dense_truth_told(const envmap::MapIrradiance& field,
                                    const std::function<void(const std::string&)>& note) {
  note("exact irradiance of the full map at the dense normals");
  return envmap::dense_truth(field);
}

struct Candidates {
  const envmap::Map& map;
  const std::function<void(const std::string&)>& note;
  envmap::MapIrradiance field;
  envmap::DenseTruth truth;
  std::vector<envmap::Vec3> normals;
  std::vector<envmap::Vec3> exact;
  envmap::Map work;

  Candidates(const envmap::Map& m, const std::function<void(const std::string&)>& n)
      : map(m),
        note(n),
        field(m),
        truth(dense_truth_told(field, n)),
        normals(reference::fibonacci_normals(envmap::kFitNormals)),
        exact(field.at(normals)),
        work(envmap::working_copy(m)) {}
  envmap::DenseError error(const envmap::Probe& p) const {
    return envmap::dense_error(truth, envmap::probe_irradiance_method(p));
  }
  envmap::Judge judge() const {
    return [this](const envmap::Probe& p) { return error(p).max_rel; };
  }
  void add(ProbeRecommendation& r, const std::string& family, const envmap::Probe& p) const {
    r.tried.push_back({family, p, error(p), std::nullopt});
  }
  void add_sh(ProbeRecommendation& r) {
    note("spherical harmonics and ZH3");
    const auto radiance = envmap::radiance_sh(map, envmap::kMaxShOrder);
    for (int l = 0; l <= envmap::kMaxShOrder; ++l) {
      add(r, "SH projection", envmap::project_sh(radiance, l));
      add(r, "SH fit", envmap::fit_sh(normals, exact, l));
      add(r, "SH minimax", envmap::fit_sh(normals, exact, l, envmap::LinearFit::minimax));
    }
    add(r, "SH L1 non-negative", envmap::project_sh_nonneg(radiance));
    const envmap::Probe zh3 = envmap::project_zh3(radiance);
    add(r, "ZH3 projection", zh3);
    add(r, "ZH3 fit", envmap::fit_zh3(normals, exact, zh3.zonal_axis()));
    add(r, "ZH3 minimax",
        envmap::fit_zh3(normals, exact, zh3.zonal_axis(), envmap::LinearFit::minimax));
  }
};

// Whether a ladder needs no more steps: two steps meet the budget with
// different functions, or the first meeting step is the last step's function
// (every count after it kept that solution plus lobes of zero amplitude: the
// fits found nothing better, and further counts would cost more for the same).
bool ladder_done(const std::vector<envmap::LadderStep>& steps, double budget) {
  const envmap::Probe* first = nullptr;
  for (const auto& s : steps) {
    if (s.judged > budget) continue;
    if (!first)
      first = &s.probe;
    else if (!same_probe_function(s.probe, *first))
      return true;
  }
  return first && first != &steps.back().probe;
}

// The ladder `fit(cap)` from 4 steps, doubled until ladder_done or `limit`
// (each fit deterministic: a longer ladder starts with the shorter one's steps;
// the lobe ladder's fit grows an envmap::LobeLadder, so its steps are fitted once).
template <class Fit>
std::vector<envmap::LadderStep> ladder_until_done(std::size_t limit, double budget, Fit fit) {
  std::vector<envmap::LadderStep> steps;
  for (std::size_t cap = std::min<std::size_t>(limit, 4); cap > 0; cap = std::min(limit, 2 * cap)) {
    steps = fit(cap);
    if (cap == limit || ladder_done(steps, budget)) break;
  }
  return steps;
}

}  // namespace

bool same_probe_function(const envmap::Probe& a, const envmap::Probe& b) {
  if (a.kind != b.kind || a.order != b.order || a.sh != b.sh || a.zonal != b.zonal) return false;
  const auto la = nonzero_lobes(a), lb = nonzero_lobes(b);
  if (la.empty() && lb.empty()) return true;
  if (a.method != b.method || la.size() != lb.size()) return false;
  for (std::size_t k = 0; k < la.size(); ++k)
    if (la[k].axis != lb[k].axis || la[k].sharpness != lb[k].sharpness ||
        la[k].amplitude != lb[k].amplitude)
      return false;
  return true;
}

ProbeRecommendation recommend_probe_by_storage(const envmap::Map& map, double budget,
                                               std::size_t max_lobes,
                                               const std::function<void(const std::string&)>& note,
                                               int restarts) {
  ProbeRecommendation r;
  Candidates c(map, note);
  c.add_sh(r);
  const std::size_t supported = std::min(max_lobes, envmap::max_lobes(c.work));
  std::size_t bound = float_bound(r.tried, budget);
  // Counts of more floats than SH's runner-up can be neither; within that,
  // the ladder stops once two counts meet the budget (more lobes, more floats).
  const std::size_t limit = std::min<std::size_t>(supported, bound / 7);
  std::vector<envmap::LadderStep> lobes;
  if (limit > 0) {
    envmap::LobeLadder ladder(c.work, c.normals, c.exact, c.judge(), 100, envmap::kMinimaxRounds,
                              restarts);
    lobes = ladder_until_done(limit, budget, [&](std::size_t cap) {
      note(fmt::format("SG lobes, 1 to {}", cap));
      return ladder.grow_to(cap);
    });
    for (const auto& s : lobes) c.add(r, "SG lobes", s.probe);
  }
  r.lobe_cap = lobes.size();
  bound = float_bound(r.tried, budget);
  const std::size_t sh2 = 3 * envmap::sh_count(2);
  r.hybrid_cap = bound >= sh2 + 7 ? std::min(lobes.size(), (bound - sh2) / 7) : 0;
  if (r.hybrid_cap > 0) {
    note(fmt::format("SH L2 + SG lobes, 1 to {}", r.hybrid_cap));
    for (const auto& s :
         envmap::fit_hybrid_ladder(c.work, c.normals, c.exact, lobes, r.hybrid_cap, c.judge()))
      c.add(r, "SH L2 + SG lobes", s.probe);
  }
  const auto [choice, runner_up] = pick(r.tried, budget);
  r.choice = choice;
  r.runner_up = runner_up;
  return r;
}

ProbeRecommendation recommend_probe_by_cost(const envmap::Map& map, double budget,
                                            std::size_t max_lobes, const ProbeCosts& cost,
                                            const std::function<void(const std::string&)>& note,
                                            int restarts) {
  ProbeRecommendation r;
  Candidates c(map, note);
  c.add_sh(r);
  const std::size_t supported = std::min(max_lobes, envmap::max_lobes(c.work));
  envmap::LobeLadder ladder(c.work, c.normals, c.exact, c.judge(), 100, envmap::kMinimaxRounds,
                            restarts);
  const auto lobes = ladder_until_done(supported, budget, [&](std::size_t cap) {
    note(fmt::format("SG lobes, 1 to {}", cap));
    return ladder.grow_to(cap);
  });
  for (const auto& s : lobes) c.add(r, "SG lobes", s.probe);
  r.lobe_cap = lobes.size();
  const auto hybrid = ladder_until_done(lobes.size(), budget, [&](std::size_t cap) {
    note(fmt::format("SH L2 + SG lobes, 1 to {}", cap));
    return envmap::fit_hybrid_ladder(c.work, c.normals, c.exact, lobes, cap, c.judge());
  });
  for (const auto& s : hybrid) c.add(r, "SH L2 + SG lobes", s.probe);
  r.hybrid_cap = hybrid.size();

  std::vector<const envmap::Probe*> costed;
  std::vector<std::size_t> where;
  for (std::size_t k = 0; k < r.tried.size(); ++k)
    if (meets(r.tried[k], budget)) {
      costed.push_back(&r.tried[k].probe);
      where.push_back(k);
    }
  if (!costed.empty()) {
    note(fmt::format("cost of the {} probes meeting the budget", costed.size()));
    const std::vector<double> costs = cost(costed);
    if (costs.size() != costed.size())
      throw std::logic_error("recommend_probe_by_cost: one cost per probe expected");
    for (std::size_t k = 0; k < where.size(); ++k) r.tried[where[k]].cost = costs[k];
  }
  const auto [choice, runner_up] = pick(r.tried, budget, true);
  r.choice = choice;
  r.runner_up = runner_up;
  return r;
}

}  // namespace sglab::report
