// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Distances.h
/// @brief How far each morph target moves the face from the neutral (the paper's
/// section 5, Table 1 and Figure 4).

#include "morph/MorphAttribute.h"

#include <vector>

namespace morphnode
{
/// Per-target distance figures, indexed by target (0 = neutral, always 0).
struct TargetDistances
{
  /// dist_morph(T_n, T_i) = sum over vertices of |v(T_i) - v(T_n)|.
  std::vector<double> DistMorph;
  /// DistMorph / max DistMorph: the paper's dist_norm (all 0 when nothing moves).
  std::vector<double> DistNorm;
  /// Largest single-vertex displacement M_i = max_v |v(T_i) - v(T_n)|: bounds the
  /// geometric effect of changing the weight of target i (see WeightOptimizer).
  std::vector<double> MaxDisplacement;
};

template <typename T>
TargetDistances ComputeTargetDistances(const MorphAttribute<T>& positions);

/// DistNorm from DistMorph: each target's DistMorph over the largest (the neutral, index 0,
/// left at 0; all 0 when nothing moves). The one computation of the paper's dist_norm, so
/// that a whole model (MakeTargetDistances) and one mesh give the same figures bit for bit.
void NormalizeDistances(TargetDistances& distances);

/// Per-vertex |v(T_i) - v(T_n)| for one target (i >= 1), the paper's Figure 4.
template <typename T>
std::vector<double> ComputePointDistances(const MorphAttribute<T>& positions, size_t target);

/// Per-vertex animated region: the largest distance a vertex moves over all targets.
template <typename T>
std::vector<double> ComputeAnimatedRegion(const MorphAttribute<T>& positions);
} // namespace morphnode
