// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file RigOptimizer.h
/// @brief Rig-aware optimization: the paper's optimizer (morph/WeightOptimizer.h) deciding
/// per rig shape instead of per face target.
///
/// A rig builds a viseme from several face targets that only work together: ARKit's PP is
/// jawOpen 0.08 + mouthClose 0.08 + mouthPress + mouthRoll, where mouthClose closes the
/// lips *over* the open jaw. Deciding per target, a threshold prunes mouthClose (small
/// weight, small reach) and keeps jawOpen (large reach, so the adjusted threshold is low):
/// the lips part at every p, b and m. Deciding per shape, a shape's targets are kept or
/// pruned together, so what reaches the face is always a sum of whole shapes, each at the
/// weight the optimizer gave it: a closure stays a closure, a rounding a rounding.
///
/// A shape's figures are measured on the geometry: its delta on a part is the sum of its
/// terms' coefficients times the part's target deltas (ComputeShapeDistances), from which
/// dist_morph, dist_norm and the largest displacement follow as for a target
/// (morph/Distances.h). With these the optimizer's guarantees carry over: the error bound
/// B = sum |w'_s - w_s| M_s bounds the vertex error of the *expanded* result as long as
/// no target weight is clamped by Rig::Expand (the rig's coefficients keep within [0, 1]).
///
/// Usage, per face (the parts' figures combined as MorphScene does):
///   auto d = MakeTargetDistances(CombineTargetDistances({ComputeShapeDistances(rig, skin),
///                                                       ComputeShapeDistances(rig, teeth)}));
///   RigOptimizer optimizer; optimizer.SetShapeDistances(d); optimizer.SetSettings(s);
///   per frame: optimizer.Optimize(shapeWeights, effective); rig.Expand(effective, targets);

#include "morph/MorphMesh.h"
#include "morph/MorphScene.h"
#include "morph/WeightOptimizer.h"
#include "rig/Rig.h"

#include <string>
#include <vector>

namespace morphnode
{
/// The distance figures of the rig's shapes on one part: names "Neutral" followed by the
/// rig's shape names (file order), DistMorph = sum over points of |shape delta| and
/// MaxDisplacement = the largest |shape delta|, from the part's Position attribute. Terms
/// naming a target the part lacks move nothing there (a tongue has no eyeBlink_L), so parts
/// with different target sets combine (CombineTargetDistances). Throws InputError when the
/// part has no Position attribute.
NamedTargetDistances ComputeShapeDistances(const Rig& rig, const MorphMesh& part);

class RigOptimizer
{
public:
  /// As WeightOptimizer::SetSettings (throws InputError for invalid settings).
  void SetSettings(const OptimizerSettings& settings) { this->Optimizer.SetSettings(settings); }
  const OptimizerSettings& GetSettings() const { return this->Optimizer.GetSettings(); }

  /// The shapes' figures, neutral first, then one per rig shape (in the rig's order).
  /// Clears the hysteresis history.
  void SetShapeDistances(const TargetDistances& distances);
  const TargetDistances& GetShapeDistances() const { return this->Optimizer.GetTargetDistances(); }
  /// Number of shapes the figures are for (0 before SetShapeDistances).
  size_t GetNumberOfShapes() const;

  /// Relative (glTF-style) shape weights, GetNumberOfShapes() of them, to the effective
  /// relative shape weights: the neutral's weight is 1 - sum, the optimizer decides on the
  /// shapes, and the neutral's share is dropped again. With the optimizer off the weights
  /// are copied. Throws InputError before SetShapeDistances or for non-finite weights.
  /// Allocates nothing per call once the count is known (optimizer off).
  void Optimize(const double* shapeWeights, double* effective);

  /// The optimizer's bound on the vertex error of the last call (0 when off).
  double GetLastErrorBound() const { return this->LastErrorBound; }
  /// Shapes with a non-zero effective weight in the last call.
  int GetLastActiveShapes() const { return this->LastActiveShapes; }
  /// Forget which shapes were active (hysteresis), e.g. after a jump in time.
  void ResetHistory() { this->Optimizer.ResetHistory(); }

private:
  WeightOptimizer Optimizer;
  std::vector<double> Absolute;
  double LastErrorBound = 0.0;
  int LastActiveShapes = 0;
};

/// One column of semantic shape weights, as a weights table holds it: the rig shape it
/// drives, its name (for errors) and one value per frame.
struct ShapeWeightColumn
{
  size_t Shape = 0;
  std::string Name;
  std::vector<double> Values;
};

/// Frames of shape weights to frames of the bound face's target weights: per frame the
/// columns of a shape add up, `optimizer` (when not null, its figures set) decides on the
/// shapes, and the rig expands them (Rig::Expand). Returns GetNumberOfBoundTargets()
/// columns of `frames` values. Throws InputError naming the column and the frame of a
/// weight that is not finite, or when a column has fewer than `frames` values.
std::vector<std::vector<double>> ExpandShapeFrames(const Rig& rig,
  const std::vector<ShapeWeightColumn>& columns, size_t frames, RigOptimizer* optimizer);
} // namespace morphnode
