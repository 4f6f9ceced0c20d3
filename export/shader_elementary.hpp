// export/shader_elementary.hpp — the elementary functions an export carries
// (shading languages have no erf, erfc or expm1): the erf tiers, their C++
// twins that measure the error in-process, the series that stand in for
// expm1 and the 2024 poles, and the text of erf/erfc and (e^x − 1)/x.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "export/shader_constants.hpp"
#include "export/shader_export.hpp"
#include "export/shader_text.hpp"

namespace sglab::shader::detail {

// ---------------------------------------------------------------------------
// Elementary tiers: the erf/erfc an export carries, cheapest first. Each is
// one of sglab's fitted erf sets (`sglab fit erf`); the structure of the code
// follows the set's parameter type.

struct Tier {
  const char* id;
  const char* description;
  ConstantSet (*set)();
};
// The tiers, cheapest first.
std::span<const Tier> elementary_tiers();
// The erf set of the tier `id`; throws std::invalid_argument for an unknown tier.
ConstantSet tier_set(std::string_view id);

bool is_listing5(const ConstantSet& s);
bool is_as(const ConstantSet& s);

// (e^x − 1)/x: Taylor series Σ x^n/(n+1)!, n = 0…10, for |x| < 1.
std::vector<double> expm1_over_x_series();
// Series of the 2024 poles at κ = 0 (closed_forms.hpp), 11 terms for float:
// upper Σ (−κ)^m/(m + 2)!, lower Σ (−κ)^m (m + 1)/(m + 2)!.
std::vector<double> pole_series(bool lower);

// The error of the float twin of an erf set's code (nullptr: expm1 only).
ElementaryError measure(const ConstantSet* erf_set);

// The text of {P}expm1_over_x, and of {P}erfc_pos, {P}erf, {P}erfc from the slot "erf".
std::string helper_expm1(const Ctx& c, const Slots&);
std::string helper_erf(const Ctx& c, const Slots& slots);

}  // namespace sglab::shader::detail
