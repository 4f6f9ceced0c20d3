// The generated runtime header agrees with data/constants/*.json, the
// published constants are the published digits, and sglab's own models have
// the errors their fits recorded.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sglab/constants.hpp>
#include <sglab/registry.hpp>

#include "common/io.hpp"
#include "fit/constants_io.hpp"
#include "fit/model_family.hpp"
#include "tests/test_support.hpp"

namespace {

// The checkout's files, named explicitly (the tests run in the build folder).
using sglab::test::kRoot;

TEST(Constants, HeaderMatchesJson) {
  const auto sets = sglab::fit::load_constant_sets(kRoot / "data" / "constants");
  ASSERT_FALSE(sets.empty());
  const std::string want = sglab::fit::render_constants_header(sets);
  const std::string have = sglab::io::read_file(kRoot / "include" / "sglab" / "constants.hpp");
  EXPECT_EQ(have, want)
      << "include/sglab/constants.hpp is stale: run `build/sglab constants --write-header`";
}

TEST(Constants, PublishedValuesAreThePublishedDigits) {
  // [Tokuyoshi2022] Listings 1 and 3; [Tokuyoshi2024].
  EXPECT_EQ(sglab::constants::clamped_cosine_published.lambda, 0.00084560872241480124);
  EXPECT_EQ(sglab::constants::clamped_cosine_published.alpha, 1182.2467339678153);
  EXPECT_EQ(sglab::constants::steepness2022_published.A, 0.65173288269070562);
  EXPECT_EQ(sglab::constants::steepness2022_published.B, 1.3418280033141288);
  EXPECT_EQ(sglab::constants::steepness2022_published.C, 7.2216687798956709);
  EXPECT_EQ(sglab::constants::steepness2024_published.A, 2.7360831611272558);
  EXPECT_EQ(sglab::constants::steepness2024_published.E, 76.087896272360737);
  EXPECT_EQ(sglab::constants::erf_as7125_published.p, 0.47047);
  EXPECT_EQ(sglab::constants::erf_listing5_published.large[6], 2.58907676e-5);
}

// Each of sglab's own models, at the coefficients the runtime compiles in (the header, tied
// to the JSON by HeaderMatchesJson), has the errors its fit recorded in the JSON's provenance:
// the max peak_rel in double on the held-out grid and on the standard grid, measured again
// here as the fitter measures (fit/model_family.hpp), and within the bound its registry card
// states. A coefficient changed after the fit, in the JSON and the header alike, moves them
// (a[0] of sglab_mid moved in its 5th digit fails both recorded maxima).
TEST(Constants, SglabModelsHaveTheErrorsTheirFitRecorded) {
  const sglab::fit::MeasuringGrids grids = sglab::fit::measuring_grids(sglab::fit::FitSpec{});
  const auto sets = sglab::fit::load_constant_sets(kRoot / "data" / "constants");
  std::size_t models = 0;
  for (const sglab::Method& m : sglab::irradiance_methods) {
    if (m.origin != sglab::Origin::sglab) continue;
    ++models;
    // one set, the one whose cpp_name the card names
    const auto set = std::find_if(sets.begin(), sets.end(), [&m](const auto& s) {
      return s.at("cpp_name").template get<std::string>() == m.constants;
    });
    ASSERT_NE(set, sets.end()) << m.id << ": no constant set named " << m.constants;
    const auto& achieved = set->at("provenance").at("achieved");
    const auto model = [&m](auto c, auto k) {
      if constexpr (std::is_same_v<decltype(c), float>)
        return double(m.f32(c, k));
      else
        return m.f64(c, k);
    };
    const auto held_out = sglab::fit::measure(model, grids.held_out);
    const auto standard = sglab::fit::measure(model, grids.standard);
    EXPECT_EQ(achieved.at("held_out_grid"), grids.held_out_name) << m.id;
    // the held-out points are none of the fit's: its registry card's bound holds on them
    EXPECT_LE(std::max(held_out.float_max, held_out.double_max), m.valid.max_peak_rel) << m.id;
    for (const auto& [measured, key] :
         {std::pair{held_out.double_max, "held_out_max_peak_rel_double"},
          std::pair{standard.double_max, "standard_max_peak_rel_double"}}) {
      const double recorded = achieved.at(key).get<double>();
      EXPECT_NEAR(measured, recorded, 1e-9 * recorded) << m.id << " " << key;
    }
  }
  EXPECT_GE(models, 6u);
}

TEST(Constants, MalformedJsonIsRejectedNamingTheFile) {
  namespace fs = std::filesystem;
  const sglab::test::TempDir tmp("constants");
  const fs::path& dir = tmp.path;
  // Both carry the format tag: damaged constant sets, refused (not skipped as foreign files).
  sglab::io::write_file_atomic(dir / "bad.json",
                               "{\"format\": \"sglab-constants\", \"target\": \"x\",");
  try {
    sglab::fit::load_constant_sets(dir);
    FAIL() << "malformed JSON accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  sglab::io::write_file_atomic(
      dir / "bad.json",
      R"({"format":"sglab-constants","version":1,"target":"t","variant":"v","cpp_name":"1x","cpp_type":"T","form":"f",
                                  "coefficients":{"a":1},"provenance":{}})");
  EXPECT_THROW(sglab::fit::load_constant_sets(dir), std::runtime_error);
  const auto r = sglab::test::run_sglab({"constants", "--dir", dir.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
}

}  // namespace
