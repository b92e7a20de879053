// SPDX-License-Identifier: BSD-3-Clause
#include "budget/SceneBudgetController.h"

#include "morph/Weights.h"

#include <algorithm>
#include <utility>
#include <variant>

namespace morphnode
{
CostModel SceneBudgetController::FirstGuessCost()
{
  CostModel cost;
  cost.Fixed = 50e-6;
  cost.PerTargetPoint = 2e-9;
  return cost;
}

std::vector<double> SceneBudgetController::MovedPoints(const MorphScene* scene, size_t numTargets)
{
  std::vector<double> moved(numTargets + 1, 0.0);
  double points = 0.0;
  for (size_t p = 0; scene && p < scene->GetNumberOfParts(); ++p)
  {
    const MorphMesh& mesh = scene->GetPart(p);
    const std::vector<size_t>& targets = scene->GetPartTargets(p);
    points += static_cast<double>(mesh.GetNumberOfPoints());
    std::visit(
      [&](const auto& positions)
      {
        for (size_t k = 1; k < positions.GetNumberOfTargets() && k < targets.size(); ++k)
        {
          if (targets[k] < numTargets)
          {
            moved[targets[k]] +=
              static_cast<double>(positions.GetTarget(k).GetNumberOfMovedPoints());
          }
        }
      },
      mesh.GetAttribute(0));
  }
  moved.back() = points;
  return moved;
}

void SceneBudgetController::SetModel(uint64_t generation, std::vector<double> movedPoints)
{
  this->Generation = generation;
  this->ModelPoints = movedPoints.empty() ? 0.0 : movedPoints.back();
  if (!movedPoints.empty())
  {
    movedPoints.pop_back();
  }
  this->Moved = std::move(movedPoints);
}

std::array<double, 3> SceneBudgetController::GetMeasurement() const
{
  return { this->HasMeasurement ? 1.0 : 0.0, this->MeasuredSeconds, this->MeasuredTargetPoints };
}

void SceneBudgetController::Skip()
{
  this->Decided = false;
  this->HasMeasurement = false;
}

double SceneBudgetController::Decide(MorphScene& scene, const std::vector<double>& requested,
  const Goals& goals, const std::array<double, 3>& measured)
{
  this->Skip();
  const bool sameModel = this->ControllerOf == this->Generation;
  const bool measuredLevel = sameModel && this->Controller.GetNumberOfLevels() > 0;
  if (measuredLevel && measured[0] > 0.0)
  {
    this->Controller.ReportMeasuredSeconds(measured[1], measured[2]);
  }
  const OptimizerSettings settings = scene.GetOptimizerSettings();
  ControllerSettings cs;
  cs.FrameBudget = goals.FrameBudget > 0.0 ? goals.FrameBudget : 1.0; // target LOD alone: no limit
  cs.TargetPixelBound = goals.HasTargetLevelOfDetail() ? goals.TargetPixelBound : 0.0;
  cs.Strategy = settings.Strategy;
  cs.AdjustThreshold = settings.AdjustThreshold;
  cs.OptimizerHysteresis = settings.Hysteresis;
  cs.MaxActiveTargets = settings.MaxActiveTargets;
  cs.MaxVertexError = settings.MaxVertexError;
  cs.GeomorphFrames = 0;
  const ControllerSettings& was = this->Settings;
  if (!measuredLevel || was.FrameBudget != cs.FrameBudget || was.Strategy != cs.Strategy ||
    was.AdjustThreshold != cs.AdjustThreshold ||
    was.OptimizerHysteresis != cs.OptimizerHysteresis ||
    was.MaxActiveTargets != cs.MaxActiveTargets || was.MaxVertexError != cs.MaxVertexError ||
    was.TargetPixelBound != cs.TargetPixelBound)
  {
    // What was measured survives a change of method.
    LevelOfDetail level;
    level.Name = "model";
    level.NumberOfPoints = static_cast<size_t>(this->ModelPoints);
    level.MovedPoints = this->Moved;
    level.Distances = scene.GetTargetDistances();
    level.Cost = measuredLevel ? this->Controller.GetCostModel(0) : FirstGuessCost();
    this->Controller = FrameBudgetController();
    this->Controller.SetSettings(cs);
    this->Controller.AddLevel(level);
    this->Settings = cs;
    this->ControllerOf = this->Generation;
  }
  ResolveWeights(scene.GetWeightMode(), requested.data(), requested.size(), this->Absolute);
  const ControllerDecision decision = this->Controller.Update(
    this->Absolute, goals.HasTargetLevelOfDetail() ? goals.PixelsPerUnit : 0.0);
  OptimizerSettings chosen = settings;
  chosen.Threshold = goals.FrameBudget > 0.0 ? decision.Threshold : settings.Threshold;
  if (decision.TargetErrorBound > 0.0)
  {
    // The target level of detail: the scene's own optimizer keeps the bound.
    chosen.MaxVertexError = chosen.MaxVertexError > 0.0
      ? std::min(chosen.MaxVertexError, decision.TargetErrorBound)
      : decision.TargetErrorBound;
  }
  scene.SetOptimizerSettings(chosen);
  this->Decided = true;
  return goals.FrameBudget > 0.0 ? decision.Threshold : -1.0;
}

void SceneBudgetController::Measure(const MorphScene& scene, double seconds)
{
  this->HasMeasurement = this->Decided;
  this->MeasuredSeconds = seconds;
  double targetPoints = 0.0;
  if (this->Decided)
  {
    const std::vector<double>& w = scene.GetEffectiveWeights();
    for (size_t i = 1; i < w.size() && i < this->Moved.size(); ++i)
    {
      targetPoints += w[i] != 0.0 ? this->Moved[i] : 0.0;
    }
  }
  this->MeasuredTargetPoints = targetPoints;
}
} // namespace morphnode
