// SPDX-License-Identifier: BSD-3-Clause
// The frame budget over a morph scene: moved points per scene target, the first guess, a
// budget nothing fits choosing the coarsest threshold and a generous one the finest, the
// measurement that follows a decision, and the target level of detail's bound.
#include "base/Error.h"
#include "budget/SceneBudgetController.h"
#include "morph/MorphScene.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

using namespace morphnode;

namespace
{
/// A part of `n` points whose target t (of `names`, neutral first) moves the first
/// (t * n / 4) points by t * 0.01.
std::shared_ptr<const MorphMesh> Part(size_t n, const std::vector<std::string>& names)
{
  auto mesh = std::make_shared<MorphMesh>(n);
  mesh->SetTargetNames(names);
  std::vector<float> neutral(3 * n);
  for (size_t i = 0; i < neutral.size(); ++i)
  {
    neutral[i] = static_cast<float>(i % 17);
  }
  auto& points = mesh->AddAttribute<float>("Points", AttributeRole::Position, 3);
  points.SetNeutral(neutral.data());
  for (size_t t = 1; t < names.size(); ++t)
  {
    std::vector<float> delta(3 * n, 0.f);
    for (size_t i = 0; i < t * n / 4; ++i)
    {
      delta[3 * i] = 0.01f * static_cast<float>(t);
    }
    points.AddRelativeTarget(delta.data(), 0.3);
  }
  mesh->Validate();
  return mesh;
}

MorphScene Scene()
{
  MorphScene scene;
  scene.SetParts({ Part(400, { "Neutral", "a", "b", "c" }), Part(200, { "Neutral", "c" }) });
  scene.SetOptimizerSettings(MakeOptimizerSettings(OptimizerPreset::Adjusted, 0.2, 0.0));
  return scene;
}

const std::vector<double> Requested{ 0.25, 0.3, 0.05, 0.4 };
} // namespace

TEST(SceneBudgetController, CountsTheModelsMovedPoints)
{
  const MorphScene scene = Scene();
  const std::vector<double> moved = SceneBudgetController::MovedPoints(&scene, 4);
  // a: 100, b: 200, c: 300 + the second part's 50; then the scene's 600 points.
  EXPECT_EQ(moved, (std::vector<double>{ 0.0, 100.0, 200.0, 350.0, 600.0 }));
  EXPECT_EQ(SceneBudgetController::MovedPoints(nullptr, 4), std::vector<double>(5, 0.0));
  const CostModel guess = SceneBudgetController::FirstGuessCost();
  EXPECT_GT(guess.Fixed, 0.0);
  EXPECT_GT(guess.PerTargetPoint, 0.0);
}

TEST(SceneBudgetController, ABudgetChoosesTheThreshold)
{
  MorphScene scene = Scene();
  SceneBudgetController budget;
  ASSERT_TRUE(budget.NeedsModel(1));
  budget.SetModel(1, SceneBudgetController::MovedPoints(&scene, 4));
  EXPECT_FALSE(budget.NeedsModel(1));
  SceneBudgetController::Goals generous;
  generous.FrameBudget = 1.0;
  EXPECT_EQ(budget.Decide(scene, Requested, generous, budget.GetMeasurement()), 0.0);
  EXPECT_EQ(scene.GetOptimizerSettings().Threshold, 0.0);
  scene.SetWeights(Requested);
  EXPECT_EQ(scene.GetActiveTargetCount(), 3);

  // A measurement follows a decision: the active targets' moved points.
  budget.Measure(scene, 2e-4);
  const auto measured = budget.GetMeasurement();
  EXPECT_EQ(measured[0], 1.0);
  EXPECT_EQ(measured[1], 2e-4);
  EXPECT_EQ(measured[2], 650.0);

  // Nothing fits 1 ns: the cheapest threshold, which leaves targets out.
  SceneBudgetController::Goals tight;
  tight.FrameBudget = 1e-9;
  const double threshold = budget.Decide(scene, Requested, tight, measured);
  EXPECT_GT(threshold, 0.2);
  EXPECT_EQ(scene.GetOptimizerSettings().Threshold, threshold);
  scene.SetWeights(Requested);
  EXPECT_LT(scene.GetActiveTargetCount(), 3);

  // An execution without budget drops the measurement.
  budget.Skip();
  budget.Measure(scene, 1e-4);
  EXPECT_EQ(budget.GetMeasurement()[0], 0.0);
}

TEST(SceneBudgetController, TheTargetLevelOfDetailBoundsTheError)
{
  MorphScene scene = Scene();
  SceneBudgetController budget;
  budget.SetModel(1, SceneBudgetController::MovedPoints(&scene, 4));
  SceneBudgetController::Goals screen;
  screen.TargetPixelBound = 1.0;
  screen.PixelsPerUnit = 100.0; // 1 px = 0.01 units
  EXPECT_EQ(budget.Decide(scene, Requested, screen, budget.GetMeasurement()), -1.0);
  EXPECT_DOUBLE_EQ(scene.GetOptimizerSettings().MaxVertexError, 0.01);
  EXPECT_EQ(scene.GetOptimizerSettings().Threshold, 0.2); // the scene's own without a budget
  EXPECT_THROW(budget.Decide(scene, { 1.0 }, screen, budget.GetMeasurement()), InputError);
}
