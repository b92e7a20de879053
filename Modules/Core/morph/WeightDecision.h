// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file WeightDecision.h
/// @brief What a morph node decides between "here are the weights" and "here is what to
/// blend with", the same for one mesh (MorphNode) and for a head of parts decided as one
/// (MorphScene): the weight mode's rule (morph/Weights.h), then the optimizer
/// (morph/WeightOptimizer.h, a preset from morph/OptimizerPresets.h), giving the effective
/// weights, the optimizer's error bound and the number of active targets.

#include "morph/Distances.h"
#include "morph/OptimizerPresets.h"
#include "morph/WeightOptimizer.h"
#include "morph/Weights.h"

#include <cstddef>
#include <vector>

namespace morphnode
{
class WeightDecision
{
public:
  ///@{
  /// How requested weights become absolute ones (ResolveWeights). Default Normalize.
  void SetWeightMode(WeightMode mode) { this->Mode = mode; }
  WeightMode GetWeightMode() const { return this->Mode; }
  ///@}

  ///@{
  /// The optimizer's settings. Throws InputError for invalid ones (negative threshold or
  /// error, hysteresis outside [0, 1), negative budget) and keeps the previous settings.
  /// Changing settings keeps the hysteresis history.
  void SetOptimizerSettings(const OptimizerSettings& settings);
  const OptimizerSettings& GetOptimizerSettings() const { return this->Optimizer.GetSettings(); }
  ///@}

  /// The settings of a preset (MakeOptimizerSettings): `threshold` is th_fix of the
  /// threshold presets, `maxVertexError` the eps of ErrorBounded. The budget
  /// (MaxActiveTargets) and the hysteresis are not part of a method and stay as set.
  void SetOptimizerPreset(OptimizerPreset preset, double threshold, double maxVertexError);

  /// DistMorph, DistNorm (the paper's Table 1) and MaxDisplacement of every target, neutral
  /// first; empty vectors before the model is known.
  const TargetDistances& GetTargetDistances() const { return this->Optimizer.GetTargetDistances(); }

  /// Whether the last decision succeeded (and nothing cleared it since).
  bool HasEffectiveWeights() const { return !this->Effective.empty(); }
  /// The weights the blend uses (absolute, summing to 1, neutral first); empty when
  /// HasEffectiveWeights() is false.
  const std::vector<double>& GetEffectiveWeights() const { return this->Effective; }
  /// The optimizer's bound on any vertex's distance from the unoptimized blend (0 when the
  /// optimizer is off).
  double GetErrorBound() const { return this->ErrorBound; }
  /// Non-neutral targets with a non-zero effective weight: the targets that cost work.
  int GetActiveTargetCount() const { return this->ActiveTargets; }

  /// Forget which targets were active (hysteresis), e.g. after a jump in time.
  void ResetHistory() { this->Optimizer.ResetHistory(); }

protected:
  /// The model's target distances (the optimizer's input); forgets the history.
  void SetTargetDistances(TargetDistances distances);
  /// Requested weights (the caller checked their count) to the effective weights: the
  /// mode's rule, then the optimizer. Throws InputError for what the mode rejects, leaving
  /// the result cleared. Allocates nothing per call once the count is known (optimizer off).
  const std::vector<double>& Decide(const double* requested, size_t count);
  /// Forgets the last result.
  void ClearDecision();

private:
  WeightMode Mode = WeightMode::Normalize;
  WeightOptimizer Optimizer;
  std::vector<double> Absolute;  ///< the mode's absolute weights (kept to reuse its storage)
  std::vector<double> Effective; ///< after the optimizer
  double ErrorBound = 0.0;
  int ActiveTargets = 0;
};
} // namespace morphnode
