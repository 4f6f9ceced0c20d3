// `sglab methods` (app/cmd_methods.cpp): its JSON lists every registered
// method with the registry's id, origin, source, split and constant sets.
#include <filesystem>
#include <fstream>
#include <string>

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
    EXPECT_EQ(e["per_light_split"], m.light_setup32 != nullptr);
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

}  // namespace
