// SPDX-License-Identifier: BSD-3-Clause
#include "StudyMethods.h"

#include "morph/OptimizerPresets.h"

#include <sstream>

namespace morphnode
{
namespace study
{
namespace
{
std::string Label(const std::string& what, double value)
{
  std::ostringstream s;
  s << what << " " << value;
  return s.str();
}

OptimizerMethod Preset(OptimizerPreset preset, double threshold, double bound, double label)
{
  return { Label(OptimizerPresetName(preset), label),
    MakeOptimizerSettings(preset, threshold, bound) };
}
} // namespace

std::vector<OptimizerMethod> StudyMethods(const std::vector<double>& thresholds,
  const std::vector<double>& errorBounds, const std::vector<int>& budgets)
{
  std::vector<OptimizerMethod> methods{ { OptimizerPresetName(OptimizerPreset::None),
    MakeOptimizerSettings(OptimizerPreset::None, 0.0, 0.0) } };
  for (double th : thresholds)
  {
    for (auto preset :
      { OptimizerPreset::FixedMaximum, OptimizerPreset::FixedRemaining, OptimizerPreset::Adjusted })
    {
      methods.push_back(Preset(preset, th, 0.0, th));
    }
  }
  for (double eps : errorBounds)
  {
    methods.push_back(Preset(OptimizerPreset::ErrorBounded, 0.0, eps, eps));
  }
  for (int k : budgets)
  {
    OptimizerSettings s;
    s.MaxActiveTargets = k;
    s.Strategy = Redistribution::Neutral;
    s.Hysteresis = 0.25;
    methods.push_back({ Label("budget", k), s });
  }
  return methods;
}

std::vector<OptimizerMethod> SweepMethods(double step, double largest)
{
  std::vector<OptimizerMethod> methods;
  for (int k = 1; step > 0.0 && k * step <= largest + 1e-9; ++k)
  {
    methods.push_back(Preset(OptimizerPreset::FixedRemaining, k * step, 0.0, k * step));
    methods.push_back(Preset(OptimizerPreset::Adjusted, k * step, 0.0, k * step));
  }
  return methods;
}

std::string MethodFamily(const std::string& name)
{
  return name.substr(0, name.find(' '));
}
} // namespace study
} // namespace morphnode
