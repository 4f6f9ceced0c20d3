#include "export/shader_constants.hpp"

#include <cmath>
#include <stdexcept>

namespace sglab::shader::detail {

ConstantSet named(std::string cpp_name, const ClampedCosineParams<double>& p) {
  return {"ClampedCosineParams<double>",
          std::move(cpp_name),
          {{"lambda", {p.lambda}}, {"alpha", {p.alpha}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const Steepness2022Params<double>& p) {
  return {"Steepness2022Params<double>",
          std::move(cpp_name),
          {{"A", {p.A}}, {"B", {p.B}}, {"C", {p.C}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const Steepness2024Params<double>& p) {
  return {"Steepness2024Params<double>",
          std::move(cpp_name),
          {{"A", {p.A}}, {"B", {p.B}}, {"C", {p.C}}, {"D", {p.D}}, {"E", {p.E}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const CosineLobeParams<double>& p) {
  return {"CosineLobeParams<double>",
          std::move(cpp_name),
          {{"lambda", {p.lambda}}, {"amplitude", {p.amplitude}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const DiffuseLobeParams<double>& p) {
  return {"DiffuseLobeParams<double>", std::move(cpp_name), {{"lambda_d", {p.lambda_d}}}, {}, {}};
}
ConstantSet named(std::string cpp_name, const HillParams<double>& p) {
  return {"HillParams<double>", std::move(cpp_name), {{"c0", {p.c0}}}, {}, {}};
}
ConstantSet named(std::string cpp_name, const Meder2018Params<double>& p) {
  return {"Meder2018Params<double>",
          std::move(cpp_name),
          {{"a2", {p.a2}},
           {"a1", {p.a1}},
           {"b1", {p.b1}},
           {"b0", {p.b0}},
           {"amplitude", {p.amplitude}},
           {"sharpness", {p.sharpness}},
           {"offset", {p.offset}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const SglabFastParams<double>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {"SglabFastParams<double>",
          std::move(cpp_name),
          {{"a", vec(p.a)},
           {"b", vec(p.b)},
           {"c", vec(p.c)},
           {"v", vec(p.v)},
           {"q", vec(p.q)},
           {"kappa_max", {p.kappa_max}}},
          {},
          {}};
}

ConstantSet named(std::string cpp_name, const SglabMidParams<double>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {"SglabMidParams<double>",
          std::move(cpp_name),
          {{"a", vec(p.a)},
           {"b", vec(p.b)},
           {"d", vec(p.d)},
           {"s", vec(p.s)},
           {"v", vec(p.v)},
           {"q", vec(p.q)},
           {"kappa_max", {p.kappa_max}}},
          {},
          {}};
}

ConstantSet named(std::string cpp_name, const SglabLiteParams<double>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {"SglabLiteParams<double>",
          std::move(cpp_name),
          {{"a", vec(p.a)},
           {"b", vec(p.b)},
           {"c", vec(p.c)},
           {"v", vec(p.v)},
           {"q", vec(p.q)},
           {"kappa_max", {p.kappa_max}}},
          {},
          {}};
}

ConstantSet named(std::string cpp_name, const SglabMinParams<double>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {"SglabMinParams<double>",
          std::move(cpp_name),
          {{"a", vec(p.a)}, {"b", vec(p.b)}, {"g", vec(p.g)}, {"s", {p.s}}},
          {},
          {}};
}

const std::vector<double>& member(const ConstantSet& set, std::string_view name) {
  for (const auto& [n, v] : set.members)
    if (n == name) return v;
  throw std::invalid_argument(
      fmt::format("constant set {} ({}) has no member '{}'", set.cpp_name, set.cpp_type, name));
}

const ConstantSet& slot(const Slots& slots, std::string_view role) {
  for (const auto& [r, s] : slots)
    if (r == role) return s;
  throw std::logic_error(fmt::format("shader export: no constant slot '{}'", role));
}

namespace {
// Throws std::invalid_argument naming the set and the key (coefficients.NAME,
// or coefficients.NAME[i] in an array) of the first coefficient that `round`
// (to the exported precision) makes infinite; `precision` says which.
template <class Round>
void check_finite_as(const ConstantSet& set, Round round, std::string_view precision) {
  for (const auto& [name, values] : set.members)
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(round(values[i])))
        throw std::invalid_argument(fmt::format(
            "constant set {}: key '{}': {} is not finite in {}, the precision of the exported code",
            set.cpp_name,
            values.size() == 1 ? "coefficients." + name
                               : fmt::format("coefficients.{}[{}]", name, i),
            values[i], precision));
}
}  // namespace

// The exported code is float: a coefficient beyond the largest float would be
// written as inf, which is no literal.
void check_finite_in_float(const ConstantSet& set) {
  check_finite_as(
      set, [](double v) { return static_cast<float>(v); }, "float");
}

// A half export writes every coefficient as a half literal (methods without a
// half form of their own): one beyond 65504 would be inf.
void check_finite_in_half(const ConstantSet& set) {
  check_finite_as(
      set,
      [](double v) { return static_cast<float>(static_cast<_Float16>(static_cast<float>(v))); },
      "half (largest 65504)");
}

}  // namespace sglab::shader::detail
