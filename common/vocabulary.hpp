// common/vocabulary.hpp — the words every tool uses for how a value is
// computed (the precision, the backend, the shading language, the form of an
// export, and the evaluation they make together), and the one way an enum's
// values are named: a table of {value, "name"} per enum, names_of(E), found by
// argument-dependent lookup in the enum's namespace. io::to_string,
// io::parse_enum, io::one_of and io::parse_option read that table.
#pragma once

#include <array>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "common/args.hpp"  // quote_escaped
#include "common/io.hpp"    // InputError

namespace sglab::io {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

// An enum with a names_of table.
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires {
  names_of(E{});
};

// The name of `e` in its table ("?" for a value the table lacks).
template <NamedEnum E>
constexpr std::string_view to_string(E e) {
  for (const auto& n : names_of(E{}))
    if (n.value == e) return n.name;
  return "?";
}

// The value named `text` (exactly); nullopt for any other text.
template <NamedEnum E>
constexpr std::optional<E> parse_enum(std::string_view text) {
  for (const auto& n : names_of(E{}))
    if (n.name == text) return n.value;
  return std::nullopt;
}

// "a, b or c": the names of `values` (every value of E when empty), for an error message.
template <NamedEnum E>
std::string one_of(std::initializer_list<E> values = {}) {
  std::string out;
  std::size_t count = values.size(), i = 0;
  if (count == 0) count = names_of(E{}).size();
  const auto add = [&](std::string_view name) {
    if (i > 0) out += i + 1 == count ? " or " : ", ";
    out += name;
    ++i;
  };
  if (values.size() == 0)
    for (const auto& n : names_of(E{})) add(n.name);
  else
    for (E v : values) add(to_string(v));
  return out;
}

// The value of option `option` among `allowed` (every value of E when empty);
// anything else is bad input: InputError "OPTION: expected a, b or c, got 'TEXT'"
// (TEXT escaped and shortened, io::quote_escaped).
template <NamedEnum E>
E parse_option(std::string_view option, std::string_view text,
               std::initializer_list<E> allowed = {}) {
  const auto parsed = parse_enum<E>(text);
  bool ok = parsed.has_value() && allowed.size() == 0;
  for (E v : allowed) ok = ok || (parsed && *parsed == v);
  if (!ok)
    throw InputError(std::string(option) + ": expected " + one_of<E>(allowed) + ", got " +
                     quote_escaped(text));
  return *parsed;
}

// The arithmetic of a value: IEEE 754 binary16, binary32 or binary64, each
// valued by its width in bits. No precision has the value 0, so a
// value-initialized Precision{} is no precision (to_string: "?"), never
// silently half; every member holding one states its value.
enum class Precision { float16 = 16, float32 = 32, float64 = 64 };
constexpr std::array<EnumName<Precision>, 3> names_of(Precision) {
  return {{{Precision::float16, "half"},
           {Precision::float32, "float"},
           {Precision::float64, "double"}}};
}
// The limits of a precision (common/args.hpp).
constexpr const NumberFormat& number_format(Precision p) {
  return p == Precision::float16   ? kHalfFormat
         : p == Precision::float32 ? kFloatFormat
         : p == Precision::float64 ? kDoubleFormat
                                   : throw std::invalid_argument("number_format: not a precision");
}

// Where a method runs: the C++ runtime on the CPU, or its shader export on a Vulkan device.
enum class Backend { cpu, vulkan };
constexpr std::array<EnumName<Backend>, 2> names_of(Backend) {
  return {{{Backend::cpu, "cpu"}, {Backend::vulkan, "vulkan"}}};
}

// The language of an export.
enum class Language { glsl, hlsl, cpp };
constexpr std::array<EnumName<Language>, 3> names_of(Language) {
  return {{{Language::glsl, "glsl"}, {Language::hlsl, "hlsl"}, {Language::cpp, "cpp"}}};
}

// The form of an export: the whole evaluation per call, or split into a
// per-light setup and a per-shading-point evaluation (`sglab export --split`).
enum class Form { whole, split };
constexpr std::array<EnumName<Form>, 2> names_of(Form) {
  return {{{Form::whole, "whole"}, {Form::split, "split"}}};
}

// Where and in what arithmetic a method is evaluated: the runtime on the CPU
// in float or double, or its export on a Vulkan device (GLSL or HLSL; float or
// half; the whole or the split form; the split form is float only).
struct Evaluation {
  Backend backend = Backend::cpu;
  Precision precision = Precision::float64;
  Language language = Language::glsl;  // vulkan: the export's language
  Form form = Form::whole;             // vulkan: the export's form
  friend constexpr auto operator<=>(const Evaluation&, const Evaluation&) = default;
};
inline constexpr Evaluation kCpuFloat{Backend::cpu, Precision::float32};
inline constexpr Evaluation kCpuDouble{Backend::cpu, Precision::float64};
constexpr Evaluation on_cpu(Precision p) { return {Backend::cpu, p}; }
constexpr Evaluation on_vulkan(Language lang, Precision p, Form form = Form::whole) {
  return {Backend::vulkan, p, lang, form};
}
// The name of an evaluation in the sweep's tables: "float" and "double" on
// the CPU, "vulkan[_hlsl][_half|_split]" on a device.
std::string to_string(const Evaluation& e);

}  // namespace sglab::io
