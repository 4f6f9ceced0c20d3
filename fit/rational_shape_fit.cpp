#include "fit/rational_shape_fit.hpp"

#include "fit/constants_io.hpp"

namespace sglab::fit {

std::vector<reference::ReferencePoint> rational_reference_grid(const std::vector<double>& kappas,
                                                               const std::vector<double>& cosines) {
  return reference::reference_engine().evaluate(product_grid(kappas, cosines));
}

std::optional<double> committed_floor(const std::string& target, const std::string& variant,
                                      double lo, double hi) {
  const auto set = committed_set(target, variant, lo, hi);
  if (!set) return std::nullopt;
  try {
    return set->at("provenance").at("achieved").at("per_kappa_floor").get<double>();
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

ordered_json per_kappa_json(const std::vector<PerKappaShape>& per) {
  ordered_json table = ordered_json::array();
  for (const auto& p : per) {
    ordered_json row = ordered_json::array();
    row.push_back(p.kappa);
    for (double v : p.shape) row.push_back(v);
    row.push_back(p.error);
    table.push_back(std::move(row));
  }
  return table;
}

}  // namespace sglab::fit
