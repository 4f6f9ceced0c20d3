// `sglab methods` (app/cmd_methods.cpp): its JSON lists every registered
// method with the registry's id, origin, source, split and constant sets.
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/sglab.hpp>

#include "tests/test_support.hpp"

namespace {

using sglab::test::run_sglab;

TEST(MethodsCommand, JsonListsEveryRegisteredMethod) {
  const auto r = run_sglab({"methods", "--json"}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j["irradiance"].size(), std::size(sglab::irradiance_methods));
  for (std::size_t i = 0; i < std::size(sglab::irradiance_methods); ++i) {
    const sglab::Method& m = sglab::irradiance_methods[i];
    const auto& e = j["irradiance"][i];
    EXPECT_EQ(e["id"], std::string(m.id));
    EXPECT_EQ(e["origin"], std::string(sglab::to_string(m.origin)));
    EXPECT_EQ(e["source"], std::string(m.source));
    EXPECT_EQ(e["summary"], std::string(m.summary));
    EXPECT_EQ(e["form"], std::string(m.form));
    EXPECT_EQ(e["half"], std::string(m.half));
    EXPECT_EQ(e["per_light_split"], m.light_setup32 != nullptr);
    // Every irradiance card says what the method is, where it comes from and its form.
    EXPECT_FALSE(m.summary.empty() || m.source.empty() || m.form.empty()) << m.id;
    for (const auto& set : e["constants"]) {
      // Every constant set named is one that the generated header defines (its JSON exists).
      bool found = false;
      for (const auto& file : std::filesystem::directory_iterator(
               std::filesystem::path(SGLAB_TEST_SOURCE_DIR) / ".." / "data" / "constants"))
        found = found || nlohmann::json::parse(std::ifstream(file.path()))["cpp_name"] == set;
      EXPECT_TRUE(found) << m.id << ": constant set " << set << " not in data/constants";
    }
  }
  EXPECT_EQ(j["hemispherical"].size(), std::size(sglab::hemispherical_methods));
  EXPECT_EQ(j["erf"].size(), std::size(sglab::erf_variants));
  std::size_t sglab_origin = 0, registered = 0;
  for (const auto& e : j["irradiance"]) sglab_origin += e["origin"] == "sglab";
  for (const sglab::Method& m : sglab::irradiance_methods)
    registered += m.origin == sglab::Origin::sglab;
  EXPECT_EQ(sglab_origin, registered);
}

// `sglab methods --format md`: one table row per irradiance card, its cells the card's text
// ('|' escaped, test_support.hpp markdown_cells reads it back).
TEST(MethodsCommand, MarkdownHasOneRowPerCard) {
  const auto r = run_sglab({"methods", "--format", "md"}, false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, std::vector<std::string>> rows;
  std::istringstream in(r.output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::vector<std::string> c = sglab::test::markdown_cells(line);
    if (c.size() != 10) continue;  // the hemispherical and erf tables
    EXPECT_TRUE(rows.emplace(c[0], c).second) << "two rows for " << c[0];
  }
  ASSERT_EQ(rows.size(), std::size(sglab::irradiance_methods)) << r.output;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    const auto it = rows.find(fmt::format("`{}`", m.id));
    ASSERT_NE(it, rows.end()) << m.id;
    const auto& c = it->second;
    EXPECT_EQ(c[1], sglab::to_string(m.origin));
    EXPECT_EQ(c[2], m.summary);
    EXPECT_EQ(c[3], m.form);
    EXPECT_EQ(c[4], m.source);
    EXPECT_EQ(c[6], m.has_split() ? "yes" : "no");
    EXPECT_EQ(c[7], m.half.empty() ? "–" : std::string(m.half));
  }
}

}  // namespace
