// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file WeightOptimizer.h
/// @brief The paper's weight optimizer (sections 4 and 5) and what goes beyond it.
///
/// Works on absolute weights w_0..w_n (w_0 = neutral) that sum to 1 and returns effective
/// weights that still sum to 1 (the Java3D rule), with fewer non-zero entries:
///
/// 1. Threshold (paper, section 4): every weight with |w_i| < th_i becomes 0, where
///    th_i = th_fix, or th_fix * (1 - dist_norm_i) with AdjustThreshold (section 5). The
///    largest weight is never pruned, so a frame never loses all its weight.
/// 2. Budget (MaxActiveTargets = k): if more than k non-neutral targets remain, only the k
///    with the largest geometric contribution |w_i| * M_i stay (M_i: the target's largest
///    vertex displacement), not the k largest raw weights.
/// 3. Error bound (MaxVertexError = eps): no vertex may end farther than eps from the
///    unoptimized result, redistribution included. With the result
///    R(v) = G_0(v) + sum_{i>0} w_i D_i(v) and D_i = G_i - G_0, changing w to w' moves a vertex
///    by E(v) = sum_{i>0} (w'_i - w_i) D_i(v), hence
///        |E(v)| <= B = sum_{i>0} |w'_i - w_i| * M_i          (triangle inequality)
///    The neutral's weight does not appear: handing weight to the neutral is free.
///    Alone, the bound prunes greedily (cheapest |w_i| M_i first) while B <= eps. With a
///    threshold or budget, it restores the most expensive pruned targets until B <= eps,
///    and a pruned neutral last: the bound always wins over the budget.
/// 4. Redistribution of the pruned weight m = sum of pruned w_i:
///    - Maximum (paper's strategy 1): the largest remaining weight gets all of m.
///    - Remaining (paper's strategy 2, "balanced"): each remaining w_j gets m * |w_j| / S,
///      S the sum of the remaining |w_j|. For non-negative weights (the paper's) this keeps
///      their ratios; with relative weights summing above 1 the neutral's weight is
///      negative, and sizes instead of signed values keep the shares bounded.
///    - Neutral (beyond the paper): w_0 gets m; geometrically this is glTF's "drop small
///      weights", whose error is just sum of pruned w_i D_i.
/// 5. Hysteresis h: a target shown in the previous frame (an incumbent: non-zero effective
///    weight) keeps its place unless a criterion beats it by the margin h, in every step,
///    so a weight hovering around a decision's edge does not flicker (the "holes over
///    time" of the paper's Figure 5):
///    - threshold: an incumbent is pruned only below th_i * (1 - h);
///    - budget: targets are ranked by c_i = |w_i| M_i, an incumbent's by c_i / (1 - h), so
///      an outsider takes the k-th place only when c_out * (1 - h) > c_in;
///    - error bound: the guarantee B <= eps is never loosened; the band lies below it. An
///      incumbent is pruned only while B stays within eps * (1 - h) (alone: greedily,
///      incumbents tried last; with a threshold or budget: incumbents that those pruned are
///      restored while B > eps * (1 - h), which, like the bound, wins over the budget); a
///      target pruned in the previous frame is restored only when B > eps.
///    The history (which targets were shown) lives in the optimizer and is the last
///    Optimize call's result; SetTargetDistances and ResetHistory clear it (then there are
///    no incumbents), SetSettings keeps it. h = 0 gives exactly the decisions without it.

#include "morph/Distances.h"

#include <vector>

namespace morphnode
{
enum class Redistribution
{
  Maximum,
  Remaining,
  Neutral
};

const char* RedistributionName(Redistribution strategy);

struct OptimizerSettings
{
  double Threshold = 0.0; ///< th_fix; 0 turns thresholding off
  Redistribution Strategy = Redistribution::Remaining;
  bool AdjustThreshold = false; ///< th_adj = th_fix * (1 - dist_norm)
  double MaxVertexError = 0.0;  ///< model units; 0 = no bound
  int MaxActiveTargets = 0;     ///< 0 = no budget
  double Hysteresis = 0.0;      ///< in [0, 1)

  bool IsActive() const
  {
    return this->Threshold > 0.0 || this->MaxVertexError > 0.0 || this->MaxActiveTargets > 0;
  }
};

class WeightOptimizer
{
public:
  /// Throws InputError on negative or non-finite values, or hysteresis outside [0, 1).
  void SetSettings(const OptimizerSettings& settings);
  const OptimizerSettings& GetSettings() const { return this->Settings; }
  const TargetDistances& GetTargetDistances() const { return this->Distances; }

  /// DistNorm (for the adjusted threshold) and MaxDisplacement (for the bound and the
  /// budget) per target. Clears the hysteresis history.
  void SetTargetDistances(const TargetDistances& distances);

  /// Absolute weights (summing to 1) to effective weights (summing to 1).
  /// Throws InputError when the weight count differs from the target count.
  std::vector<double> Optimize(const std::vector<double>& absolute);

  /// Bound B on the vertex error of the last Optimize call.
  double GetLastErrorBound() const { return this->LastErrorBound; }
  /// Forget which targets were active (hysteresis), e.g. after a jump in time.
  void ResetHistory() { this->WasActive.clear(); }

  /// B = sum_{i>0} |effective_i - original_i| * maxDisplacement_i.
  static double ErrorBound(const std::vector<double>& original,
    const std::vector<double>& effective, const std::vector<double>& maxDisplacement);
  /// Zeroes the weights not kept and hands their sum on by `strategy`.
  static std::vector<double> Redistribute(
    const std::vector<double>& absolute, const std::vector<bool>& keep, Redistribution strategy);

private:
  double Bound(const std::vector<double>& w, const std::vector<bool>& keep) const;

  OptimizerSettings Settings;
  TargetDistances Distances;
  std::vector<bool> WasActive;
  double LastErrorBound = 0.0;
};
} // namespace morphnode
