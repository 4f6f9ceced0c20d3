// report/probe_recommend.cpp — the probe of fewest floats meeting a budget
// (probe_recommend.hpp).
#include "report/probe_recommend.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sglab::report {

namespace {

bool meets(const ProbeCandidate& c, double budget) { return c.error.max_rel <= budget; }

// Indices of the candidates meeting the budget, fewest floats first (ties:
// smaller error, then the order tried).
std::vector<std::size_t> ranking(const std::vector<ProbeCandidate>& tried, double budget) {
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < tried.size(); ++k)
    if (meets(tried[k], budget)) idx.push_back(k);
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    const auto fa = tried[a].probe.floats(), fb = tried[b].probe.floats();
    if (fa != fb) return fa < fb;
    return tried[a].error.max_rel < tried[b].error.max_rel;
  });
  return idx;
}

// The choice and the runner-up of another label.
std::pair<std::optional<std::size_t>, std::optional<std::size_t>> pick(
    const std::vector<ProbeCandidate>& tried, double budget) {
  const auto idx = ranking(tried, budget);
  if (idx.empty()) return {std::nullopt, std::nullopt};
  for (std::size_t k : idx)
    if (tried[k].probe.label() != tried[idx[0]].probe.label()) return {idx[0], k};
  return {idx[0], std::nullopt};
}

// Floats a candidate may have and still be the choice or the runner-up.
std::size_t float_bound(const std::vector<ProbeCandidate>& tried, double budget) {
  const auto [choice, runner_up] = pick(tried, budget);
  if (runner_up) return tried[*runner_up].probe.floats();
  return static_cast<std::size_t>(-1);
}

}  // namespace

ProbeRecommendation recommend_probe_by_storage(
    const envmap::Map& map, double budget, std::size_t max_lobes,
    const std::function<void(const std::string&)>& note) {
  ProbeRecommendation r;
  note("exact irradiance of the full map at the dense normals");
  const envmap::MapIrradiance field(map);
  const envmap::DenseTruth truth = envmap::dense_truth(field);
  const auto normals = reference::fibonacci_normals(envmap::kFitNormals);
  const auto exact = field.at(normals);
  const auto error = [&](const envmap::Probe& p) {
    return envmap::dense_error(truth, envmap::probe_irradiance_method(p));
  };
  const auto add = [&](const std::string& family, const envmap::Probe& p) {
    r.tried.push_back({family, p, error(p)});
  };

  note("spherical harmonics and ZH3");
  const auto radiance = envmap::radiance_sh(map, envmap::kMaxShOrder);
  for (int l = 0; l <= envmap::kMaxShOrder; ++l) {
    add("SH projection", envmap::project_sh(radiance, l));
    add("SH fit", envmap::fit_sh(normals, exact, l));
  }
  add("SH L1 non-negative", envmap::project_sh_nonneg(radiance));
  const envmap::Probe zh3 = envmap::project_zh3(radiance);
  add("ZH3 projection", zh3);
  add("ZH3 fit", envmap::fit_zh3(normals, exact, zh3.zonal_axis()));

  const envmap::Map work = envmap::working_copy(map);
  const std::size_t supported = std::min(max_lobes, envmap::max_lobes(work));
  const auto judge = [&](const envmap::Probe& p) { return error(p).max_rel; };
  std::size_t bound = float_bound(r.tried, budget);
  r.lobe_cap = std::min<std::size_t>(supported, bound / 7);
  std::vector<envmap::LadderStep> lobes;
  if (r.lobe_cap > 0) {
    note(fmt::format("SG lobes, 1 to {}", r.lobe_cap));
    lobes = envmap::fit_lobe_ladder(work, normals, exact, r.lobe_cap, judge);
    for (const auto& s : lobes) add("SG lobes", s.probe);
  }
  bound = float_bound(r.tried, budget);
  const std::size_t sh2 = 3 * envmap::sh_count(2);
  r.hybrid_cap = bound >= sh2 + 7 ? std::min(lobes.size(), (bound - sh2) / 7) : 0;
  if (r.hybrid_cap > 0) {
    note(fmt::format("SH L2 + SG lobes, 1 to {}", r.hybrid_cap));
    for (const auto& s :
         envmap::fit_hybrid_ladder(work, normals, exact, lobes, r.hybrid_cap, judge))
      add("SH L2 + SG lobes", s.probe);
  }
  const auto [choice, runner_up] = pick(r.tried, budget);
  r.choice = choice;
  r.runner_up = runner_up;
  return r;
}

}  // namespace sglab::report
