#include "export/shader_export.hpp"

#include <cctype>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <sglab/registry.hpp>

#include "common/comment_text.hpp"
#include "export/shader_constants.hpp"
#include "export/shader_elementary.hpp"
#include "export/shader_methods.hpp"
#include "export/shader_text.hpp"
#include "validate/kappa_range.hpp"
#include "validate/sweep.hpp"

namespace sglab::shader {

std::string entry_point_name(std::string_view method) {
  std::string out = "sglab_irradiance_";
  for (char ch : method) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return out;
}

using namespace detail;

namespace {

// The registry card of an exportable method (every one has a card: test_shader_export).
const Method& registry_card(std::string_view id) {
  const Method* m = find_method(irradiance_methods, id);
  if (!m) throw std::logic_error(fmt::format("exported method {} has no registry card", id));
  return *m;
}

// The C++ export's prelude: <cmath>, its namespace (opened here, closed by
// export_source) and the shading-language functions and types its code calls.
std::string prelude(const Ctx& c) {
  if (c.lang != Language::cpp) return {};
  return "#include <cmath>\n\nnamespace sglab_export_{ID} {\n" + subst(R"(using std::abs;
using std::exp;
using std::exp2;
using std::floor;
using std::log;
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
struct float4 {
  float x, y, z, w;
  constexpr float4(float a, float b, float c, float d) : x(a), y(b), z(c), w(d) {}
};
inline float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

)",
                                                                       c);
}

// The vector form of the entry point (every export).
constexpr std::string_view kVectorForm =
    R"(// Vector form: light axis v (unit), sharpness kappa, surface normal n (unit).
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
  std::string h = lang == Language::glsl ? "// Precision: half (binary16, float16_t through "
                                           "GL_EXT_shader_explicit_arithmetic_types_float16);\n"
                                         : "// Precision: half (binary16, `half` with 16-bit "
                                           "types: DXC -enable-16bit-types, glslang "
                                           "--hlsl-enable-16bit-types);\n";
  if (find_half_form(m.id))
    h += fmt::format("//   the method's half form: {}.\n", registry_card(m.id).half);
  else
    h += "//   every operation and constant in half.\n";
  if (lang == Language::hlsl)
    h += "//   glslang's HLSL intrinsics take float only: exp, exp2, sqrt run in float, rounded "
         "once to half.\n";
  return h +
         "//   binary16 has 11 bits and normal values 6.1e-5 ... 65504: e^-kappa underflows above "
         "kappa ~ 17\n"
         "//   and 1/kappa^2 overflows below kappa ~ 4e-3 wherever a method forms them, and kappa "
         "above\n"
         "//   65504 is infinite (`sglab stability --half` measures the kappa range each method "
         "survives).\n";
}

std::string fmt_error(std::optional<double> e) {
  return e ? fmt::format("{:.3g}", *e) : std::string("not measured");
}

// The header line of the GPU cost: each family's figure, or "not measured".
std::string gpu_cost_line(const ExportRequest& request) {
  std::string costs;
  bool measured = false;
  for (const GpuCost& g : request.gpu_cost) {
    costs += fmt::format(
        "{}{} {}", costs.empty() ? "" : ", ", g.family,
        g.inverse_throughput ? fmt::format("{}", *g.inverse_throughput) : "not measured");
    measured = measured || g.inverse_throughput.has_value();
  }
  if (!measured)
    return fmt::format(
        "// GPU cost of one call (ACO inverse throughput, cycles per wave, `sglab gpucost`): not "
        "measured{}\n",
        request.gpu_cost_source.empty()
            ? std::string()
            : fmt::format(" for this code in {}", io::comment_text(request.gpu_cost_source)));
  return fmt::format(
      "// GPU cost of one call (ACO inverse throughput, cycles per wave, `sglab gpucost`; {}): "
      "{}\n",
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

ErrorBudget runtime_budget(std::string_view method) {
  ErrorBudget b;
  const Method* m = find_method(irradiance_methods, method);
  if (!m) return b;
  validate::SweepOptions options;
  options.keep_points = false;
  options.progress = false;
  const std::vector<validate::SweepMethod> one{{validate::Quantity::irradiance, *m}};
  const validate::SweepResult r = sweep(validate::SweepGrid{}, one, options);
  if (const validate::SweepEntry* e =
          r.find(method, validate::Quantity::irradiance, io::kCpuDouble))
    b.model = e->summary.peak_rel.max;
  if (const validate::SweepEntry* e = r.find(method, validate::Quantity::irradiance, io::kCpuFloat))
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

namespace {

// The constant slots of the request's method: its compiled-in sets, the erf
// tier it takes (recorded in `result`), and the overrides in place of the sets
// of their type.
Slots request_slots(const ExportRequest& request, const ShaderMethod& m, ExportResult& result) {
  Slots slots = m.constants();
  if (m.erf == ErfUse::tiered) {
    result.tier = choose_tier(request.budget.model);
    slots.emplace_back("erf", tier_set(result.tier.id));
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
            throw std::invalid_argument(
                fmt::format("constant set {}: member '{}' has {} values, {} expects {}", o.cpp_name,
                            name, nv.size(), o.cpp_type, values.size()));
        }
        set = o;
        used = true;
      }
    if (!used) {
      std::string types;
      for (const auto& [role, set] : slots) types += (types.empty() ? "" : ", ") + set.cpp_type;
      throw std::invalid_argument(fmt::format("constant set {} has type {}; method {} uses {}",
                                              o.cpp_name, o.cpp_type, request.method,
                                              types.empty() ? "no constants" : types));
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
  h += fmt::format(
      "// Irradiance E(c, kappa) = integral of exp(kappa (w.v - 1)) max(w.n, 0) dw, c = v.n, of a\n"
      "// unit-amplitude SG light of sharpness kappa >= 0.\n");
  const Method& card = registry_card(m.id);
  h += fmt::format("// {}: {}.\n// Source: {}.\n", m.id, io::comment_text(card.summary),
                   io::comment_text(card.source));
  h += "// Constants:\n";
  for (const auto& [role, set] : slots) {
    std::string prov = set.provenance;
    if (prov.empty()) {
      prov = "compiled in from include/sglab/constants.hpp";
      if (auto it = request.provenance.find(set.cpp_name); it != request.provenance.end())
        prov += "; " + it->second;
    }
    h += fmt::format("//   {}: {} ({})\n", role, io::comment_text(set.cpp_name),
                     io::comment_text(prov));
  }
  if (!result.tier.id.empty())
    h += fmt::format("// erf/erfc: tier '{}': {}.\n", result.tier.id, result.tier.description);
  h += request.overrides.empty()
           ? "// Error budget (max |E~ - E|/E(1, kappa), kappa in [1e-3, 1e4], 41 cosines):\n"
           : "// Error budget (max |E~ - E|/E(1, kappa)):\n";
  if (request.overrides.empty()) {
    h += fmt::format("//   model (double precision vs reference): {}\n", fmt_error(b.model));
    h += fmt::format("//   C++ float runtime vs reference:        {}\n", fmt_error(b.float_cpp));
  } else {
    h += fmt::format(
        "//   model (as recorded by the constant set's fit, over its own kappa range): {}\n",
        fmt_error(b.model));
  }
  if (has_erf)
    h += fmt::format(
        "//   elementary, float: erf abs {:.2g}, erf rel (|x| <= 1) {:.2g}, erfc abs {:.2g}, (e^x "
        "- 1)/x rel {:.2g}\n",
        b.elementary.erf_abs, b.elementary.erf_rel_small, b.elementary.erfc_abs,
        b.elementary.expm1_over_x_rel);
  else
    h += fmt::format("//   elementary, float: (e^x - 1)/x rel {:.2g}\n",
                     b.elementary.expm1_over_x_rel);
  if (b.vulkan)
    h += fmt::format("//   measured on Vulkan ({}): {}\n", io::comment_text(b.vulkan_device),
                     fmt_error(b.vulkan));
  // The registry card holds for the compiled-in constants only.
  if (card.valid.max_peak_rel > 0 && request.overrides.empty())
    h += fmt::format(
        "// Valid kappa range (registry card of the runtime, `sglab range`): max |E~ - E|/E(1, "
        "kappa) <= {:.2g} for kappa in {}; outside it that bound does not hold.\n",
        card.valid.max_peak_rel, validate::kappa_range_text(card.valid));
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
  body += fmt::format(
      "// {}: the per-light state of {}, {} floats. std430 layout (floats only): field k\n"
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
  body += fmt::format(
      "// Per light (once per frame): everything of {} that depends on kappa alone.\n", form.id);
  body += fmt::format("{}{} sglab_light_{}(float kappa) {{\n  {} light;\n",
                      c.lang == Language::cpp ? "inline " : "", light, c.id, light);
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
  return "SglabLight_" +
         entry_point_name(method).substr(std::string_view("sglab_irradiance_").size());
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
    throw std::invalid_argument(fmt::format("unknown or non-exportable method '{}'; exportable: {}",
                                            request.method, known));
  }
  const SplitForm* form = request.split ? find_split_form(m->id) : nullptr;
  if (request.split && !form)
    throw std::invalid_argument(
        fmt::format("method '{}' has no per-light split (--split); methods with one: {}",
                    request.method, fmt::format("{}", fmt::join(split_methods(), ", "))));
  if (request.split && request.precision == Precision::float16)
    throw std::invalid_argument(
        "--split with --precision half: the per-light split export is float only (its light struct "
        "is std430 floats filled by the float runtime); use one or the other");
  if (request.precision == Precision::float16 && request.lang == Language::cpp)
    throw std::invalid_argument(
        "--precision half: the C++ export is float only (g++'s _Float16 may keep float "
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

  Ctx c{request.lang,
        entry_point_name(request.method).substr(std::string_view("sglab_irradiance_").size()),
        {}};
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
      body += "using sglab_export_{ID}::" + result.light_function +
              ";\nusing sglab_export_{ID}::" + result.light_struct + ";\n";
      body = replace_all(body, "sglab_export_{ID}", "sglab_export_{ID}_split");
    }
  }
  // {ID} only occurs in the C++ namespace lines.
  result.source = replace_all(body, "{ID}", c.id);
  return result;
}

}  // namespace sglab::shader
