#include "export/shader_methods.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include <sglab/constants.hpp>

#include "export/shader_elementary.hpp"

namespace sglab::shader::detail {

std::string helper_product(const Ctx& c, const Slots&) {
  return subst(R"(// Product of the light SG with an SG (n, lambda) about the normal, c = v.n:
// (sharpness, log-amplitude, cosine of the product axis with n), without
// cancellation or overflow (sglab/sg.hpp sg_product_with_normal; [Tokuyoshi2022] Eq. 1-2).
{INLINE}{VEC3} {P}product_with_normal(float c, float kappa, float lambda) {
  float m = max(kappa, lambda);
  {VEC3} prod = {VEC3}(0.0f, 0.0f, 1.0f);
  if (m > 0.0f) {
    float ks = kappa / m;
    float ls = lambda / m;
    float diff = (kappa - lambda) / m;  // exact where kappa - lambda cancels (Sterbenz)
    float k3s = sqrt(diff * diff + 2.0f * ks * ls * (1.0f + c));
    float kmin = min(kappa, lambda);
    float log_amp = -2.0f * (kmin * ((1.0f - c) / (k3s + ks + ls)));
    float c3 = 1.0f;
    if (k3s > 0.0f) c3 = clamp((ks * c + ls) / k3s, -1.0f, 1.0f);
    prod = {VEC3}(m * k3s, log_amp, c3);
  }
  return prod;
}
)",
               c);
}

std::string helper_steepness2022(const Ctx& c, const Slots&) {
  return subst(
      R"(// t(kappa) = kappa sqrt((0.5 kappa + A)/((kappa + B) kappa + C)) ([Tokuyoshi2022] Eq. 6),
// in powers of 1/kappa for kappa >= 1 so that nothing overflows.
{INLINE}float {P}steepness(float kappa) {
  float t;
  if (kappa < 1.0f) {
    t = kappa * sqrt((0.5f * kappa + {P}steepness_A) / ((kappa + {P}steepness_B) * kappa + {P}steepness_C));
  } else {
    float r = 1.0f / kappa;
    t = sqrt(kappa) * sqrt((0.5f + {P}steepness_A * r) / (1.0f + ({P}steepness_B + {P}steepness_C * r) * r));
  }
  return t;
}
)",
      c);
}

std::string helper_steepness2024(const Ctx& c, const Slots&) {
  return subst(
      R"(// t(kappa) = kappa sqrt(0.5((kappa + A) kappa + B)/(((kappa + C) kappa + D) kappa + E))
// ([Tokuyoshi2024] Listing 7), in powers of 1/kappa for kappa >= 1.
{INLINE}float {P}steepness(float kappa) {
  float t;
  if (kappa < 1.0f) {
    t = kappa * sqrt(0.5f * ((kappa + {P}steepness_A) * kappa + {P}steepness_B) /
                     (((kappa + {P}steepness_C) * kappa + {P}steepness_D) * kappa + {P}steepness_E));
  } else {
    float r = 1.0f / kappa;
    t = sqrt(kappa) * sqrt(0.5f * (1.0f + ({P}steepness_A + {P}steepness_B * r) * r) /
                           (1.0f + ({P}steepness_C + ({P}steepness_D + {P}steepness_E * r) * r) * r));
  }
  return t;
}
)",
      c);
}

std::string helper_hemispherical2022(const Ctx& c, const Slots&) {
  return subst(
      R"(// H~(c, kappa) = 2 pi lerp(e^-kappa, 1, s~) (1 - e^-kappa)/kappa, s~ = 1/2 + erf(t c)/(2 erf(t))
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
  return subst(
      fmt::format(
          R"(// Exact poles (E(-1, kappa), E(+1, kappa))/2 pi (sglab/closed_forms.hpp), series at kappa < 1;
// beyond, upper = (1 - m)/kappa and lower = e (m - e)/kappa share e = e^-kappa and
// m = (1 - e)/kappa (one branch, one exp for both).
{{INLINE}}{{VEC2}} {{P}}poles_over_two_pi(float kappa) {{
  float e = exp(-kappa);
  {{VEC2}} poles = {{VEC2}}(0.0f, 0.0f);
  if (kappa < 1.0f) {{
    poles = {{VEC2}}(e * {}, {});
  }} else {{
    float m = (1.0f - e) / kappa;
    poles = {{VEC2}}(e * ((m - e) / kappa), (1.0f - m) / kappa);
  }}
  return poles;
}}
)",
          horner_text("kappa", literals(pole_series(true))),
          horner_text("kappa", literals(pole_series(false)))),
      c);
}

std::string helper_lerp2024(const Ctx& c, const Slots&) {
  return subst(
      R"(// f = 1/2 (c erfc(-t c) + erfc(t)) - e^(-t^2 c^2) expm1(t^2 (c^2 - 1))/(2 sqrt(pi) t),
// saturated ([Tokuyoshi2024] Listing 7); t = t(kappa) >= 0, so erfc(t) is erfc_pos(t).
{INLINE}float {P}lerp_factor(float cosine, float t) {
  float c = clamp(cosine, -1.0f, 1.0f);
  float tz = t * c;
  float x = t * t * (c * c - 1.0f);
  float tail = 0.0f;
  if (t > 0.0f) tail = exp(-tz * tz) * (x * {P}expm1_over_x(x)) / t;
  return clamp(0.5f * (c * {P}erfc(-tz) + {P}erfc_pos(t) - 0.564189584f * tail), 0.0f, 1.0f);
}
)",
      c);
}

std::string helper_meder2018(const Ctx& c, const Slots&) {
  return subst(
      R"(// [Meder2018] normalized logistic hemispherical integral, t(kappa) = sqrt(kappa) (a2 kappa^2 + a1 kappa)/
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

// The number of correction terms N, the degree D and the steepness order M of
// an SglabAccParams set (from its type, SglabAccParams<double, N, D, M>, checked
// against its member sizes: steep 2M + 1, num N (D + 1), scale 1).
SglabAccShape sglab_acc_shape(const ConstantSet& s) {
  std::size_t n = 0, d = 0, m = 0;
  char tail = 0;
  const bool typed = std::sscanf(s.cpp_type.c_str(), "SglabAccParams<double, %zu, %zu, %zu%c", &n,
                                 &d, &m, &tail) == 4 &&
                     tail == '>';
  if (!typed || n == 0 || m == 0 || member(s, "num").size() != n * (d + 1) ||
      member(s, "steep").size() != 2 * m + 1 || member(s, "scale").size() != 1)
    throw std::invalid_argument(
        fmt::format("constant set {}: member sizes do not form SglabAccParams", s.cpp_name));
  return {n, d, m};
}

// t(kappa) = kappa sqrt(0.5 P/Q) of order M (sglab_acc.hpp, steepness_rational in
// hemispherical.hpp): monic Horner in kappa below 1, in powers of 1/kappa from 1 on.
std::string helper_sglab_acc_steepness(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const std::size_t m = sglab_acc_shape(set).m;
  const auto s = names(c, "model", set, "steep");
  // Below 1: P = (..(kappa + s0) kappa + ..) + s[M-1], Q likewise from s[M].
  const auto monic = [&](std::size_t first, std::size_t count) {
    std::string t = "kappa";
    for (std::size_t i = 0; i < count; ++i)
      t = i + 1 < count ? fmt::format("({} + {}) * kappa", t, s[first + i])
                        : fmt::format("{} + {}", t, s[first + i]);
    return t;
  };
  // From 1 on: P/kappa^M = 1 + (s0 + (s1 + .. + s[M-1] r) r) r, Q/kappa^(M+1) likewise.
  const auto reciprocal = [&](std::size_t first, std::size_t count) {
    std::string t = s[first + count - 1];
    for (std::size_t i = count - 1; i-- > 0;)
      t = i + 2 == count ? fmt::format("{} + {} * r", s[first + i], t)
                         : fmt::format("{} + ({}) * r", s[first + i], t);
    return count == 1 ? fmt::format("1.0f + {} * r", t) : fmt::format("1.0f + ({}) * r", t);
  };
  const std::string form =
      m == 2 ? "kappa sqrt(0.5((kappa + s0) kappa + s1)/(((kappa + s2) kappa + s3) kappa + s4))\n"
               "// ([Tokuyoshi2024] Listing 7 form, sglab's coefficients)"
             : fmt::format(
                   "kappa sqrt(0.5 P/Q), P monic of degree {}, Q of degree {}\n"
                   "// (the [Tokuyoshi2024] Listing 7 form of a higher order, sglab's "
                   "coefficients)",
                   m, m + 1);
  return subst(
      fmt::format(R"(// t(kappa) = {}, in powers of 1/kappa for kappa >= 1.
{{INLINE}}float {{P}}steepness(float kappa) {{
  float t;
  if (kappa < 1.0f) {{
    t = kappa * sqrt(0.5f * ({}) / ({}));
  }} else {{
    float r = 1.0f / kappa;
    t = sqrt(kappa) * sqrt(0.5f * ({}) / ({}));
  }}
  return t;
}}
)",
                  form, monic(0, m), monic(m, m + 1), reciprocal(0, m), reciprocal(m, m + 1)),
      c);
}

// sglab_acc<N>: b_j = u (1 - u)^3 P_j(u), u = t/(t + scale) (sglab_acc.hpp
// sglab_acc_fade), and sum_j b_j z2^j.
std::string helper_sglab_acc_correction(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto [n, d, m] = sglab_acc_shape(set);
  const auto num = names(c, "model", set, "num"), scale = names(c, "model", set, "scale");
  std::string products;
  std::vector<std::string> b;
  for (std::size_t j = 0; j < n; ++j) {
    const std::vector<std::string> poly(num.begin() + j * (d + 1), num.begin() + (j + 1) * (d + 1));
    products += fmt::format("  float p{} = {};\n", j, horner_text("u", poly));
    b.push_back(fmt::format("p{}", j));
  }
  const std::string text = fmt::format(
      R"(// b_j = u (1 - u)^3 P_j(u), u = t/(t + s), P_j of degree {}: the correction fades for
// small and for large kappa; and the correction polynomial sum_j b_j z2^j (sglab/sglab_acc.hpp),
// with the common factor u (1 - u)^3 applied once.
{{INLINE}}float {{P}}correction(float t, float z2) {{
  float w = 1.0f / (t + {});
  float u = t * w;
  float v = {} * w;
  float fade = u * (v * v) * v;
{}  return fade * ({});
}}
)",
      d, scale[0], scale[0], products, horner_text("z2", b));
  return subst(text, c);
}

std::string helper_sglab_acc_lerp(const Ctx& c, const Slots&) {
  return subst(
      R"(// f = f2024 + (1 - c^2) e^(-z^2) sum_j b_j z^2j, z = t c, saturated: the [Tokuyoshi2024]
// Listing 7 factor f2024 = 1/2 (c erfc(-z) + erfc(t)) - e^(-z^2) expm1(t^2 (c^2 - 1))/(2 sqrt(pi) t)
// with sglab's fitted even correction (sglab/sglab_acc.hpp). With x = -t^2 (1 - c^2) the tail is
// -e^(-z^2) x E(x)/(2 sqrt(pi) t) = e^(-z^2) (1 - c^2) t E(x)/(2 sqrt(pi)), E(x) = expm1(x)/x, so
// f = 1/2 (c erfc(-z) + erfc(t)) + e^(-z^2) (1 - c^2) (t E(x)/(2 sqrt(pi)) + sum_j b_j z^2j): no
// division by t, and the correction shares the tail's factor. Where e^(-z^2) has underflowed the
// correction is left out (its polynomial would overflow first for huge kappa). t = t(kappa) >= 0,
// so erfc(t) is erfc_pos(t).
{INLINE}float {P}lerp_factor(float cosine, float t) {
  float c = clamp(cosine, -1.0f, 1.0f);
  float tz = t * c;
  float z2 = tz * tz;
  float one_minus_c2 = 1.0f - c * c;
  float x = -(t * t) * one_minus_c2;
  float g = exp(-z2);
  float h = 0.282094792f * t * {P}expm1_over_x(x);
  if (g > 0.0f) h += {P}correction(t, z2);
  return clamp(0.5f * (c * {P}erfc(-tz) + {P}erfc_pos(t)) + g * one_minus_c2 * h, 0.0f, 1.0f);
}
)",
      c);
}

// E(1, kappa)/2 pi of sglab_fast and sglab_mid (sglab/sglab_fast.hpp upper_over_two_pi_fast).
std::string upper_over_two_pi_text(const Ctx& c) {
  std::vector<double> series;  // sum_{m<6} (-kappa)^m/(m + 2)!, the float series of sglab_fast.hpp
  {
    const auto all = pole_series(false);
    series.assign(all.begin(), all.begin() + 6);
  }
  return subst(
      fmt::format(
          R"(// E(1, kappa)/2 pi = (kappa - 1 + e^-kappa)/kappa^2: Taylor series below kappa = 1/4,
// (1 - (1 - e^-kappa)/kappa)/kappa from there on, e^-kappa's argument stopped at 80
// (sglab/sglab_fast.hpp upper_over_two_pi_fast).
{{INLINE}}float {{P}}upper_over_two_pi(float kappa) {{
  float upper;
  if (kappa < 0.25f) {{
    upper = {0};
  }} else {{
    float r = 1.0f / kappa;
    upper = (1.0f - (1.0f - exp(-min(kappa, 80.0f))) * r) * r;
  }}
  return upper;
}}
)",
          horner_text("kappa", literals(series))),
      c);
}

// The ramp's v^3 (2 - v), v = w/2, is written v^3 * 0.5 (4 - w): the same value
// (halving is exact), but spirv-opt (HLSL legalization, -O) would fuse 2 - w/2
// into an fma that ACO cannot fold the 1/2 into, 8 % more per light in the loop.
std::string ramp_text(const Ctx& c) {
  return subst(
      R"(// The C2 ramp rho(u) = 0 | u^3 (2 - u) | 2u - 1 on u <= 0 | (0, 1) | u >= 1, branch-free.
{INLINE}float {P}ramp(float u) {
  float over = abs(u - 1.0f);
  float w = abs(u) - over + 1.0f;
  float v = 0.5f * w;
  return v * v * v * (0.5f * (4.0f - w)) + (u - 1.0f + over);
}
)",
      c);
}

std::string helper_sglab_fast(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return upper_over_two_pi_text(c) + ramp_text(c) +
         subst(
             fmt::format(
                 R"(// sglab_fast: E = E(1, kappa) max(0, A + B c + C rho(V c + 1/2)), A, B, C, V = P(k)/Q(k),
// k = min(kappa, kappa_max), Q = k^4 + q3 k^3 + ... + q0 (sglab/sglab_fast.hpp).
{{INLINE}}float {{P}}fast(float cosine, float kappa) {{
  float k = min(kappa, {0});
  float inv_q = 1.0f / ({1} + k * k * k * k);
  float scale = 6.28318548f * {{P}}upper_over_two_pi(kappa) * inv_q;
  float s = ({2} + {3} * cosine + {4} * {{P}}ramp({5} * inv_q * cosine + 0.5f)) * scale;
  return 0.5f * (s + abs(s));
}}
)",
                 names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"), poly("c"),
                 poly("v")),
             c);
}

// The monic Q(k) = k^n + q[n-1] k^(n-1) + ... + q[0] as ((k + q[n-1]) k + ...) k + q[0].
std::string monic_horner_text(std::string_view x, const std::vector<std::string>& q) {
  std::string t = fmt::format("{} + {}", x, q.back());
  for (std::size_t i = q.size() - 1; i-- > 0;) t = fmt::format("({}) * {} + {}", t, x, q[i]);
  return t;
}

std::string helper_sglab_lite(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return ramp_text(c) +
         subst(
             fmt::format(
                 R"(// sglab_lite: E = max(0, A + B c + C rho(V c + 1/2)), A, B, C = P(k)/((1 + k) Q(k)),
// V = Pv(k)/Q(k) (E(1, kappa) folded into A, B, C), k = min(kappa, kappa_max),
// Q = (((k + q3) k + q2) k + q1) k + q0 (sglab/sglab_lite.hpp).
{{INLINE}}float {{P}}lite(float cosine, float kappa) {{
  float k = min(kappa, {0});
  float one_k = 1.0f + k;
  float inv = 1.0f / (({1}) * one_k);
  float s = ({2} + {3} * cosine + {4} * {{P}}ramp({5} * inv * one_k * cosine + 0.5f)) * inv;
  return 0.5f * (s + abs(s));
}}
)",
                 names(c, "model", set, "kappa_max")[0],
                 monic_horner_text("k", names(c, "model", set, "q")), poly("a"), poly("b"),
                 poly("c"), poly("v")),
             c);
}

std::string helper_sglab_min(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("y", names(c, "model", set, m)); };
  return subst(
      fmt::format(
          R"(// sglab_min: E = y max(0, A(y) + B(y) c + G(y) c^2), y = 1/(kappa + s), A quadratic,
// B and G linear in y (sglab/sglab_min.hpp).
{{INLINE}}float {{P}}min(float cosine, float kappa) {{
  float y = 1.0f / (kappa + {0});
  float e = ({1} + cosine * ({2} + cosine * {3})) * y;
  return 0.5f * (e + abs(e));
}}
)",
          names(c, "model", set, "s")[0], poly("a"), poly("b"), poly("g")),
      c);
}

std::string helper_sglab_mid(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  return upper_over_two_pi_text(c) +
         subst(
             fmt::format(
                 R"(// sglab_mid: E = E(1, kappa) max(0, A + B (c + sqrt(c^2 + exp(S - V c^2))) + D c^2),
// the exponent clamped to [-80, 80]; A, B, D = P(k)/Q(k), S = Ps(k)/Q(k) - ln(1 + kappa),
// V = kappa Pv(k)/Q(k) = k Pv(k)/Q(k) max(1, kappa/kappa_max), k = min(kappa, kappa_max),
// Q = k^4 + q3 k^3 + ... + q0 (sglab/sglab_mid.hpp).
{{INLINE}}float {{P}}mid(float cosine, float kappa) {{
  float k = min(kappa, {0});
  float inv_q = 1.0f / ({1} + k * k * k * k);
  float scale = 6.28318548f * {{P}}upper_over_two_pi(kappa) * inv_q;
  float s_k = {2} * inv_q - log(1.0f + kappa);
  float v_k = k * {3} * inv_q * max(1.0f, kappa / {0});
  float c2 = cosine * cosine;
  float x = clamp(s_k - v_k * c2, -80.0f, 80.0f);
  float s = ({4} + {5} * (cosine + sqrt(c2 + exp(x))) + {6} * c2) * scale;
  return 0.5f * (s + abs(s));
}}
)",
                 names(c, "model", set, "kappa_max")[0], poly("q"), poly("s"), poly("v"), poly("a"),
                 poly("b"), poly("d")),
             c);
}

// sglab_tab's κ-only part: the cell of u = √κ/(1 + √κ) and its seven cubics (the table
// {P}model_coef, a row of four coefficients per cubic, 7 rows a cell), as sglab/sglab_tab.hpp
// sglab_tab_light, E(1, κ) apart: `lhs`A = …; … `lhs`V = …; in the caller's scope.
std::string sglab_tab_values_text(const Ctx& c, const Slots& slots, const std::string& lhs) {
  const ConstantSet& set = slot(slots, "model");
  const std::string table = names(c, "model", set, "coef")[0];
  const std::size_t cells = member(set, "coef").size() / 28;
  // Row 7j + m of the table holds the cubic of value m on cell j, lowest order first.
  const auto cubic = [&](int m) {
    return fmt::format(
        "{0}[o + {1}].x + t * ({0}[o + {1}].y + t * ({0}[o + {1}].z + t * "
        "{0}[o + {1}].w))",
        table, m);
  };
  return subst(fmt::format(R"(  float r = sqrt(kappa);
  float x = r / (1.0f + r) * {0}.0f;
  float j = min(floor(x), {1}.0f);
  float t = 2.0f * (x - j) - 1.0f;
  int o = int(j) * 7;
  {2}A = {3};
  {2}B = {4};
  {2}D = {5};
  {2}G = {6};
  {2}H = {7};
  {2}S = {8} - log(1.0f + kappa);
  {2}V = kappa * ({9});
)",
                           cells, cells - 1, lhs, cubic(0), cubic(1), cubic(2), cubic(3), cubic(4),
                           cubic(5), cubic(6)),
               c);
}

std::string helper_sglab_tab(const Ctx& c, const Slots& slots) {
  return upper_over_two_pi_text(c) +
         subst(
             R"(// sglab_tab: E = E(1, kappa) max(0, A + B (c + sqrt(c^2 + g)) + D c^2 + (G + H c^2) g),
// g = exp(clamp(S - V c^2, -80, 80)), S = s - ln(1 + kappa), V = kappa v; A, B, D, G, H, s, v
// cubics in t on the cell j of u = sqrt(kappa)/(1 + sqrt(kappa)) (equal cells of [0, 1],
// t = 2(u cells - j) - 1), 28 coefficients a cell in the table (sglab/sglab_tab.hpp).
{INLINE}float {P}tab(float cosine, float kappa) {
)",
             c) +
         sglab_tab_values_text(c, slots, "float ") +
         subst(R"(  float c2 = cosine * cosine;
  float g = exp(clamp(S - V * c2, -80.0f, 80.0f));
  float e = (A + B * (cosine + sqrt(c2 + g)) + D * c2 + (G + H * c2) * g) *
            (6.28318548f * {P}upper_over_two_pi(kappa));
  return 0.5f * (e + abs(e));
}
)",
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
                           h, abs16, names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"),
                           poly("b"), poly("c"), poly("v")),
               c);
}

// The half form of sglab_mid: as sglab_fast's, its κ-only part (E(1, κ) and the
// rational A, B, D, S, V, whose κ^4 overflows half above κ = 16) in float, the
// per-pixel shape in half: the runtime's per-light split (sglab/sglab_mid.hpp
// sglab_mid_light, sglab_mid_eval) with the light's five numbers rounded to half
// (S ∈ [−9.7, 2.6] and V ≤ 5.9e3 over κ ∈ [1e−3, 1e4] for the shipped set, so
// e^{S − V c²} stays within half). Unlike the float form, S and V take
// k = min(κ, kappa_max) throughout: κ·Pv/Q itself would leave half's range
// (65504) above κ ≈ 1e5, so beyond kappa_max the half form keeps the shape of
// kappa_max (its claims are on κ ∈ [1e−2, 1e3], tests/tolerances.hpp).
std::string helper_sglab_mid_half(const Ctx& c, const Slots& slots) {
  const ConstantSet& set = slot(slots, "model");
  const auto poly = [&](std::string_view m) { return horner_text("k", names(c, "model", set, m)); };
  const bool glsl = c.lang == Language::glsl;
  const std::string h(half_type(c.lang));
  const std::string fn = glsl ? "" : c.prefix + "h_";  // the HLSL prelude's half intrinsics
  return subst(
      fmt::format(
          R"(// sglab_mid in half: a, b, d = (A, B, D) E(1, kappa), s = S, v = V in float (kappa alone),
// rounded to half; max(0, a + b (c + sqrt(c^2 + exp(s - v c^2))) + d c^2) in half.
{0} {{P}}mid_half({0} cosine, float kappa) {{
  float k = min(kappa, {2});
  float inv_q = 1.0f / ({3} + k * k * k * k);
  float scale = 6.28318548f * {{P}}upper_over_two_pi(kappa) * inv_q;
  {0} a = {0}({4} * scale);
  {0} b = {0}({5} * scale);
  {0} d = {0}({6} * scale);
  {0} s_k = {0}({7} * inv_q - log(1.0f + k));
  {0} v_k = {0}(k * {8} * inv_q);
  {0} c2 = cosine * cosine;
  {0} x = {1}clamp(s_k - v_k * c2, {0}(-80.0), {0}(80.0));
  {0} s = a + b * (cosine + {1}sqrt(c2 + {1}exp(x))) + d * c2;
  return {0}(0.5) * (s + {1}abs(s));
}}
)",
          h, fn, names(c, "model", set, "kappa_max")[0], poly("q"), poly("a"), poly("b"), poly("d"),
          poly("s"), poly("v")),
      c);
}

const std::vector<HalfForm>& half_forms() {
  static const std::vector<HalfForm> table = {
      {"sglab_fast",
       {helper_sglab_fast, helper_sglab_fast_half},
       "  return {P}fast_half(cosine, float(kappa));\n"},
      {"sglab_mid",
       {helper_sglab_mid, helper_sglab_mid_half},
       "  return {P}mid_half(cosine, float(kappa));\n"},
  };
  return table;
}
const HalfForm* find_half_form(std::string_view id) {
  for (const HalfForm& f : half_forms())
    if (f.id == id) return &f;
  return nullptr;
}

constexpr std::string_view kBodyTokuyoshi2022 = R"(  float lambda = {P}clamped_cosine_lambda;
  float alpha = {P}clamped_cosine_alpha;
  {VEC3} prod = {P}product_with_normal(cosine, kappa, lambda);
  float p = {P}hemispherical(prod.z, prod.x) * exp(lambda + prod.y);
  float q = {P}hemispherical(cosine, kappa);
  return max(alpha * p - alpha * q, 0.0f);
)";
constexpr std::string_view kBodyTokuyoshi2024 =
    R"(  float f = {P}lerp_factor(cosine, {P}steepness(kappa));
  {VEC2} poles = {P}poles_over_two_pi(kappa);  // (lower, upper)
  return 6.28318548f * (poles.x + f * (poles.y - poles.x));
)";
// [Wang2009] a e^{d - kappa - lambda} 2 pi (1 - e^{-2d})/d, d = |kappa v + lambda n|, through the
// stable product (sglab/sg.hpp sg_inner_product): d - kappa - lambda without cancellation and
// S(d) = 4 pi (e^{-2d} - 1)/(-2d) with its d -> 0 limit.
constexpr std::string_view kBodyWang2009 =
    R"(  {VEC3} prod = {P}product_with_normal(cosine, kappa, {P}cosine_lobe_lambda);
  float s = 12.566371f * {P}expm1_over_x(-2.0f * prod.x);
  return max({P}cosine_lobe_amplitude * (exp(prod.y) * s), 0.0f);
)";
const std::vector<Helper> kHelpersWang2009 = {helper_expm1, helper_product};
constexpr std::string_view kBodyVsgl2015 = R"(  float sum = kappa + {P}diffuse_lobe_lambda_d;
  float lam = sum > 0.0f ? kappa * {P}diffuse_lobe_lambda_d / sum : 0.0f;
  return 6.28318548f * exp(lam * (cosine - 1.0f)) / sum;
)";

const std::vector<Helper>& helpers2022() {
  static const std::vector<Helper> list = {helper_expm1, helper_erf, helper_steepness2022,
                                           helper_product, helper_hemispherical2022};
  return list;
}
const std::vector<Helper>& helpers2024() {
  static const std::vector<Helper> list = {helper_expm1, helper_erf, helper_steepness2024,
                                           helper_poles2024, helper_lerp2024};
  return list;
}

constexpr std::string_view kBodySglabAcc =
    R"(  float f = {P}lerp_factor(cosine, {P}steepness(kappa));
  {VEC2} poles = {P}poles_over_two_pi(kappa);  // (lower, upper)
  return 6.28318548f * (poles.x + f * (poles.y - poles.x));
)";
const std::vector<Helper> kHelpersSglabAcc = {helper_expm1,
                                              helper_erf,
                                              helper_sglab_acc_steepness,
                                              helper_poles2024,
                                              helper_sglab_acc_correction,
                                              helper_sglab_acc_lerp};

// THE table: one entry per exportable method. To add a method (e.g. one of
// sglab's own models): append {id (its registry card, include/sglab/registry.hpp, says what
// it is and where it comes from), its constant slots as
// Slots{{"role", named("NAME", the set NAME of constants.hpp)}}, how it uses erf, the
// helpers it calls, and the body in the shading-language subset used here
// (float, exp/exp2/sqrt/abs/min/max/clamp/dot, ?: with cheap arms and if/else
// where an arm costs (glslang's HLSL front end evaluates both arms of ?:),
// {VEC3}, {VEC2}; constants as {P}<role>_<member>)}. A constant set of a parameter type not yet
// listed above also needs a named() overload. tests/test_shader_export.cpp then compiles it to
// SPIR-V (GLSL and HLSL), compiles the C++ form and runs the shader forms on Vulkan against the
// runtime.
const std::vector<ShaderMethod>& shader_methods() {
  static const std::vector<ShaderMethod> table = {
      {"wang2009",
       [] {
         return Slots{
             {"cosine_lobe", named("cosine_lobe_published", constants::cosine_lobe_published)}};
       },
       ErfUse::none, kHelpersWang2009, kBodyWang2009},
      {"punctual",
       [] { return Slots{}; },
       ErfUse::none,
       {},
       "  return clamp(cosine, 0.0f, 1.0f) * (6.28318548f / kappa);\n"},
      {"hill",
       [] {
         return Slots{{"hill", named("hill_published", constants::hill_published)}};
       },
       ErfUse::none,
       {helper_hill},
       "  return {P}hill_normalized(cosine, kappa) * (6.28318548f / kappa);\n"},
      {"hill_exact",
       [] {
         return Slots{{"hill", named("hill_published", constants::hill_published)}};
       },
       ErfUse::none,
       {helper_expm1, helper_hill},
       "  return {P}hill_normalized(cosine, kappa) * (12.566371f * {P}expm1_over_x(-2.0f * "
       "kappa));\n"},
      {"vsgl2015",
       [] {
         return Slots{
             {"diffuse_lobe", named("diffuse_lobe_published", constants::diffuse_lobe_published)}};
       },
       ErfUse::none,
       {},
       kBodyVsgl2015},
      {"meder2018",
       [] {
         return Slots{{"meder", named("meder2018_published", constants::meder2018_published)}};
       },
       ErfUse::none,
       {helper_expm1, helper_product, helper_meder2018},
       R"(  {VEC3} prod = {P}product_with_normal(cosine, kappa, {P}meder_sharpness);
  float upper = exp(prod.y) * {P}hemispherical(prod.z, prod.x);
  return {P}meder_amplitude * upper - {P}meder_offset * {P}hemispherical(cosine, kappa);
)"},
      {"tokuyoshi2022",
       [] {
         return Slots{
             {"clamped_cosine",
              named("clamped_cosine_published", constants::clamped_cosine_published)},
             {"steepness", named("steepness2022_published", constants::steepness2022_published)}};
       },
       ErfUse::tiered, helpers2022(), kBodyTokuyoshi2022},
      {"tokuyoshi2024",
       [] {
         return Slots{
             {"steepness", named("steepness2024_published", constants::steepness2024_published)}};
       },
       ErfUse::tiered, helpers2024(), kBodyTokuyoshi2024},
      {"tokuyoshi2022_listing5",
       [] {
         return Slots{
             {"clamped_cosine",
              named("clamped_cosine_published", constants::clamped_cosine_published)},
             {"steepness", named("steepness2022_published", constants::steepness2022_published)},
             {"erf", named("erf_listing5_published", constants::erf_listing5_published)}};
       },
       ErfUse::own, helpers2022(), kBodyTokuyoshi2022},
      {"tokuyoshi2022_refit",
       [] {
         return Slots{
             {"clamped_cosine", named("clamped_cosine_float", constants::clamped_cosine_float)},
             {"steepness", named("steepness2022_irradiance", constants::steepness2022_irradiance)}};
       },
       ErfUse::tiered, helpers2022(), kBodyTokuyoshi2022},
      {"tokuyoshi2024_refit",
       [] {
         return Slots{
             {"steepness", named("steepness2024_irradiance", constants::steepness2024_irradiance)}};
       },
       ErfUse::tiered, helpers2024(), kBodyTokuyoshi2024},
      {"vsgl2015_refit",
       [] {
         return Slots{{"diffuse_lobe", named("lambda_d_diffuse_lobe_irradiance",
                                             constants::lambda_d_diffuse_lobe_irradiance)}};
       },
       ErfUse::none,
       {},
       kBodyVsgl2015},
      {"wang2009_refit",
       [] {
         return Slots{{"cosine_lobe", named("lambda_d_cosine_lobe_free_amplitude",
                                            constants::lambda_d_cosine_lobe_free_amplitude)}};
       },
       ErfUse::none, kHelpersWang2009, kBodyWang2009},
      {"sglab_fast",
       [] {
         return Slots{{"model", named("sglab_fast_float", constants::sglab_fast_float)}};
       },
       ErfUse::none,
       {helper_sglab_fast},
       "  return {P}fast(cosine, kappa);\n"},
      {"sglab_lite",
       [] {
         return Slots{{"model", named("sglab_lite_float", constants::sglab_lite_float)}};
       },
       ErfUse::none,
       {helper_sglab_lite},
       "  return {P}lite(cosine, kappa);\n"},
      {"sglab_min",
       [] {
         return Slots{{"model", named("sglab_min_float", constants::sglab_min_float)}};
       },
       ErfUse::none,
       {helper_sglab_min},
       "  return {P}min(cosine, kappa);\n"},
      {"sglab_mid",
       [] {
         return Slots{{"model", named("sglab_mid_float", constants::sglab_mid_float)}};
       },
       ErfUse::none,
       {helper_sglab_mid},
       "  return {P}mid(cosine, kappa);\n"},
      {"sglab_tab",
       [] {
         return Slots{{"model", named("sglab_tab_float", constants::sglab_tab_float)}};
       },
       ErfUse::none,
       {helper_sglab_tab},
       "  return {P}tab(cosine, kappa);\n"},
      {"sglab_acc1",
       [] {
         return Slots{{"model", named("sglab_acc1", constants::sglab_acc1)}};
       },
       ErfUse::tiered, kHelpersSglabAcc, kBodySglabAcc},
      {"sglab_acc2",
       [] {
         return Slots{{"model", named("sglab_acc2", constants::sglab_acc2)}};
       },
       ErfUse::tiered, kHelpersSglabAcc, kBodySglabAcc},
      {"sglab_acc3",
       [] {
         return Slots{{"model", named("sglab_acc3", constants::sglab_acc3)}};
       },
       ErfUse::tiered, kHelpersSglabAcc, kBodySglabAcc},
      {"sglab_acc4",
       [] {
         return Slots{{"model", named("sglab_acc4", constants::sglab_acc4)}};
       },
       ErfUse::tiered, kHelpersSglabAcc, kBodySglabAcc},
  };
  return table;
}

const ShaderMethod* find_shader_method(std::string_view id) {
  for (const ShaderMethod& m : shader_methods())
    if (m.id == id) return &m;
  return nullptr;
}

}  // namespace sglab::shader::detail
