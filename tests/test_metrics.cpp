// Error metrics (docs/quantities.md) against hand-computed cases, including zero,
// infinite and NaN references and non-finite outputs; and the table writer:
// CSV, Markdown and JSON that parse back to the cells written.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/io.hpp"
#include "reference/error_measures.hpp"
#include "tests/test_support.hpp"
#include "validate/metrics.hpp"
#include "validate/table.hpp"

namespace sr = sglab::reference;
namespace sv = sglab::validate;

namespace {
using sglab::test::kInf;
using sglab::test::kNaN;
}  // namespace

TEST(Metrics, AbsPeakRelRelOnOrdinaryValues) {
  EXPECT_EQ(sr::abs_error(1.25, 1.0), 0.25);
  EXPECT_EQ(sr::abs_error(0.75, 1.0), 0.25);
  EXPECT_EQ(sr::peak_rel_error(1.25, 1.0, 2.0), 0.125);
  EXPECT_EQ(sr::peak_rel_error(1.25, 1.0, -2.0), 0.125);  // |peak|
  EXPECT_EQ(sr::rel_error(1.25, 1.0), 0.25);
  EXPECT_EQ(sr::rel_error(0.5, 2.0), 0.75);
  EXPECT_EQ(sr::rel_error(3.0, 3.0), 0.0);
}

TEST(Metrics, SignificanceThresholdIsOnePercentOfPeak) {
  EXPECT_TRUE(sr::significant(0.01, 1.0));
  EXPECT_TRUE(sr::significant(0.5, 1.0));
  EXPECT_FALSE(sr::significant(0.0099, 1.0));
  EXPECT_FALSE(sr::significant(0.0, 1.0));
  EXPECT_TRUE(sr::significant(0.0, 0.0));  // 0 ≥ 1e−2·0
  EXPECT_FALSE(sr::significant(kNaN, 1.0));
  EXPECT_FALSE(sr::significant(1.0, kNaN));
}

TEST(Metrics, ZeroReferenceAndZeroPeak) {
  EXPECT_EQ(sr::abs_error(0.5, 0.0), 0.5);
  EXPECT_EQ(sr::peak_rel_error(0.5, 0.0, 2.0), 0.25);
  EXPECT_EQ(sr::rel_error(0.0, 0.0), 0.0);
  EXPECT_EQ(sr::rel_error(1e-300, 0.0), kInf);
  EXPECT_EQ(sr::rel_error(-0.0, 0.0), 0.0);
  EXPECT_EQ(sr::peak_rel_error(0.0, 0.0, 0.0), 0.0);
  EXPECT_EQ(sr::peak_rel_error(1.0, 0.0, 0.0), kInf);
  EXPECT_EQ(sr::peak_rel_error(2.0, 2.0, 0.0), 0.0);
}

TEST(Metrics, InfiniteReference) {
  EXPECT_EQ(sr::abs_error(kInf, kInf), 0.0);
  EXPECT_EQ(sr::abs_error(-kInf, -kInf), 0.0);
  EXPECT_EQ(sr::abs_error(1.0, kInf), kInf);
  EXPECT_EQ(sr::abs_error(-kInf, kInf), kInf);
  EXPECT_EQ(sr::rel_error(kInf, kInf), 0.0);
  EXPECT_EQ(sr::rel_error(1.0, kInf), 1.0);
  EXPECT_EQ(sr::rel_error(-kInf, kInf), kInf);
  EXPECT_EQ(sr::peak_rel_error(1.0, 0.5, kInf), 0.0);
  EXPECT_TRUE(std::isnan(sr::peak_rel_error(1.0, kInf, kInf)));  // inf/inf
}

TEST(Metrics, NaNAnywhereGivesNaN) {
  EXPECT_TRUE(std::isnan(sr::abs_error(kNaN, 1.0)));
  EXPECT_TRUE(std::isnan(sr::abs_error(1.0, kNaN)));
  EXPECT_TRUE(std::isnan(sr::abs_error(kNaN, kNaN)));
  EXPECT_TRUE(std::isnan(sr::peak_rel_error(1.0, 1.0, kNaN)));
  EXPECT_TRUE(std::isnan(sr::rel_error(kNaN, 0.0)));
  EXPECT_TRUE(std::isnan(sr::ulp_error<float>(kNaN, 1.0)));
}

TEST(Metrics, UlpInTheEvaluatedPrecision) {
  EXPECT_EQ(sr::ulp_of<float>(1.0), 0x1p-23);
  EXPECT_EQ(sr::ulp_of<double>(1.0), 0x1p-52);
  EXPECT_EQ(sr::ulp_of<float>(-1.0), 0x1p-23);
  EXPECT_EQ(sr::ulp_of<float>(1.5), 0x1p-23);
  EXPECT_EQ(sr::ulp_of<float>(0.0), static_cast<double>(std::numeric_limits<float>::denorm_min()));
  EXPECT_EQ(sr::ulp_of<double>(0.0), std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(sr::ulp_of<float>(1e-40),
            static_cast<double>(std::numeric_limits<float>::denorm_min()));
  EXPECT_EQ(sr::ulp_of<float>(static_cast<double>(std::numeric_limits<float>::max())), 0x1p104);
  EXPECT_EQ(sr::ulp_of<float>(1e39), 0x1p104);  // rounds to inf in float: spacing below FLT_MAX
  EXPECT_TRUE(std::isnan(sr::ulp_of<float>(kInf)));
  EXPECT_EQ(sr::ulp_error<float>(1.0 + 0x1p-23, 1.0), 1.0);
  EXPECT_EQ(sr::ulp_error<float>(1.0 + 0x1p-24, 1.0), 0.5);
  EXPECT_EQ(sr::ulp_error<double>(1.0 + 0x1p-51, 1.0), 2.0);
  EXPECT_EQ(sr::ulp_error<double>(0.75, 0.75), 0.0);
  EXPECT_EQ(sr::ulp_error<float>(1.0, kInf), kInf);
}

TEST(Metrics, CompareClassifiesBeforeMeasuring) {
  auto p = sv::compare(1.25, 1.0, 2.0);
  EXPECT_EQ(p.status, sv::PointStatus::ok);
  EXPECT_EQ(p.abs, 0.25);
  EXPECT_EQ(p.peak_rel, 0.125);
  EXPECT_TRUE(p.significant);
  EXPECT_EQ(p.rel, 0.25);

  p = sv::compare(0.001, 0.0005, 1.0);  // reference below 1e−2·peak: no rel
  EXPECT_EQ(p.status, sv::PointStatus::ok);
  EXPECT_FALSE(p.significant);
  EXPECT_TRUE(std::isnan(p.rel));
  EXPECT_EQ(p.abs, 0.0005);

  for (double bad : {kNaN, kInf, -kInf}) {
    p = sv::compare(bad, 1.0, 1.0);
    EXPECT_EQ(p.status, sv::PointStatus::nonfinite_output);
    EXPECT_TRUE(std::isnan(p.peak_rel));
    EXPECT_TRUE(std::isnan(p.abs));
  }
  // A non-finite output is the method's failure even against a bad reference.
  EXPECT_EQ(sv::compare(kNaN, kNaN, 1.0).status, sv::PointStatus::nonfinite_output);
  EXPECT_EQ(sv::compare(1.0, kNaN, 1.0).status, sv::PointStatus::invalid_reference);
  EXPECT_EQ(sv::compare(1.0, kInf, 1.0).status, sv::PointStatus::invalid_reference);
  EXPECT_EQ(sv::compare(1.0, 1.0, kNaN).status, sv::PointStatus::invalid_reference);
}

TEST(Metrics, AccumulatorMaxWhereRms) {
  sv::ErrorAccumulator acc;
  EXPECT_EQ(acc.stats().count, 0u);
  EXPECT_TRUE(std::isnan(acc.stats().max));
  acc.add(1.0, 0.0, 0.1);
  acc.add(2.0, 0.5, 0.3);
  acc.add(3.0, 1.0, 0.2);
  acc.add(4.0, -1.0, 0.3);  // tie: the first occurrence stays
  acc.add(5.0, -1.0, kNaN);
  const auto s = acc.stats();
  EXPECT_EQ(s.count, 4u);
  EXPECT_EQ(acc.skipped(), 1u);
  EXPECT_EQ(s.max, 0.3);
  EXPECT_EQ(s.worst_kappa, 2.0);
  EXPECT_EQ(s.worst_cosine, 0.5);
  EXPECT_NEAR(s.rms, std::sqrt((0.01 + 0.09 + 0.04 + 0.09) / 4), 1e-16);
}

TEST(Metrics, AccumulatorMergeEqualsSequential) {
  sv::ErrorAccumulator a, b, all;
  const double errs[] = {1e-3, 5e-2, 5e-2, 2e-8, 0.04, 0.0};
  for (int i = 0; i < 6; ++i) {
    (i < 3 ? a : b).add(i, -i, errs[i]);
    all.add(i, -i, errs[i]);
  }
  a.merge(b);
  EXPECT_EQ(a.stats().max, all.stats().max);
  EXPECT_EQ(a.stats().worst_kappa, all.stats().worst_kappa);
  EXPECT_EQ(a.stats().worst_cosine, all.stats().worst_cosine);
  EXPECT_EQ(a.stats().count, all.stats().count);
  EXPECT_NEAR(a.stats().rms, all.stats().rms, 1e-17);
}

TEST(Metrics, MetricAccumulatorCountsNonFiniteAndExcludesIt) {
  sv::MetricAccumulator acc;
  // peak 4 at this κ; references 4 (c = 1), 1, 0.01 (insignificant: < 0.04)
  acc.add(1.0, 1.0, 4.5, 4.0, 4.0);     // peak_rel 0.125, rel 0.125
  acc.add(1.0, 0.0, 1.5, 1.0, 4.0);     // peak_rel 0.125, rel 0.5
  acc.add(1.0, -0.5, 0.03, 0.01, 4.0);  // peak_rel 0.005, rel not significant
  acc.add(1.0, -1.0, kNaN, 0.0, 4.0);   // non-finite output
  acc.add(2.0, -1.0, kInf, 0.0, 4.0);   // non-finite output
  acc.add(2.0, 0.0, 1.0, kNaN, 4.0);    // invalid reference
  const auto s = acc.summary();
  EXPECT_EQ(s.points, 6u);
  EXPECT_EQ(s.nonfinite, 2u);
  EXPECT_EQ(s.invalid_reference, 1u);
  EXPECT_EQ(s.first_nonfinite_kappa, 1.0);
  EXPECT_EQ(s.first_nonfinite_cosine, -1.0);
  EXPECT_EQ(s.peak_rel.count, 3u);
  EXPECT_EQ(s.peak_rel.max, 0.125);
  EXPECT_EQ(s.peak_rel.worst_cosine, 1.0);  // first of the tie
  EXPECT_NEAR(s.peak_rel.rms, std::sqrt((0.125 * 0.125 * 2 + 0.005 * 0.005) / 3), 1e-16);
  EXPECT_EQ(s.rel.count, 2u);
  EXPECT_EQ(s.rel.max, 0.5);
  EXPECT_EQ(s.rel.worst_cosine, 0.0);
  EXPECT_EQ(s.abs.max, 0.5);
}

// ---------------------------------------------------------------------------
// Table writer

namespace {

sv::Table sample_table() {
  sv::Table t("Sample | with pipe", {{"name"}, {"x", 3}, {"n"}, {"flag"}, {"note"}});
  t.add_row({sv::Table::text("plain"), sv::Table::real(1.0 / 3.0), sv::Table::integer(-7),
             sv::Cell{true}, sv::Table::text("a,b")});
  t.add_row({sv::Table::text("quote \"q\""), sv::Table::real(kNaN), sv::Table::integer(0),
             sv::Cell{false}, sv::Table::text("pipe | here")});
  t.add_row({sv::Table::text("line\nbreak"), sv::Table::real(kInf), sv::Table::count(42),
             sv::Cell{}, sv::Cell{}});
  t.add_row({sv::Table::text("tiny"), sv::Table::real(4.9406564584124654e-324),
             sv::Table::integer(1), sv::Cell{true}, sv::Table::text("")});
  t.add_row({sv::Table::text("neg"), sv::Table::real(-0.1), sv::Table::integer(2), sv::Cell{true},
             sv::Table::text("x")});
  return t;
}

// RFC 4180 reader.
std::vector<std::vector<std::string>> parse_csv(const std::string& s) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    if (quoted) {
      if (ch == '"' && i + 1 < s.size() && s[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
      any = true;
    } else if (ch == ',') {
      row.push_back(field);
      field.clear();
    } else if (ch == '\n') {
      row.push_back(field);
      rows.push_back(row);
      row.clear();
      field.clear();
      any = false;
    } else {
      field += ch;
      any = true;
    }
  }
  EXPECT_FALSE(quoted);
  if (any || !row.empty()) {
    row.push_back(field);
    rows.push_back(row);
  }
  return rows;
}

// Markdown pipe-table row: cells split at unescaped '|', "\|" unescaped.
std::vector<std::string> parse_markdown_row(const std::string& line) {
  EXPECT_FALSE(line.empty());
  EXPECT_EQ(line.front(), '|');
  EXPECT_EQ(line.back(), '|');
  return sglab::test::markdown_cells(line);
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < s.size()) {
    const auto end = s.find('\n', start);
    out.push_back(s.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

}  // namespace

TEST(Table, RejectsRowsOfTheWrongWidth) {
  sv::Table t("t", {{"a"}, {"b"}});
  EXPECT_THROW(t.add_row({sv::Table::text("only one")}), std::invalid_argument);
  EXPECT_NO_THROW(t.add_row({sv::Cell{}, sv::Cell{}}));
  EXPECT_EQ(t.column_index("b"), 1u);
  EXPECT_THROW(t.column_index("c"), std::out_of_range);
}

TEST(Table, CsvParsesBackExactly) {
  const sv::Table t = sample_table();
  const auto rows = parse_csv(sv::to_csv(t));
  ASSERT_EQ(rows.size(), 1 + t.rows().size());
  EXPECT_EQ(rows[0], (std::vector<std::string>{"name", "x", "n", "flag", "note"}));
  for (const auto& r : rows) ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(rows[1][0], "plain");
  EXPECT_EQ(std::strtod(rows[1][1].c_str(), nullptr), 1.0 / 3.0);  // full precision
  EXPECT_EQ(rows[1][2], "-7");
  EXPECT_EQ(rows[1][3], "true");
  EXPECT_EQ(rows[1][4], "a,b");
  EXPECT_EQ(rows[2][0], "quote \"q\"");
  EXPECT_EQ(rows[2][1], "nan");
  EXPECT_EQ(rows[2][4], "pipe | here");
  EXPECT_EQ(rows[3][0], "line\nbreak");
  EXPECT_EQ(rows[3][1], "inf");
  EXPECT_EQ(rows[3][2], "42");
  EXPECT_EQ(rows[3][3], "");
  EXPECT_EQ(std::strtod(rows[4][1].c_str(), nullptr), 4.9406564584124654e-324);
  EXPECT_EQ(std::strtod(rows[5][1].c_str(), nullptr), -0.1);
}

TEST(Table, MarkdownParsesBack) {
  const sv::Table t = sample_table();
  const auto ls = lines(sv::to_markdown(t));
  ASSERT_GE(ls.size(), 4 + t.rows().size());
  EXPECT_EQ(ls[0], "**Sample \\| with pipe**");
  EXPECT_EQ(ls[1], "");
  EXPECT_EQ(parse_markdown_row(ls[2]),
            (std::vector<std::string>{"name", "x", "n", "flag", "note"}));
  // Numeric columns right-aligned, the others left-aligned.
  EXPECT_EQ(parse_markdown_row(ls[3]),
            (std::vector<std::string>{":---", "---:", "---:", ":---", ":---"}));
  std::vector<std::vector<std::string>> body;
  for (std::size_t i = 4; i < ls.size(); ++i)
    if (!ls[i].empty()) body.push_back(parse_markdown_row(ls[i]));
  ASSERT_EQ(body.size(), t.rows().size());
  for (const auto& r : body) ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(body[0][0], "plain");
  EXPECT_EQ(body[0][1], "0.333");  // 3 significant digits for column x
  EXPECT_EQ(body[0][4], "a,b");
  EXPECT_EQ(body[1][1], "nan");
  EXPECT_EQ(body[1][4], "pipe | here");
  EXPECT_EQ(body[2][0], "line break");
  EXPECT_EQ(body[2][1], "inf");
  EXPECT_EQ(body[2][3], "");
  EXPECT_EQ(body[3][1], "4.94e-324");
}

TEST(Table, JsonParsesBack) {
  const sv::Table t = sample_table();
  const auto j = nlohmann::json::parse(sv::render(t, sv::TableFormat::json));
  EXPECT_EQ(j.at("title"), "Sample | with pipe");
  EXPECT_EQ(j.at("columns"), nlohmann::json({"name", "x", "n", "flag", "note"}));
  const auto& rows = j.at("rows");
  ASSERT_EQ(rows.size(), t.rows().size());
  EXPECT_EQ(rows[0].at("name"), "plain");
  EXPECT_EQ(rows[0].at("x").get<double>(), 1.0 / 3.0);
  EXPECT_EQ(rows[0].at("n").get<int>(), -7);
  EXPECT_EQ(rows[0].at("flag"), true);
  EXPECT_TRUE(rows[1].at("x").is_null());  // NaN
  EXPECT_EQ(rows[1].at("name"), "quote \"q\"");
  EXPECT_TRUE(rows[2].at("x").is_null());  // inf
  EXPECT_TRUE(rows[2].at("note").is_null());
  EXPECT_EQ(rows[3].at("x").get<double>(), 4.9406564584124654e-324);
  // Keys in column order.
  const nlohmann::ordered_json records = sv::to_json_records(t);
  std::vector<std::string> keys;
  for (const auto& [key, value] : records[0].items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"name", "x", "n", "flag", "note"}));
}

TEST(Table, WritesEveryFormatAtomically) {
  namespace fs = std::filesystem;
  const sglab::test::TempDir tmp("table");
  const fs::path dir = tmp.path / "out";  // write_table makes the folder
  const sv::Table t = sample_table();
  const auto paths = sv::write_table(
      t, dir, "sample", {sv::TableFormat::csv, sv::TableFormat::markdown, sv::TableFormat::json});
  ASSERT_EQ(paths.size(), 3u);
  EXPECT_EQ(paths[0], dir / "sample.csv");
  EXPECT_EQ(paths[1], dir / "sample.md");
  EXPECT_EQ(paths[2], dir / "sample.json");
  EXPECT_EQ(sglab::io::read_file(paths[0]), sv::to_csv(t));
  EXPECT_EQ(sglab::io::read_file(paths[1]), sv::to_markdown(t));
  EXPECT_EQ(nlohmann::json::parse(sglab::io::read_file(paths[2])),
            nlohmann::json::parse(sv::to_json(t).dump()));
}

// ---- ulp of an exact value (the erf checker's metric) ----------------------

TEST(Metrics, UlpFloatAtPowersOfTwoAndBetween) {
  // 2^e has ulp 2^(e−23); every value in [2^e, 2^(e+1)) shares it.
  for (int e = -126; e <= 127; ++e) {
    const double p = std::ldexp(1.0, e);
    ASSERT_EQ(sr::ulp_float(p), std::ldexp(1.0, e - 23)) << "2^" << e;
    ASSERT_EQ(sr::ulp_float(-p), std::ldexp(1.0, e - 23)) << "-2^" << e;
    ASSERT_EQ(sr::ulp_float(1.5 * p), std::ldexp(1.0, e - 23)) << "1.5*2^" << e;
    // Just below a power of two (the exact value's binade, not its rounding's);
    // below FLT_MIN = 2^−126 the subnormal spacing 2^−149.
    ASSERT_EQ(sr::ulp_float(std::nextafter(p, 0.0)), e > -126 ? std::ldexp(1.0, e - 24) : 0x1p-149)
        << "below 2^" << e;
  }
  EXPECT_EQ(sr::ulp_float(1.0), 0x1p-23);
  EXPECT_EQ(sr::ulp_float(static_cast<double>(std::numeric_limits<float>::max())), 0x1p104);
  EXPECT_EQ(sr::ulp_float(0x1p200), 0x1p177);  // beyond the float range: the same formula
}

TEST(Metrics, UlpFloatDenormalsZeroInfNaN) {
  const double denorm_min = static_cast<double>(std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(denorm_min, 0x1p-149);
  EXPECT_EQ(sr::ulp_float(0.0), 0x1p-149);
  EXPECT_EQ(sr::ulp_float(-0.0), 0x1p-149);
  EXPECT_EQ(sr::ulp_float(denorm_min), 0x1p-149);
  EXPECT_EQ(sr::ulp_float(0x1p-130), 0x1p-149);
  EXPECT_EQ(sr::ulp_float(std::nextafter(0x1p-126, 0.0)), 0x1p-149);  // largest value below FLT_MIN
  EXPECT_EQ(sr::ulp_float(0x1p-126), 0x1p-149);  // FLT_MIN: normal, same spacing
  EXPECT_EQ(sr::ulp_float(0x1p-125), 0x1p-148);
  EXPECT_EQ(sr::ulp_float(1e-300), 0x1p-149);
  EXPECT_EQ(sr::ulp_float(kInf), kInf);
  EXPECT_EQ(sr::ulp_float(-kInf), kInf);
  EXPECT_TRUE(std::isnan(sr::ulp_float(kNaN)));
}

TEST(Metrics, UlpDoubleAtPowersOfTwoDenormalsZeroInfNaN) {
  for (int e = -1022; e <= 1023; ++e) {
    const long double p = std::ldexp(1.0L, e);
    ASSERT_EQ(sr::ulp_double(p), std::ldexp(1.0L, e - 52)) << "2^" << e;
    ASSERT_EQ(sr::ulp_double(-p), std::ldexp(1.0L, e - 52)) << "-2^" << e;
    ASSERT_EQ(sr::ulp_double(std::nextafter(p, 0.0L)),
              e > -1022 ? std::ldexp(1.0L, e - 53) : 0x1p-1074L)
        << "below 2^" << e;
  }
  EXPECT_EQ(sr::ulp_double(1.0L), 0x1p-52L);
  EXPECT_EQ(sr::ulp_double(0.0L), 0x1p-1074L);
  EXPECT_EQ(sr::ulp_double(-0.0L), 0x1p-1074L);
  EXPECT_EQ(sr::ulp_double(static_cast<long double>(std::numeric_limits<double>::denorm_min())),
            0x1p-1074L);
  EXPECT_EQ(sr::ulp_double(0x1p-1050L), 0x1p-1074L);
  EXPECT_EQ(sr::ulp_double(static_cast<long double>(std::numeric_limits<double>::max())), 0x1p971L);
  EXPECT_EQ(sr::ulp_double(static_cast<long double>(kInf)), static_cast<long double>(kInf));
  EXPECT_EQ(sr::ulp_double(-static_cast<long double>(kInf)), static_cast<long double>(kInf));
  EXPECT_TRUE(std::isnan(sr::ulp_double(static_cast<long double>(kNaN))));
}

TEST(Metrics, ExactUlpErrorSpecialValues) {
  // Ordinary: one float ulp at 1 is 2^−23; just below 1 it is 2^−24.
  EXPECT_EQ(sr::exact_ulp_error_float(1.0 + 0x1p-23, 1.0), 1.0);
  EXPECT_EQ(sr::exact_ulp_error_float(1.0, 1.0 - 0x1p-30), 0x1p-30 / 0x1p-24);
  EXPECT_EQ(sr::exact_ulp_error_float(-1.0 - 0x1p-24, -1.0), 0.5);
  EXPECT_EQ(sr::exact_ulp_error_float(0x1p-149, 0.0), 1.0);  // denormals: spacing 2^−149
  EXPECT_EQ(sr::exact_ulp_error_float(0.0, -0.0), 0.0);      // ±0 are equal
  EXPECT_EQ(sr::exact_ulp_error_float(kInf, kInf), 0.0);
  EXPECT_EQ(sr::exact_ulp_error_float(1.0, kInf), kInf);
  EXPECT_EQ(sr::exact_ulp_error_float(kInf, 1.0), kInf);
  EXPECT_EQ(sr::exact_ulp_error_float(-kInf, kInf), kInf);
  EXPECT_TRUE(std::isnan(sr::exact_ulp_error_float(kNaN, 1.0)));
  EXPECT_TRUE(std::isnan(sr::exact_ulp_error_float(1.0, kNaN)));

  EXPECT_EQ(sr::exact_ulp_error_double(1.0 + 0x1p-52, 1.0L), 1.0);
  // long double exact value
  EXPECT_EQ(sr::exact_ulp_error_double(1.0, 1.0L - 0x1p-60L), 0x1p-60 / 0x1p-53);
  EXPECT_EQ(sr::exact_ulp_error_double(0x1p-1074, 0.0L), 1.0);
  EXPECT_EQ(sr::exact_ulp_error_double(-0.0, 0.0L), 0.0);
  EXPECT_EQ(sr::exact_ulp_error_double(kInf, static_cast<long double>(kInf)), 0.0);
  EXPECT_EQ(sr::exact_ulp_error_double(1.0, static_cast<long double>(kInf)), kInf);
  EXPECT_EQ(sr::exact_ulp_error_double(kInf, 1.0L), kInf);
  EXPECT_TRUE(std::isnan(sr::exact_ulp_error_double(kNaN, 1.0L)));
  EXPECT_TRUE(std::isnan(sr::exact_ulp_error_double(1.0, static_cast<long double>(kNaN))));
}

TEST(Metrics, ExactUlpDiffersFromRoundedUlpJustBelowAPowerOfTwo) {
  // ulp_of<float> takes the spacing at the value rounded to float (1.0f: 2^−23),
  // ulp_float the binade of the exact value (below 1: 2^−24).
  const double y = 1.0 - 0x1p-30;
  EXPECT_EQ(sr::ulp_of<float>(y), 0x1p-23);
  EXPECT_EQ(sr::ulp_float(y), 0x1p-24);
}

// ---- worst peak_rel as a fit reports it --------------------------------------

TEST(Metrics, MaxPeakRelErrorIsTheMaxOrInfinity) {
  const std::vector<double> ref = {1.0, 2.0, 0.5};
  const std::vector<double> peak = {4.0, 4.0, 2.0};
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.0, 2.0, 0.5}, ref, peak), 0.0);
  // |1.5 − 1|/4 = 0.125, |2 − 2|/4 = 0, |0.25 − 0.5|/2 = 0.125 → 0.125; with 3 at the second point
  // |3 − 2|/4 = 0.25.
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.5, 2.0, 0.25}, ref, peak), 0.125);
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.5, 3.0, 0.25}, ref, peak), 0.25);
  // One non-finite output anywhere makes the worst case infinite, whatever comes after.
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{kNaN, 2.0, 0.5}, ref, peak), kInf);
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.0, kInf, 0.5}, ref, peak), kInf);
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.0, 2.0, -kInf}, ref, peak), kInf);
  // A zero peak with a non-zero difference is infinite too; with no difference it is 0.
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.0}, std::vector<double>{1.0},
                                   std::vector<double>{0.0}),
            0.0);
  EXPECT_EQ(sr::max_peak_rel_error(std::vector<double>{1.5}, std::vector<double>{1.0},
                                   std::vector<double>{0.0}),
            kInf);
  EXPECT_EQ(sr::max_peak_rel_error({}, {}, {}), 0.0);  // no points
  EXPECT_THROW(sr::max_peak_rel_error(std::vector<double>{1.0}, ref, peak), std::invalid_argument);
}
