// Included by the suites that run fits: the process fails when any fit it ran
// evaluated a NaN or ±inf residual or derivative (fit/minimax.hpp,
// nonfinite_residual_evaluations). Such a residual is a defect of the model or
// of its search space, which Ceres would otherwise log and step around.
#pragma once

#include <gtest/gtest.h>

#include "fit/minimax.hpp"

namespace sglab::test {

class FiniteResidualsEnvironment final : public ::testing::Environment {
 public:
  void TearDown() override {
    EXPECT_EQ(sglab::fit::nonfinite_residual_evaluations(), 0u)
        << "a fit in this process evaluated a NaN or inf residual (a model defect on the search "
           "space)";
  }
};

inline ::testing::Environment* const kFiniteResiduals =
    ::testing::AddGlobalTestEnvironment(new FiniteResidualsEnvironment);

}  // namespace sglab::test
