#include "export/shader_text.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

#include "common/comment_text.hpp"

namespace sglab::shader::detail {

// Float literal that the three languages read as the float nearest to v.
std::string lit(double v) {
  std::string s = fmt::format("{:.9g}", static_cast<float>(v));
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

// Horner text c0 + x * (c1 + x * (…)) of literal coefficients, evaluated in
// the order of math.hpp's horner.
std::string horner_text(std::string_view x, const std::vector<std::string>& c) {
  std::string s = c.back();
  for (std::size_t i = c.size() - 1; i-- > 0;) s = fmt::format("{} + {} * ({})", c[i], x, s);
  return "(" + s + ")";
}
std::vector<std::string> literals(const std::vector<double>& v) {
  std::vector<std::string> out;
  for (double x : v) out.push_back(lit(x));
  return out;
}

std::string replace_all(std::string s, std::string_view from, std::string_view to) {
  for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size())
    s.replace(pos, from.size(), to);
  return s;
}

// {P}: the method's prefix; {VEC4}, {VEC3}, {VEC2}: the vector types; {INLINE}: `inline ` in C++.
std::string subst(std::string_view tmpl, const Ctx& c) {
  std::string s(tmpl);
  s = replace_all(s, "{P}", c.prefix);
  s = replace_all(s, "{VEC3}", c.lang == Language::glsl ? "vec3" : "float3");
  s = replace_all(s, "{VEC2}", c.lang == Language::glsl ? "vec2" : "float2");
  s = replace_all(s, "{VEC4}", c.lang == Language::glsl ? "vec4" : "float4");
  s = replace_all(s, "{INLINE}", c.lang == Language::cpp ? "inline " : "");
  s = replace_all(s, "{ENTRY}", "sglab_irradiance_" + c.id);
  return s;
}

// The constant names of a slot: {P}<role>_<member>, arrays <member><i>.
std::vector<std::string> names(const Ctx& c, std::string_view role, const ConstantSet& s,
                               std::string_view m) {
  const auto& v = member(s, m);
  std::vector<std::string> out;
  if (v.size() == 1 || is_table(v)) {
    out.push_back(fmt::format("{}{}_{}", c.prefix, role, m));
  } else {
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(fmt::format("{}{}_{}{}", c.prefix, role, m, i));
  }
  return out;
}

std::string constant_decls(const Ctx& c, std::string_view role, const ConstantSet& s) {
  const char* kw = c.lang == Language::glsl   ? "const float"
                   : c.lang == Language::hlsl ? "static const float"
                                              : "inline constexpr float";
  std::string out = fmt::format("// {}: {} {}\n", role, io::comment_text(s.cpp_type),
                                io::comment_text(s.cpp_name));
  for (const auto& [m, v] : s.members) {
    const auto n = names(c, role, s, m);
    if (is_table(v)) {
      // One array of 4-vectors, a row of four values each: GLSL `vec4 x[n] = vec4[n](vec4(…),
      // …);`, HLSL `static float4 x[n] = {float4(…), …};`, C++ `inline constexpr float4 …`.
      // A private global the code never writes, not a `const` one: glslang copies a constant
      // array indexed by a varying index at every use, and Mesa takes about 80 s (GLSL) and
      // 100 s (HLSL) to compile eight inlined calls of sglab_tab that way (the loop harness of
      // `sglab gpucost`) against 0.3 s for the private global, at the same ACO inverse
      // throughput; an array of floats instead of 4-vectors takes 20 s for one call.
      const std::string vec = c.lang == Language::glsl ? "vec4" : "float4";
      std::string items;
      for (std::size_t i = 0; i < v.size(); i += 4)
        items += fmt::format("{}\n    {}({}, {}, {}, {})", i == 0 ? "" : ",", vec, lit(v[i]),
                             lit(v[i + 1]), lit(v[i + 2]), lit(v[i + 3]));
      const std::string_view vkw = c.lang == Language::glsl   ? ""
                                   : c.lang == Language::hlsl ? "static "
                                                              : "inline constexpr ";
      out += c.lang == Language::glsl
                 ? fmt::format("{}{} {}[{}] = {}[{}]({});\n", vkw, vec, n[0], v.size() / 4, vec,
                               v.size() / 4, items)
                 : fmt::format("{}{} {}[{}] = {{{}}};\n", vkw, vec, n[0], v.size() / 4, items);
      continue;
    }
    for (std::size_t i = 0; i < v.size(); ++i)
      out += fmt::format("{} {} = {};\n", kw, n[i], lit(v[i]));
  }
  return out;
}

// ---------------------------------------------------------------------------
// Half precision: the float text of an export translated token by token.

// The half type of a language: GLSL float16_t
// (GL_EXT_shader_explicit_arithmetic_types_float16), HLSL `half` (16-bit with
// glslang's EShMsgHlslEnable16BitTypes).
std::string_view half_type(Language lang) { return lang == Language::glsl ? "float16_t" : "half"; }

// A float literal's value rounded to binary16, written so that the shading
// language reads exactly that half (a half is a float, whose 9 digits round
// back to it). Throws std::invalid_argument when it is not finite in half.
std::string half_literal(std::string_view digits, Language lang) {
  const float f = std::strtof(std::string(digits).c_str(), nullptr);
  const auto h = static_cast<_Float16>(f);
  if (!std::isfinite(static_cast<float>(h)))
    throw std::invalid_argument(
        fmt::format("literal {} is not finite in half (largest 65504)", digits));
  std::string s = fmt::format("{:.9g}", static_cast<float>(h));
  if (s.find('.') == std::string::npos) {
    const auto e = s.find('e');
    s.insert(e == std::string::npos ? s.size() : e, ".0");
  }
  return s + (lang == Language::glsl ? "hf" : "h");
}

bool ident_char(char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; }
bool is_digit(char ch) { return std::isdigit(static_cast<unsigned char>(ch)) != 0; }

// The end of the number that starts at text[i]: digits and '.', then an
// optional exponent e[+-]digits (a suffix such as f is not part of it).
std::size_t number_end(std::string_view text, std::size_t i) {
  while (i < text.size() && (is_digit(text[i]) || text[i] == '.')) ++i;
  if (i < text.size() && text[i] == 'e') {
    ++i;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
    while (i < text.size() && is_digit(text[i])) ++i;
  }
  return i;
}

// The HLSL intrinsics an export calls, which glslang's HLSL front end (12.0)
// declares for float only: a half export calls {P}h_<name> (hlsl_half_prelude).
// (and int(x), which it does not construct from a half).
constexpr std::string_view kHlslHalfIntrinsics[] = {"exp", "exp2",  "log", "sqrt",  "abs", "min",
                                                    "max", "clamp", "dot", "floor", "int"};

// One identifier of the code translated to half: float and the vector types
// become half types; in HLSL the intrinsics become the prelude's functions.
std::string half_identifier(std::string_view id, bool call, const Ctx& c) {
  const bool glsl = c.lang == Language::glsl;
  if (id == "float") return std::string(half_type(c.lang));
  if (id == "vec2" || id == "float2") return glsl ? "f16vec2" : "half2";
  if (id == "vec3" || id == "float3") return glsl ? "f16vec3" : "half3";
  if (id == "vec4" || id == "float4") return glsl ? "f16vec4" : "half4";
  if (!glsl && call &&
      std::find(std::begin(kHlslHalfIntrinsics), std::end(kHlslHalfIntrinsics), id) !=
          std::end(kHlslHalfIntrinsics))
    return c.prefix + "h_" + std::string(id);
  return std::string(id);
}

// The code of a float export translated to half: types, f-suffixed literals
// (rounded to half) and, in HLSL, intrinsic calls; // comments are left as
// they are. The code uses no other float-typed construct (see shader_methods.cpp).
std::string to_half_code(std::string_view text, const Ctx& c) {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == '/' && i + 1 < text.size() &&
        text[i + 1] == '/') {  // comment: to the end of the line
      const std::size_t end = std::min(text.find('\n', i), text.size());
      out.append(text.substr(i, end - i));
      i = end;
    } else if (is_digit(ch) || (ch == '.' && i + 1 < text.size() && is_digit(text[i + 1]))) {
      const std::size_t j = number_end(text, i);
      const bool is_float =
          j < text.size() && text[j] == 'f' && (j + 1 == text.size() || !ident_char(text[j + 1]));
      out += is_float ? half_literal(text.substr(i, j - i), c.lang)
                      : std::string(text.substr(i, j - i));
      i = is_float ? j + 1 : j;
    } else if (ident_char(ch)) {
      std::size_t j = i;
      while (j < text.size() && ident_char(text[j])) ++j;
      out += half_identifier(text.substr(i, j - i), j < text.size() && text[j] == '(', c);
      i = j;
    } else {
      out += ch;
      ++i;
    }
  }
  return out;
}

// The functions an HLSL half export calls in place of the float-only
// intrinsics: min, max, clamp, abs and dot in half arithmetic; exp, exp2, log,
// sqrt and floor evaluated in float and rounded once to half (floor exactly); int(x) through
// float.
std::string hlsl_half_prelude(const Ctx& c) {
  return subst(R"(// glslang's HLSL front end declares its intrinsics for float only: half versions.
half {P}h_min(half a, half b) { return b < a ? b : a; }
half {P}h_max(half a, half b) { return a < b ? b : a; }
half {P}h_clamp(half x, half lo, half hi) { return {P}h_min({P}h_max(x, lo), hi); }
half {P}h_abs(half x) { return x < 0.0h ? -x : x; }
half {P}h_dot(half3 a, half3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
half {P}h_exp(half x) { return (half)exp((float)x); }
half {P}h_exp2(half x) { return (half)exp2((float)x); }
half {P}h_log(half x) { return (half)log((float)x); }
half {P}h_sqrt(half x) { return (half)sqrt((float)x); }
half {P}h_floor(half x) { return (half)floor((float)x); }
int {P}h_int(half x) { return (int)(float)x; }
)",
               c);
}

}  // namespace sglab::shader::detail
