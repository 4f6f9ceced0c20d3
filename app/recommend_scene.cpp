// `sglab recommend --scene FILE --budget E`: the cheapest irradiance method
// whose error on a scene of SG lights (validate/scene.hpp) is ≤ E. The scene's
// total RGB irradiance is evaluated at --normals Fibonacci normals exactly
// (reference engine) and with every registered irradiance method; error =
// max over normals and channels of |Ê − E| / the scene's largest exact
// irradiance. Ranking and cost (--cost, default GPU inverse throughput on
// navi21) as `sglab recommend --kappa` (validate/pareto.hpp, app/costs_option.hpp).
// Then the scene's κ range and, over that range, the error of each of sglab's
// own models on the standard 29 κ × 41 c sub-grid: which of them suffices.
#include "app/recommend_scene.hpp"

#include <cmath>
#include <filesystem>
#include <iterator>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "common/io.hpp"
#include "report/pareto.hpp"
#include "validate/scene.hpp"

namespace sglab::app {

namespace {

nlohmann::ordered_json number(double x) {
  if (!std::isfinite(x)) return nullptr;
  return x;
}

}  // namespace

void recommend_scene(const SceneRecommendArgs& args) {
  const report::CostSource cost = args.costs.source(args.precision);  // a bad --cost before any work
  std::string text;
  try {
    text = io::read_input_file(args.scene, validate::kMaxSceneFileBytes, "a scene file");
  } catch (const InputError& e) {
    throw InputError(fmt::format("--scene: {}", e.what()));
  }
  validate::Scene scene;
  try {
    scene = validate::parse_scene(text, args.scene);
  } catch (const validate::SceneError& e) {
    throw InputError(e.what());
  }

  // Limits (validate/scene.hpp, README) before anything is allocated for the normals.
  try {
    validate::check_scene_limits(scene.lights.size(), args.normals);
  } catch (const validate::SceneError& e) {
    throw InputError(fmt::format("--scene {}: {}", args.scene, e.what()));
  }
  const auto normals = validate::fibonacci_normals(args.normals);
  const std::vector<double> errors = validate::scene_errors(scene, normals, irradiance_methods, args.precision);
  std::vector<report::MethodPoint> points;
  std::vector<Origin> origins;
  for (std::size_t i = 0; i < std::size(irradiance_methods); ++i) {
    const Method& m = irradiance_methods[i];
    report::MethodPoint p;
    p.method = std::string(m.id);
    p.origin = m.origin;
    p.max_peak_rel = errors[i];
    points.push_back(p);
    origins.push_back(m.origin);
  }
  const CostsOption::From source = args.costs.fill(points, args.precision, /*repetitions=*/7, /*min_time=*/0.01);
  const report::Recommendation r = report::recommend(points, args.budget);

  // sglab's models over the scene's κ range (κ = 0 lights: the range starts at 1e-3).
  const double lo = std::max(scene.kappa_min(), 1e-3), hi = std::max(scene.kappa_max(), lo);
  const auto range_errors = report::irradiance_errors(lo, hi, args.precision);
  struct ModelOnRange {
    std::string id;
    double error, cost;
  };
  std::vector<ModelOnRange> models;
  const ModelOnRange* sufficient = nullptr;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (origins[i] != Origin::sglab) continue;
    for (const auto& e : range_errors)
      if (e.method == points[i].method) models.push_back({e.method, e.max_peak_rel, points[i].cost});
  }
  for (const auto& m : models)
    if (m.error <= args.budget && std::isfinite(m.cost) && (!sufficient || m.cost < sufficient->cost)) sufficient = &m;

  if (args.json) {
    nlohmann::ordered_json doc;
    doc["scene"] = args.scene;
    doc["lights"] = scene.lights.size();
    doc["normals"] = normals.size();
    doc["kappa_range"] = {scene.kappa_min(), scene.kappa_max()};
    doc["budget"] = args.budget;
    doc["precision"] = std::string(validate::to_string(args.precision));
    doc["cost_source"] = cost.name();
    doc["cost_unit"] = std::string(cost.unit());
    doc["cost_from"] = source.text;
    doc["error"] = "max over normals and RGB channels of |E_approx - E_exact| / max exact irradiance of the scene";
    auto point = [](const std::optional<report::MethodPoint>& p) -> nlohmann::ordered_json {
      if (!p) return nullptr;
      return {{"method", p->method}, {"scene_error", number(p->max_peak_rel)}, {"cost", number(p->cost)},
              {"cost_unit", p->cost_unit}};
    };
    doc["choice"] = point(r.choice);
    doc["runner_up"] = point(r.runner_up);
    doc["most_accurate"] = point(r.most_accurate);
    nlohmann::ordered_json methods = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < points.size(); ++i)
      methods.push_back({{"method", points[i].method},
                         {"origin", std::string(to_string(origins[i]))},
                         {"scene_error", number(points[i].max_peak_rel)},
                         {"cost", number(points[i].cost)},
                         {"cost_unit", points[i].cost_unit},
                         {"qualifies", std::isfinite(points[i].max_peak_rel) && std::isfinite(points[i].cost) &&
                                           points[i].max_peak_rel <= args.budget}});
    doc["methods"] = std::move(methods);
    nlohmann::ordered_json sg = nlohmann::ordered_json::array();
    for (const auto& m : models)
      sg.push_back({{"method", m.id}, {"range_max_peak_rel", number(m.error)}, {"meets_budget", m.error <= args.budget}});
    doc["sglab_models_on_range"] = {{"kappa_lo", lo}, {"kappa_hi", hi}, {"models", sg},
                                    {"sufficient", sufficient ? nlohmann::ordered_json(sufficient->id) : nullptr}};
    fmt::print("{}\n", doc.dump(2));
    return;
  }

  fmt::print("scene {}: {} light(s), κ in [{:.4g}, {:.4g}], {} Fibonacci normals, {}, budget {}\n", args.scene,
             scene.lights.size(), scene.kappa_min(), scene.kappa_max(), normals.size(),
             validate::to_string(args.precision), args.budget);
  fmt::print("error = max over normals and RGB channels of |Ê − E| / the scene's largest exact irradiance\n\n");
  fmt::print("  {:<24} {:<10} {:>12} {:>12}  {}\n", "method", "origin", "scene error", "cost", "meets budget");
  for (std::size_t i = 0; i < points.size(); ++i)
    fmt::print("  {:<24} {:<10} {:>12.4g} {:>12}  {}\n", points[i].method, to_string(origins[i]),
               points[i].max_peak_rel, report::cost_text(points[i]),
               std::isfinite(points[i].max_peak_rel) && points[i].max_peak_rel <= args.budget ? "yes" : "no");
  fmt::print("\n");
  if (r.choice) {
    fmt::print("  choice:    {} (scene error {:.4g}, {})\n", r.choice->method, r.choice->max_peak_rel,
               report::cost_text(*r.choice));
    if (r.runner_up)
      fmt::print("  runner-up: {} (scene error {:.4g}, {})\n", r.runner_up->method, r.runner_up->max_peak_rel,
                 report::cost_text(*r.runner_up));
  } else {
    fmt::print("  no method meets the budget on this scene.\n");
    if (r.most_accurate)
      fmt::print("  most accurate: {} (scene error {:.4g})\n", r.most_accurate->method, r.most_accurate->max_peak_rel);
  }
  fmt::print("\n  sglab models over the scene's κ range [{:.4g}, {:.4g}] (max peak_rel, 29 κ × 41 c):\n", lo, hi);
  for (const auto& m : models)
    fmt::print("    {:<22} {:.4g}{}\n", m.id, m.error, m.error <= args.budget ? "  meets the budget" : "");
  if (sufficient)
    fmt::print("  cheapest sglab model sufficient for the range: {}\n", sufficient->id);
  else
    fmt::print("  no registered sglab model meets the budget over this κ range.\n");
  fmt::print("(cost in {}: {}; costs within {}% are ties, broken by error)\n", cost.unit(), source.text,
             report::kCostTieMargin * 100);
}

}  // namespace sglab::app
