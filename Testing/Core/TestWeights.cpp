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
  EXPECT_THROW(ResolveWeights(WeightMode::Normalize, { 1.5, -0.5 }), InputError);
  EXPECT_THROW(ResolveWeights(WeightMode::Normalize, { -0.1, 0.6, 0.5 }), InputError);
}

// Java3D's Morph checks only that the weights sum to 1 (within 1e-4): a negative neutral,
// 1 - sum of expression weights summing above 1, is accepted there and so in Strict mode.
TEST(Weights, StrictAcceptsNegativeWeightsSummingToOneAsJava3DDoes)
{
  const std::vector<double> negativeNeutral{ -0.2, 0.7, 0.5 };
  EXPECT_EQ(ResolveWeights(WeightMode::Strict, negativeNeutral), negativeNeutral);
  const std::vector<double> negativeTargets{ 1.3, -0.1, -0.2 };
  EXPECT_EQ(ResolveWeights(WeightMode::Strict, negativeTargets), negativeTargets);
  EXPECT_NO_THROW(ResolveWeights(WeightMode::Strict, { 1.5, -0.5 }));
  // The sum rule still holds for them: off by 2e-4 is an error.
  EXPECT_THROW(ResolveWeights(WeightMode::Strict, { 1.3, -0.1, -0.1998 }), InputError);
  EXPECT_THROW(ResolveWeights(WeightMode::Strict, { -0.2, 0.7, 0.5002 }), InputError);
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
