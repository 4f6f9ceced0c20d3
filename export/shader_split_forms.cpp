#include "export/shader_methods.hpp"

#include <fmt/format.h>

#include "export/shader_elementary.hpp"

namespace sglab::shader::detail {

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
                           names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"),
                           poly("c"), poly("v")),
               c);
}
std::string pixel_sglab_fast(const Ctx& c, const Slots&) {
  return subst(
      R"(  float s = light.a + light.b * cosine + light.c_ramp * {P}ramp(light.v * cosine + 0.5f);
  return 0.5f * (s + abs(s));
)",
      c);
}

std::vector<LightField> fields_sglab_lite(const Slots&) {
  return {{"a", "A(kappa), E(1, kappa) folded in"},
          {"b", "B(kappa), E(1, kappa) folded in"},
          {"c_ramp", "C(kappa), E(1, kappa) folded in"},
          {"v", "V(kappa)"}};
}
std::string light_sglab_lite(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return subst(fmt::format(R"(  float k = min(kappa, {});
  float one_k = 1.0f + k;
  float inv = 1.0f / (({}) * one_k);
  light.a = {} * inv;
  light.b = {} * inv;
  light.c_ramp = {} * inv;
  light.v = {} * inv * one_k;
)",
                           names(c, "model", set, "kappa_max")[0],
                           monic_horner_text("k", names(c, "model", set, "q")), poly("a"),
                           poly("b"), poly("c"), poly("v")),
               c);
}

std::vector<LightField> fields_sglab_min(const Slots&) {
  return {{"a", "A(y) y"}, {"b", "B(y) y"}, {"g", "G(y) y"}};
}
std::string light_sglab_min(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("y", names(c, "model", set, m)); };
  return subst(fmt::format(R"(  float y = 1.0f / (kappa + {0});
  light.a = {1} * y;
  light.b = {2} * y;
  light.g = {3} * y;
)",
                           names(c, "model", set, "s")[0], poly("a"), poly("b"), poly("g")),
               c);
}
std::string pixel_sglab_min(const Ctx& c, const Slots&) {
  return subst(R"(  float e = light.a + cosine * (light.b + cosine * light.g);
  return 0.5f * (e + abs(e));
)",
               c);
}

std::vector<LightField> fields_sglab_mid(const Slots&) {
  return {{"a", "A(kappa) E(1, kappa)"},
          {"b", "B(kappa) E(1, kappa)"},
          {"d", "D(kappa) E(1, kappa)"},
          {"s", "S(kappa) = Ps/Q - ln(1 + kappa)"},
          {"v", "V(kappa) = kappa Pv/Q"}};
}
std::string light_sglab_mid(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return subst(fmt::format(R"(  float k = min(kappa, {0});
  float inv_q = 1.0f / ({1} + k * k * k * k);
  float e1 = 6.28318548f * {{P}}upper_over_two_pi(kappa);
  light.a = {2} * inv_q * e1;
  light.b = {3} * inv_q * e1;
  light.d = {4} * inv_q * e1;
  light.s = {5} * inv_q - log(1.0f + kappa);
  light.v = k * {6} * inv_q * max(1.0f, kappa / {0});
)",
                           names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"),
                           poly("d"), poly("s"), poly("v")),
               c);
}
std::string pixel_sglab_mid(const Ctx& c, const Slots&) {
  return subst(
      R"(  float c2 = cosine * cosine;
  float x = clamp(light.s - light.v * c2, -80.0f, 80.0f);
  float s = light.a + light.b * (cosine + sqrt(c2 + exp(x))) + light.d * c2;
  return 0.5f * (s + abs(s));
)",
      c);
}

std::vector<LightField> fields_sglab_tab(const Slots&) {
  return {{"a", "A(kappa) E(1, kappa)"}, {"b", "B(kappa) E(1, kappa)"},
          {"d", "D(kappa) E(1, kappa)"}, {"g", "G(kappa) E(1, kappa)"},
          {"h", "H(kappa) E(1, kappa)"}, {"s", "S(kappa) = s - ln(1 + kappa)"},
          {"v", "V(kappa) = kappa v"}};
}
std::string light_sglab_tab(const Ctx& c, const Slots& slots) {
  return sglab_tab_values_text(c, slots, "float ") +
         subst(R"(  float e1 = 6.28318548f * {P}upper_over_two_pi(kappa);
  light.a = A * e1;
  light.b = B * e1;
  light.d = D * e1;
  light.g = G * e1;
  light.h = H * e1;
  light.s = S;
  light.v = V;
)",
               c);
}
std::string pixel_sglab_tab(const Ctx& c, const Slots&) {
  return subst(
      R"(  float c2 = cosine * cosine;
  float e = exp(clamp(light.s - light.v * c2, -80.0f, 80.0f));
  float f = light.a + light.b * (cosine + sqrt(c2 + e)) + light.d * c2 + (light.g + light.h * c2) * e;
  return 0.5f * (f + abs(f));
)",
      c);
}

std::vector<LightField> fields_sglab_acc(const Slots& slots) {
  std::vector<LightField> f = {{"t", "steepness t(kappa)"},
                               {"half_erfc_t", "erfc(t)/2"},
                               {"tail_scale", "1/(2 sqrt(pi) (t + 2^-126))"},
                               {"t2", "t^2"},
                               {"lower", "E(-1, kappa)/2 pi"},
                               {"upper", "E(+1, kappa)/2 pi"}};
  const std::size_t n = sglab_acc_shape(slot(slots, "model")).n;
  for (std::size_t j = 0; j < n; ++j)
    f.push_back({fmt::format("b{}", j), fmt::format("correction coefficient b_{}(kappa)", j)});
  return f;
}
// sglab_acc.hpp sglab_acc_light: t and the poles as tokuyoshi2024's setup, the tail scale
// 1/(2 sqrt(pi) (t + FLT_MIN)) and b_j = u (1 - u)^3 P_j(u), u = t/(t + scale) (sglab_acc_fade).
std::string light_sglab_acc(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto [n, d, m] = sglab_acc_shape(set);
  const auto num = names(c, "model", set, "num"), scale = names(c, "model", set, "scale");
  std::string products;
  for (std::size_t j = 0; j < n; ++j) {
    const std::vector<std::string> poly(num.begin() + j * (d + 1), num.begin() + (j + 1) * (d + 1));
    products += fmt::format("  light.b{} = fade * ({});\n", j, horner_text("u", poly));
  }
  return subst(fmt::format(R"(  light.t = {{P}}steepness(kappa);
  light.half_erfc_t = 0.5f * {{P}}erfc_pos(light.t);
  light.tail_scale = 0.5f * 0.564189584f / (light.t + 1.17549435e-38f);
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
// 1/(2 sqrt(pi) t) and t^2, plus (1 - c^2) e^(-z^2) sum_j b_j z^2j (0 where e^(-z^2) underflowed),
// the tail written as e^(-z^2) (1 - c^2) t^2 E(x)/(2 sqrt(pi) t), x = -t^2 (1 - c^2), E(x) =
// expm1(x)/x, so that the correction shares its factor (as the unsplit helper_sglab_acc_lerp).
std::string pixel_sglab_acc(const Ctx& c, const Slots& slots) {
  const std::size_t n = sglab_acc_shape(slot(slots, "model")).n;
  std::vector<std::string> b;
  for (std::size_t j = 0; j < n; ++j) b.push_back(fmt::format("light.b{}", j));
  return subst(fmt::format(R"(  float c = clamp(cosine, -1.0f, 1.0f);
  float z = light.t * c;
  float z2 = z * z;
  float one_minus_c2 = 1.0f - c * c;
  float g = exp(-z2);
  float x = -(light.t2 * one_minus_c2);
  float h = light.t2 * light.tail_scale * {{P}}expm1_over_x(x);
  if (g > 0.0f) h += {};
  float f = clamp(0.5f * c * {{P}}erfc(-z) + light.half_erfc_t + g * one_minus_c2 * h, 0.0f, 1.0f);
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
  return {{"kappa",
           "the sharpness kappa (the product with the clamped-cosine SG depends on the cosine)"},
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
std::string light_punctual(const Ctx&, const Slots&) {
  return "  light.s = 6.28318548f / kappa;\n";
}
std::string pixel_punctual(const Ctx&, const Slots&) {
  return "  return clamp(cosine, 0.0f, 1.0f) * light.s;\n";
}

std::vector<LightField> fields_hill(const Slots&) {
  return {
      {"scale", "1 + 2 e^-2kappa - 1/kappa"},
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
std::string light_hill_approx(const Ctx& c, const Slots& s) {
  return light_hill(c, s, "6.28318548f / kappa");
}
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
    const SplitForm t2024{
        "tokuyoshi2024",
        "sglab::Tokuyoshi2024Light<float> (sglab/irradiance.hpp tokuyoshi2024_light)",
        fields_tokuyoshi2024,
        helpers2024(),
        light_tokuyoshi2024,
        pixel_tokuyoshi2024};
    const SplitForm t2022{"tokuyoshi2022",      "",
                          fields_tokuyoshi2022, helpers2022(),
                          light_tokuyoshi2022,  pixel_tokuyoshi2022};
    const SplitForm acc{
        "sglab_acc",      "sglab::SglabAccLight<float, N> (sglab/sglab_acc.hpp sglab_acc_light)",
        fields_sglab_acc, {helper_expm1, helper_erf, helper_sglab_acc_steepness, helper_poles2024},
        light_sglab_acc,  pixel_sglab_acc};
    const SplitForm vsgl{"vsgl2015", "", fields_vsgl2015, {}, light_vsgl2015, pixel_vsgl2015};
    std::vector<SplitForm> v = {
        {"punctual", "", fields_punctual, {}, light_punctual, pixel_punctual},
        {"hill", "", fields_hill, {}, light_hill_approx, pixel_hill},
        {"hill_exact", "", fields_hill, {helper_expm1}, light_hill_exact, pixel_hill},
        vsgl};
    v.push_back(vsgl), v.back().id = "vsgl2015_refit";
    for (std::string_view id : {"tokuyoshi2024", "tokuyoshi2024_refit"})
      v.push_back(t2024), v.back().id = id;
    for (std::string_view id : {"tokuyoshi2022", "tokuyoshi2022_listing5", "tokuyoshi2022_refit"})
      v.push_back(t2022), v.back().id = id;
    v.push_back({"sglab_fast",
                 "sglab::SglabFastLight<float> (sglab/sglab_fast.hpp sglab_fast_light)",
                 fields_sglab_fast,
                 {helper_sglab_fast},
                 light_sglab_fast,
                 pixel_sglab_fast});
    v.push_back({"sglab_lite",
                 "sglab::SglabLiteLight<float> (sglab/sglab_lite.hpp sglab_lite_light)",
                 fields_sglab_lite,
                 {helper_sglab_lite},
                 light_sglab_lite,
                 pixel_sglab_fast});
    v.push_back({"sglab_min",
                 "sglab::SglabMinLight<float> (sglab/sglab_min.hpp sglab_min_light)",
                 fields_sglab_min,
                 {helper_sglab_min},
                 light_sglab_min,
                 pixel_sglab_min});
    v.push_back({"sglab_mid",
                 "sglab::SglabMidLight<float> (sglab/sglab_mid.hpp sglab_mid_light)",
                 fields_sglab_mid,
                 {helper_sglab_mid},
                 light_sglab_mid,
                 pixel_sglab_mid});
    v.push_back({"sglab_tab",
                 "sglab::SglabTabLight<float> (sglab/sglab_tab.hpp sglab_tab_light)",
                 fields_sglab_tab,
                 {helper_sglab_tab},
                 light_sglab_tab,
                 pixel_sglab_tab});
    for (std::string_view id : {"sglab_acc1", "sglab_acc2", "sglab_acc3", "sglab_acc4"})
      v.push_back(acc), v.back().id = id;
    return v;
  }();
  return table;
}

const SplitForm* find_split_form(std::string_view id) {
  for (const SplitForm& s : split_forms())
    if (s.id == id) return &s;
  return nullptr;
}

}  // namespace sglab::shader::detail
