#include "export/shader_export.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sglab/constants.hpp>
#include <sglab/registry.hpp>

#include "common/comment_text.hpp"
#include "validate/sweep.hpp"

namespace sglab::shader {

std::string_view to_string(Language lang) {
  switch (lang) {
    case Language::glsl: return "glsl";
    case Language::hlsl: return "hlsl";
    case Language::cpp: return "cpp";
  }
  return "?";
}

std::optional<Language> parse_language(std::string_view text) {
  if (text == "glsl") return Language::glsl;
  if (text == "hlsl") return Language::hlsl;
  if (text == "cpp") return Language::cpp;
  return std::nullopt;
}

std::string_view to_string(Precision p) { return p == Precision::float16 ? "half" : "float"; }

std::optional<Precision> parse_precision(std::string_view text) {
  if (text == "float") return Precision::float32;
  if (text == "half") return Precision::float16;
  return std::nullopt;
}

std::string entry_point_name(std::string_view method) {
  std::string out = "sglab_irradiance_";
  for (char ch : method) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return out;
}

namespace {

// ---------------------------------------------------------------------------
// Constant sets of the runtime, by parameter type (params.hpp).

ConstantSet named(std::string cpp_name, const ClampedCosineParams<double>& p) {
  return {"ClampedCosineParams<double>", std::move(cpp_name), {{"lambda", {p.lambda}}, {"alpha", {p.alpha}}}, {}, {}};
}
ConstantSet named(std::string cpp_name, const Steepness2022Params<double>& p) {
  return {"Steepness2022Params<double>", std::move(cpp_name), {{"A", {p.A}}, {"B", {p.B}}, {"C", {p.C}}}, {}, {}};
}
ConstantSet named(std::string cpp_name, const Steepness2024Params<double>& p) {
  return {"Steepness2024Params<double>",
          std::move(cpp_name),
          {{"A", {p.A}}, {"B", {p.B}}, {"C", {p.C}}, {"D", {p.D}}, {"E", {p.E}}},
          {},
          {}};
}
ConstantSet named(std::string cpp_name, const CosineLobeParams<double>& p) {
  return {"CosineLobeParams<double>", std::move(cpp_name), {{"lambda", {p.lambda}}, {"amplitude", {p.amplitude}}}, {}, {}};
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

ConstantSet named(std::string cpp_name, const SglabFastParams<double>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {"SglabFastParams<double>",
          std::move(cpp_name),
          {{"a", vec(p.a)}, {"b", vec(p.b)}, {"c", vec(p.c)}, {"v", vec(p.v)}, {"q", vec(p.q)}, {"kappa_max", {p.kappa_max}}},
          {},
          {}};
}
template <std::size_t N, std::size_t D>
ConstantSet named(std::string cpp_name, const SglabAccParams<double, N, D>& p) {
  const auto vec = [](const auto& a) { return std::vector<double>(std::begin(a), std::end(a)); };
  return {fmt::format("SglabAccParams<double, {}, {}>", N, D),
          std::move(cpp_name),
          {{"steep", vec(p.steep)}, {"num", vec(p.num)}, {"scale", {p.scale}}},
          {},
          {}};
}


const std::vector<double>& member(const ConstantSet& set, std::string_view name) {
  for (const auto& [n, v] : set.members)
    if (n == name) return v;
  throw std::invalid_argument(fmt::format("constant set {} ({}) has no member '{}'", set.cpp_name, set.cpp_type, name));
}

// ---------------------------------------------------------------------------
// Elementary tiers: the erf/erfc an export carries, cheapest first. Each is
// one of sglab's fitted erf sets (`sglab fit erf`); the structure of the code
// follows the set's parameter type.

struct Tier {
  const char* id;
  const char* description;
  ConstantSet (*set)();
};
const Tier kTiers[] = {
    {"as7125", "[AS1964] 7.1.25 form with sglab's float refit erf_as7125_float (erfc = t P(t) e^{-x^2})",
     [] { return named("erf_as7125_float", constants::erf_as7125_float); }},
    {"listing5",
     "[Tokuyoshi2022] Listing 5 form with sglab's float refit erf_listing5_float "
     "(erf = x P(x^2) for |x| <= split, erfc = 2^{-|x| Q(|x|)} beyond, no 1 - erf cancellation)",
     [] { return named("erf_listing5_float", constants::erf_listing5_float); }},
};

bool is_listing5(const ConstantSet& s) { return s.cpp_type.rfind("Listing5Params", 0) == 0; }
bool is_as(const ConstantSet& s) { return s.cpp_type.rfind("AbramowitzStegunParams", 0) == 0; }

// The C++ twin of the exported erf/erfc (same structure, same float
// arithmetic), for measuring the elementary error in-process.
template <class T> T horner_v(T x, const std::vector<double>& c) {
  T y = T(static_cast<float>(c.back()));
  for (std::size_t i = c.size() - 1; i-- > 0;) y = y * x + T(static_cast<float>(c[i]));
  return y;
}
float twin_erfc_pos(const ConstantSet& s, float a) {
  if (is_listing5(s)) {
    if (a >= float(member(s, "cutoff")[0])) return 0.0f;
    if (a > float(member(s, "split")[0])) return std::exp2(-a * horner_v(a, member(s, "large")));
    return 1.0f - a * horner_v(a * a, member(s, "small"));
  }
  const float t = 1.0f / (1.0f + float(member(s, "p")[0]) * a);
  return t * horner_v(t, member(s, "a")) * std::exp(-a * a);
}
float twin_erf(const ConstantSet& s, float x) {
  const float a = std::fabs(x);
  float y;
  if (is_listing5(s)) {
    y = a >= float(member(s, "cutoff")[0])  ? 1.0f
        : a > float(member(s, "split")[0]) ? 1.0f - std::exp2(-a * horner_v(a, member(s, "large")))
                                           : a * horner_v(a * a, member(s, "small"));
  } else {
    y = 1.0f - twin_erfc_pos(s, a);
  }
  return x < 0.0f ? -y : y;
}
float twin_erfc(const ConstantSet& s, float x) {
  const float r = twin_erfc_pos(s, std::fabs(x));
  return x < 0.0f ? 2.0f - r : r;
}

// (e^x − 1)/x: Taylor series Σ x^n/(n+1)! for |x| < 1, n = 0…10 (the first
// omitted term is below 1/12! < 2.1e−9), (e^x − 1)/x beyond.
std::vector<double> expm1_over_x_series() {
  std::vector<double> c;
  double f = 1;
  for (int n = 0; n <= 10; ++n) {
    f *= (n + 1);
    c.push_back(1.0 / f);
  }
  return c;
}
float twin_expm1_over_x(float x) {
  if (std::fabs(x) < 1.0f) return horner_v(x, expm1_over_x_series());
  return (std::exp(x) - 1.0f) / x;
}

// Series of the 2024 poles at κ = 0 (closed_forms.hpp), 11 terms for float:
// upper Σ (−κ)^m/(m + 2)!, lower Σ (−κ)^m (m + 1)/(m + 2)!.
std::vector<double> pole_series(bool lower) {
  std::vector<double> c;
  for (int m = 0; m <= 10; ++m) {
    double f = 1;
    for (int i = 2; i <= m + 2; ++i) f *= i;
    c.push_back((m % 2 ? -1.0 : 1.0) * (lower ? m + 1 : 1) / f);
  }
  return c;
}

ElementaryError measure(const ConstantSet* erf_set) {
  ElementaryError e;
  if (erf_set) {
    const int n = 400000;
    for (int i = 0; i <= n; ++i) {
      const float x = float(-6.0 + 12.0 * i / n);
      e.erf_abs = std::max(e.erf_abs, std::fabs(double(twin_erf(*erf_set, x)) - std::erf(double(x))));
    }
    for (int i = 0; i <= n; ++i) {
      const float x = float(-6.0 + 16.0 * i / n);
      e.erfc_abs = std::max(e.erfc_abs, std::fabs(double(twin_erfc(*erf_set, x)) - std::erfc(double(x))));
    }
    for (int i = 0; i <= n; ++i) {  // log-spaced 1e-6 … 1
      const float x = float(std::pow(10.0, -6.0 + 6.0 * i / n));
      const double ref = std::erf(double(x));
      e.erf_rel_small = std::max(e.erf_rel_small, std::fabs(double(twin_erf(*erf_set, x)) - ref) / ref);
    }
  }
  for (int i = 0; i <= 200000; ++i) {
    // x = −100 … −1e−7, log-spaced in |x|, and 0.
    const float x = i == 0 ? 0.0f : -float(std::pow(10.0, -7.0 + 9.0 * i / 200000));
    const double xd = x;
    const double ref = xd == 0 ? 1.0 : std::expm1(xd) / xd;
    e.expm1_over_x_rel = std::max(e.expm1_over_x_rel, std::fabs(double(twin_expm1_over_x(x)) - ref) / ref);
  }
  return e;
}

// ---------------------------------------------------------------------------
// Source text.

struct Ctx {
  Language lang;
  std::string id;      // sanitized method id
  std::string prefix;  // sglab_<id>_
};

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

// {P}: the method's prefix; {VEC3}, {VEC2}: the vector types; {INLINE}: `inline ` in C++.
std::string subst(std::string_view tmpl, const Ctx& c) {
  std::string s(tmpl);
  s = replace_all(s, "{P}", c.prefix);
  s = replace_all(s, "{VEC3}", c.lang == Language::glsl ? "vec3" : "float3");
  s = replace_all(s, "{VEC2}", c.lang == Language::glsl ? "vec2" : "float2");
  s = replace_all(s, "{INLINE}", c.lang == Language::cpp ? "inline " : "");
  s = replace_all(s, "{ENTRY}", "sglab_irradiance_" + c.id);
  return s;
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
    throw std::invalid_argument(fmt::format("literal {} is not finite in half (largest 65504)", digits));
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
constexpr std::string_view kHlslHalfIntrinsics[] = {"exp", "exp2", "sqrt", "abs", "min", "max", "clamp", "dot"};

// One identifier of the code translated to half: float and the vector types
// become half types; in HLSL the intrinsics become the prelude's functions.
std::string half_identifier(std::string_view id, bool call, const Ctx& c) {
  const bool glsl = c.lang == Language::glsl;
  if (id == "float") return std::string(half_type(c.lang));
  if (id == "vec2" || id == "float2") return glsl ? "f16vec2" : "half2";
  if (id == "vec3" || id == "float3") return glsl ? "f16vec3" : "half3";
  if (!glsl && call && std::find(std::begin(kHlslHalfIntrinsics), std::end(kHlslHalfIntrinsics), id) !=
                           std::end(kHlslHalfIntrinsics))
    return c.prefix + "h_" + std::string(id);
  return std::string(id);
}

// The code of a float export translated to half: types, f-suffixed literals
// (rounded to half) and, in HLSL, intrinsic calls; // comments are left as
// they are. The code uses no other float-typed construct (see kShaderMethods).
std::string to_half_code(std::string_view text, const Ctx& c) {
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == '/' && i + 1 < text.size() && text[i + 1] == '/') {  // comment: to the end of the line
      const std::size_t end = std::min(text.find('\n', i), text.size());
      out.append(text.substr(i, end - i));
      i = end;
    } else if (is_digit(ch) || (ch == '.' && i + 1 < text.size() && is_digit(text[i + 1]))) {
      const std::size_t j = number_end(text, i);
      const bool is_float = j < text.size() && text[j] == 'f' && (j + 1 == text.size() || !ident_char(text[j + 1]));
      out += is_float ? half_literal(text.substr(i, j - i), c.lang) : std::string(text.substr(i, j - i));
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
// intrinsics: min, max, clamp, abs and dot in half arithmetic; exp, exp2 and
// sqrt evaluated in float and rounded once to half.
std::string hlsl_half_prelude(const Ctx& c) {
  return subst(R"(// glslang's HLSL front end declares its intrinsics for float only: half versions.
half {P}h_min(half a, half b) { return b < a ? b : a; }
half {P}h_max(half a, half b) { return a < b ? b : a; }
half {P}h_clamp(half x, half lo, half hi) { return {P}h_min({P}h_max(x, lo), hi); }
half {P}h_abs(half x) { return x < 0.0h ? -x : x; }
half {P}h_dot(half3 a, half3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
half {P}h_exp(half x) { return (half)exp((float)x); }
half {P}h_exp2(half x) { return (half)exp2((float)x); }
half {P}h_sqrt(half x) { return (half)sqrt((float)x); }
)",
               c);
}

// The constant names of a slot: {P}<role>_<member>, arrays <member><i>.
std::vector<std::string> names(const Ctx& c, std::string_view role, const ConstantSet& s, std::string_view m) {
  const auto& v = member(s, m);
  std::vector<std::string> out;
  if (v.size() == 1) {
    out.push_back(fmt::format("{}{}_{}", c.prefix, role, m));
  } else {
    for (std::size_t i = 0; i < v.size(); ++i) out.push_back(fmt::format("{}{}_{}{}", c.prefix, role, m, i));
  }
  return out;
}

std::string constant_decls(const Ctx& c, std::string_view role, const ConstantSet& s) {
  const char* kw = c.lang == Language::glsl ? "const float" : c.lang == Language::hlsl ? "static const float"
                                                                                       : "inline constexpr float";
  std::string out = fmt::format("// {}: {} {}\n", role, io::comment_text(s.cpp_type), io::comment_text(s.cpp_name));
  for (const auto& [m, v] : s.members) {
    const auto n = names(c, role, s, m);
    for (std::size_t i = 0; i < v.size(); ++i) out += fmt::format("{} {} = {};\n", kw, n[i], lit(v[i]));
  }
  return out;
}

// Helpers: text generated from the context and the method's constant slots.
using Slots = std::vector<std::pair<std::string, ConstantSet>>;
const ConstantSet& slot(const Slots& slots, std::string_view role) {
  for (const auto& [r, s] : slots)
    if (r == role) return s;
  throw std::logic_error(fmt::format("shader export: no constant slot '{}'", role));
}

std::string helper_expm1(const Ctx& c, const Slots&) {
  return subst(fmt::format(R"(// (e^x - 1)/x: Taylor series sum x^n/(n+1)!, n <= 10, for |x| < 1 (first omitted
// term < 2.1e-9), (e^x - 1)/x beyond (no expm1 in shading languages).
{{INLINE}}float {{P}}expm1_over_x(float x) {{
  if (abs(x) < 1.0f) return {};
  return (exp(x) - 1.0f) / x;
}}
)",
                           horner_text("x", literals(expm1_over_x_series()))),
               c);
}

std::string helper_erf(const Ctx& c, const Slots& slots) {
  const ConstantSet& s = slot(slots, "erf");
  std::string text;
  if (is_listing5(s)) {
    const auto split = names(c, "erf", s, "split")[0], cutoff = names(c, "erf", s, "cutoff")[0];
    const auto P = horner_text("a * a", names(c, "erf", s, "small"));
    const auto Q = horner_text("a", names(c, "erf", s, "large"));
    text = fmt::format(R"(// erf/erfc, [Tokuyoshi2022] Listing 5 structure: erf = x P(x^2) for |x| <= split,
// erfc(|x|) = 2^(-|x| Q(|x|)) for split < |x| < cutoff (no 1 - erf cancellation), 0 beyond.
{{INLINE}}float {{P}}erfc_pos(float a) {{
  if (a >= {1}) return 0.0f;
  if (a > {0}) return exp2(-a * {3});
  return 1.0f - a * {2};
}}
{{INLINE}}float {{P}}erf(float x) {{
  float a = abs(x);
  float y;
  if (a >= {1})
    y = 1.0f;
  else if (a > {0})
    y = 1.0f - exp2(-a * {3});
  else
    y = a * {2};
  return x < 0.0f ? -y : y;
}}
)",
                       split, cutoff, P, Q);
  } else if (is_as(s)) {
    const auto p = names(c, "erf", s, "p")[0];
    text = fmt::format(R"(// erf/erfc, [AS1964] 7.1.25 structure: erfc(a) = t P(t) e^(-a^2), t = 1/(1 + p a), a >= 0.
{{INLINE}}float {{P}}erfc_pos(float a) {{
  float t = 1.0f / (1.0f + {} * a);
  return t * {} * exp(-a * a);
}}
{{INLINE}}float {{P}}erf(float x) {{
  float y = 1.0f - {{P}}erfc_pos(abs(x));
  return x < 0.0f ? -y : y;
}}
)",
                       p, horner_text("t", names(c, "erf", s, "a")));
  } else {
    throw std::invalid_argument(fmt::format("shader export: no erf code for constant type {}", s.cpp_type));
  }
  text += R"({INLINE}float {P}erfc(float x) {
  float r = {P}erfc_pos(abs(x));
  return x < 0.0f ? 2.0f - r : r;
}
)";
  return subst(text, c);
}

std::string helper_product(const Ctx& c, const Slots&) {
  return subst(R"(// Product of the light SG with an SG (n, lambda) about the normal, c = v.n:
// (sharpness, log-amplitude, cosine of the product axis with n), without
// cancellation or overflow (sglab/sg.hpp sg_product_with_normal; [Tokuyoshi2022] Eq. 1-2).
{INLINE}{VEC3} {P}product_with_normal(float c, float kappa, float lambda) {
  float m = max(kappa, lambda);
  if (!(m > 0.0f)) return {VEC3}(0.0f, 0.0f, 1.0f);
  float ks = kappa / m;
  float ls = lambda / m;
  float diff = (kappa - lambda) / m;  // exact where kappa - lambda cancels (Sterbenz)
  float k3s = sqrt(diff * diff + 2.0f * ks * ls * (1.0f + c));
  float kmin = min(kappa, lambda);
  float log_amp = -2.0f * (kmin * ((1.0f - c) / (k3s + ks + ls)));
  float c3 = 1.0f;
  if (k3s > 0.0f) c3 = clamp((ks * c + ls) / k3s, -1.0f, 1.0f);
  return {VEC3}(m * k3s, log_amp, c3);
}
)",
               c);
}

std::string helper_steepness2022(const Ctx& c, const Slots&) {
  return subst(R"(// t(kappa) = kappa sqrt((0.5 kappa + A)/((kappa + B) kappa + C)) ([Tokuyoshi2022] Eq. 6),
// in powers of 1/kappa for kappa >= 1 so that nothing overflows.
{INLINE}float {P}steepness(float kappa) {
  if (kappa < 1.0f)
    return kappa * sqrt((0.5f * kappa + {P}steepness_A) / ((kappa + {P}steepness_B) * kappa + {P}steepness_C));
  float r = 1.0f / kappa;
  return sqrt(kappa) * sqrt((0.5f + {P}steepness_A * r) / (1.0f + ({P}steepness_B + {P}steepness_C * r) * r));
}
)",
               c);
}

std::string helper_steepness2024(const Ctx& c, const Slots&) {
  return subst(R"(// t(kappa) = kappa sqrt(0.5((kappa + A) kappa + B)/(((kappa + C) kappa + D) kappa + E))
// ([Tokuyoshi2024] Listing 7), in powers of 1/kappa for kappa >= 1.
{INLINE}float {P}steepness(float kappa) {
  if (kappa < 1.0f)
    return kappa * sqrt(0.5f * ((kappa + {P}steepness_A) * kappa + {P}steepness_B) /
                        (((kappa + {P}steepness_C) * kappa + {P}steepness_D) * kappa + {P}steepness_E));
  float r = 1.0f / kappa;
  return sqrt(kappa) * sqrt(0.5f * (1.0f + ({P}steepness_A + {P}steepness_B * r) * r) /
                            (1.0f + ({P}steepness_C + ({P}steepness_D + {P}steepness_E * r) * r) * r));
}
)",
               c);
}

std::string helper_hemispherical2022(const Ctx& c, const Slots&) {
  return subst(R"(// H~(c, kappa) = 2 pi lerp(e^-kappa, 1, s~) (1 - e^-kappa)/kappa, s~ = 1/2 + erf(t c)/(2 erf(t))
// ([Tokuyoshi2022] Eq. 5-6, Listing 3); the ratio is c below t = 2^-13.
{INLINE}float {P}hemispherical(float cosine, float kappa) {
  float t = {P}steepness(kappa);
  float c = clamp(cosine, -1.0f, 1.0f);
  float ratio;
  if (t < 0.0001220703125f)
    ratio = c;
  else
    ratio = clamp({P}erf(t * c) / {P}erf(t), -1.0f, 1.0f);
  float s = 0.5f + 0.5f * ratio;
  float e = exp(-kappa);
  return 6.28318548f * (e + s * (1.0f - e)) * {P}expm1_over_x(-kappa);
}
)",
               c);
}

std::string helper_poles2024(const Ctx& c, const Slots&) {
  return subst(fmt::format(R"(// Exact poles (E(-1, kappa), E(+1, kappa))/2 pi (sglab/closed_forms.hpp), series at kappa < 1;
// beyond, upper = (1 - m)/kappa and lower = e (m - e)/kappa share e = e^-kappa and
// m = (1 - e)/kappa (one branch, one exp for both).
{{INLINE}}{{VEC2}} {{P}}poles_over_two_pi(float kappa) {{
  float e = exp(-kappa);
  if (kappa < 1.0f) return {{VEC2}}(e * {}, {});
  float m = (1.0f - e) / kappa;
  return {{VEC2}}(e * ((m - e) / kappa), (1.0f - m) / kappa);
}}
)",
                           horner_text("kappa", literals(pole_series(true))),
                           horner_text("kappa", literals(pole_series(false)))),
               c);
}

std::string helper_lerp2024(const Ctx& c, const Slots&) {
  return subst(R"(// f = 1/2 (c erfc(-t c) + erfc(t)) - e^(-t^2 c^2) expm1(t^2 (c^2 - 1))/(2 sqrt(pi) t),
// saturated ([Tokuyoshi2024] Listing 7); t = t(kappa) >= 0, so erfc(t) is erfc_pos(t).
{INLINE}float {P}lerp_factor(float cosine, float t) {
  float c = clamp(cosine, -1.0f, 1.0f);
  float tz = t * c;
  float x = t * t * (c * c - 1.0f);
  float tail = 0.0f;
  if (t > 0.0f) tail = exp(-tz * tz) * (x * {P}expm1_over_x(x)) / t;
  return clamp(0.5f * (c * {P}erfc(-tz) + {P}erfc_pos(t)) - 0.5f * 0.564189584f * tail, 0.0f, 1.0f);
}
)",
               c);
}

std::string helper_meder2018(const Ctx& c, const Slots&) {
  return subst(R"(// [Meder2018] normalized logistic hemispherical integral, t(kappa) = sqrt(kappa) (a2 kappa^2 + a1 kappa)/
// (kappa^2 + b1 kappa + b0) as published, s = sigma(t c) (1 - e^(-t(1+c)))/(1 - e^(-t)), evaluated as
// sglab/hemispherical.hpp normalized_meder2018: sigma from e^(-t|c|), the ratio as
// (1 + c) E(-t(1+c))/E(-t) with E(x) = (e^x - 1)/x (no 0/0 at t = 0).
{INLINE}float {P}hemispherical(float cosine, float kappa) {
  float t = sqrt(kappa) * ({P}meder_a2 * kappa * kappa + {P}meder_a1 * kappa) /
            (kappa * kappa + {P}meder_b1 * kappa + {P}meder_b0);
  float c = clamp(cosine, -1.0f, 1.0f);
  float e = exp(-(t * abs(c)));
  float sigma = c < 0.0f ? e / (1.0f + e) : 1.0f / (1.0f + e);
  float u = 1.0f + c;
  float s = clamp(sigma * (u * ({P}expm1_over_x(-(t * u)) / {P}expm1_over_x(-t))), 0.0f, 1.0f);
  float em = exp(-kappa);
  return 6.28318548f * (em + s * (1.0f - em)) * {P}expm1_over_x(-kappa);
}
)",
               c);
}

std::string helper_hill(const Ctx& c, const Slots&) {
  return subst(R"(// Stephen Hill's fitted curve for a normalized SG ([Pettineo2016]).
{INLINE}float {P}hill_normalized(float cosine, float kappa) {
  float c0 = {P}hill_c0;
  float c1 = 1.0f / (4.0f * c0);
  float eml = exp(-kappa);
  float em2l = eml * eml;
  float rl = 1.0f / kappa;
  float scale = 1.0f + 2.0f * em2l - rl;
  float bias = (eml - em2l) * rl - em2l;
  float x = sqrt(1.0f - scale);
  float x0 = c0 * cosine;
  float x1 = c1 * x;
  float n = x0 + x1;
  float y = abs(x0) <= x1 ? n * n / x : clamp(cosine, 0.0f, 1.0f);
  return scale * y + bias;
}
)",
               c);
}

// The number of correction terms N and the degree D of an SglabAccParams set
// (from its type, SglabAccParams<double, N, D>, checked against its member
// sizes: steep 5, num N (D + 1), scale 1).
std::pair<std::size_t, std::size_t> sglab_acc_shape(const ConstantSet& s) {
  std::size_t n = 0, d = 0;
  char tail = 0;
  const bool typed = std::sscanf(s.cpp_type.c_str(), "SglabAccParams<double, %zu, %zu%c", &n, &d, &tail) == 3 &&
                     tail == '>';
  if (!typed || n == 0 || member(s, "num").size() != n * (d + 1) || member(s, "steep").size() != 5 ||
      member(s, "scale").size() != 1)
    throw std::invalid_argument(fmt::format("constant set {}: member sizes do not form SglabAccParams", s.cpp_name));
  return {n, d};
}

std::string helper_sglab_acc_steepness(const Ctx& c, const Slots& slots) {
  const auto s = names(c, "model", slot(slots, "model"), "steep");
  return subst(fmt::format(R"(// t(kappa) = kappa sqrt(0.5((kappa + s0) kappa + s1)/(((kappa + s2) kappa + s3) kappa + s4))
// ([Tokuyoshi2024] Listing 7 form, sglab's coefficients), in powers of 1/kappa for kappa >= 1.
{{INLINE}}float {{P}}steepness(float kappa) {{
  if (kappa < 1.0f)
    return kappa * sqrt(0.5f * ((kappa + {0}) * kappa + {1}) / (((kappa + {2}) * kappa + {3}) * kappa + {4}));
  float r = 1.0f / kappa;
  return sqrt(kappa) * sqrt(0.5f * (1.0f + ({0} + {1} * r) * r) / (1.0f + ({2} + ({3} + {4} * r) * r) * r));
}}
)",
                           s[0], s[1], s[2], s[3], s[4]),
               c);
}

// sglab_acc<N>: b_j = u (1 - u)^3 P_j(u), u = t/(t + scale) (sglab_acc.hpp
// sglab_acc_fade), and sum_j b_j z2^j.
std::string helper_sglab_acc_correction(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto [n, d] = sglab_acc_shape(set);
  const auto num = names(c, "model", set, "num"), scale = names(c, "model", set, "scale");
  std::string products;
  std::vector<std::string> b;
  for (std::size_t j = 0; j < n; ++j) {
    const std::vector<std::string> poly(num.begin() + j * (d + 1), num.begin() + (j + 1) * (d + 1));
    products += fmt::format("  float b{} = fade * ({});\n", j, horner_text("u", poly));
    b.push_back(fmt::format("b{}", j));
  }
  const std::string text = fmt::format(R"(// b_j = u (1 - u)^3 P_j(u), u = t/(t + s), P_j of degree {}: the correction fades for
// small and for large kappa; and the correction polynomial sum_j b_j z2^j (sglab/sglab_acc.hpp).
{{INLINE}}float {{P}}correction(float t, float z2) {{
  float w = 1.0f / (t + {});
  float u = t * w;
  float v = {} * w;
  float fade = u * (v * v) * v;
{}  return {};
}}
)",
                                       d, scale[0], scale[0], products, horner_text("z2", b));
  return subst(text, c);
}

std::string helper_sglab_acc_lerp(const Ctx& c, const Slots&) {
  return subst(R"(// f = f2024 + (1 - c^2) e^(-z^2) sum_j b_j z^2j, z = t c, saturated: the [Tokuyoshi2024]
// Listing 7 factor f2024 = 1/2 (c erfc(-z) + erfc(t)) - e^(-z^2) expm1(t^2 (c^2 - 1))/(2 sqrt(pi) t)
// with sglab's fitted even correction (sglab/sglab_acc.hpp). Where e^(-z^2) has underflowed
// the correction is 0 (its polynomial would overflow first for huge kappa). t = t(kappa) >= 0,
// so erfc(t) is erfc_pos(t).
{INLINE}float {P}lerp_factor(float cosine, float t) {
  float c = clamp(cosine, -1.0f, 1.0f);
  float tz = t * c;
  float z2 = tz * tz;
  float x = t * t * (c * c - 1.0f);
  float g = exp(-z2);
  float tail = 0.0f;
  if (t > 0.0f) tail = g * (x * {P}expm1_over_x(x)) / t;
  float f = 0.5f * (c * {P}erfc(-tz) + {P}erfc_pos(t)) - 0.5f * 0.564189584f * tail;
  float corr = 0.0f;
  if (g > 0.0f) corr = (1.0f - c * c) * g * {P}correction(t, z2);
  return clamp(f + corr, 0.0f, 1.0f);
}
)",
               c);
}

std::string helper_sglab_fast(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  std::vector<double> series;  // sum_{m<6} (-kappa)^m/(m + 2)!, the float series of sglab_fast.hpp
  {
    const auto all = pole_series(false);
    series.assign(all.begin(), all.begin() + 6);
  }
  return subst(fmt::format(R"(// E(1, kappa)/2 pi = (kappa - 1 + e^-kappa)/kappa^2: Taylor series below kappa = 1/4,
// (1 - (1 - e^-kappa)/kappa)/kappa from there on, e^-kappa's argument stopped at 80
// (sglab/sglab_fast.hpp upper_over_two_pi_fast).
{{INLINE}}float {{P}}upper_over_two_pi(float kappa) {{
  if (kappa < 0.25f) return {0};
  float r = 1.0f / kappa;
  return (1.0f - (1.0f - exp(-min(kappa, 80.0f))) * r) * r;
}}
// The C2 ramp rho(u) = 0 | u^3 (2 - u) | 2u - 1 on u <= 0 | (0, 1) | u >= 1, branch-free.
{{INLINE}}float {{P}}ramp(float u) {{
  float over = abs(u - 1.0f);
  float v = 0.5f * (abs(u) - over + 1.0f);
  return v * v * v * (2.0f - v) + (u - 1.0f + over);
}}
// sglab_fast: E = E(1, kappa) max(0, A + B c + C rho(V c + 1/2)), A, B, C, V = P(k)/Q(k),
// k = min(kappa, kappa_max), Q = k^4 + q3 k^3 + ... + q0 (sglab/sglab_fast.hpp).
{{INLINE}}float {{P}}fast(float cosine, float kappa) {{
  float k = min(kappa, {1});
  float inv_q = 1.0f / ({2} + k * k * k * k);
  float scale = 6.28318548f * {{P}}upper_over_two_pi(kappa) * inv_q;
  float s = {3} * scale + {4} * scale * cosine + {5} * scale * {{P}}ramp({6} * inv_q * cosine + 0.5f);
  return 0.5f * (s + abs(s));
}}
)",
                           horner_text("kappa", literals(series)), names(c, "model", set, "kappa_max")[0],
                           poly("q"), poly("a"), poly("b"), poly("c"), poly("v")),
               c);
}

// The half form of sglab_fast: its κ-only part (E(1, κ) and the rational A, B,
// C, V, whose κ^4 overflows half above κ = 16) in float, the per-pixel shape in
// half: the runtime's per-light split (sglab/sglab_fast.hpp sglab_fast_light,
// sglab_fast_eval) with the light's four numbers rounded to half.
std::string helper_sglab_fast_half(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  const bool glsl = c.lang == Language::glsl;
  const std::string h(half_type(c.lang)), abs16 = glsl ? "abs" : c.prefix + "h_abs";
  return subst(fmt::format(R"(// The C2 ramp rho(u) in half (as {{P}}ramp).
{0} {{P}}ramp_half({0} u) {{
  {0} over = {1}(u - {0}(1.0));
  {0} v = {0}(0.5) * ({1}(u) - over + {0}(1.0));
  return v * v * v * ({0}(2.0) - v) + (u - {0}(1.0) + over);
}}
// sglab_fast in half: a = A E(1, kappa)/Q, b, c_ramp, v = V/Q in float (kappa alone), rounded to
// half; max(0, a + b c + c_ramp rho(v c + 1/2)) in half.
{0} {{P}}fast_half({0} cosine, float kappa) {{
  float k = min(kappa, {2});
  float inv_q = 1.0f / ({3} + k * k * k * k);
  float scale = 6.28318548f * {{P}}upper_over_two_pi(kappa) * inv_q;
  {0} a = {0}({4} * scale);
  {0} b = {0}({5} * scale);
  {0} c_ramp = {0}({6} * scale);
  {0} v = {0}({7} * inv_q);
  {0} s = a + b * cosine + c_ramp * {{P}}ramp_half(v * cosine + {0}(0.5));
  return {0}(0.5) * (s + {1}(s));
}}
)",
                           h, abs16, names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"),
                           poly("c"), poly("v")),
               c);
}

using Helper = std::string (*)(const Ctx&, const Slots&);

// A method's own half form, where the translated float code would fail in
// half: its constants and helpers stay as written (float where they say
// float), and the body of the half entry point calls them.
struct HalfForm {
  std::string_view id;
  std::string_view description;  // for the header comment
  std::vector<Helper> helpers;
  std::string_view body;
};
const std::vector<HalfForm>& half_forms() {
  static const std::vector<HalfForm> table = {
      {"sglab_fast",
       "kappa-only part (E(1, kappa), the rational A, B, C, V) in float, per-pixel shape in half",
       {helper_sglab_fast, helper_sglab_fast_half},
       "  return {P}fast_half(cosine, float(kappa));\n"},
  };
  return table;
}
const HalfForm* find_half_form(std::string_view id) {
  for (const HalfForm& f : half_forms())
    if (f.id == id) return &f;
  return nullptr;
}

// How a method uses erf: not at all, through the tier the exporter picks for
// the model's accuracy, or through its own constant slot "erf" (the method is
// defined by that erf, e.g. tokuyoshi2022_listing5).
enum class ErfUse { none, tiered, own };

// One exportable method: the registry id, the paper it comes from, its
// compiled-in constant slots (role → set), the helpers it needs in order and
// the body of the entry point {ENTRY}(float cosine, float kappa).
// Constants are named {P}<role>_<member> in the body.
struct ShaderMethod {
  std::string_view id;
  std::string_view citation;
  Slots (*constants)();
  ErfUse erf;
  std::vector<Helper> helpers;
  std::string_view body;
};

constexpr std::string_view kBodyTokuyoshi2022 = R"(  float lambda = {P}clamped_cosine_lambda;
  float alpha = {P}clamped_cosine_alpha;
  {VEC3} prod = {P}product_with_normal(cosine, kappa, lambda);
  float p = {P}hemispherical(prod.z, prod.x) * exp(lambda + prod.y);
  float q = {P}hemispherical(cosine, kappa);
  return max(alpha * p - alpha * q, 0.0f);
)";
constexpr std::string_view kBodyTokuyoshi2024 = R"(  float f = {P}lerp_factor(cosine, {P}steepness(kappa));
  {VEC2} poles = {P}poles_over_two_pi(kappa);  // (lower, upper)
  return 6.28318548f * (poles.x + f * (poles.y - poles.x));
)";
// [Wang2009] a e^{d - kappa - lambda} 2 pi (1 - e^{-2d})/d, d = |kappa v + lambda n|, through the
// stable product (sglab/sg.hpp sg_inner_product): d - kappa - lambda without cancellation and
// S(d) = 4 pi (e^{-2d} - 1)/(-2d) with its d -> 0 limit.
constexpr std::string_view kBodyWang2009 = R"(  {VEC3} prod = {P}product_with_normal(cosine, kappa, {P}cosine_lobe_lambda);
  float s = 12.566371f * {P}expm1_over_x(-2.0f * prod.x);
  return max({P}cosine_lobe_amplitude * (exp(prod.y) * s), 0.0f);
)";
const std::vector<Helper> kHelpersWang2009 = {helper_expm1, helper_product};
constexpr std::string_view kBodyVsgl2015 = R"(  float sum = kappa + {P}diffuse_lobe_lambda_d;
  float lam = sum > 0.0f ? kappa * {P}diffuse_lobe_lambda_d / sum : 0.0f;
  return 6.28318548f * exp(lam * (cosine - 1.0f)) / sum;
)";

const std::vector<Helper> kHelpers2022 = {helper_expm1, helper_erf, helper_steepness2022, helper_product,
                                          helper_hemispherical2022};
const std::vector<Helper> kHelpers2024 = {helper_expm1, helper_erf, helper_steepness2024, helper_poles2024,
                                          helper_lerp2024};

constexpr std::string_view kBodySglabAcc = R"(  float f = {P}lerp_factor(cosine, {P}steepness(kappa));
  {VEC2} poles = {P}poles_over_two_pi(kappa);  // (lower, upper)
  return 6.28318548f * (poles.x + f * (poles.y - poles.x));
)";
const std::vector<Helper> kHelpersSglabAcc = {helper_expm1,        helper_erf,
                                              helper_sglab_acc_steepness, helper_poles2024,
                                              helper_sglab_acc_correction, helper_sglab_acc_lerp};

// THE table: one entry per exportable method. To add a method (e.g. one of
// sglab's own models): append {id, citation, its constant slots as
// Slots{{"role", named("NAME", the set NAME of constants.hpp)}}, how it uses erf, the
// helpers it calls, and the body in the shading-language subset used here
// (float, exp/exp2/sqrt/abs/min/max/clamp/dot, ?: with cheap arms and if/else
// where an arm costs (glslang's HLSL front end evaluates both arms of ?:),
// {VEC3}, {VEC2}; constants as {P}<role>_<member>)}. A constant set of a parameter type not yet listed
// above also needs a named() overload. tests/test_shader_export.cpp then
// compiles it to SPIR-V (GLSL and HLSL), compiles the C++ form and runs the
// shader forms on Vulkan against the runtime.
const std::vector<ShaderMethod>& shader_methods() {
  static const std::vector<ShaderMethod> table = {
      {"wang2009", "[Wang2009] cosine-lobe SG inner product, as quoted in [Pettineo2016]",
       [] { return Slots{{"cosine_lobe", named("cosine_lobe_published", constants::cosine_lobe_published)}}; }, ErfUse::none, kHelpersWang2009, kBodyWang2009},
      {"punctual", "[Pettineo2016] punctual approximation, max(c, 0) 2 pi/kappa", [] { return Slots{}; },
       ErfUse::none, {}, "  return clamp(cosine, 0.0f, 1.0f) * (6.28318548f / kappa);\n"},
      {"hill", "[Pettineo2016] Hill's fitted curve times 2 pi/kappa",
       [] { return Slots{{"hill", named("hill_published", constants::hill_published)}}; }, ErfUse::none, {helper_hill},
       "  return {P}hill_normalized(cosine, kappa) * (6.28318548f / kappa);\n"},
      {"hill_exact", "[Pettineo2016] Hill's fitted curve times the exact SG integral",
       [] { return Slots{{"hill", named("hill_published", constants::hill_published)}}; }, ErfUse::none, {helper_expm1, helper_hill},
       "  return {P}hill_normalized(cosine, kappa) * (12.566371f * {P}expm1_over_x(-2.0f * kappa));\n"},
      {"vsgl2015", "[Tokuyoshi2015] diffuse SG lambda_d = 2 with the [Iwasaki2012] product integral",
       [] { return Slots{{"diffuse_lobe", named("diffuse_lobe_published", constants::diffuse_lobe_published)}}; }, ErfUse::none, {}, kBodyVsgl2015},
      {"meder2018", "[Meder2018] logistic hemispherical integral with an SG cosine fit",
       [] { return Slots{{"meder", named("meder2018_published", constants::meder2018_published)}}; }, ErfUse::none,
       {helper_expm1, helper_product, helper_meder2018},
       R"(  {VEC3} prod = {P}product_with_normal(cosine, kappa, {P}meder_sharpness);
  float upper = exp(prod.y) * {P}hemispherical(prod.z, prod.x);
  return {P}meder_amplitude * upper - {P}meder_offset * {P}hemispherical(cosine, kappa);
)"},
      {"tokuyoshi2022", "[Tokuyoshi2022] Eq. 3-6, Listings 1-4",
       [] {
         return Slots{{"clamped_cosine", named("clamped_cosine_published", constants::clamped_cosine_published)},
                      {"steepness", named("steepness2022_published", constants::steepness2022_published)}};
       },
       ErfUse::tiered, kHelpers2022, kBodyTokuyoshi2022},
      {"tokuyoshi2024", "[Tokuyoshi2024] supplementary Listings 6-7",
       [] { return Slots{{"steepness", named("steepness2024_published", constants::steepness2024_published)}}; }, ErfUse::tiered, kHelpers2024,
       kBodyTokuyoshi2024},
      {"tokuyoshi2022_listing5", "[Tokuyoshi2022] Eq. 3-6, Listings 1-5 (its own Listing 5 erf)",
       [] {
         return Slots{{"clamped_cosine", named("clamped_cosine_published", constants::clamped_cosine_published)},
                      {"steepness", named("steepness2022_published", constants::steepness2022_published)},
                      {"erf", named("erf_listing5_published", constants::erf_listing5_published)}};
       },
       ErfUse::own, kHelpers2022, kBodyTokuyoshi2022},
      {"tokuyoshi2022_refit", "[Tokuyoshi2022] Eq. 3-6 with sglab's refitted constants",
       [] {
         return Slots{{"clamped_cosine", named("clamped_cosine_float", constants::clamped_cosine_float)},
                      {"steepness", named("steepness2022_irradiance", constants::steepness2022_irradiance)}};
       },
       ErfUse::tiered, kHelpers2022, kBodyTokuyoshi2022},
      {"tokuyoshi2024_refit", "[Tokuyoshi2024] Listings 6-7 with sglab's refitted t(kappa)",
       [] { return Slots{{"steepness", named("steepness2024_irradiance", constants::steepness2024_irradiance)}}; }, ErfUse::tiered, kHelpers2024,
       kBodyTokuyoshi2024},
      {"vsgl2015_refit", "[Tokuyoshi2015] with sglab's refitted lambda_d",
       [] { return Slots{{"diffuse_lobe", named("lambda_d_diffuse_lobe_irradiance", constants::lambda_d_diffuse_lobe_irradiance)}}; }, ErfUse::none, {},
       kBodyVsgl2015},
      {"wang2009_refit", "[Wang2009] with sglab's refitted cosine lobe (lambda, a)",
       [] { return Slots{{"cosine_lobe", named("lambda_d_cosine_lobe_free_amplitude", constants::lambda_d_cosine_lobe_free_amplitude)}}; }, ErfUse::none, kHelpersWang2009,
       kBodyWang2009},
      {"sglab_fast", "sglab_fast: E(1, kappa) times a line plus a C2 ramp, rational in kappa (sglab_fast.hpp)",
       [] { return Slots{{"model", named("sglab_fast_float", constants::sglab_fast_float)}}; }, ErfUse::none, {helper_sglab_fast},
       "  return {P}fast(cosine, kappa);\n"},
      {"sglab_acc1", "sglab: [Tokuyoshi2024] lerp factor + fitted even correction fading at both ends, N = 1, D = 3 (sglab_acc.hpp)",
       [] { return Slots{{"model", named("sglab_acc_acc1", constants::sglab_acc_acc1)}}; }, ErfUse::tiered, kHelpersSglabAcc,
       kBodySglabAcc},
      {"sglab_acc2", "sglab: [Tokuyoshi2024] lerp factor + fitted even correction fading at both ends, N = 2, D = 3 (sglab_acc.hpp)",
       [] { return Slots{{"model", named("sglab_acc_acc2", constants::sglab_acc_acc2)}}; }, ErfUse::tiered, kHelpersSglabAcc,
       kBodySglabAcc},
      {"sglab_acc3", "sglab: [Tokuyoshi2024] lerp factor + fitted even correction fading at both ends, N = 3, D = 4 (sglab_acc.hpp)",
       [] { return Slots{{"model", named("sglab_acc_acc3", constants::sglab_acc_acc3)}}; }, ErfUse::tiered, kHelpersSglabAcc,
       kBodySglabAcc},
  };
  return table;
}

const ShaderMethod* find_shader_method(std::string_view id) {
  for (const ShaderMethod& m : shader_methods())
    if (m.id == id) return &m;
  return nullptr;
}

// ---------------------------------------------------------------------------
// Per-light split forms (`sglab export --split`): everything that depends on
// kappa alone goes into a light struct, filled once per light by
// sglab_light_<ID>(float kappa); the pixel pays {ENTRY}({LIGHT} light, float
// cosine). {LIGHT} is the struct's name. The struct holds floats only, so its
// std430 layout is field k at byte 4k, and where the C++ runtime splits the
// method (registry.hpp light_setup32) the fields are its state, in its order.

// One float of a light struct and what it holds (for the header comment).
struct LightField {
  std::string name;
  std::string doc;
};

struct SplitForm {
  std::string_view id;
  // The C++ runtime state the struct equals, or empty when the runtime has no split.
  std::string_view runtime;
  std::vector<LightField> (*fields)(const Slots&);
  std::vector<Helper> helpers;
  // The bodies of sglab_light_<ID>(float kappa) (fills `light` and returns it)
  // and of {ENTRY}({LIGHT} light, float cosine).
  std::string (*light_body)(const Ctx&, const Slots&);
  std::string (*pixel_body)(const Ctx&, const Slots&);
};

std::vector<LightField> fields_tokuyoshi2024(const Slots&) {
  return {{"t", "steepness t(kappa) ([Tokuyoshi2024] Listing 7)"},
          {"lower", "E(-1, kappa)/2 pi, the exact lower pole (closed_forms.hpp)"},
          {"upper", "E(+1, kappa)/2 pi, the exact upper pole"}};
}
std::string light_tokuyoshi2024(const Ctx& c, const Slots&) {
  return subst(R"(  light.t = {P}steepness(kappa);
  {VEC2} poles = {P}poles_over_two_pi(kappa);  // (lower, upper)
  light.lower = poles.x;
  light.upper = poles.y;
)",
               c);
}
std::string pixel_tokuyoshi2024(const Ctx& c, const Slots&) {
  return subst(R"(  float f = {P}lerp_factor(cosine, light.t);
  return 6.28318548f * (light.lower + f * (light.upper - light.lower));
)",
               c);
}

std::vector<LightField> fields_sglab_fast(const Slots&) {
  return {{"a", "A(kappa) E(1, kappa)"},
          {"b", "B(kappa) E(1, kappa)"},
          {"c_ramp", "C(kappa) E(1, kappa)"},
          {"v", "V(kappa)"}};
}
std::string light_sglab_fast(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return subst(fmt::format(R"(  float k = min(kappa, {});
  float inv_q = 1.0f / ({} + k * k * k * k);
  float e1 = 6.28318548f * {{P}}upper_over_two_pi(kappa);
  light.a = {} * inv_q * e1;
  light.b = {} * inv_q * e1;
  light.c_ramp = {} * inv_q * e1;
  light.v = {} * inv_q;
)",
                           names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"), poly("c"),
                           poly("v")),
               c);
}
std::string pixel_sglab_fast(const Ctx& c, const Slots&) {
  return subst(R"(  float s = light.a + light.b * cosine + light.c_ramp * {P}ramp(light.v * cosine + 0.5f);
  return 0.5f * (s + abs(s));
)",
               c);
}

std::vector<LightField> fields_sglab_acc(const Slots& slots) {
  std::vector<LightField> f = {{"t", "steepness t(kappa)"},
                               {"half_erfc_t", "erfc(t)/2"},
                               {"tail_scale", "1/(2 sqrt(pi) max(t, 2^-23))"},
                               {"t2", "t^2"},
                               {"lower", "E(-1, kappa)/2 pi"},
                               {"upper", "E(+1, kappa)/2 pi"}};
  const std::size_t n = sglab_acc_shape(slot(slots, "model")).first;
  for (std::size_t j = 0; j < n; ++j) f.push_back({fmt::format("b{}", j), fmt::format("correction coefficient b_{}(kappa)", j)});
  return f;
}
// sglab_acc.hpp sglab_acc_light: t and the poles as tokuyoshi2024's setup, the tail scale
// 1/(2 sqrt(pi) max(t, eps)) and b_j = u (1 - u)^3 P_j(u), u = t/(t + scale) (sglab_acc_fade).
std::string light_sglab_acc(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto [n, d] = sglab_acc_shape(set);
  const auto num = names(c, "model", set, "num"), scale = names(c, "model", set, "scale");
  std::string products;
  for (std::size_t j = 0; j < n; ++j) {
    const std::vector<std::string> poly(num.begin() + j * (d + 1), num.begin() + (j + 1) * (d + 1));
    products += fmt::format("  light.b{} = fade * ({});\n", j, horner_text("u", poly));
  }
  return subst(fmt::format(R"(  light.t = {{P}}steepness(kappa);
  light.half_erfc_t = 0.5f * {{P}}erfc_pos(light.t);
  float t_or_eps = light.t;
  if (t_or_eps <= 1.1920929e-7f) t_or_eps = 1.1920929e-7f;
  light.tail_scale = 0.5f * 0.564189584f / t_or_eps;
  light.t2 = light.t * light.t;
  {{VEC2}} poles = {{P}}poles_over_two_pi(kappa);  // (lower, upper)
  light.lower = poles.x;
  light.upper = poles.y;
  float w = 1.0f / (light.t + {0});
  float u = light.t * w;
  float v = {0} * w;
  float fade = u * (v * v) * v;
{1})",
                           scale[0], products),
               c);
}
// sglab_acc.hpp sglab_acc_eval: the [Tokuyoshi2024] Listing 7 factor from the light's t, erfc(t)/2,
// 1/(2 sqrt(pi) t) and t^2, plus (1 - c^2) e^(-z^2) sum_j b_j z^2j (0 where e^(-z^2) underflowed).
std::string pixel_sglab_acc(const Ctx& c, const Slots& slots) {
  const std::size_t n = sglab_acc_shape(slot(slots, "model")).first;
  std::vector<std::string> b;
  for (std::size_t j = 0; j < n; ++j) b.push_back(fmt::format("light.b{}", j));
  return subst(fmt::format(R"(  float c = clamp(cosine, -1.0f, 1.0f);
  float z = light.t * c;
  float z2 = z * z;
  float one_minus_c2 = 1.0f - c * c;
  float g = exp(-z2);
  float x = -light.t2 * one_minus_c2;
  float f = 0.5f * c * {{P}}erfc(-z) + light.half_erfc_t - g * (x * {{P}}expm1_over_x(x)) * light.tail_scale;
  if (g > 0.0f) f += one_minus_c2 * g * {};
  f = clamp(f, 0.0f, 1.0f);
  return 6.28318548f * (light.lower + f * (light.upper - light.lower));
)",
                           horner_text("z2", b)),
               c);
}

// tokuyoshi2022: the product SG's sharpness and axis depend on the cosine, so
// its term keeps kappa; the light's own hemispherical term
// H(c, kappa) = 2 pi lerp(e^-kappa, 1, s) (1 - e^-kappa)/kappa needs per pixel only erf(t c).
// alpha p - alpha q cancels heavily at small kappa, so H is formed by the very
// operations of the unsplit export (helper_hemispherical2022): the same float result.
std::vector<LightField> fields_tokuyoshi2022(const Slots&) {
  return {{"kappa", "the sharpness kappa (the product with the clamped-cosine SG depends on the cosine)"},
          {"t", "steepness t(kappa) ([Tokuyoshi2022] Eq. 6)"},
          {"erf_t", "erf(t)"},
          {"e", "e^-kappa"},
          {"m", "(1 - e^-kappa)/kappa"}};
}
std::string light_tokuyoshi2022(const Ctx& c, const Slots&) {
  return subst(R"(  light.kappa = kappa;
  light.t = {P}steepness(kappa);
  light.erf_t = {P}erf(light.t);
  light.e = exp(-kappa);
  light.m = {P}expm1_over_x(-kappa);
)",
               c);
}
std::string pixel_tokuyoshi2022(const Ctx& c, const Slots&) {
  return subst(R"(  float lambda = {P}clamped_cosine_lambda;
  float alpha = {P}clamped_cosine_alpha;
  {VEC3} prod = {P}product_with_normal(cosine, light.kappa, lambda);
  float p = {P}hemispherical(prod.z, prod.x) * exp(lambda + prod.y);
  float c = clamp(cosine, -1.0f, 1.0f);
  float ratio;
  if (light.t < 0.0001220703125f)
    ratio = c;
  else
    ratio = clamp({P}erf(light.t * c) / light.erf_t, -1.0f, 1.0f);
  float s = 0.5f + 0.5f * ratio;
  float q = 6.28318548f * (light.e + s * (1.0f - light.e)) * light.m;
  return max(alpha * p - alpha * q, 0.0f);
)",
               c);
}

// punctual, hill, hill_exact ([Pettineo2016]): the curve's kappa-only terms and
// the integral factor, per pixel the operations of the unsplit export
// (helper_hill), so the values are the same floats.
std::vector<LightField> fields_punctual(const Slots&) { return {{"s", "2 pi/kappa"}}; }
std::string light_punctual(const Ctx&, const Slots&) { return "  light.s = 6.28318548f / kappa;\n"; }
std::string pixel_punctual(const Ctx&, const Slots&) { return "  return clamp(cosine, 0.0f, 1.0f) * light.s;\n"; }

std::vector<LightField> fields_hill(const Slots&) {
  return {{"scale", "1 + 2 e^-2kappa - 1/kappa"},
          {"bias", "(e^-kappa - e^-2kappa)/kappa - e^-2kappa"},
          {"x", "sqrt(1 - scale)"},
          {"x1", "x/(4 c0)"},
          {"s", "the integral factor: 2 pi/kappa (hill), 4 pi (1 - e^-2kappa)/(2 kappa) (hill_exact)"}};
}
std::string light_hill(const Ctx& c, const Slots&, std::string_view integral) {
  return subst(fmt::format(R"(  float c0 = {{P}}hill_c0;
  float c1 = 1.0f / (4.0f * c0);
  float eml = exp(-kappa);
  float em2l = eml * eml;
  float rl = 1.0f / kappa;
  light.scale = 1.0f + 2.0f * em2l - rl;
  light.bias = (eml - em2l) * rl - em2l;
  light.x = sqrt(1.0f - light.scale);
  light.x1 = c1 * light.x;
  light.s = {};
)",
                           integral),
               c);
}
std::string light_hill_approx(const Ctx& c, const Slots& s) { return light_hill(c, s, "6.28318548f / kappa"); }
std::string light_hill_exact(const Ctx& c, const Slots& s) {
  return light_hill(c, s, "12.566371f * {P}expm1_over_x(-2.0f * kappa)");
}
std::string pixel_hill(const Ctx& c, const Slots&) {
  return subst(R"(  float x0 = {P}hill_c0 * cosine;
  float n = x0 + light.x1;
  float y = abs(x0) <= light.x1 ? n * n / light.x : clamp(cosine, 0.0f, 1.0f);
  return (light.scale * y + light.bias) * light.s;
)",
               c);
}

// vsgl2015 ([Tokuyoshi2015], [Iwasaki2012]): the product's sharpness and 1/|kappa v + lambda_d n|.
std::vector<LightField> fields_vsgl2015(const Slots&) {
  return {{"lam", "kappa lambda_d/(kappa + lambda_d)"}, {"sum", "kappa + lambda_d"}};
}
std::string light_vsgl2015(const Ctx& c, const Slots&) {
  return subst(R"(  light.sum = kappa + {P}diffuse_lobe_lambda_d;
  light.lam = light.sum > 0.0f ? kappa * {P}diffuse_lobe_lambda_d / light.sum : 0.0f;
)",
               c);
}
std::string pixel_vsgl2015(const Ctx&, const Slots&) {
  return "  return 6.28318548f * exp(light.lam * (cosine - 1.0f)) / light.sum;\n";
}

// THE table of split forms, by method id (every other method: no split).
const std::vector<SplitForm>& split_forms() {
  static const std::vector<SplitForm> table = [] {
    const SplitForm t2024{"tokuyoshi2024", "sglab::Tokuyoshi2024Light<float> (sglab/irradiance.hpp tokuyoshi2024_light)",
                          fields_tokuyoshi2024, kHelpers2024, light_tokuyoshi2024, pixel_tokuyoshi2024};
    const SplitForm t2022{"tokuyoshi2022", "", fields_tokuyoshi2022, kHelpers2022, light_tokuyoshi2022,
                          pixel_tokuyoshi2022};
    const SplitForm acc{"sglab_acc", "sglab::SglabAccLight<float, N> (sglab/sglab_acc.hpp sglab_acc_light)",
                        fields_sglab_acc,
                        {helper_expm1, helper_erf, helper_sglab_acc_steepness, helper_poles2024},
                        light_sglab_acc, pixel_sglab_acc};
    const SplitForm vsgl{"vsgl2015", "", fields_vsgl2015, {}, light_vsgl2015, pixel_vsgl2015};
    std::vector<SplitForm> v = {
        {"punctual", "", fields_punctual, {}, light_punctual, pixel_punctual},
        {"hill", "", fields_hill, {}, light_hill_approx, pixel_hill},
        {"hill_exact", "", fields_hill, {helper_expm1}, light_hill_exact, pixel_hill},
        vsgl};
    v.push_back(vsgl), v.back().id = "vsgl2015_refit";
    for (std::string_view id : {"tokuyoshi2024", "tokuyoshi2024_refit"}) v.push_back(t2024), v.back().id = id;
    for (std::string_view id : {"tokuyoshi2022", "tokuyoshi2022_listing5", "tokuyoshi2022_refit"})
      v.push_back(t2022), v.back().id = id;
    v.push_back({"sglab_fast", "sglab::SglabFastLight<float> (sglab/sglab_fast.hpp sglab_fast_light)",
                 fields_sglab_fast, {helper_sglab_fast}, light_sglab_fast, pixel_sglab_fast});
    for (std::string_view id : {"sglab_acc1", "sglab_acc2", "sglab_acc3"}) v.push_back(acc), v.back().id = id;
    return v;
  }();
  return table;
}

const SplitForm* find_split_form(std::string_view id) {
  for (const SplitForm& s : split_forms())
    if (s.id == id) return &s;
  return nullptr;
}

std::string prelude(const Ctx& c) {
  if (c.lang != Language::cpp) return {};
  return subst(R"(#include <cmath>

namespace sglab_export_{ID} {
using std::abs;
using std::exp;
using std::exp2;
using std::sqrt;
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
inline float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
struct float3 {
  float x, y, z;
  float3(float a, float b, float c) : x(a), y(b), z(c) {}
};
struct float2 {
  float x, y;
  float2(float a, float b) : x(a), y(b) {}
};
inline float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

)",
               c);
}

// The exported code is float: a coefficient beyond the largest float would be
// written as inf, which is no literal. Throws std::invalid_argument naming the
// set and the key (coefficients.NAME, or coefficients.NAME[i] in an array).
void check_finite_in_float(const ConstantSet& set) {
  for (const auto& [name, values] : set.members)
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(static_cast<float>(values[i])))
        throw std::invalid_argument(fmt::format(
            "constant set {}: key '{}': {} is not finite in float, the precision of the exported code", set.cpp_name,
            values.size() == 1 ? "coefficients." + name : fmt::format("coefficients.{}[{}]", name, i), values[i]));
}

// A half export writes every coefficient as a half literal (methods without a
// half form of their own): one beyond 65504 would be inf. Throws
// std::invalid_argument naming the set and the key.
void check_finite_in_half(const ConstantSet& set) {
  for (const auto& [name, values] : set.members)
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(static_cast<float>(static_cast<_Float16>(static_cast<float>(values[i])))))
        throw std::invalid_argument(fmt::format(
            "constant set {}: key '{}': {} is not finite in half (largest 65504), the precision of the exported code",
            set.cpp_name, values.size() == 1 ? "coefficients." + name : fmt::format("coefficients.{}[{}]", name, i),
            values[i]));
}

// The vector form of the entry point (every export).
constexpr std::string_view kVectorForm = R"(// Vector form: light axis v (unit), sharpness kappa, surface normal n (unit).
{INLINE}float {ENTRY}({VEC3} axis, float sharpness, {VEC3} normal) {
  return {ENTRY}(clamp(dot(axis, normal), -1.0f, 1.0f), sharpness);
}
)";

// The code (after the header comment) of a half export: the float code
// translated to half (to_half_code), or the method's own half form.
std::string half_code(const Ctx& c, const ShaderMethod& m, const Slots& slots) {
  const HalfForm* form = find_half_form(m.id);
  std::string out = c.lang == Language::glsl
                        ? "#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require\n\n"
                        : hlsl_half_prelude(c) + "\n";
  for (const auto& [role, set] : slots) {
    if (!form) check_finite_in_half(set);
    const std::string decls = constant_decls(c, role, set);
    out += form ? decls : to_half_code(decls, c);
  }
  out += "\n";
  if (form) {
    for (Helper helper : form->helpers) out += helper(c, slots) + "\n";
  } else {
    for (Helper helper : m.helpers) out += to_half_code(helper(c, slots), c) + "\n";
  }
  out += to_half_code(subst("{INLINE}float {ENTRY}(float cosine, float kappa) {\n", c), c);
  out += form ? subst(form->body, c) : to_half_code(subst(m.body, c), c);
  out += "}\n\n";
  out += to_half_code(subst(kVectorForm, c), c);
  return out;
}

// The header lines of a half export: what is half and what is not.
std::string half_header(const ShaderMethod& m, Language lang) {
  std::string h = lang == Language::glsl
                      ? "// Precision: half (binary16, float16_t through GL_EXT_shader_explicit_arithmetic_types_float16);\n"
                      : "// Precision: half (binary16, `half` with 16-bit types: DXC -enable-16bit-types, glslang "
                        "--hlsl-enable-16bit-types);\n";
  if (const HalfForm* form = find_half_form(m.id))
    h += fmt::format("//   the method's half form: {}.\n", form->description);
  else
    h += "//   every operation and constant in half.\n";
  if (lang == Language::hlsl)
    h += "//   glslang's HLSL intrinsics take float only: exp, exp2, sqrt run in float, rounded once to half.\n";
  return h + "//   binary16 has 11 bits and normal values 6.1e-5 ... 65504: e^-kappa underflows above kappa ~ 17\n"
             "//   and 1/kappa^2 overflows below kappa ~ 4e-3 wherever a method forms them, and kappa above\n"
             "//   65504 is infinite (`sglab stability --half` measures the kappa range each method survives).\n";
}

std::string fmt_error(std::optional<double> e) { return e ? fmt::format("{:.3g}", *e) : std::string("not measured"); }

// The header line of the GPU cost: each family's figure, or "not measured".
std::string gpu_cost_line(const ExportRequest& request) {
  std::string costs;
  bool measured = false;
  for (const GpuCost& g : request.gpu_cost) {
    costs += fmt::format("{}{} {}", costs.empty() ? "" : ", ", g.family,
                         g.inverse_throughput ? fmt::format("{}", *g.inverse_throughput) : "not measured");
    measured = measured || g.inverse_throughput.has_value();
  }
  if (!measured)
    return fmt::format("// GPU cost (ACO inverse throughput, cycles per wave, `sglab gpucost`): not measured{}\n",
                       request.gpu_cost_source.empty()
                           ? std::string()
                           : fmt::format(" for this code in {}", io::comment_text(request.gpu_cost_source)));
  return fmt::format("// GPU cost (ACO inverse throughput, cycles per wave, `sglab gpucost`; {}): {}\n",
                     io::comment_text(request.gpu_cost_source), io::comment_text(costs));
}

}  // namespace

std::vector<std::string> exportable_methods() {
  std::vector<std::string> out;
  for (const ShaderMethod& m : shader_methods()) out.emplace_back(m.id);
  return out;
}

std::vector<ConstantSet> method_constants(std::string_view method) {
  const ShaderMethod* m = find_shader_method(method);
  if (!m) return {};
  std::vector<ConstantSet> out;
  for (auto& [role, set] : m->constants()) out.push_back(set);
  return out;
}

ElementaryError measure_elementary(std::string_view tier_id) {
  static std::mutex mutex;
  static std::map<std::string, ElementaryError, std::less<>> cache;
  std::lock_guard lock(mutex);
  if (auto it = cache.find(tier_id); it != cache.end()) return it->second;
  ElementaryError e;
  if (tier_id.empty()) {
    e = measure(nullptr);
  } else {
    const Tier* t = nullptr;
    for (const Tier& x : kTiers)
      if (x.id == tier_id) t = &x;
    if (!t) throw std::invalid_argument(fmt::format("unknown elementary tier '{}'", tier_id));
    const ConstantSet s = t->set();
    e = measure(&s);
  }
  cache.emplace(std::string(tier_id), e);
  return e;
}

ErrorBudget runtime_budget(std::string_view method) {
  ErrorBudget b;
  const Method* m = find_method(irradiance_methods, method);
  if (!m) return b;
  validate::SweepOptions options;
  options.keep_points = false;
  options.progress = false;
  const std::vector<validate::SweepMethod> one{{validate::Quantity::irradiance, *m}};
  const validate::SweepResult r = sweep(validate::SweepGrid{}, one, options);
  if (const validate::SweepEntry* e = r.find(method, validate::Quantity::irradiance, validate::FloatFormat::binary64)) b.model = e->summary.peak_rel.max;
  if (const validate::SweepEntry* e = r.find(method, validate::Quantity::irradiance, validate::FloatFormat::binary32))
    b.float_cpp = e->summary.peak_rel.max;
  return b;
}

ExportRequest standard_request(Language lang, std::string_view method, Precision precision) {
  ExportRequest req;
  req.lang = lang;
  req.method = std::string(method);
  req.precision = precision;
  req.command = fmt::format("sglab export --lang {} --method {}{}", to_string(lang), method,
                            precision == Precision::float16 ? " --precision half" : "");
  req.budget = runtime_budget(method);
  return req;
}

ElementaryTier choose_tier(std::optional<double> model_error) {
  // The erf/erfc error must stay within 1/100 of the model's error, both
  // absolutely (erfc in the 2024 interpolation factor) and relatively near 0
  // (the erf(t c)/erf(t) ratio of the 2022 method at small κ).
  for (const Tier& t : kTiers) {
    const ElementaryError e = measure_elementary(t.id);
    const double worst = std::max(e.max_abs(), e.erf_rel_small);
    if (model_error && worst <= *model_error / 100) return {t.id, t.description};
  }
  const Tier& best = kTiers[std::size(kTiers) - 1];
  return {best.id, best.description};
}

namespace {

// The constant slots of the request's method: its compiled-in sets, the erf
// tier it takes (recorded in `result`), and the overrides in place of the sets
// of their type.
Slots request_slots(const ExportRequest& request, const ShaderMethod& m, ExportResult& result) {
  Slots slots = m.constants();
  if (m.erf == ErfUse::tiered) {
    result.tier = choose_tier(request.budget.model);
    for (const Tier& t : kTiers)
      if (t.id == result.tier.id) slots.emplace_back("erf", t.set());
  } else if (m.erf == ErfUse::own) {
    result.tier = {"own", "the method's own erf constants (slot 'erf')"};
  }
  // Overrides replace the slot of the same parameter type.
  for (const ConstantSet& o : request.overrides) {
    bool used = false;
    for (auto& [role, set] : slots)
      if (set.cpp_type == o.cpp_type) {
        for (const auto& [name, values] : set.members) {
          const auto& nv = member(o, name);  // throws when a member is missing
          if (nv.size() != values.size())
            throw std::invalid_argument(fmt::format("constant set {}: member '{}' has {} values, {} expects {}",
                                                    o.cpp_name, name, nv.size(), o.cpp_type, values.size()));
        }
        set = o;
        used = true;
      }
    if (!used) {
      std::string types;
      for (const auto& [role, set] : slots) types += (types.empty() ? "" : ", ") + set.cpp_type;
      throw std::invalid_argument(fmt::format("constant set {} has type {}; method {} uses {}", o.cpp_name, o.cpp_type,
                                              request.method, types.empty() ? "no constants" : types));
    }
  }
  return slots;
}

// The header comment: method, source, constants, tier, error budget, GPU cost, command.
std::string header_comment(const ExportRequest& request, const ShaderMethod& m, const Slots& slots,
                           const ExportResult& result, bool has_erf) {
  const ErrorBudget& b = result.budget;
  std::string h;
  h += fmt::format("// {}: sglab export of method `{}` ({}{})\n", result.entry_point, m.id,
                   request.lang == Language::glsl   ? "GLSL 4.50"
                   : request.lang == Language::hlsl ? "HLSL, Shader Model 6"
                                                    : "C++",
                   request.split ? ", per-light split" : "");
  h += fmt::format("// Irradiance E(c, kappa) = integral of exp(kappa (w.v - 1)) max(w.n, 0) dw, c = v.n, of a\n"
                   "// unit-amplitude SG light of sharpness kappa >= 0.\n");
  h += fmt::format("// Source: {}.\n", m.citation);
  h += "// Constants:\n";
  for (const auto& [role, set] : slots) {
    std::string prov = set.provenance;
    if (prov.empty()) {
      prov = "compiled in from include/sglab/constants.hpp";
      if (auto it = request.provenance.find(set.cpp_name); it != request.provenance.end()) prov += "; " + it->second;
    }
    h += fmt::format("//   {}: {} ({})\n", role, io::comment_text(set.cpp_name), io::comment_text(prov));
  }
  if (!result.tier.id.empty()) h += fmt::format("// erf/erfc: tier '{}': {}.\n", result.tier.id, result.tier.description);
  h += request.overrides.empty()
           ? "// Error budget (max |E~ - E|/E(1, kappa), kappa in [1e-3, 1e4], 41 cosines):\n"
           : "// Error budget (max |E~ - E|/E(1, kappa)):\n";
  if (request.overrides.empty()) {
    h += fmt::format("//   model (double precision vs reference): {}\n", fmt_error(b.model));
    h += fmt::format("//   C++ float runtime vs reference:        {}\n", fmt_error(b.float_cpp));
  } else {
    h += fmt::format("//   model (as recorded by the constant set's fit, over its own kappa range): {}\n", fmt_error(b.model));
  }
  if (has_erf)
    h += fmt::format("//   elementary, float: erf abs {:.2g}, erf rel (|x| <= 1) {:.2g}, erfc abs {:.2g}, "
                     "(e^x - 1)/x rel {:.2g}\n",
                     b.elementary.erf_abs, b.elementary.erf_rel_small, b.elementary.erfc_abs,
                     b.elementary.expm1_over_x_rel);
  else
    h += fmt::format("//   elementary, float: (e^x - 1)/x rel {:.2g}\n", b.elementary.expm1_over_x_rel);
  if (b.vulkan)
    h += fmt::format("//   measured on Vulkan ({}): {}\n", io::comment_text(b.vulkan_device), fmt_error(b.vulkan));
  if (request.lang != Language::cpp) h += gpu_cost_line(request);
  if (request.precision == Precision::float16) h += half_header(m, request.lang);
  h += fmt::format("// Produced by: {}\n", io::comment_text(request.command));
  return h;
}

// The entry point {ENTRY}(float cosine, float kappa) and its vector form.
std::string unsplit_functions(const Ctx& c, const ShaderMethod& m, const Slots& slots) {
  std::string body;
  for (Helper helper : m.helpers) body += helper(c, slots) + "\n";
  body += subst("{INLINE}float {ENTRY}(float cosine, float kappa) {\n", c);
  body += subst(m.body, c);
  body += "}\n\n";
  body += subst(kVectorForm, c);
  return body;
}

// The light struct (documented field by field), sglab_light_<ID>(float kappa)
// and the per-pixel {ENTRY}({LIGHT} light, float cosine).
std::string split_functions(const Ctx& c, const SplitForm& form, const Slots& slots) {
  const std::string light = light_struct_name(c.id);
  const std::vector<LightField> fields = form.fields(slots);
  std::string body;
  for (Helper helper : form.helpers) body += helper(c, slots) + "\n";
  body += fmt::format("// {}: the per-light state of {}, {} floats. std430 layout (floats only): field k\n"
                      "// at byte offset 4k, struct size {} bytes, array stride {} bytes. {}.\n",
                      light, form.id, fields.size(), 4 * fields.size(), 4 * fields.size(),
                      form.runtime.empty()
                          ? "The C++ runtime has no split of this method: fill it with sglab_light_" + c.id +
                                " (the C++ export on the host, or a shader pre-pass)"
                          : fmt::format("The same floats, in the same order, as the C++ runtime's {} (the state "
                                        "of registry.hpp light_setup32), so the host can fill it from the runtime",
                                        form.runtime));
  body += "struct " + light + " {\n";
  for (std::size_t i = 0; i < fields.size(); ++i)
    body += fmt::format("  float {};  // offset {}: {}\n", fields[i].name, 4 * i, fields[i].doc);
  body += "};\n\n";
  body += fmt::format("// Per light (once per frame): everything of {} that depends on kappa alone.\n", form.id);
  body += fmt::format("{}{} sglab_light_{}(float kappa) {{\n  {} light;\n", c.lang == Language::cpp ? "inline " : "",
                      light, c.id, light);
  body += form.light_body(c, slots);
  body += "  return light;\n}\n\n";
  body += "// Per pixel: the irradiance at cosine c = v.n from the light's state.\n";
  body += subst("{INLINE}float {ENTRY}(", c) + light + " light, float cosine) {\n";
  body += form.pixel_body(c, slots);
  body += "}\n";
  return body;
}

}  // namespace

std::string light_struct_name(std::string_view method) {
  return "SglabLight_" + entry_point_name(method).substr(std::string_view("sglab_irradiance_").size());
}

std::vector<std::string> split_methods() {
  std::vector<std::string> out;
  for (const ShaderMethod& m : shader_methods())
    if (find_split_form(m.id)) out.emplace_back(m.id);
  return out;
}

ExportResult export_source(const ExportRequest& request) {
  const ShaderMethod* m = find_shader_method(request.method);
  if (!m) {
    std::string known;
    for (const auto& id : exportable_methods()) known += (known.empty() ? "" : ", ") + id;
    throw std::invalid_argument(
        fmt::format("unknown or non-exportable method '{}'; exportable: {}", request.method, known));
  }
  const SplitForm* form = request.split ? find_split_form(m->id) : nullptr;
  if (request.split && !form)
    throw std::invalid_argument(fmt::format("method '{}' has no per-light split (--split); methods with one: {}",
                                            request.method, fmt::format("{}", fmt::join(split_methods(), ", "))));
  if (request.split && request.precision == Precision::float16)
    throw std::invalid_argument("--split with --precision half: the per-light split export is float only (its light "
                                "struct is std430 floats filled by the float runtime); use one or the other");
  if (request.precision == Precision::float16 && request.lang == Language::cpp)
    throw std::invalid_argument("--precision half: the C++ export is float only (g++'s _Float16 may keep float "
                                "intermediates, so it would not be a faithful half twin); use --lang glsl or hlsl");
  ExportResult result;
  result.budget = request.budget;
  const Slots slots = request_slots(request, *m, result);
  const ConstantSet* erf_set = nullptr;
  for (const auto& [role, set] : slots) {
    check_finite_in_float(set);
    if (role == "erf") erf_set = &set;
  }
  result.budget.elementary = erf_set ? measure(erf_set) : measure_elementary("");

  Ctx c{request.lang, entry_point_name(request.method).substr(std::string_view("sglab_irradiance_").size()), {}};
  c.prefix = "sglab_" + c.id + "_";
  result.entry_point = "sglab_irradiance_" + c.id;
  if (form) {
    result.light_function = "sglab_light_" + c.id;
    result.light_struct = light_struct_name(c.id);
    result.light_floats = form->fields(slots).size();
  }

  const std::string header = header_comment(request, *m, slots, result, erf_set != nullptr);
  if (request.precision == Precision::float16) {
    result.source = header + "\n" + half_code(c, *m, slots);
    return result;
  }
  std::string body = header + "\n" + prelude(c);
  for (const auto& [role, set] : slots) body += constant_decls(c, role, set);
  body += "\n";
  body += form ? split_functions(c, *form, slots) : unsplit_functions(c, *m, slots);
  if (c.lang == Language::cpp) {
    body += subst("\n}  // namespace sglab_export_{ID}\nusing sglab_export_{ID}::{ENTRY};\n", c);
    if (form) {
      // Its own namespace, so that a program may hold the split and the unsplit export of a method.
      body += "using sglab_export_{ID}::" + result.light_function + ";\nusing sglab_export_{ID}::" +
              result.light_struct + ";\n";
      body = replace_all(body, "sglab_export_{ID}", "sglab_export_{ID}_split");
    }
  }
  // {ID} only occurs in the C++ namespace lines.
  result.source = replace_all(body, "{ID}", c.id);
  return result;
}

namespace {

// The wrapper of a half export: float buffers, converted at the call.
std::string compute_shader_half(Language lang, std::string_view exported, std::string_view entry) {
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(cosine_kappa.length()))
    result[i] = float({}(float16_t(cosine_kappa[i].x), float16_t(cosine_kappa[i].y)));
}}
)",
                       exported, entry);
  if (lang == Language::hlsl)
    return fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  cosine_kappa.GetDimensions(n, stride);
  if (id.x < n) result[id.x] = (float){}((half)cosine_kappa[id.x].x, (half)cosine_kappa[id.x].y);
}}
)",
                       exported, entry);
  throw std::invalid_argument("compute_shader: C++ is not a shader language");
}

}  // namespace

std::string compute_shader(Language lang, std::string_view exported, std::string_view entry, Precision precision) {
  if (precision == Precision::float16) return compute_shader_half(lang, exported, entry);
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs {{ vec2 cosine_kappa[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};

{}
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(cosine_kappa.length())) result[i] = {}(cosine_kappa[i].x, cosine_kappa[i].y);
}}
)",
                       exported, entry);
  if (lang == Language::hlsl)
    return fmt::format(R"([[vk::binding(0, 0)]] StructuredBuffer<float2> cosine_kappa;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;

{}
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  cosine_kappa.GetDimensions(n, stride);
  if (id.x < n) result[id.x] = {}(cosine_kappa[id.x].x, cosine_kappa[id.x].y);
}}
)",
                       exported, entry);
  throw std::invalid_argument("compute_shader: C++ is not a shader language");
}

namespace {
void require_split(const ExportResult& exported, const char* who) {
  if (exported.light_struct.empty() || exported.light_function.empty())
    throw std::invalid_argument(fmt::format("{}: the export is not a split form (ExportRequest::split)", who));
}
}  // namespace

std::string split_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "split_compute_shader");
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;

{0}
layout(std430, set = 0, binding = 0) readonly buffer Cosines {{ float cosines[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Outputs {{ float result[]; }};
layout(std430, set = 0, binding = 2) readonly buffer Lights {{ {1} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_WorkGroupID.y;
  uint n = uint(cosines.length());
  if (i < n) result[l * n + i] = {2}(lights[l], cosines[i]);
}}
)",
                       exported, ex.light_struct, ex.entry_point);
  if (lang == Language::hlsl)
    return fmt::format(R"({0}
[[vk::binding(0, 0)]] StructuredBuffer<float> cosines;
[[vk::binding(1, 0)]] RWStructuredBuffer<float> result;
[[vk::binding(2, 0)]] StructuredBuffer<{1}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID, uint3 group : SV_GroupID) {{
  uint n, stride;
  cosines.GetDimensions(n, stride);
  if (id.x < n) result[group.y * n + id.x] = {2}(lights[group.y], cosines[id.x]);
}}
)",
                       exported, ex.light_struct, ex.entry_point);
  throw std::invalid_argument("split_compute_shader: C++ is not a shader language");
}

std::string light_compute_shader(Language lang, std::string_view exported, const ExportResult& ex) {
  require_split(ex, "light_compute_shader");
  if (lang == Language::glsl)
    return fmt::format(R"(#version 450
layout(local_size_x = 64) in;

{0}
layout(std430, set = 0, binding = 0) readonly buffer Kappas {{ float kappas[]; }};
layout(std430, set = 0, binding = 1) writeonly buffer Lights {{ {1} lights[]; }};

void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(kappas.length())) lights[i] = {2}(kappas[i]);
}}
)",
                       exported, ex.light_struct, ex.light_function);
  if (lang == Language::hlsl)
    return fmt::format(R"({0}
[[vk::binding(0, 0)]] StructuredBuffer<float> kappas;
[[vk::binding(1, 0)]] RWStructuredBuffer<{1}> lights;

[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {{
  uint n, stride;
  kappas.GetDimensions(n, stride);
  if (id.x < n) lights[id.x] = {2}(kappas[id.x]);
}}
)",
                       exported, ex.light_struct, ex.light_function);
  throw std::invalid_argument("light_compute_shader: C++ is not a shader language");
}

}  // namespace sglab::shader
