// export/shader_text.hpp — the source text of an export: literals, Horner
// text, the {P}/{VEC3}/{ENTRY} placeholders, constant declarations, and the
// half translation of float code (token by token).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "export/shader_constants.hpp"
#include "export/shader_export.hpp"

namespace sglab::shader::detail {

struct Ctx {
  Language lang;
  std::string id;      // sanitized method id
  std::string prefix;  // sglab_<id>_
};

// Float literal that the three languages read as the float nearest to v.
std::string lit(double v);
// Horner text c0 + x * (c1 + x * (…)) of literal coefficients, evaluated in
// the order of math.hpp's horner.
std::string horner_text(std::string_view x, const std::vector<std::string>& c);
std::vector<std::string> literals(const std::vector<double>& v);
std::string replace_all(std::string s, std::string_view from, std::string_view to);
// {P}: the method's prefix; {VEC3}, {VEC2}: the vector types; {INLINE}: `inline ` in C++.
std::string subst(std::string_view tmpl, const Ctx& c);

// The constant names of a slot: {P}<role>_<member>, arrays <member><i>; a member longer
// than kTableMembers (sglab_tab's table) is one array of 4-vectors, {P}<role>_<member>, row i
// its values 4i … 4i + 3, which the code indexes.
inline constexpr std::size_t kTableMembers = 64;
inline bool is_table(const std::vector<double>& v) {
  return v.size() > kTableMembers && v.size() % 4 == 0;
}
std::vector<std::string> names(const Ctx& c, std::string_view role, const ConstantSet& s,
                               std::string_view m);
// The declarations of a slot's constants, one per value (a table: one array).
std::string constant_decls(const Ctx& c, std::string_view role, const ConstantSet& s);

// The half type of a language: GLSL float16_t, HLSL `half`.
std::string_view half_type(Language lang);
// The code of a float export translated to half: types, f-suffixed literals
// (rounded to half) and, in HLSL, intrinsic calls; // comments are left as
// they are.
std::string to_half_code(std::string_view text, const Ctx& c);
// The functions an HLSL half export calls in place of the float-only intrinsics.
std::string hlsl_half_prelude(const Ctx& c);

}  // namespace sglab::shader::detail
