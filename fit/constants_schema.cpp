#include "fit/constants_schema.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "common/args.hpp"
#include "common/io.hpp"
#include "common/json_input.hpp"

namespace sglab::fit {

// ---------------------------------------------------------------------------
// The parameter structs of include/sglab/params.hpp, one line each (see the
// top of constants_schema.hpp). Members in declaration order.
// ---------------------------------------------------------------------------
std::span<const ParamStruct> param_structs() {
  static const std::vector<ParamStruct> table = {
      {"ClampedCosineParams", {}, {"lambda", "alpha"}},
      {"Steepness2022Params", {}, {"A", "B", "C"}},
      {"Steepness2024Params", {}, {"A", "B", "C", "D", "E"}},
      {"SteepnessRationalParams", {"M"}, {"p[M > 0 ? M : 1]", "q[M + 1]"}},
      {"Listing5Params", {"NS", "NL"}, {"split", "cutoff", "small[NS]", "large[NL]"}},
      {"AbramowitzStegunParams", {"N"}, {"p", "a[N]"}},
      {"CosineLobeParams", {}, {"lambda", "amplitude"}},
      {"DiffuseLobeParams", {}, {"lambda_d"}},
      {"HillParams", {}, {"c0"}},
      {"Meder2018Params", {}, {"a2", "a1", "b1", "b0", "amplitude", "sharpness", "offset"}},
      {"SglabFastParams", {}, {"a[5]", "b[5]", "c[5]", "v[5]", "q[4]", "kappa_max"}},
      {"SglabMidParams", {}, {"a[5]", "b[5]", "d[5]", "s[5]", "v[5]", "q[4]", "kappa_max"}},
      {"SglabLiteParams", {}, {"a[5]", "b[5]", "c[5]", "v[5]", "q[4]", "kappa_max"}},
      {"SglabMinParams", {}, {"a[3]", "b[2]", "g[2]", "s"}},
      {"SglabTabParams", {"N", "D"}, {"coef[N * 7 * (D + 1)]"}},
      {"SglabAccParams", {"N", "D", "M"}, {"steep[2 * M + 1]", "num[N * (D + 1)]", "scale"}},
  };
  return table;
}

// ---------------------------------------------------------------------------
// The sets that code in include/, validate/, fit/, app/, bench/ and tests/
// names as constants::NAME, one line each, with the type it was written
// against. A header without any of them does not compile.
// ---------------------------------------------------------------------------
std::span<const RequiredSet> required_sets() {
  static const std::vector<RequiredSet> table = {
      {"clamped_cosine_published", "ClampedCosineParams<double>"},
      {"clamped_cosine_double", "ClampedCosineParams<double>"},
      {"clamped_cosine_float_alpha_free", "ClampedCosineParams<double>"},
      {"clamped_cosine_half", "ClampedCosineParams<double>"},
      {"erf_as7125_float", "AbramowitzStegunParams<double, 3>"},
      {"erf_listing5_float", "Listing5Params<double, 6, 7>"},
      {"clamped_cosine_float", "ClampedCosineParams<double>"},
      {"cosine_lobe_published", "CosineLobeParams<double>"},
      {"diffuse_lobe_published", "DiffuseLobeParams<double>"},
      {"erf_as7125_published", "AbramowitzStegunParams<double, 3>"},
      {"erf_listing5_published", "Listing5Params<double, 6, 7>"},
      {"hill_published", "HillParams<double>"},
      {"lambda_d_cosine_lobe_free_amplitude", "CosineLobeParams<double>"},
      {"lambda_d_diffuse_lobe_hemisphere_ls", "DiffuseLobeParams<double>"},
      {"lambda_d_diffuse_lobe_irradiance", "DiffuseLobeParams<double>"},
      {"lambda_d_diffuse_lobe_sphere_ls", "DiffuseLobeParams<double>"},
      {"meder2018_published", "Meder2018Params<double>"},
      {"sglab_acc1", "SglabAccParams<double, 1, 3, 2>"},
      {"sglab_acc2", "SglabAccParams<double, 2, 5, 2>"},
      {"sglab_acc3", "SglabAccParams<double, 3, 6, 3>"},
      {"sglab_acc4", "SglabAccParams<double, 4, 6, 3>"},
      {"sglab_fast_float", "SglabFastParams<double>"},
      {"sglab_lite_float", "SglabLiteParams<double>"},
      {"sglab_mid_float", "SglabMidParams<double>"},
      {"sglab_min_float", "SglabMinParams<double>"},
      {"sglab_tab_float", "SglabTabParams<double, 32, 3>"},
      {"steepness2022_irradiance", "Steepness2022Params<double>"},
      {"steepness2022_optimal_t", "Steepness2022Params<double>"},
      {"steepness2022_published", "Steepness2022Params<double>"},
      {"steepness2024_irradiance", "Steepness2024Params<double>"},
      {"steepness2024_published", "Steepness2024Params<double>"},
  };
  return table;
}

namespace {

std::string q(std::string_view s) { return io::quote_escaped(s); }

[[noreturn]] void fail(const std::string& file, std::string_view key, const std::string& what) {
  if (key.empty()) throw ConstantsError(fmt::format("{}: {}", file, what));
  throw ConstantsError(fmt::format("{}: key {}: {}", file, q(key), what));
}

// Member lengths as params.hpp writes them: cond := sum ['>' sum '?' cond ':' cond],
// sum := product {('+' | '-') product}, product := primary {'*' primary},
// primary := atom | '(' cond ')', atom := integer | size parameter.
class LengthExpression {
 public:
  LengthExpression(std::string_view text, const std::map<std::string, long long, std::less<>>& vars)
      : text_(text), vars_(vars) {}
  std::optional<long long> evaluate() {
    auto v = cond();
    skip();
    if (!v || pos_ != text_.size()) return std::nullopt;
    return v;
  }

 private:
  void skip() {
    while (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < text_.size() && text_[pos_] == c) return ++pos_, true;
    return false;
  }
  std::optional<long long> atom() {
    skip();
    const std::size_t start = pos_;
    while (pos_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_'))
      ++pos_;
    const std::string_view token = text_.substr(start, pos_ - start);
    if (token.empty()) return std::nullopt;
    if (std::isdigit(static_cast<unsigned char>(token[0]))) {
      long long v = 0;
      const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
      if (ec != std::errc() || p != token.data() + token.size()) return std::nullopt;
      return v;
    }
    const auto it = vars_.find(token);
    if (it == vars_.end()) return std::nullopt;
    return it->second;
  }
  std::optional<long long> primary() {
    if (!eat('(')) return atom();
    auto v = cond();
    if (!v || !eat(')')) return std::nullopt;
    return v;
  }
  std::optional<long long> product() {
    auto v = primary();
    while (v && eat('*')) {
      auto r = primary();
      if (!r) return std::nullopt;
      *v *= *r;
    }
    return v;
  }
  std::optional<long long> sum() {
    auto v = product();
    while (v) {
      if (eat('+')) {
        auto r = product();
        if (!r) return std::nullopt;
        *v += *r;
      } else if (eat('-')) {
        auto r = product();
        if (!r) return std::nullopt;
        *v -= *r;
      } else {
        break;
      }
    }
    return v;
  }
  std::optional<long long> cond() {
    auto v = sum();
    if (!v || !eat('>')) return v;
    auto rhs = sum();
    if (!rhs || !eat('?')) return std::nullopt;
    auto a = cond();
    if (!a || !eat(':')) return std::nullopt;
    auto b = cond();
    if (!b) return std::nullopt;
    return *v > *rhs ? a : b;
  }

  std::string_view text_;
  const std::map<std::string, long long, std::less<>>& vars_;
  std::size_t pos_ = 0;
};

bool plain_identifier(std::string_view s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// target and variant: they name files (<target>-<variant>.json) and appear in comments.
bool is_name(std::string_view s) {
  if (s.empty() || s.size() > kMaxIdentifierLength ||
      !std::isalnum(static_cast<unsigned char>(s[0])))
    return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ||
           c == '+';
  });
}

const ordered_json* find(const ordered_json& object, std::string_view key) {
  const auto it = object.find(std::string(key));
  return it == object.end() ? nullptr : &*it;
}

}  // namespace

bool is_cpp_identifier(std::string_view s) {
  static constexpr std::string_view keywords[] = {
      "alignas",       "alignof",     "and",
      "and_eq",        "asm",         "auto",
      "bitand",        "bitor",       "bool",
      "break",         "case",        "catch",
      "char",          "char8_t",     "char16_t",
      "char32_t",      "class",       "compl",
      "concept",       "const",       "consteval",
      "constexpr",     "constinit",   "const_cast",
      "continue",      "co_await",    "co_return",
      "co_yield",      "decltype",    "default",
      "delete",        "do",          "double",
      "dynamic_cast",  "else",        "enum",
      "explicit",      "export",      "extern",
      "false",         "float",       "for",
      "friend",        "goto",        "if",
      "inline",        "int",         "long",
      "mutable",       "namespace",   "new",
      "noexcept",      "not",         "not_eq",
      "nullptr",       "operator",    "or",
      "or_eq",         "private",     "protected",
      "public",        "register",    "reinterpret_cast",
      "requires",      "return",      "short",
      "signed",        "sizeof",      "static",
      "static_assert", "static_cast", "struct",
      "switch",        "template",    "this",
      "thread_local",  "throw",       "true",
      "try",           "typedef",     "typeid",
      "typename",      "union",       "unsigned",
      "using",         "virtual",     "void",
      "volatile",      "wchar_t",     "while",
      "xor",           "xor_eq",      "final",
      "override",      "import",      "module"};
  if (!plain_identifier(s) || s.size() > kMaxIdentifierLength) return false;
  if (s.find("__") != std::string_view::npos) return false;  // reserved
  if (s[0] == '_' && s.size() > 1 && std::isupper(static_cast<unsigned char>(s[1])))
    return false;  // reserved
  return std::find(std::begin(keywords), std::end(keywords), s) == std::end(keywords);
}

ResolvedType resolve_cpp_type(std::string_view text, const std::string& where) {
  const auto bad = [&](const std::string& why) -> ConstantsError {
    return ConstantsError(fmt::format("{}: cpp_type {}: {}", where, q(text), why));
  };
  const auto open = text.find('<');
  if (open == std::string_view::npos || text.empty() || text.back() != '>')
    throw bad("expected Name<double> or Name<double, N...>");
  const std::string_view name = text.substr(0, open);
  const auto it = std::find_if(param_structs().begin(), param_structs().end(),
                               [&](const ParamStruct& p) { return p.name == name; });
  if (it == param_structs().end()) {
    std::string known;
    for (const auto& p : param_structs())
      known += (known.empty() ? "" : ", ") + std::string(p.name);
    throw bad(fmt::format("unknown parameter struct (known: {})", known));
  }
  std::vector<std::string_view> args;
  std::string_view inner = text.substr(open + 1, text.size() - open - 2);
  for (std::size_t start = 0;;) {
    const auto comma = inner.find(',', start);
    std::string_view arg = inner.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    while (!arg.empty() && arg.front() == ' ') arg.remove_prefix(1);
    while (!arg.empty() && arg.back() == ' ') arg.remove_suffix(1);
    args.push_back(arg);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (args[0] != "double") throw bad("the scalar type must be double");
  if (args.size() != it->size_params.size() + 1)
    throw bad(fmt::format("{} takes {} size parameter(s) after double, got {}", name,
                          it->size_params.size(), args.size() - 1));
  ResolvedType r;
  r.canonical = std::string(name) + "<double";
  std::map<std::string, long long, std::less<>> vars;
  for (std::size_t i = 0; i < it->size_params.size(); ++i) {
    const std::string_view a = args[i + 1];
    long long v = -1;
    const bool digits =
        !a.empty() && std::all_of(a.begin(), a.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) std::from_chars(a.data(), a.data() + a.size(), v);
    if (!digits || v < 0 || v > static_cast<long long>(kMaxArrayLength))
      throw bad(fmt::format("size parameter {} must be an integer in [0, {}], got {}",
                            it->size_params[i], kMaxArrayLength, q(a)));
    vars.emplace(std::string(it->size_params[i]), v);
    r.canonical += fmt::format(", {}", v);
  }
  r.canonical += ">";
  for (std::string_view m : it->members) {
    const auto bracket = m.find('[');
    if (bracket == std::string_view::npos) {
      r.members.emplace_back(std::string(m), 0);
      continue;
    }
    const auto length =
        LengthExpression(m.substr(bracket + 1, m.size() - bracket - 2), vars).evaluate();
    if (!length) throw bad(fmt::format("internal: cannot evaluate the length of member {}", m));
    if (*length < 1 || *length > static_cast<long long>(kMaxArrayMembers))
      throw bad(fmt::format("member {} would have {} elements (must be 1 to {})",
                            m.substr(0, bracket), *length, kMaxArrayMembers));
    r.members.emplace_back(std::string(m.substr(0, bracket)), static_cast<std::size_t>(*length));
  }
  return r;
}

ordered_json parse_untrusted_json(std::string_view text, const std::string& file) {
  if (text.size() > kMaxConstantsFileBytes)
    throw ConstantsError(fmt::format("{}: {} bytes, more than the {} a constants file may have",
                                     file, text.size(), kMaxConstantsFileBytes));
  try {
    return io::parse_json_strict(text, file);
  } catch (const io::InputError& e) {
    throw ConstantsError(e.what());
  }
}

std::optional<std::string> why_not_a_constant_set(std::string_view text) {
  const std::string tag = fmt::format("\"{}\"", kConstantSetFormat);
  std::string why;
  try {
    const ordered_json v = parse_untrusted_json(text, "");
    if (const ordered_json* format = v.is_object() ? find(v, "format") : nullptr) {
      if (format->is_string() && format->get<std::string>() == kConstantSetFormat)
        return std::nullopt;
      return fmt::format("its \"format\" is {}, not {}", format->dump(), tag);
    }
    why = v.is_object() ? "a JSON object without \"format\""
                        : fmt::format("a JSON {}, not an object", v.type_name());
  } catch (const ConstantsError&) {
    why = text.empty() ? "empty, not JSON" : "not JSON";
  }
  if (text.find(tag) != std::string_view::npos)
    return std::nullopt;  // a damaged set: validated, then refused
  return fmt::format("{} (a constant set has \"format\": {})", why, tag);
}

namespace {

// The provenance block: its string and object fields, κ range, objective and certificate.
void validate_provenance(const ordered_json& set, const std::string& file) {
  const ordered_json* provenance = find(set, "provenance");
  if (!provenance) fail(file, "provenance", "missing");
  if (!provenance->is_object())
    fail(file, "provenance", fmt::format("must be an object, got {}", provenance->type_name()));
  for (const char* key : {"objective", "source", "command", "tool", "date", "precision"})
    if (const ordered_json* v = find(*provenance, key); v && !v->is_string())
      fail(file, std::string("provenance.") + key,
           fmt::format("must be a string, got {}", v->type_name()));
  for (const char* key : {"grid", "achieved"})
    if (const ordered_json* v = find(*provenance, key); v && !v->is_object())
      fail(file, std::string("provenance.") + key,
           fmt::format("must be an object, got {}", v->type_name()));
  if (const ordered_json* v = find(*provenance, "kappa_range");
      v && !(v->is_array() && v->size() == 2 && (*v)[0].is_number() && (*v)[1].is_number()))
    fail(file, "provenance.kappa_range", "must be an array of two numbers [LO, HI]");
  if (const ordered_json* a = find(*provenance, "achieved"))
    if (const ordered_json* v = find(*a, "objective"); v && !v->is_number())
      fail(file, "provenance.achieved.objective",
           fmt::format("must be a number, got {}", v->type_name()));
  // A fit's certificate (fit/lp_minimax.hpp; sglab-acc, sglab-fast, erf): its
  // kind and grid, the max achieved and the lower bound for the family, both
  // finite, the bound positive and not above what the fit achieved.
  if (const ordered_json* c = find(*provenance, "certificate")) {
    if (!c->is_object())
      fail(file, "provenance.certificate",
           fmt::format("must be an object, got {}", c->type_name()));
    for (const char* key : {"kind", "grid"})
      if (const ordered_json* v = find(*c, key); !v || !v->is_string())
        fail(file, std::string("provenance.certificate.") + key,
             v ? fmt::format("must be a string, got {}", v->type_name()) : "missing");
    for (const char* key : {"achieved", "lower_bound"})
      if (const ordered_json* v = find(*c, key);
          !v || !v->is_number() || !std::isfinite(v->get<double>()))
        fail(file, std::string("provenance.certificate.") + key,
             v ? "must be a finite number" : "missing");
    const double achieved = c->at("achieved").get<double>(),
                 bound = c->at("lower_bound").get<double>();
    if (!(bound > 0 && bound <= achieved * (1 + 1e-9)))
      fail(file, "provenance.certificate.lower_bound",
           fmt::format("must be positive and at most achieved ({}), got {}", achieved, bound));
  }
}
}  // namespace

void validate_constant_set(const ordered_json& set, const std::string& file) {
  if (!set.is_object()) fail(file, "", "not a JSON object");
  const ordered_json* format = find(set, "format");
  if (!format)
    fail(file, "format",
         fmt::format("missing: a constant set has \"format\": \"{}\"", kConstantSetFormat));
  if (!format->is_string() || format->get<std::string>() != kConstantSetFormat)
    fail(file, "format", fmt::format("must be \"{}\", got {}", kConstantSetFormat, format->dump()));
  const ordered_json* version = find(set, "version");
  if (!version || !version->is_number_integer() || version->get<long long>() != kConstantSetVersion)
    fail(file, "version",
         fmt::format("must be {} (the version of the format this sglab reads){}",
                     kConstantSetVersion,
                     version ? ", got " + version->dump() : std::string(", missing")));
  const auto string_field = [&](const char* key) -> std::string {
    const ordered_json* v = find(set, key);
    if (!v) fail(file, key, "missing");
    if (!v->is_string()) fail(file, key, fmt::format("must be a string, got {}", v->type_name()));
    return v->get<std::string>();
  };
  const std::string target = string_field("target"), variant = string_field("variant");
  const std::string cpp_name = string_field("cpp_name"), cpp_type = string_field("cpp_type");
  string_field("form");
  for (const auto& [key, value] : {std::pair{"target", &target}, std::pair{"variant", &variant}})
    if (!is_name(*value))
      fail(file, key,
           fmt::format("{} is not a name (letters, digits, '-', '_', '.', '+', starting with a "
                       "letter or digit, at most {} characters)",
                       q(*value), kMaxIdentifierLength));
  if (!is_cpp_identifier(cpp_name))
    fail(file, "cpp_name", fmt::format("{} is not a C++ identifier (or is reserved)", q(cpp_name)));
  const ResolvedType type = resolve_cpp_type(cpp_type, file);

  const ordered_json* coefficients = find(set, "coefficients");
  if (!coefficients) fail(file, "coefficients", "missing");
  if (!coefficients->is_object())
    fail(file, "coefficients", fmt::format("must be an object, got {}", coefficients->type_name()));
  for (const auto& [name, value] : coefficients->items()) {
    const auto member = std::find_if(type.members.begin(), type.members.end(),
                                     [&](const auto& m) { return m.first == name; });
    const std::string key = "coefficients." + name;
    if (member == type.members.end()) {
      std::string known;
      for (const auto& m : type.members) known += (known.empty() ? "" : ", ") + m.first;
      fail(file, key,
           fmt::format("{} has no member of this name (members: {})", type.canonical, known));
    }
    const auto check_number = [&](const ordered_json& v, const std::string& k) {
      if (!v.is_number()) fail(file, k, fmt::format("must be a number, got {}", v.type_name()));
      if (!std::isfinite(v.get<double>())) fail(file, k, "must be finite");
    };
    if (member->second == 0) {
      check_number(value, key);
    } else {
      if (!value.is_array())
        fail(file, key,
             fmt::format("must be an array of {} numbers, got {}", member->second,
                         value.type_name()));
      if (value.size() != member->second)
        fail(file, key,
             fmt::format("has {} values; {} needs {}", value.size(), type.canonical,
                         member->second));
      for (std::size_t i = 0; i < value.size(); ++i)
        check_number(value[i], fmt::format("{}[{}]", key, i));
    }
  }
  for (const auto& [name, length] : type.members)
    if (!coefficients->contains(name))
      fail(file, "coefficients." + name,
           fmt::format("missing: {} needs every member", type.canonical));

  validate_provenance(set, file);
}

void validate_header_sets(const std::vector<ordered_json>& sets,
                          const std::vector<std::string>& files) {
  std::map<std::string, std::size_t> by_name;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const std::string name = sets[i]["cpp_name"].get<std::string>();
    const auto [it, fresh] = by_name.emplace(name, i);
    if (!fresh)
      fail(files[i], "cpp_name",
           fmt::format("{} is also the cpp_name of {}", q(name), files[it->second]));
  }
  for (const RequiredSet& r : required_sets()) {
    const auto it = by_name.find(std::string(r.cpp_name));
    if (it == by_name.end())
      throw ConstantsError(
          fmt::format("no constant set has cpp_name {} ({}), which the runtime and tools use; the "
                      "header would not compile",
                      q(r.cpp_name), r.cpp_type));
    const std::string& file = files[it->second];
    const std::string have =
        resolve_cpp_type(sets[it->second]["cpp_type"].get<std::string>(), file).canonical;
    if (have != r.cpp_type)
      fail(file, "cpp_type",
           fmt::format("{} is {}, but the code uses it as {}", r.cpp_name, have, r.cpp_type));
  }
}

}  // namespace sglab::fit
