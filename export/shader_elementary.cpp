#include "export/shader_elementary.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>

#include <sglab/constants.hpp>

namespace sglab::shader {
namespace detail {

namespace {
const Tier kTiers[] = {
    {"as7125",
     "[AS1964] 7.1.25 form with sglab's float refit erf_as7125_float (erfc = t P(t) e^{-x^2})",
     [] { return named("erf_as7125_float", constants::erf_as7125_float); }},
    {"listing5",
     "[Tokuyoshi2022] Listing 5 form with sglab's float refit erf_listing5_float (erf = x P(x^2) "
     "for |x| <= split, erfc = 2^{-|x| Q(|x|)} beyond, no 1 - erf cancellation)",
     [] { return named("erf_listing5_float", constants::erf_listing5_float); }},
};
}  // namespace

std::span<const Tier> elementary_tiers() { return kTiers; }

ConstantSet tier_set(std::string_view id) {
  for (const Tier& t : kTiers)
    if (t.id == id) return t.set();
  throw std::invalid_argument(fmt::format("unknown elementary tier '{}'", id));
}

bool is_listing5(const ConstantSet& s) { return s.cpp_type.rfind("Listing5Params", 0) == 0; }
bool is_as(const ConstantSet& s) { return s.cpp_type.rfind("AbramowitzStegunParams", 0) == 0; }

// The C++ twin of the exported erf/erfc (same structure, same float
// arithmetic), for measuring the elementary error in-process. The set's
// members are looked up once, not at every point measured.
template <class T>
T horner_v(T x, const std::vector<double>& c) {
  T y = T(static_cast<float>(c.back()));
  for (std::size_t i = c.size() - 1; i-- > 0;) y = y * x + T(static_cast<float>(c[i]));
  return y;
}
class TwinErf {
 public:
  explicit TwinErf(const ConstantSet& s) : listing5_(is_listing5(s)) {
    if (listing5_) {
      cutoff_ = float(member(s, "cutoff")[0]);
      split_ = float(member(s, "split")[0]);
      small_ = member(s, "small");
      large_ = member(s, "large");
    } else {
      p_ = float(member(s, "p")[0]);
      a_ = member(s, "a");
    }
  }
  float erfc_pos(float a) const {
    if (listing5_) {
      if (a >= cutoff_) return 0.0f;
      if (a > split_) return std::exp2(-a * horner_v(a, large_));
      return 1.0f - a * horner_v(a * a, small_);
    }
    const float t = 1.0f / (1.0f + p_ * a);
    return t * horner_v(t, a_) * std::exp(-a * a);
  }
  float erf(float x) const {
    const float a = std::fabs(x);
    float y;
    if (listing5_) {
      y = a >= cutoff_ ? 1.0f
          : a > split_ ? 1.0f - std::exp2(-a * horner_v(a, large_))
                       : a * horner_v(a * a, small_);
    } else {
      y = 1.0f - erfc_pos(a);
    }
    return x < 0.0f ? -y : y;
  }
  float erfc(float x) const {
    const float r = erfc_pos(std::fabs(x));
    return x < 0.0f ? 2.0f - r : r;
  }

 private:
  bool listing5_;
  float cutoff_ = 0, split_ = 0, p_ = 0;
  std::vector<double> small_, large_, a_;
};

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
float twin_expm1_over_x(float x, const std::vector<double>& series) {
  if (std::fabs(x) < 1.0f) return horner_v(x, series);
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
    const TwinErf twin(*erf_set);
    const int n = 400000;
    for (int i = 0; i <= n; ++i) {
      const float x = float(-6.0 + 12.0 * i / n);
      e.erf_abs = std::max(e.erf_abs, std::fabs(double(twin.erf(x)) - std::erf(double(x))));
    }
    for (int i = 0; i <= n; ++i) {
      const float x = float(-6.0 + 16.0 * i / n);
      e.erfc_abs = std::max(e.erfc_abs, std::fabs(double(twin.erfc(x)) - std::erfc(double(x))));
    }
    for (int i = 0; i <= n; ++i) {  // log-spaced 1e-6 … 1
      const float x = float(std::pow(10.0, -6.0 + 6.0 * i / n));
      const double ref = std::erf(double(x));
      e.erf_rel_small = std::max(e.erf_rel_small, std::fabs(double(twin.erf(x)) - ref) / ref);
    }
  }
  const std::vector<double> series = expm1_over_x_series();
  for (int i = 0; i <= 200000; ++i) {
    // x = −100 … −1e−7, log-spaced in |x|, and 0.
    const float x = i == 0 ? 0.0f : -float(std::pow(10.0, -7.0 + 9.0 * i / 200000));
    const double xd = x;
    const double ref = xd == 0 ? 1.0 : std::expm1(xd) / xd;
    e.expm1_over_x_rel =
        std::max(e.expm1_over_x_rel, std::fabs(double(twin_expm1_over_x(x, series)) - ref) / ref);
  }
  return e;
}

std::string helper_expm1(const Ctx& c, const Slots&) {
  return subst(
      fmt::format(
          R"(// (e^x - 1)/x: Taylor series sum x^n/(n+1)!, n <= 10, for |x| < 1 (first omitted
// term < 2.1e-9), (e^x - 1)/x beyond (no expm1 in shading languages).
{{INLINE}}float {{P}}expm1_over_x(float x) {{
  float r;
  if (abs(x) < 1.0f)
    r = {};
  else
    r = (exp(x) - 1.0f) / x;
  return r;
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
    text = fmt::format(
        R"(// erf/erfc, [Tokuyoshi2022] Listing 5 structure: erf = x P(x^2) for |x| <= split,
// erfc(|x|) = 2^(-|x| Q(|x|)) for split < |x| < cutoff (no 1 - erf cancellation), 0 beyond.
{{INLINE}}float {{P}}erfc_pos(float a) {{
  float r;
  if (a >= {1})
    r = 0.0f;
  else if (a > {0})
    r = exp2(-a * {3});
  else
    r = 1.0f - a * {2};
  return r;
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
    text = fmt::format(
        R"(// erf/erfc, [AS1964] 7.1.25 structure: erfc(a) = t P(t) e^(-a^2), t = 1/(1 + p a), a >= 0.
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
    throw std::invalid_argument(
        fmt::format("shader export: no erf code for constant type {}", s.cpp_type));
  }
  text += R"({INLINE}float {P}erfc(float x) {
  float r = {P}erfc_pos(abs(x));
  return x < 0.0f ? 2.0f - r : r;
}
)";
  return subst(text, c);
}

}  // namespace detail

ElementaryError measure_elementary(std::string_view tier_id) {
  static std::mutex mutex;
  static std::map<std::string, ElementaryError, std::less<>> cache;
  std::lock_guard lock(mutex);
  if (auto it = cache.find(tier_id); it != cache.end()) return it->second;
  ElementaryError e;
  if (tier_id.empty()) {
    e = detail::measure(nullptr);
  } else {
    const ConstantSet s = detail::tier_set(tier_id);
    e = detail::measure(&s);
  }
  cache.emplace(std::string(tier_id), e);
  return e;
}

ElementaryTier choose_tier(std::optional<double> model_error) {
  // The erf/erfc error must stay within 1/100 of the model's error, both
  // absolutely (erfc in the 2024 interpolation factor) and relatively near 0
  // (the erf(t c)/erf(t) ratio of the 2022 method at small κ).
  for (const detail::Tier& t : detail::elementary_tiers()) {
    const ElementaryError e = measure_elementary(t.id);
    const double worst = std::max(e.max_abs(), e.erf_rel_small);
    if (model_error && worst <= *model_error / 100) return {t.id, t.description};
  }
  const detail::Tier& best = detail::elementary_tiers().back();
  return {best.id, best.description};
}

}  // namespace sglab::shader
