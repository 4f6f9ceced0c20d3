// export/shader_constants.hpp — the constant-set adapters of the shader
// export: each parameter type of include/sglab/params.hpp as a ConstantSet
// (its members by name), a method's constant slots (role → set), and the
// checks that a set's coefficients are literals of the exported precision.
#pragma once

#include <iterator>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <sglab/params.hpp>

#include "export/shader_export.hpp"

namespace sglab::shader::detail {

// Constant sets of the runtime, by parameter type (params.hpp).
ConstantSet named(std::string cpp_name, const ClampedCosineParams<double>& p);
ConstantSet named(std::string cpp_name, const Steepness2022Params<double>& p);
ConstantSet named(std::string cpp_name, const Steepness2024Params<double>& p);
ConstantSet named(std::string cpp_name, const CosineLobeParams<double>& p);
ConstantSet named(std::string cpp_name, const DiffuseLobeParams<double>& p);
ConstantSet named(std::string cpp_name, const HillParams<double>& p);
ConstantSet named(std::string cpp_name, const Meder2018Params<double>& p);
ConstantSet named(std::string cpp_name, const SglabFastParams<double>& p);
ConstantSet named(std::string cpp_name, const SglabMidParams<double>& p);
ConstantSet named(std::string cpp_name, const SglabLiteParams<double>& p);
ConstantSet named(std::string cpp_name, const SglabMinParams<double>& p);
template <std::size_t NS, std::size_t NL>
ConstantSet named(std::string cpp_name, const Listing5Params<double, NS, NL>& p) {
  return {fmt::format("Listing5Params<double, {}, {}>", NS, NL),
          std::move(cpp_name),
          {{"split", {p.split}},
           {"cutoff", {p.cutoff}},
           {"small", std::vector<double>(std::begin(p.small), std::end(p.small))},
           {"large", std::vector<double>(std::begin(p.large), std::end(p.large))}},
          {},
          {}};
}
template <std::size_t N>
ConstantSet named(std::string cpp_name, const AbramowitzStegunParams<double, N>& p) {
  return {fmt::format("AbramowitzStegunParams<double, {}>", N),
          std::move(cpp_name),
          {{"p", {p.p}}, {"a", std::vector<double>(std::begin(p.a), std::end(p.a))}},
          {},
          {}};
}
template <std::size_t N, std::size_t D, std::size_t M>
ConstantSet named(std::string cpp_name, const SglabAccParams<double, N, D, M>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {fmt::format("SglabAccParams<double, {}, {}, {}>", N, D, M),
          std::move(cpp_name),
          {{"steep", vec(p.steep)}, {"num", vec(p.num)}, {"scale", {p.scale}}},
          {},
          {}};
}

template <std::size_t N, std::size_t D>
ConstantSet named(std::string cpp_name, const SglabTabParams<double, N, D>& p) {
  return {fmt::format("SglabTabParams<double, {}, {}>", N, D),
          std::move(cpp_name),
          {{"coef", std::vector<double>(std::begin(p.coef), std::end(p.coef))}},
          {},
          {}};
}

// The values of a member; throws std::invalid_argument naming the set when it has none.
const std::vector<double>& member(const ConstantSet& set, std::string_view name);

// A method's constant slots: role (e.g. "steepness", "erf") → set.
using Slots = std::vector<std::pair<std::string, ConstantSet>>;
const ConstantSet& slot(const Slots& slots, std::string_view role);

// The exported code is float: a coefficient beyond the largest float would be
// written as inf, which is no literal. Throws std::invalid_argument naming the
// set and the key (coefficients.NAME, or coefficients.NAME[i] in an array).
void check_finite_in_float(const ConstantSet& set);

// A half export writes every coefficient as a half literal (methods without a
// half form of their own): one beyond 65504 would be inf. Throws
// std::invalid_argument naming the set and the key.
void check_finite_in_half(const ConstantSet& set);

}  // namespace sglab::shader::detail
