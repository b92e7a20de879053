// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StudyMethods.h
/// @brief The methods OptimizerStudy compares (docs/optimizer-study.md), named by the
/// optimizer presets of morph/OptimizerPresets.h and their parameter: "none",
/// "fixed-maximum 0.1", "fixed-remaining 0.1", "adjusted 0.1", "error-bounded 0.0005",
/// and "budget 4" (no preset: at most k targets by geometric contribution, neutral
/// redistribution, hysteresis 0.25).

#include "morph/OptimizerQuality.h"

#include <vector>

namespace morphnode
{
namespace study
{
/// none; fixed-maximum, fixed-remaining and adjusted at each threshold; error-bounded at
/// each bound (model units); the budget for each count.
std::vector<OptimizerMethod> StudyMethods(const std::vector<double>& thresholds,
  const std::vector<double>& errorBounds, const std::vector<int>& budgets);

/// fixed-remaining and adjusted at thresholds step, 2 step, ... up to `largest`: the
/// curves that compare them at an equal number of active targets. Empty for step <= 0.
std::vector<OptimizerMethod> SweepMethods(double step, double largest = 0.7);

/// The family of a method's name (its first word): "adjusted 0.3" -> "adjusted".
std::string MethodFamily(const std::string& name);
} // namespace study
} // namespace morphnode
