// common/args.hpp — the one parser of κ ranges (`--kappa LO:HI` and
// `--kappa LO:HI:N`) shared by `sglab fit`, `sweep`, `pareto` and
// `recommend`, its number syntax, and the log-spaced points of a range.
//
// Rules (every command, one set):
// - A number is a plain decimal: an optional '-', digits with an optional
//   fraction ("1", "1.5", ".5", "5."), an optional exponent ("e-3", "E+4").
//   No hex floats, no "inf"/"nan", no leading '+', no whitespace, nothing after
//   the number.
// - A decimal beyond the largest double, or nonzero but below the smallest
//   positive double (about 4.9e-324), is "out of range".
// - LO and HI are finite, 0 < LO ≤ HI (the points are log-spaced, so LO = 0 is
//   refused).
// - The values must survive the precision κ is used in (`KappaRangeRules::
//   format`: float for the sweep, pareto and recommend, which round their
//   inputs to float; the working precision for `fit`): a nonzero LO that rounds
//   to 0 there is refused, and so is an HI above its largest finite value.
//   Subnormal values that do not round to 0 are accepted (1e-310 in double,
//   1e-40 in float).
// - N is a decimal integer (digits only), 1 ≤ N ≤ kMaxKappaCount; N = 1 needs
//   LO = HI.
// - Error messages quote the offending text escaped (printable ASCII as is,
//   every other byte as \xNN, so a NUL byte cannot cut the message short) and
//   shortened to kMaxQuotedChars characters.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace sglab::io {

// The largest N of LO:HI:N.
inline constexpr int kMaxKappaCount = 100000;
// The longest piece of bad input quoted in an error message.
inline constexpr std::size_t kMaxQuotedChars = 64;

// The precision a value is used in: its smallest positive (subnormal) value
// and its largest finite value.
struct NumberFormat {
  std::string_view name;
  double denorm_min;
  double max_finite;
};
inline constexpr NumberFormat kHalfFormat{"half", 0x1p-24, 65504.0};
inline constexpr NumberFormat kFloatFormat{"float", 0x1p-149, 0x1.fffffep127};
inline constexpr NumberFormat kDoubleFormat{"double", 0x0.0000000000001p-1022,
                                            0x1.fffffffffffffp1023};

// Whether a nonzero `value` rounds to 0 in format f: it is at most half the
// smallest subnormal (the halfway case rounds to even, i.e. to 0).
constexpr bool rounds_to_zero(double value, const NumberFormat& f) {
  return value != 0 && (value < 0 ? -value : value) <= f.denorm_min / 2;
}
// Whether `value` is beyond the largest finite value of format f.
constexpr bool exceeds_max_finite(double value, const NumberFormat& f) {
  return (value < 0 ? -value : value) > f.max_finite;
}

// The rules a (κ, c) point of `sglab eval` and `sglab reference` meets (and
// of the Python module's arrays): finite κ ≥ 0, c ∈ [−1, 1], and, when κ is
// evaluated in a narrower precision (kappa_format), a κ that neither exceeds
// its largest finite value nor rounds to 0 there. point_ok says whether it
// does; point_error gives the message of the first rule it breaks (empty when
// none).
constexpr bool point_ok(double kappa, double cosine, const NumberFormat* kappa_format) {
  const bool base = kappa >= 0 && kappa <= 0x1.fffffffffffffp1023 && cosine >= -1 && cosine <= 1;
  return base && (!kappa_format || (!exceeds_max_finite(kappa, *kappa_format) &&
                                    !rounds_to_zero(kappa, *kappa_format)));
}
std::string point_error(double kappa, double cosine, const NumberFormat* kappa_format);

struct KappaRangeRules {
  bool with_count = false;             // LO:HI:N (true) or LO:HI (false)
  NumberFormat format = kFloatFormat;  // the precision the κ values are used in
  int max_count = kMaxKappaCount;
};

struct KappaRange {
  double lo = 0, hi = 0;
  int count = 0;  // N of LO:HI:N; 0 for LO:HI
};

// `text` as LO:HI or LO:HI:N under `rules`. On failure, the error message
// (quoting the bad part escaped; the caller prefixes the option name).
std::variant<KappaRange, std::string> parse_kappa_range(std::string_view text,
                                                        const KappaRangeRules& rules);

// One plain decimal number (syntax above) as a double. On failure, why:
// "is not a number" or "is out of range (...)".
std::variant<double, std::string> parse_decimal(std::string_view text);

// A whole-number option (`--normals 4096`, `--cosines 41`): digits only (no
// sign, blanks or exponent), min ≤ value ≤ max. On failure, why (quoting the
// text escaped; the caller prefixes the option name): "'-1' is not a whole
// number (digits only)", "'2147483648' is out of range (at most 1000000)",
// "must be at least 2, got '1'".
std::variant<long long, std::string> parse_count(std::string_view text, long long min,
                                                 long long max);

// `count` values log-spaced over [lo, hi]: v_j = 10^(e_lo + (e_hi − e_lo)·j/(N − 1))
// with e = log10, then made to start exactly at lo, end exactly at hi and be
// non-decreasing (lo = hi gives N copies of lo). count = 1 gives {lo}; the
// exponent step (e_hi − e_lo)·j is exact for integral exponents, so the
// standard grid 1e-3:1e4:29 gives the correctly rounded 10^(i/4).
// Requires 0 < lo ≤ hi finite.
std::vector<double> log_spaced(double lo, double hi, int count);

// `text` for an error message: printable ASCII as is, '\' and every other
// byte as \xNN, at most `max_chars` characters of it followed by
// "... (N bytes)" when longer.
std::string quote_escaped(std::string_view text, std::size_t max_chars = kMaxQuotedChars);

}  // namespace sglab::io
