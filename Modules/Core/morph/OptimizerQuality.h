// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file OptimizerQuality.h
/// @brief The paper's future work, done: the quality of an optimized animation measured as
/// vertex error against the unoptimized one, frame by frame.

#include "morph/MorphAttribute.h"
#include "morph/WeightOptimizer.h"
#include "track/WeightTrack.h"

#include <string>
#include <vector>

namespace morphnode
{
/// One optimization method: a name for tables and its settings.
struct OptimizerMethod
{
  std::string Name; ///< e.g. "fixed-maximum 0.2"
  OptimizerSettings Settings;
};

/// What one frame cost and how far it strayed.
struct FrameQuality
{
  int ActiveTargets = 0;       ///< non-neutral targets with a non-zero weight
  double RmsError = 0.0;       ///< over all vertices, model units
  double MaxError = 0.0;       ///< largest vertex distance, model units
  double ErrorBound = 0.0;     ///< the optimizer's bound (>= MaxError)
  double MorphSeconds = 0.0;   ///< time of the blend with the optimized weights
  std::vector<double> Weights; ///< effective absolute weights, neutral first
};

/// Runs every frame of `absoluteWeights` (one channel per target, neutral first, each
/// frame summing to 1) through the method and compares each optimized blend with the
/// unoptimized one. `positions` is the face's position attribute.
std::vector<FrameQuality> MeasureOptimizerQuality(const MorphAttribute<float>& positions,
  const TargetDistances& distances, const WeightTrack& absoluteWeights,
  const OptimizerMethod& method);

/// Turns relative (glTF) target weights into absolute weights: a "Neutral" channel first,
/// 1 - sum of the others. Channels are reordered to `targetNames` (neutral first);
/// targets missing from the track get 0; unknown channels are an InputError.
WeightTrack ToAbsoluteWeights(
  const WeightTrack& relative, const std::vector<std::string>& targetNames);
} // namespace morphnode
