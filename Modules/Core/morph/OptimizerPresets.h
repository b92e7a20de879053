// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file OptimizerPresets.h
/// @brief The optimizer methods users pick by name: the paper's three, none, and the
/// error-bounded one. The one place that spells them; programs, the VTK filter, Python and
/// the studies all use these names.

#include "morph/WeightOptimizer.h"

#include <string>

namespace morphnode
{
enum class OptimizerPreset
{
  None,           ///< every target blended
  FixedMaximum,   ///< th_fix, pruned weight to the largest remaining (paper, strategy 1)
  FixedRemaining, ///< th_fix, pruned weight shared by the remaining (paper, strategy 2)
  Adjusted,       ///< th_adj = th_fix * (1 - dist_norm), remaining (paper, section 5)
  ErrorBounded    ///< no vertex farther than eps from the unoptimized result (ours)
};

constexpr int NumberOfOptimizerPresets = 5;

/// "none", "fixed-maximum", "fixed-remaining", "adjusted", "error-bounded".
const char* OptimizerPresetName(OptimizerPreset preset);
/// A label for overlays and plots, e.g. "fixed threshold + maximum".
const char* OptimizerPresetLabel(OptimizerPreset preset);
/// A name above (case-insensitive) or its number "0".."4". Throws InputError otherwise,
/// listing the names.
OptimizerPreset ParseOptimizerPreset(const std::string& text);

/// The settings of a preset: `threshold` is th_fix of the threshold presets,
/// `maxVertexError` the eps of ErrorBounded (model units). Other settings keep their
/// defaults (no budget, no hysteresis).
OptimizerSettings MakeOptimizerSettings(
  OptimizerPreset preset, double threshold, double maxVertexError);
} // namespace morphnode
