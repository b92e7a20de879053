// SPDX-License-Identifier: BSD-3-Clause
#include "OptimizerSetup.h"

#include "vtkMorphNodeFilter.h"

namespace morphnode
{
namespace appkit
{
void ApplyOptimizerSettings(vtkMorphNodeFilter* filter, const OptimizerSettings& s)
{
  filter->SetThreshold(s.Threshold);
  switch (s.Strategy)
  {
    case Redistribution::Maximum:
      filter->SetRedistributionStrategyToMaximum();
      break;
    case Redistribution::Remaining:
      filter->SetRedistributionStrategyToRemaining();
      break;
    case Redistribution::Neutral:
      filter->SetRedistributionStrategyToNeutral();
      break;
  }
  filter->SetAdjustThreshold(s.AdjustThreshold);
  filter->SetMaxVertexError(s.MaxVertexError);
  filter->SetMaxActiveTargets(s.MaxActiveTargets);
  filter->SetHysteresis(s.Hysteresis);
  filter->ResetHysteresis();
}
} // namespace appkit
} // namespace morphnode
