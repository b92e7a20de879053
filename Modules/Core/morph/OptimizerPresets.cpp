// SPDX-License-Identifier: BSD-3-Clause
#include "morph/OptimizerPresets.h"

#include "base/Error.h"
#include "base/Text.h"

namespace morphnode
{
namespace
{
struct PresetText
{
  const char* Name;
  const char* Label;
};
constexpr PresetText Texts[NumberOfOptimizerPresets] = {
  { "none", "none (all targets)" },
  { "fixed-maximum", "fixed threshold + maximum" },
  { "fixed-remaining", "fixed threshold + remaining" },
  { "adjusted", "adjusted threshold + remaining" },
  { "error-bounded", "error-bounded" },
};
} // namespace

const char* OptimizerPresetName(OptimizerPreset preset)
{
  return Texts[static_cast<int>(preset)].Name;
}

const char* OptimizerPresetLabel(OptimizerPreset preset)
{
  return Texts[static_cast<int>(preset)].Label;
}

OptimizerPreset ParseOptimizerPreset(const std::string& textIn)
{
  const std::string lower = text::ToLower(text::Trim(textIn));
  for (int i = 0; i < NumberOfOptimizerPresets; ++i)
  {
    if (lower == Texts[i].Name || lower == std::to_string(i))
    {
      return static_cast<OptimizerPreset>(i);
    }
  }
  std::string names;
  for (int i = 0; i < NumberOfOptimizerPresets; ++i)
  {
    names += std::string(i ? ", " : "") + std::to_string(i) + "|" + Texts[i].Name;
  }
  throw InputError("unknown optimizer method " + text::Quote(textIn) + " (known: " + names + ")");
}

OptimizerSettings MakeOptimizerSettings(
  OptimizerPreset preset, double threshold, double maxVertexError)
{
  OptimizerSettings s;
  switch (preset)
  {
    case OptimizerPreset::None:
      break;
    case OptimizerPreset::FixedMaximum:
      s.Threshold = threshold;
      s.Strategy = Redistribution::Maximum;
      break;
    case OptimizerPreset::FixedRemaining:
      s.Threshold = threshold;
      s.Strategy = Redistribution::Remaining;
      break;
    case OptimizerPreset::Adjusted:
      s.Threshold = threshold;
      s.Strategy = Redistribution::Remaining;
      s.AdjustThreshold = true;
      break;
    case OptimizerPreset::ErrorBounded:
      s.MaxVertexError = maxVertexError;
      s.Strategy = Redistribution::Neutral;
      break;
  }
  return s;
}
} // namespace morphnode
