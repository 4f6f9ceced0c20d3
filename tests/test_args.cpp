// The one κ-range parser (common/args.hpp) and the commands that use it:
// fit, sweep, pareto and recommend give the same answer for the same text.
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/args.hpp"
#include "common/vocabulary.hpp"
#include "tests/test_support.hpp"
#include "validate/sweep.hpp"

namespace {

using sglab::io::KappaRange;
using sglab::io::KappaRangeRules;
using sglab::io::parse_kappa_range;

KappaRangeRules range(sglab::io::NumberFormat f = sglab::io::kFloatFormat) {
  KappaRangeRules r;
  r.format = f;
  return r;
}
KappaRangeRules grid(sglab::io::NumberFormat f = sglab::io::kFloatFormat) {
  KappaRangeRules r = range(f);
  r.with_count = true;
  return r;
}

// The error message, or "" when accepted.
std::string error_of(std::string_view text, const KappaRangeRules& rules) {
  const auto r = parse_kappa_range(text, rules);
  const auto* why = std::get_if<std::string>(&r);
  return why ? *why : std::string();
}
KappaRange accepted(std::string_view text, const KappaRangeRules& rules) {
  const auto r = parse_kappa_range(text, rules);
  if (const auto* why = std::get_if<std::string>(&r))
    ADD_FAILURE() << "'" << text << "' refused: " << *why;
  return std::holds_alternative<KappaRange>(r) ? std::get<KappaRange>(r) : KappaRange{};
}

TEST(KappaRange, PlainDecimalsAccepted) {
  const KappaRange r = accepted("1e-3:1e4", range());
  EXPECT_EQ(r.lo, 1e-3);
  EXPECT_EQ(r.hi, 1e4);
  EXPECT_EQ(r.count, 0);
  const KappaRange g = accepted("0.5:250.:29", grid());
  EXPECT_EQ(g.lo, 0.5);
  EXPECT_EQ(g.hi, 250.0);
  EXPECT_EQ(g.count, 29);
  EXPECT_EQ(accepted(".5:5E+2", range()).hi, 500.0);
  EXPECT_EQ(accepted("5:5", range()).lo, 5.0);  // LO = HI is a range of one value
}

TEST(KappaRange, OnlyPlainDecimals) {
  for (const char* bad :
       {"0x1p3:10", "+1:10", " 1:10", "1 :10", "1:10 ", "1:\t10", "1e:10", "1e+:10", ".:10",
        "1:10x", "inf:10", "1:nan", "1:infinity", "--1:10", "1..2:3", "1:1e4.5", ":", "1:"}) {
    const std::string e = error_of(bad, range());
    EXPECT_NE(e.find("not a number"), std::string::npos) << "'" << bad << "' gave: " << e;
  }
  for (const char* bad : {"", "1", "1:2:3", "1:2:3:4"})
    EXPECT_NE(error_of(bad, range()).find("expected LO:HI"), std::string::npos) << bad;
  for (const char* bad : {"1:2", "1:2:3:4"})
    EXPECT_NE(error_of(bad, grid()).find("expected LO:HI:N"), std::string::npos) << bad;
}

TEST(KappaRange, OverflowAndUnderflowSayOutOfRange) {
  for (const char* bad : {"1:1e400", "1e-400:1",
                          "1:"
                          "100000000000000000000000000000000000000000000000000000000000000000000000"
                          "000000000000000000000000000000000000000000000000000000000000000000000000"
                          "000000000000000000000000000000000000000000000000000000000000000000000000"
                          "0000000000000000000000000000000000000000000000000000000000"
                          "0000000000000000000000000000000000000000000000"}) {
    const std::string e = error_of(bad, range(sglab::io::kDoubleFormat));
    EXPECT_NE(e.find("out of range"), std::string::npos) << e;
    EXPECT_EQ(e.find("not a number"), std::string::npos) << e;
  }
  EXPECT_NE(error_of("0."
                     "00000000000000000000000000000000000000000000000000000000000000000000000000000"
                     "00000000000000000000000000000000000000000000000000000000000000000000000000000"
                     "00000000000000000000000000000000000000000000000000000000000000000000000000000"
                     "00000000000000000000000000000000000000000000000000000000000000000000000000000"
                     "00000000000000000000000000000000000000000000000000000001:1",
                     range(sglab::io::kDoubleFormat))
                .find("nonzero but smaller"),
            std::string::npos);
  EXPECT_NE(error_of("1:2:99999999999999999999", grid()).find("out of range"), std::string::npos);
}

TEST(KappaRange, PrecisionOfUseDecidesTinyAndHugeBounds) {
  // 1e-310 is a subnormal double: valid where κ is used in double, 0 in float.
  EXPECT_EQ(accepted("1e-310:1", range(sglab::io::kDoubleFormat)).lo, 1e-310);
  EXPECT_NE(error_of("1e-310:1", range()).find("rounds to 0 in float"), std::string::npos);
  // 1e-46 is below half the smallest float subnormal (2^-150 ≈ 7.0e-46): 0 in float.
  EXPECT_NE(error_of("1e-46:1", range()).find("rounds to 0 in float"), std::string::npos);
  // 1e-45 rounds to the smallest float subnormal 2^-149: accepted.
  EXPECT_EQ(accepted("1e-45:1", range()).lo, 1e-45);
  // Half: the smallest subnormal is 2^-24 ≈ 5.96e-8, the largest finite 65504.
  EXPECT_NE(error_of("2e-8:1", range(sglab::io::kHalfFormat)).find("rounds to 0 in half"),
            std::string::npos);
  EXPECT_NE(error_of("1:1e5", range(sglab::io::kHalfFormat)).find("largest finite half"),
            std::string::npos);
  EXPECT_NE(error_of("1:1e39", range()).find("largest finite float"), std::string::npos);
  EXPECT_EQ(accepted("1:1e39", range(sglab::io::kDoubleFormat)).hi, 1e39);
}

TEST(KappaRange, BoundsAndCount) {
  EXPECT_NE(error_of("0:1", range()).find("LO must be > 0"), std::string::npos);
  EXPECT_NE(error_of("-1:1", range()).find("LO must be > 0"), std::string::npos);
  EXPECT_NE(error_of("2:1", range()).find("HI must be >= LO"), std::string::npos);
  for (const char* bad : {"1:2:0", "1:2:-3", "1:2:+3", "1:2:2.5", "1:2:1e3", "1:2: 3", "1:2:"})
    EXPECT_FALSE(error_of(bad, grid()).empty()) << bad;
  EXPECT_NE(error_of("1:2:1", grid()).find("N = 1 needs LO = HI"), std::string::npos);
  EXPECT_EQ(accepted("3:3:1", grid()).count, 1);
  EXPECT_EQ(accepted("1:2:100000", grid()).count, sglab::io::kMaxKappaCount);
  EXPECT_NE(error_of("1:2:100001", grid()).find("out of range (at most 100000)"),
            std::string::npos);
}

TEST(KappaRange, MessagesEscapeTheTextAndStayShort) {
  // A NUL byte in the input: the message quotes it escaped and goes on past it.
  const std::string with_nul("1\0x:10", 6);
  const std::string e = error_of(with_nul, range());
  EXPECT_EQ(e.find('\0'), std::string::npos);
  EXPECT_NE(e.find("'1\\x00x'"), std::string::npos) << e;
  EXPECT_NE(e.find("is not a number"), std::string::npos) << e;
  // 10 MB of junk: a short message that says how long the input was.
  const std::string huge = "1:" + std::string(10 << 20, '9') + "x";
  const std::string h = error_of(huge, range());
  EXPECT_LT(h.size(), 300u) << h.substr(0, 300);
  EXPECT_NE(h.find(std::to_string(huge.size() - 2) + " bytes"), std::string::npos) << h;
  // Control characters and non-ASCII bytes are escaped.
  EXPECT_EQ(sglab::io::quote_escaped("a\nb\xc3\xa9\\"), "'a\\x0ab\\xc3\\xa9\\x5c'");
}

TEST(LogSpaced, SortedAndExactAtTheEnds) {
  for (const auto& [lo, hi, n] :
       {std::tuple{5.0, 5.0, 4}, std::tuple{1e-3, 1e4, 29}, std::tuple{0.1, 0.3, 7},
        std::tuple{1e-310, 1e300, 1000}, std::tuple{3.0, 3.0000000000000004, 50}}) {
    const auto v = sglab::io::log_spaced(lo, hi, n);
    ASSERT_EQ(v.size(), static_cast<std::size_t>(n));
    EXPECT_EQ(v.front(), lo);
    EXPECT_EQ(v.back(), hi);
    for (std::size_t i = 1; i < v.size(); ++i) {
      EXPECT_LE(v[i - 1], v[i]) << "at " << i << ": " << sglab::test::hex(v[i - 1]) << " > "
                                << sglab::test::hex(v[i]);
      EXPECT_GE(v[i], lo);
      EXPECT_LE(v[i], hi);
    }
  }
  // LO = HI: N copies of LO (pow(10, log10(5)) is not 5).
  EXPECT_EQ(sglab::io::log_spaced(5, 5, 4), (std::vector<double>{5, 5, 5, 5}));
  // The standard grid is the correctly rounded 10^(i/4).
  const auto s = sglab::io::log_spaced(1e-3, 1e4, 29);
  const auto want = sglab::test::standard_kappas();
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(s[i], want[i], 1e-15 * want[i]);
  // The sweep grid uses it.
  sglab::validate::SweepGrid g;
  g.kappa_lo = g.kappa_hi = 5;
  g.kappa_count = 4;
  EXPECT_EQ(g.kappas(), (std::vector<double>{5, 5, 5, 5}));
}

// ---- every command that takes --kappa uses the same parser -----------------

TEST(KappaRangeCli, EveryCommandRefusesTheSameBadText) {
  const std::vector<std::vector<std::string>> commands = {
      {"fit", "steepness2022", "--dry-run", "--kappa"},
      {"sweep", "--kappa"},
      {"pareto", "--kappa"},
      {"recommend", "--budget", "1e-2", "--kappa"},
  };
  for (const auto& base : commands) {
    const bool with_count = base[0] == "sweep";
    const std::string n = with_count ? ":5" : "";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"0x1p3:10" + n, "is not a number"},     {"+1:10" + n, "is not a number"},
        {" 1:10" + n, "is not a number"},        {"1:1e400" + n, "out of range"},
        {"1e-46:1" + n, "rounds to 0 in float"}, {"10:1" + n, "HI must be >= LO"}};
    for (const auto& [text, want] : cases) {
      std::vector<std::string> args = base;
      args.push_back(text);
      const auto r = sglab::test::run_sglab(args);
      EXPECT_EQ(r.exit_code, 2) << base[0] << " " << text << "\n" << r.output;
      EXPECT_NE(r.output.find("--kappa: "), std::string::npos) << base[0] << " " << text << "\n"
                                                               << r.output;
      EXPECT_NE(r.output.find(want), std::string::npos) << base[0] << " " << text << "\n"
                                                        << r.output;
    }
  }
}

TEST(KappaRangeCli, FitAcceptsSubnormalKappaInDouble) {
  // 1e-310 is valid where κ is used in double (clamped-cosine --precision double),
  // and refused in float (the default), naming the precision.
  auto r = sglab::test::run_sglab({"fit", "clamped-cosine", "--precision", "double", "--kappa",
                                   "1e-310:1", "--dry-run", "--json"},
                                  false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["dry_run"], true);
  r = sglab::test::run_sglab({"fit", "clamped-cosine", "--kappa", "1e-310:1", "--dry-run"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("rounds to 0 in float"), std::string::npos) << r.output;
}

// The sweep rounds κ to float, which would hide a 1-ulp error of a nominal
// grid (LogSpaced.SortedAndExactAtTheEnds catches that); this checks the end
// to end result.
TEST(KappaRangeCli, SweepEqualBoundsGiveEqualKappas) {
  namespace fs = std::filesystem;
  const sglab::test::TempDir tmp("args");
  const fs::path dir = tmp.path / "out";
  const auto r = sglab::test::run_sglab({"sweep", "--kappa", "5:5:4", "--cosines", "3", "--method",
                                         "tokuyoshi2024", "--out", dir.string(), "--json"},
                                        false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv =
      sglab::test::run_program({"cat", (dir / "per_kappa.csv").string()}).output;
  // Every κ column of per_kappa.csv is exactly 5 (4 rows per method and precision).
  std::size_t rows = 0;
  std::size_t pos = csv.find('\n');
  while (pos != std::string::npos && pos + 1 < csv.size()) {
    const std::size_t end = csv.find('\n', pos + 1);
    const std::string line = csv.substr(pos + 1, end - pos - 1);
    std::vector<std::string> cells;
    for (std::size_t s = 0, c;; s = c + 1) {
      c = line.find(',', s);
      cells.push_back(line.substr(s, c - s));
      if (c == std::string::npos) break;
    }
    ASSERT_GE(cells.size(), 4u) << line;
    EXPECT_EQ(std::stod(cells[3]), 5.0) << line;
    ++rows;
    pos = end;
  }
  EXPECT_EQ(rows, 8u) << csv;  // 4 κ × float and double
}

// The vocabulary (common/vocabulary.hpp): each name parses back to its value,
// and an option outside its allowed values is refused naming the option and
// listing what it takes.
template <class E>
void expect_round_trip() {
  for (const auto& n : names_of(E{})) {
    EXPECT_EQ(sglab::io::to_string(n.value), n.name);
    EXPECT_EQ(sglab::io::parse_enum<E>(n.name), n.value) << n.name;
  }
  EXPECT_FALSE(sglab::io::parse_enum<E>(""));
}

TEST(Vocabulary, NamesParseBackToTheirValues) {
  expect_round_trip<sglab::io::Precision>();
  expect_round_trip<sglab::io::Backend>();
  expect_round_trip<sglab::io::Language>();
  expect_round_trip<sglab::io::Form>();
  EXPECT_EQ(sglab::io::to_string(sglab::io::Precision::float16), "half");
  EXPECT_EQ(sglab::io::to_string(sglab::io::Precision::float64), "double");
  EXPECT_FALSE(sglab::io::parse_enum<sglab::io::Precision>("Float"));
}

// A value-initialized Precision is no precision (not half): it has no name and
// no number format.
TEST(Vocabulary, AValueInitializedPrecisionIsNone) {
  constexpr sglab::io::Precision none{};
  for (const auto& n : names_of(sglab::io::Precision{})) EXPECT_NE(n.value, none) << n.name;
  EXPECT_EQ(sglab::io::to_string(none), "?");
  EXPECT_THROW(sglab::io::number_format(none), std::invalid_argument);
}

TEST(Vocabulary, AnOptionOutsideItsValuesNamesTheOptionAndTheValues) {
  using sglab::io::Precision;
  EXPECT_EQ(
      sglab::io::parse_option("--precision", "half", {Precision::float32, Precision::float16}),
      Precision::float16);
  try {
    sglab::io::parse_option("--precision", "double", {Precision::float32, Precision::float16});
    ADD_FAILURE() << "double accepted where only float and half are";
  } catch (const sglab::io::InputError& e) {
    EXPECT_STREQ(e.what(), "--precision: expected float or half, got 'double'");
  }
  try {
    sglab::io::parse_option<Precision>("--precision", "quad");
    ADD_FAILURE() << "quad accepted";
  } catch (const sglab::io::InputError& e) {
    EXPECT_STREQ(e.what(), "--precision: expected half, float or double, got 'quad'");
  }
}

// The names of the sweep's precision column (data/results/vulkan_sweep.json).
TEST(Vocabulary, EvaluationsAreNamedAsTheSweepNamesThem) {
  using namespace sglab::io;
  EXPECT_EQ(to_string(kCpuFloat), "float");
  EXPECT_EQ(to_string(kCpuDouble), "double");
  EXPECT_EQ(to_string(on_vulkan(Language::glsl, Precision::float32)), "vulkan");
  EXPECT_EQ(to_string(on_vulkan(Language::hlsl, Precision::float32)), "vulkan_hlsl");
  EXPECT_EQ(to_string(on_vulkan(Language::glsl, Precision::float16)), "vulkan_half");
  EXPECT_EQ(to_string(on_vulkan(Language::hlsl, Precision::float16)), "vulkan_hlsl_half");
  EXPECT_EQ(to_string(on_vulkan(Language::glsl, Precision::float32, Form::split)), "vulkan_split");
  EXPECT_EQ(to_string(on_vulkan(Language::hlsl, Precision::float32, Form::split)),
            "vulkan_hlsl_split");
}

}  // namespace
