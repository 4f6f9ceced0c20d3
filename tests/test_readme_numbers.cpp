// tests/test_readme_numbers.cpp — the numbers README.md states about sglab's
// own models are the ones data/results holds: the errors of the sweep
// summaries (`sglab sweep`, standard and held-out grids) and the costs of the
// cost table (`sglab bench`, `sglab gpucost`). A regenerated result that
// moves a stated number makes this fail until README is brought in line.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;
const fs::path kRoot = fs::path(SGLAB_TEST_SOURCE_DIR) / "..";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The cells of a Markdown table row "| a | b |" (trimmed), empty when `line`
// is not a row.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  if (line.empty() || line[0] != '|') return out;
  std::size_t i = 1;
  while (i < line.size()) {
    const std::size_t j = line.find('|', i);
    if (j == std::string::npos) break;
    std::string c = line.substr(i, j - i);
    const auto b = c.find_first_not_of(' '), e = c.find_last_not_of(' ');
    out.push_back(b == std::string::npos ? "" : c.substr(b, e - b + 1));
    i = j + 1;
  }
  return out;
}

// The rows of the first Markdown table in `text` whose header starts with
// `header` (cells), header and separator excluded.
std::vector<std::vector<std::string>> table_after(const std::string& text, const std::vector<std::string>& header) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::vector<std::string>> rows;
  bool inside = false;
  while (std::getline(in, line)) {
    const auto c = cells(line);
    if (!inside) {
      inside = c.size() >= header.size() && std::equal(header.begin(), header.end(), c.begin());
      if (inside) std::getline(in, line);  // the separator
      continue;
    }
    if (c.empty()) break;
    rows.push_back(c);
  }
  return rows;
}

// "**3.05e−5**" → 3.05e-5 and its significant digits (3); nullopt when the
// cell holds no number.
struct Stated {
  double value;
  int digits;
};
std::optional<Stated> number(std::string cell) {
  std::string s;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    if (cell.compare(i, 3, "\xE2\x88\x92") == 0) {  // U+2212 minus sign
      s += '-';
      i += 2;
    } else if (cell[i] != '*') {
      s += cell[i];
    }
  }
  if (s.empty()) return std::nullopt;
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size()) return std::nullopt;
  const std::string mantissa = s.substr(0, s.find_first_of("eE"));
  int digits = 0;
  bool leading = true;
  for (char ch : mantissa) {
    if (ch < '0' || ch > '9') continue;
    if (leading && ch == '0') continue;
    leading = false;
    ++digits;
  }
  return Stated{v, digits};
}

// `truth` printed with the stated number of significant digits is the stated value.
void expect_matches(const Stated& stated, double truth, const std::string& what) {
  const double scale = std::pow(10.0, std::floor(std::log10(std::fabs(truth))) - (stated.digits - 1));
  const double rounded = std::nearbyint(truth / scale) * scale;
  EXPECT_NEAR(stated.value, rounded, 0.01 * scale) << what << ": README states " << stated.value
                                                      << ", data/results gives " << truth;
}

// Float irradiance max_peak_rel by method from a `sglab sweep` summary.
std::map<std::string, double> sweep_errors(const fs::path& summary) {
  std::map<std::string, double> out;
  for (const auto& r : table_after(slurp(summary), {"method", "quantity", "precision", "max_peak_rel"}))
    if (r[1] == "irradiance" && r[2] == "float") out[r[0]] = std::stod(r[3]);
  return out;
}

// The same from the JSON `sglab sweep --json` prints (the held-out grid).
std::map<std::string, double> held_out_errors(const fs::path& json) {
  std::map<std::string, double> out;
  const auto doc = nlohmann::json::parse(slurp(json));
  // The grid README names: 217 κ over [1.1e−3, 9.7e3] × 401 cosines, none a fit used.
  EXPECT_EQ(doc.at("grid").at("kappa_count"), 217);
  EXPECT_EQ(doc.at("grid").at("cosine_count"), 401);
  for (const auto& r : doc.at("results"))
    if (r.at("quantity") == "irradiance" && r.at("precision") == "float")
      out[r.at("method").get<std::string>()] = r.at("max_peak_rel").get<double>();
  return out;
}

std::string method_of(std::string cell) {
  for (const char* drop : {"`", "**"})
    for (std::size_t p; (p = cell.find(drop)) != std::string::npos;) cell.erase(p, std::string(drop).size());
  return cell.substr(0, cell.find(' '));
}

TEST(ReadmeNumbers, SglabModelsTableMatchesTheResults) {
  const std::string readme = slurp(kRoot / "README.md");
  const auto rows =
      table_after(readme, {"method", "form", "held-out max peak_rel", "standard grid", "GPU cycles", "batch ns"});
  ASSERT_GE(rows.size(), 5u) << "README has no table of sglab's own models with the expected header";

  const auto standard = sweep_errors(kRoot / "data" / "results" / "sweep_summary.md");
  const auto held_out = held_out_errors(kRoot / "data" / "results" / "heldout_sweep.json");
  const auto costs = nlohmann::json::parse(slurp(kRoot / "data" / "results" / "costs.json"));
  std::map<std::string, double> gpu, batch;
  for (const auto& r : costs.at("gpu").at("rows"))
    if (r.at("family") == "navi21" && r.at("lang") == "glsl" && !r.at("split").get<bool>() &&
        r.at("precision") == "float")
      gpu[r.at("method").get<std::string>()] = r.at("inverse_throughput").get<double>();
  for (const auto& c : costs.at("costs"))
    if (c.at("kind") == "irradiance" && c.at("precision") == "float" && c.at("mode") == "batch")
      batch[c.at("method").get<std::string>()] = c.at("ns_per_eval").get<double>();

  for (const auto& r : rows) {
    ASSERT_GE(r.size(), 6u);
    const std::string m = method_of(r[0]);
    const auto check = [&](const std::string& cell, const std::map<std::string, double>& truth, const char* column) {
      const auto stated = number(cell);
      ASSERT_TRUE(stated) << m << ", " << column << ": '" << cell << "' is not a number";
      ASSERT_TRUE(truth.count(m)) << m << ", " << column << ": not in data/results";
      expect_matches(*stated, truth.at(m), m + ", " + column);
    };
    check(r[2], held_out, "held-out max peak_rel");
    check(r[3], standard, "standard grid");
    check(r[4], gpu, "GPU cycles");
    check(r[5], batch, "batch ns");
  }
}

}  // namespace
