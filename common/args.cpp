#include "common/args.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

namespace sglab::io {

std::string quote_escaped(std::string_view text, std::size_t max_chars) {
  std::string out = "'";
  std::size_t shown = 0;
  for (const char ch : text) {
    if (shown == max_chars) {
      out += fmt::format("'... ({} bytes)", text.size());
      return out;
    }
    const auto b = static_cast<unsigned char>(ch);
    if (b >= 0x20 && b < 0x7f && b != '\\' && b != '\'')
      out += ch;
    else
      out += fmt::format("\\x{:02x}", b);
    ++shown;
  }
  return out + "'";
}

std::string point_error(double kappa, double cosine, const NumberFormat* kappa_format) {
  if (!(std::isfinite(kappa) && kappa >= 0))
    return fmt::format("kappa must be finite and >= 0, got {}", kappa);
  if (!(cosine >= -1 && cosine <= 1))
    return fmt::format("cosine must be in [-1, 1], got {}", cosine);
  if (kappa_format && exceeds_max_finite(kappa, *kappa_format))
    return fmt::format(
        "kappa {} exceeds the largest finite {} ({:g}), the precision it is evaluated in", kappa,
        kappa_format->name, kappa_format->max_finite);
  if (kappa_format && rounds_to_zero(kappa, *kappa_format))
    return fmt::format(
        "kappa {} rounds to 0 in {}, the precision it is evaluated in (smallest positive {}: {:g})",
        kappa, kappa_format->name, kappa_format->name, kappa_format->denorm_min);
  return {};
}

namespace {

// The plain decimal syntax: -?(digits(.digits?)?|.digits)([eE][+-]?digits)?
// Returns whether `text` matches and whether its significand has a nonzero digit.
bool plain_decimal(std::string_view text, bool& nonzero) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') {
      nonzero = nonzero || text[i] != '0';
      ++i;
    }
    return i - start;
  };
  nonzero = false;
  if (i < text.size() && text[i] == '-') ++i;
  std::size_t mantissa = digits();
  if (i < text.size() && text[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    bool ignored = false;
    std::swap(ignored, nonzero);  // exponent digits do not make the value nonzero
    const std::size_t exponent = digits();
    std::swap(ignored, nonzero);
    if (exponent == 0) return false;
  }
  return i == text.size();
}

// For a plain decimal with a nonzero significand: the order k with
// value = 0.d1d2… × 10^k, d1 ≠ 0 (so |value| < 1 iff k ≤ 0).
long long decimal_order(std::string_view text) {
  const auto e = text.find_first_of("eE");
  const std::string_view significand = text.substr(0, e);
  long long exponent = 0;
  if (e != std::string_view::npos) {
    std::string_view digits = text.substr(e + 1);
    const bool negative = !digits.empty() && digits[0] == '-';
    if (!digits.empty() && (digits[0] == '-' || digits[0] == '+')) digits.remove_prefix(1);
    for (char c : digits) exponent = std::min(exponent * 10 + (c - '0'), 1000000000LL);
    if (negative) exponent = -exponent;
  }
  long long order = 0;
  bool seen_point = false, seen_nonzero = false;
  for (char c : significand) {
    if (c == '.') {
      seen_point = true;
    } else if (c >= '0' && c <= '9') {
      if (!seen_nonzero && c != '0') seen_nonzero = true;
      if (seen_nonzero && !seen_point) ++order;  // integer digits from the first nonzero one
      if (!seen_nonzero && seen_point) --order;  // fraction zeros before it
    }
  }
  return order + exponent;
}

}  // namespace

std::variant<double, std::string> parse_decimal(std::string_view text) {
  bool nonzero = false;
  if (!plain_decimal(text, nonzero))
    return fmt::format("{} is not a number (plain decimal expected, e.g. 1e-3 or 250)",
                       quote_escaped(text));
  double v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && nonzero && v == 0)) {
    // from_chars says out of range for both overflow and underflow: the
    // decimal order of magnitude tells which.
    const bool tiny = decimal_order(text) <= 0;
    return fmt::format("{} is out of range ({} than any double)", quote_escaped(text),
                       tiny ? "nonzero but smaller" : "larger");
  }
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
    return fmt::format("{} is not a number", quote_escaped(text));
  return v;
}

std::variant<KappaRange, std::string> parse_kappa_range(std::string_view text,
                                                        const KappaRangeRules& rules) {
  const std::string form = rules.with_count ? "LO:HI:N, e.g. 1e-3:1e4:29" : "LO:HI, e.g. 1e-3:1e4";
  std::vector<std::string_view> fields;
  for (std::size_t start = 0;;) {
    const auto colon = text.find(':', start);
    fields.push_back(text.substr(
        start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  const std::size_t want = rules.with_count ? 3 : 2;
  if (fields.size() != want)
    return fmt::format("expected {} ({} fields separated by ':'); got {}", form, want,
                       quote_escaped(text));

  double bound[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const char* name = i == 0 ? "LO" : "HI";
    auto v = parse_decimal(fields[static_cast<std::size_t>(i)]);
    if (auto* why = std::get_if<std::string>(&v)) return fmt::format("{} {}", name, *why);
    bound[i] = std::get<double>(v);
  }
  KappaRange r{bound[0], bound[1], 0};
  const NumberFormat& f = rules.format;
  if (!(r.lo > 0))
    return fmt::format("LO must be > 0 (κ values are log-spaced); got {}",
                       quote_escaped(fields[0]));
  if (!(r.hi >= r.lo))
    return fmt::format("HI must be >= LO; got HI = {} < LO = {}", quote_escaped(fields[1]),
                       quote_escaped(fields[0]));
  if (rounds_to_zero(r.lo, f))
    return fmt::format(
        "LO = {} rounds to 0 in {}, the precision κ is used in (smallest positive {}: {:g})",
        quote_escaped(fields[0]), f.name, f.name, f.denorm_min);
  if (exceeds_max_finite(r.hi, f))
    return fmt::format("HI = {} exceeds the largest finite {} ({:g}), the precision κ is used in",
                       quote_escaped(fields[1]), f.name, f.max_finite);
  if (rules.with_count) {
    const std::string_view n = fields[2];
    const bool digits =
        !n.empty() && std::all_of(n.begin(), n.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits)
      return fmt::format("N {} is not a positive integer (digits only)", quote_escaped(n));
    int count = 0;
    const auto [ptr, ec] = std::from_chars(n.data(), n.data() + n.size(), count);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && count > rules.max_count))
      return fmt::format("N {} is out of range (at most {})", quote_escaped(n), rules.max_count);
    if (ec != std::errc() || ptr != n.data() + n.size())
      return fmt::format("N {} is not an integer", quote_escaped(n));
    if (count < 1) return fmt::format("N must be >= 1; got {}", quote_escaped(n));
    if (count == 1 && r.lo != r.hi)
      return fmt::format("N = 1 needs LO = HI; got {}", quote_escaped(text));
    r.count = count;
  }
  return r;
}

std::variant<long long, std::string> parse_count(std::string_view text, long long min,
                                                 long long max) {
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(),
                                                   [](char c) { return c >= '0' && c <= '9'; });
  if (!digits) return fmt::format("{} is not a whole number (digits only)", quote_escaped(text));
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && value > max))
    return fmt::format("{} is out of range (at most {})", quote_escaped(text), max);
  if (ec != std::errc() || ptr != text.data() + text.size())
    return fmt::format("{} is not a whole number (digits only)", quote_escaped(text));
  if (value < min) return fmt::format("must be at least {}, got {}", min, quote_escaped(text));
  return value;
}

std::vector<double> log_spaced(double lo, double hi, int count) {
  std::vector<double> v;
  if (count < 1) return v;
  v.reserve(static_cast<std::size_t>(count));
  const double e_lo = std::log10(lo), e_hi = std::log10(hi);
  const int last = count - 1;
  for (int j = 0; j < count; ++j) {
    if (j == 0 || lo == hi) {
      v.push_back(lo);
    } else if (j == last) {
      v.push_back(hi);
    } else {
      // (e_hi − e_lo)·j is exact for integral exponents; the division then
      // rounds once (exactly 0.25·j for the standard grid). pow may land an
      // ulp outside [lo, hi] or below its neighbour: clamp.
      const double x = std::pow(10.0, e_lo + ((e_hi - e_lo) * j) / last);
      v.push_back(std::clamp(x, v.back(), hi));
    }
  }
  return v;
}

}  // namespace sglab::io
