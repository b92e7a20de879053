// SPDX-License-Identifier: BSD-3-Clause
#include "base/Error.h"
#include "morph/Weights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace morphnode;

TEST(Weights, StrictAcceptsJava3DWeightsAsGiven)
{
  const auto w = ResolveWeights(WeightMode::Strict, { 0.5, 0.25, 0.25 });
  EXPECT_EQ(w, (std::vector<double>{ 0.5, 0.25, 0.25 }));
  // Within Java3D's tolerance of 1e-4.
  EXPECT_NO_THROW(ResolveWeights(WeightMode::Strict, { 0.50005, 0.5 }));
}

TEST(Weights, StrictRejectsASumOffOne)
{
  EXPECT_THROW(ResolveWeights(WeightMode::Strict, { 0.5, 0.6 }), InputError);
  EXPECT_THROW(ResolveWeights(WeightMode::Strict, { 0.5, 0.4998 }), InputError);
}

TEST(Weights, NormalizeDividesBySum)
{
  const auto w = ResolveWeights(WeightMode::Normalize, { 1.0, 1.0, 2.0 });
  EXPECT_DOUBLE_EQ(w[0], 0.25);
  EXPECT_DOUBLE_EQ(w[1], 0.25);
  EXPECT_DOUBLE_EQ(w[2], 0.5);
  EXPECT_THROW(ResolveWeights(WeightMode::Normalize, { 0.0, 0.0 }), InputError);
}

TEST(Weights, RelativeIgnoresNeutralAndReportsTheRest)
{
  const auto w = ResolveWeights(WeightMode::Relative, { 7.0, 0.5, 0.75 });
  EXPECT_DOUBLE_EQ(w[0], 1.0 - 1.25);
  EXPECT_DOUBLE_EQ(w[1], 0.5);
  EXPECT_DOUBLE_EQ(w[2], 0.75);
  EXPECT_NO_THROW(ResolveWeights(WeightMode::Relative, { 1.0, -0.5 }));
}

TEST(Weights, RejectsNonFiniteAndNegativeWeights)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (WeightMode mode : { WeightMode::Strict, WeightMode::Normalize, WeightMode::Relative })
  {
    EXPECT_THROW(ResolveWeights(mode, { 1.0, nan }), InputError) << WeightModeName(mode);
    EXPECT_THROW(ResolveWeights(mode, { 1.0, inf }), InputError) << WeightModeName(mode);
    EXPECT_THROW(ResolveWeights(mode, {}), InputError) << WeightModeName(mode);
  }
  EXPECT_THROW(ResolveWeights(WeightMode::Strict, { 1.5, -0.5 }), InputError);
  EXPECT_THROW(ResolveWeights(WeightMode::Normalize, { 1.5, -0.5 }), InputError);
}

TEST(Weights, ErrorMessagesNameTheWeight)
{
  try
  {
    ResolveWeights(WeightMode::Normalize, { 1.0, 0.0, std::nan("") });
    FAIL() << "no error";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("weight 2"), std::string::npos) << e.what();
  }
}

TEST(Weights, CountsActiveNonNeutralTargets)
{
  EXPECT_EQ(CountActiveTargets({ 1.0, 0.0, 0.0 }), 0);
  EXPECT_EQ(CountActiveTargets({ 0.0, 0.5, 0.0, 0.5 }), 2);
}
