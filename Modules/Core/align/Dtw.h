// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Dtw.h
/// @brief Dynamic time warping of two feature sequences with a slope constraint that
/// silence may break, in windows around a coarse path for long sequences.
///
/// Steps (Sakoe & Chiba's symmetric pattern with slope constraint P = 1, local slope between
/// 1/2 and 2): (1,1) weighted 2d, (1,2) and (2,1) through their middle cell. A silent frame
/// may be held while the other sequence advances (steps (0,1) and (1,0), weight d plus a
/// penalty): pauses of any length match, speech keeps a bounded tempo. Sequences whose full
/// matrix exceeds MaximumCells are solved at half resolution first (recursively), then only
/// within Radius frames of that path (as FastDTW does): memory and time grow linearly.

#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace morphnode
{
/// Rows of equal dimension, row-major.
struct FeatureMatrix
{
  size_t Rows = 0;
  int Dimension = 0;
  std::vector<float> Values;
  const float* Row(size_t i) const
  {
    return this->Values.data() + i * static_cast<size_t>(this->Dimension);
  }
};

struct DtwOptions
{
  bool SlopeConstraint = true;   ///< off: plain symmetric steps (0,1) (1,0) (1,1) everywhere
  double SilencePenalty = 0.0;   ///< added to each held-silence step, in local-distance units
  size_t MaximumCells = 4000000; ///< above: coarse-to-fine windows
  int Radius = 16;               ///< frames around the projected coarse path
  /// Called with the fraction done; returning false cancels (InputError "cancelled").
  std::function<bool(double)> Progress;
};

struct DtwResult
{
  std::vector<std::pair<size_t, size_t>> Path; ///< (row of A, row of B), from (0,0) to the ends
  double MeanDistance = 0.0;                   ///< mean local distance along the path
  size_t CellsEvaluated = 0;                   ///< work done, all levels
};

/// Aligns A to B (Euclidean local distance). `silentA` / `silentB` (empty or one flag per
/// row) mark the rows that may be held. InputError for empty or mismatched input, or when
/// no path satisfies the constraints (then retry without them).
DtwResult AlignFeatures(const FeatureMatrix& a, const FeatureMatrix& b,
  const std::vector<bool>& silentA, const std::vector<bool>& silentB,
  const DtwOptions& options = {});
} // namespace morphnode
