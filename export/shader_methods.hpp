// export/shader_methods.hpp — the method snippets of the shader export: the
// helpers each method's code calls (the runtime math as shading-language
// text), THE table of exportable methods (shader_methods.cpp), their own half
// forms, and the per-light split forms (shader_split_forms.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "export/shader_constants.hpp"
#include "export/shader_text.hpp"

namespace sglab::shader::detail {

using Helper = std::string (*)(const Ctx&, const Slots&);

// A method's own half form, where the translated float code would fail in
// half: its constants and helpers stay as written (float where they say
// float), and the body of the half entry point calls them. What stays in float
// is on the method's registry card (Card::half), which the header comment states.
struct HalfForm {
  std::string_view id;
  std::vector<Helper> helpers;
  std::string_view body;
};

// How a method uses erf: not at all, through the tier the exporter picks for
// the model's accuracy, or through its own constant slot "erf" (the method is
// defined by that erf, e.g. tokuyoshi2022_listing5).
enum class ErfUse { none, tiered, own };

// One exportable method: the registry id (its card says what it is and its source), its
// compiled-in constant slots (role → set), the helpers it needs in order and
// the body of the entry point {ENTRY}(float cosine, float kappa).
// Constants are named {P}<role>_<member> in the body.
struct ShaderMethod {
  std::string_view id;
  Slots (*constants)();
  ErfUse erf;
  std::vector<Helper> helpers;
  std::string_view body;
};

// THE table of exportable methods (shader_methods.cpp), in registry order.
const std::vector<ShaderMethod>& shader_methods();
const ShaderMethod* find_shader_method(std::string_view id);
const HalfForm* find_half_form(std::string_view id);

// The helpers of the 2022 and 2024 methods, in order (shared with their split forms).
const std::vector<Helper>& helpers2022();
const std::vector<Helper>& helpers2024();

// Helpers the split forms call besides those lists.
std::string helper_hill(const Ctx& c, const Slots&);
std::string helper_hemispherical2022(const Ctx& c, const Slots&);
std::string helper_poles2024(const Ctx& c, const Slots&);
std::string helper_sglab_acc_steepness(const Ctx& c, const Slots& slots);
std::string helper_sglab_fast(const Ctx& c, const Slots& slots);
std::string helper_sglab_mid(const Ctx& c, const Slots& slots);
std::string helper_sglab_tab(const Ctx& c, const Slots& slots);
// sglab_tab's A … V of κ as `lhs`A = …; (shader_methods.cpp).
std::string sglab_tab_values_text(const Ctx& c, const Slots& slots, const std::string& lhs);
std::string helper_sglab_lite(const Ctx& c, const Slots& slots);
std::string helper_sglab_min(const Ctx& c, const Slots& slots);
// The monic Q(k) of sglab_lite in Horner form, its coefficients `q` lowest order first.
std::string monic_horner_text(std::string_view x, const std::vector<std::string>& q);
// The number of correction terms N, the degree D and the steepness order M
// of an SglabAccParams set (from its type, SglabAccParams<double, N, D, M>,
// checked against its member sizes: steep 2M + 1, num N (D + 1), scale 1).
struct SglabAccShape {
  std::size_t n, d, m;
};
SglabAccShape sglab_acc_shape(const ConstantSet& s);

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

// THE table of split forms, by method id (every other method: no split).
const std::vector<SplitForm>& split_forms();
const SplitForm* find_split_form(std::string_view id);

}  // namespace sglab::shader::detail
