// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Weights.h
/// @brief Weight rules of the morph node: Java3D's absolute weights and glTF's relative ones.
///
/// Every mode resolves the user's weights to *absolute* weights w_0..w_n (w_0 = neutral)
/// that sum to 1, so that result = sum w_i G_i = G_0 + sum_{i>0} w_i (G_i - G_0).
/// The blending kernels work on the right-hand (relative) form, where the neutral is free.

#include <string>
#include <vector>

namespace morphnode
{
enum class WeightMode
{
  /// Java3D Morph: weights are used as given; |sum - 1| > StrictTolerance is an error.
  /// Like Java3D, only the sum is checked: negative weights are accepted (e.g. the
  /// neutral's 1 - sum when expression weights sum above 1).
  Strict,
  /// Weights are divided by their sum; a sum <= 0 is an error. The default.
  Normalize,
  /// glTF: result = neutral + sum_{i>0} w_i (target_i - neutral); w_0 is ignored and
  /// reported as 1 - sum_{i>0} w_i. No constraint on the sum; negative weights allowed
  /// (glTF allows them).
  Relative
};

/// Java3D's tolerance for the sum of the weights.
constexpr double StrictTolerance = 1e-4;

const char* WeightModeName(WeightMode mode);

/// Resolves requested weights (neutral first) to absolute weights summing to 1.
/// Throws InputError for: an empty vector, NaN or infinite weights, negative weights
/// (Normalize only), a sum off 1 (Strict), a sum <= 0 (Normalize).
std::vector<double> ResolveWeights(WeightMode mode, const std::vector<double>& requested);
/// The same into `absolute` (resized to `count`), so that a caller resolving weights every
/// frame allocates nothing once `absolute` has the capacity.
void ResolveWeights(
  WeightMode mode, const double* requested, size_t count, std::vector<double>& absolute);

/// Number of non-neutral targets with a non-zero weight: the targets that cost work.
int CountActiveTargets(const std::vector<double>& absolute);
} // namespace morphnode
