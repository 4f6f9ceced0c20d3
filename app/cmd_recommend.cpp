// `sglab recommend --kappa LO:HI --budget E`: the cheapest irradiance method
// whose max peak_rel over [LO, HI] (29 log-spaced κ × 41 cosines, the same
// grid as `sglab pareto` and `sglab sweep --kappa LO:HI:29 --cosines 41`) is
// ≤ E, and the runner-up. Cost: --cost gpu:FAMILY (ACO's inverse throughput,
// cycles; default gpu:navi21), cpu-batch or cpu-scalar (ns/eval) from the cost
// table (--costs; data/results/costs.json by default), or with --live-timing
// CPU ns, the median of 7 repetitions timed now (app/costs_option.hpp);
// costs within 5% of the cheapest remaining
// candidate are ties, broken by the smaller error (validate/pareto.hpp).
// When no method meets the budget, says so and names the most accurate (exit
// 0: that is an answer). A method whose valid κ range (its registry card,
// sglab::ValidRange) does not hold [LO, HI] is not considered and is named as
// such. --json adds every candidate.
// `sglab recommend --scene FILE --budget E` ranks the methods by their error on
// a scene of SG lights instead (app/recommend_scene.cpp, validate/scene_errors.hpp).
#include <cmath>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sglab/registry.hpp>

#include "app/commands.hpp"
#include "app/costs_option.hpp"
#include "app/recommend_scene.hpp"
#include "common/args.hpp"
#include "report/pareto.hpp"

namespace sglab::app {

namespace {

struct RecommendArgs {
  std::string kappa;
  std::string scene;
  std::size_t normals = 4096;
  std::string budget;
  std::string precision = "float";
  bool json = false;
  CostsOption costs;
};

nlohmann::ordered_json point_json(const std::optional<report::MethodPoint>& p) {
  if (!p) return nullptr;
  return {{"method", p->method},
          {"origin", std::string(to_string(p->origin))},
          {"max_peak_rel", json_number(p->max_peak_rel)},
          {"cost", json_number(p->cost)},
          {"cost_unit", p->cost_unit},
          {"cost_form", p->cost_form},
          {"in_valid_range", p->in_valid_range}};
}

std::string describe(const report::MethodPoint& p) {
  return fmt::format(
      "{}{} (max peak_rel {:.4g}, {})", p.method,
      p.origin == Origin::published ? std::string() : fmt::format(" [{}]", to_string(p.origin)),
      p.max_peak_rel, report::cost_text(p));
}

// The κ-range answer (the request, choice, runner-up, most accurate) with every candidate, as JSON.
void print_recommendation_json(double lo, double hi, double budget, io::Precision precision,
                               const std::vector<report::MethodPoint>& points,
                               const report::Recommendation& r, const cost::CostSource& cost,
                               const CostsOption::From& source) {
  nlohmann::ordered_json doc;
  doc["kappa_lo"] = lo;
  doc["kappa_hi"] = hi;
  doc["budget"] = budget;
  doc["precision"] = std::string(io::to_string(precision));
  doc["choice"] = point_json(r.choice);
  doc["runner_up"] = point_json(r.runner_up);
  doc["most_accurate"] = point_json(r.most_accurate);
  doc["tie_margin"] = report::kCostTieMargin;
  doc["cost_source"] = cost.name();
  doc["cost_unit"] = std::string(cost.unit());
  doc["cost_from"] = source.text;
  nlohmann::ordered_json candidates = nlohmann::ordered_json::array();
  for (const auto& p : points) {
    auto j = point_json(p);
    j["qualifies"] = std::isfinite(p.max_peak_rel) && std::isfinite(p.cost) &&
                     p.max_peak_rel <= budget && p.in_valid_range;
    if (const Method* m = find_method(irradiance_methods, p.method))
      j["valid_kappa"] = {m->valid.kappa_lo, m->valid.kappa_hi};
    candidates.push_back(std::move(j));
  }
  doc["candidates"] = std::move(candidates);
  nlohmann::ordered_json outside = nlohmann::ordered_json::array();
  for (const auto& p : points)
    if (!p.in_valid_range) outside.push_back(p.method);
  doc["outside_valid_range"] = std::move(outside);
  fmt::print("{}\n", doc.dump(2));
}

// The κ-range answer as text.
void print_recommendation_text(double lo, double hi, double budget, io::Precision precision,
                               const std::vector<report::MethodPoint>& points,
                               const report::Recommendation& r, const cost::CostSource& cost,
                               const CostsOption::From& source) {
  fmt::print("κ in [{}, {}], {}, budget max peak_rel ≤ {}:\n", lo, hi, io::to_string(precision),
             budget);
  if (r.choice) {
    fmt::print("  choice:    {}\n", describe(*r.choice));
    if (r.runner_up)
      fmt::print("  runner-up: {}\n", describe(*r.runner_up));
    else
      fmt::print("  runner-up: none (no other method meets the budget)\n");
  } else {
    fmt::print("  no method meets the budget.\n");
    if (r.most_accurate)
      fmt::print("  most accurate: {}\n", describe(*r.most_accurate));
    else
      fmt::print("  no method has a finite error over this range.\n");
  }
  if (const std::string outside = report::outside_valid_range_text(points); !outside.empty())
    fmt::print(
        "  not considered: outside their valid κ range (registry card; their stated bound does "
        "not hold there): {}\n",
        outside);
  fmt::print("(cost in {}: {}; costs within {}% are ties, broken by error)\n", cost.unit(),
             source.text, report::kCostTieMargin * 100);
}

// `sglab recommend`: the options checked, then the scene ranking or the κ-range answer.
void run_recommend(const RecommendArgs& args) {
  double lo = 0, hi = 0, budget = 0;
  if (args.kappa.empty() == args.scene.empty())
    throw InputError("give exactly one of --kappa LO:HI and --scene FILE");
  if (const auto parsed = io::parse_decimal(args.budget);
      const auto* why = std::get_if<std::string>(&parsed))
    throw InputError("--budget: " + *why);
  else
    budget = std::get<double>(parsed);
  if (!(budget > 0)) throw InputError(fmt::format("--budget: must be > 0, got {}", budget));
  const auto precision = io::parse_option("--precision", args.precision,
                                          {io::Precision::float32, io::Precision::float64});
  if (!args.scene.empty()) {
    recommend_scene({args.scene, budget, precision, args.normals, args.json, args.costs});
    return;
  }
  {
    const auto parsed = io::parse_kappa_range(args.kappa, io::KappaRangeRules{});  // LO:HI, float
    if (const auto* why = std::get_if<std::string>(&parsed)) throw InputError("--kappa: " + *why);
    lo = std::get<io::KappaRange>(parsed).lo;
    hi = std::get<io::KappaRange>(parsed).hi;
  }

  const cost::CostSource cost = args.costs.source(precision);  // a bad --cost before the sweep
  std::vector<report::MethodPoint> points = report::irradiance_errors(lo, hi, precision);
  const CostsOption::From source =
      args.costs.fill(points, precision, /*repetitions=*/7, /*min_time=*/0.01);
  const report::Recommendation r = report::recommend(points, budget);
  if (args.json)
    print_recommendation_json(lo, hi, budget, precision, points, r, cost, source);
  else
    print_recommendation_text(lo, hi, budget, precision, points, r, cost, source);
}

}  // namespace

void add_recommend_command(CLI::App& app) {
  auto args = std::make_shared<RecommendArgs>();
  auto* cmd = app.add_subcommand("recommend",
                                 "The cheapest irradiance method whose max peak_rel over a κ range "
                                 "(or error on a scene) meets an error budget");
  cmd->add_option("--kappa", args->kappa, "κ range LO:HI");
  add_path_option(cmd, "--scene", args->scene,
                  "scene JSON {\"lights\": [{\"axis\": [x, y, z], \"sharpness\": κ, \"amplitude\": "
                  "[r, g, b]}, …]}: rank the methods by their error on the scene's irradiance "
                  "instead");
  cmd->add_option("--normals", args->normals, "--scene: number of Fibonacci normals")
      ->check(count_in(1, 1000000))
      ->capture_default_str();
  cmd->footer(
      "peak_rel = |Ê − E| / E(1, κ), the irradiance error relative to the lobe's peak "
      "(docs/quantities.md)");
  cmd->add_option("--budget", args->budget, "max peak_rel allowed (> 0)")->required();
  cmd->add_option("--precision", args->precision, "float or double")->capture_default_str();
  cmd->add_flag("--json", args->json, "print the answer as JSON on stdout");
  args->costs.add_to(cmd);
  cmd->callback([args] { run_recommend(*args); });
}

}  // namespace sglab::app
