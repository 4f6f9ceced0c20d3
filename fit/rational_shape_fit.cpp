#include "fit/rational_shape_fit.hpp"

#include <cctype>

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

namespace {

// "x", "x and y", "x, y and z" (`comma` between all but the last two).
std::string and_list(const std::vector<std::string>& words, const std::string& comma,
                     const std::string& and_) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i)
    out += (i == 0 ? "" : i + 1 == words.size() ? and_ : comma) + words[i];
  return out;
}

std::string upper(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

}  // namespace

CertificateTexts certificate_texts(const RationalLayout& layout, std::size_t certified) {
  std::vector<std::string> free, fixed = {"Q"}, fixed_of_kappa = {"Q"}, fitted = {"denominator"};
  for (std::size_t n = 0; n < layout.numerators.size(); ++n) {
    const std::string& name = layout.numerators[n];
    if (n < certified) {
      free.push_back(upper(name));
    } else {
      fixed.push_back(upper(name));
      fixed_of_kappa.push_back(upper(name) + "(kappa)");
      fitted.push_back(name);
    }
  }
  return {and_list(free, ", ", ", "), and_list(fixed, ", ", " and "),
          fmt::format("lp_at_fitted_{}: the numerators of {} free, {} as fitted; bound min(LP "
                      "optimum, L)",
                      and_list(fitted, "_", "_and_"), and_list(free, ", ", " and "),
                      and_list(fixed_of_kappa, ", ", " and "))};
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
