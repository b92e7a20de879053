// SPDX-License-Identifier: BSD-3-Clause
#include "morph/WeightDecision.h"

#include <utility>

namespace morphnode
{
void WeightDecision::SetOptimizerSettings(const OptimizerSettings& settings)
{
  this->Optimizer.SetSettings(settings);
}

void WeightDecision::SetOptimizerPreset(
  OptimizerPreset preset, double threshold, double maxVertexError)
{
  OptimizerSettings settings = MakeOptimizerSettings(preset, threshold, maxVertexError);
  settings.MaxActiveTargets = this->Optimizer.GetSettings().MaxActiveTargets;
  settings.Hysteresis = this->Optimizer.GetSettings().Hysteresis;
  this->Optimizer.SetSettings(settings);
}

void WeightDecision::SetTargetDistances(TargetDistances distances)
{
  this->Optimizer.SetTargetDistances(std::move(distances));
}

const std::vector<double>& WeightDecision::Decide(const double* requested, size_t count)
{
  this->ClearDecision();
  ResolveWeights(this->Mode, requested, count, this->Absolute);
  double bound = 0.0;
  if (this->Optimizer.GetSettings().IsActive())
  {
    this->Effective = this->Optimizer.Optimize(this->Absolute);
    bound = this->Optimizer.GetLastErrorBound();
  }
  else
  {
    this->Effective.assign(this->Absolute.begin(), this->Absolute.end());
  }
  this->ErrorBound = bound;
  this->ActiveTargets = CountActiveTargets(this->Effective);
  return this->Effective;
}

void WeightDecision::ClearDecision()
{
  this->Effective.clear();
  this->ErrorBound = 0.0;
  this->ActiveTargets = 0;
}
} // namespace morphnode
