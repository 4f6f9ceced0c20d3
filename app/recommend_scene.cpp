// `sglab recommend --scene FILE --budget E`: the cheapest irradiance method
// whose error on a scene of SG lights (validate/scene_errors.hpp) is ≤ E. The scene's
// total RGB irradiance is evaluated at --normals Fibonacci normals exactly
// (reference engine) and with every registered irradiance method; error =
// max over normals and channels of |Ê − E| / the scene's largest exact
// irradiance. Ranking and cost (--cost, default GPU inverse throughput on
// navi21) as `sglab recommend --kappa` (report/scene_ranking.hpp, report/pareto.hpp,
// app/costs_option.hpp).
// Then the scene's κ range and, over that range, the error of each of sglab's
// own models on the standard 29 κ × 41 c sub-grid: which of them suffices.
#include "app/recommend_scene.hpp"

#include <algorithm>
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
#include "report/scene_ranking.hpp"
#include "validate/scene_errors.hpp"

namespace sglab::app {

namespace {

reference::Scene read_scene(const SceneRecommendArgs& args) {
  std::string text;
  try {
    text = io::read_input_file(args.scene, reference::kMaxSceneFileBytes, "a scene file");
  } catch (const InputError& e) {
    throw InputError(fmt::format("--scene: {}", e.what()));
  }
  reference::Scene scene;
  try {
    scene = reference::parse_scene(text, args.scene);
  } catch (const reference::SceneError& e) {
    throw InputError(e.what());
  }
  // Limits (reference/scene.hpp, docs/cli.md) before anything is allocated for the normals.
  try {
    reference::check_scene_limits(scene.lights.size(), args.normals);
  } catch (const reference::SceneError& e) {
    throw InputError(fmt::format("--scene {}: {}", args.scene, e.what()));
  }
  return scene;
}

// What both outputs show.
struct SceneOutput {
  const SceneRecommendArgs& args;
  const reference::Scene& scene;
  std::size_t normals;
  const cost::CostSource& cost;
  const CostsOption::From& source;
  const std::vector<report::MethodPoint>& points;
  const report::SceneRanking& ranking;
};

void print_json(const SceneOutput& o) {
  const report::Recommendation& r = o.ranking.recommendation;
  nlohmann::ordered_json doc;
  doc["scene"] = o.args.scene;
  doc["lights"] = o.scene.lights.size();
  doc["normals"] = o.normals;
  doc["kappa_range"] = {o.scene.kappa_min(), o.scene.kappa_max()};
  doc["budget"] = o.args.budget;
  doc["precision"] = std::string(io::to_string(o.args.precision));
  doc["cost_source"] = o.cost.name();
  doc["cost_unit"] = std::string(o.cost.unit());
  doc["cost_from"] = o.source.text;
  doc["error"] =
      "max over normals and RGB channels of |E_approx - E_exact| / max exact irradiance of the "
      "scene";
  auto point = [](const std::optional<report::MethodPoint>& p) -> nlohmann::ordered_json {
    if (!p) return nullptr;
    return {{"method", p->method},
            {"scene_error", json_number(p->max_peak_rel)},
            {"cost", json_number(p->cost)},
            {"cost_unit", p->cost_unit},
            {"cost_form", p->cost_form}};
  };
  doc["choice"] = point(r.choice);
  doc["runner_up"] = point(r.runner_up);
  doc["most_accurate"] = point(r.most_accurate);
  nlohmann::ordered_json methods = nlohmann::ordered_json::array();
  for (const auto& p : o.points)
    methods.push_back({{"method", p.method},
                       {"origin", std::string(to_string(p.origin))},
                       {"scene_error", json_number(p.max_peak_rel)},
                       {"cost", json_number(p.cost)},
                       {"cost_unit", p.cost_unit},
                       {"cost_form", p.cost_form},
                       {"in_valid_range", p.in_valid_range},
                       {"qualifies", std::isfinite(p.max_peak_rel) && std::isfinite(p.cost) &&
                                         p.max_peak_rel <= o.args.budget && p.in_valid_range}});
  doc["methods"] = std::move(methods);
  nlohmann::ordered_json outside = nlohmann::ordered_json::array();
  for (const auto& p : o.points)
    if (!p.in_valid_range) outside.push_back(p.method);
  doc["outside_valid_range"] = std::move(outside);
  nlohmann::ordered_json sg = nlohmann::ordered_json::array();
  for (const auto& m : o.ranking.models_on_range)
    sg.push_back({{"method", m.method},
                  {"range_max_peak_rel", json_number(m.max_peak_rel)},
                  {"in_valid_range", m.in_valid_range},
                  {"meets_budget", m.max_peak_rel <= o.args.budget}});
  // sglab's models' errors over the scene's κ range alone (not its lights), and the cheapest
  // of them meeting the budget there.
  const auto& sufficient = o.ranking.sufficient;
  doc["errors_on_kappa_range"] = {
      {"kappa_lo", o.ranking.kappa_lo},
      {"kappa_hi", o.ranking.kappa_hi},
      {"models", sg},
      {"sufficient", sufficient ? nlohmann::ordered_json(sufficient->method) : nullptr}};
  fmt::print("{}\n", doc.dump(2));
}

void print_text(const SceneOutput& o) {
  const report::Recommendation& r = o.ranking.recommendation;
  fmt::print("scene {}: {} light(s), κ in [{:.4g}, {:.4g}], {} Fibonacci normals, {}, budget {}\n",
             o.args.scene, o.scene.lights.size(), o.scene.kappa_min(), o.scene.kappa_max(),
             o.normals, io::to_string(o.args.precision), o.args.budget);
  fmt::print(
      "error = max over normals and RGB channels of |Ê − E| / the scene's largest exact "
      "irradiance\n\n");
  // The GPU figure's form (gpu:FAMILY: per light in the loop, split or kappa per light) last.
  const bool forms = std::any_of(o.points.begin(), o.points.end(),
                                 [](const report::MethodPoint& p) { return !p.cost_form.empty(); });
  fmt::print("  {:<24} {:<10} {:>12} {:>12}  {}\n", "method", "origin", "scene error", "cost",
             forms ? "meets budget  cost form" : "meets budget");
  for (const auto& p : o.points) {
    const char* meets = !p.in_valid_range ? "outside its valid κ range"
                        : std::isfinite(p.max_peak_rel) && p.max_peak_rel <= o.args.budget ? "yes"
                                                                                           : "no";
    fmt::print("  {:<24} {:<10} {:>12.4g} {:>12}  {}\n", p.method, to_string(p.origin),
               p.max_peak_rel, report::cost_text(p, /*with_form=*/false),
               forms ? fmt::format("{:<12}  {}", meets, p.cost_form) : std::string(meets));
  }
  if (const std::string outside = report::outside_valid_range_text(o.points); !outside.empty())
    fmt::print(
        "  not considered: a light's κ is outside their valid κ range (registry card; their "
        "stated bound does not hold there): {}\n",
        outside);
  fmt::print("\n");
  if (r.choice) {
    fmt::print("  choice:    {} (scene error {:.4g}, {})\n", r.choice->method,
               r.choice->max_peak_rel, report::cost_text(*r.choice));
    if (r.runner_up)
      fmt::print("  runner-up: {} (scene error {:.4g}, {})\n", r.runner_up->method,
                 r.runner_up->max_peak_rel, report::cost_text(*r.runner_up));
  } else {
    fmt::print("  no method meets the budget on this scene.\n");
    if (r.most_accurate)
      fmt::print("  most accurate: {} (scene error {:.4g})\n", r.most_accurate->method,
                 r.most_accurate->max_peak_rel);
  }
  fmt::print(
      "\n  sglab models over the scene's κ range [{:.4g}, {:.4g}] (max peak_rel, 29 κ × 41 c):\n",
      o.ranking.kappa_lo, o.ranking.kappa_hi);
  for (const auto& m : o.ranking.models_on_range)
    fmt::print("    {:<22} {:.4g}{}\n", m.method, m.max_peak_rel,
               !m.in_valid_range                 ? "  outside its valid κ range"
               : m.max_peak_rel <= o.args.budget ? "  meets the budget"
                                                 : "");
  if (o.ranking.sufficient)
    fmt::print("  cheapest sglab model sufficient for the range: {}\n",
               o.ranking.sufficient->method);
  else
    fmt::print("  no registered sglab model meets the budget over this κ range.\n");
  fmt::print("(cost in {}: {}; costs within {}% are ties, broken by error)\n", o.cost.unit(),
             o.source.text, report::kCostTieMargin * 100);
}

}  // namespace

nlohmann::ordered_json json_number(double x) {
  if (!std::isfinite(x)) return nullptr;
  return x;
}

void recommend_scene(const SceneRecommendArgs& args) {
  // a bad --cost before any work
  const cost::CostSource cost = args.costs.source(args.precision);
  const reference::Scene scene = read_scene(args);
  const auto normals = reference::fibonacci_normals(args.normals);
  std::vector<report::MethodPoint> points = report::scene_points(scene, normals, args.precision);
  const CostsOption::From source =
      args.costs.fill(points, args.precision, /*repetitions=*/7, /*min_time=*/0.01);
  const report::SceneRanking ranking =
      report::rank_scene(points, scene, args.budget, args.precision);
  const SceneOutput out{args, scene, normals.size(), cost, source, points, ranking};
  if (args.json)
    print_json(out);
  else
    print_text(out);
}

}  // namespace sglab::app
