// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file SceneBudgetController.h
/// @brief A frame budget and a target level of detail for a MorphScene: per execution, the
/// optimizer threshold (and error bound) that keeps the scene's morph within the budget,
/// from what the previous executions measured.
///
/// A FrameBudgetController with the scene's whole model as its one level. The controller is
/// made again when the model or the method changes, keeping the cost model it measured. Its
/// first guess, before anything is measured, is FirstGuessCost.
///
/// Pieces of one model on several processes decide alike when they exchange two things
/// (the caller's collectives): the moved points of a new model (MovedPoints: sum them) and
/// the last execution's measurement (GetMeasurement: the largest of each, the slowest
/// process). A piece without a scene takes part in both and decides nothing.
///
/// @code
/// morphnode::SceneBudgetController budget;
/// // every execution, before scene.SetWeights(requested):
/// std::array<double, 3> measured = budget.GetMeasurement();  // (AllReduce MAX in parallel)
/// if (budget.NeedsModel(generation))
///   budget.SetModel(generation, SceneBudgetController::MovedPoints(&scene, n)); // (AllReduce SUM)
/// const double threshold = budget.Decide(scene, requested, goals, measured);
/// scene.SetWeights(requested);
/// // ... blend, timed ...
/// budget.Measure(scene, seconds);
/// @endcode

#include "budget/FrameBudgetController.h"
#include "morph/MorphScene.h"

#include <array>
#include <cstdint>
#include <vector>

namespace morphnode
{
class SceneBudgetController
{
public:
  /// What to keep the morph within.
  struct Goals
  {
    double FrameBudget = 0.0;      ///< seconds for the morph; <= 0: none
    double TargetPixelBound = 0.0; ///< the target level of detail's bound, pixels; <= 0: none
    double PixelsPerUnit = 0.0;    ///< the screen's, for the target level of detail

    bool HasTargetLevelOfDetail() const
    {
      return this->PixelsPerUnit > 0.0 && this->TargetPixelBound > 0.0;
    }
    /// Anything to decide.
    bool Any() const { return this->FrameBudget > 0.0 || this->HasTargetLevelOfDetail(); }
  };

  /// The cost model before the first measurement: about a desktop's blend, 50 us plus
  /// 2 ns per moved point of every active target. Replaced by measurements from the first
  /// execution on.
  static CostModel FirstGuessCost();

  /// Points each of the model's `numTargets` targets moves (its position deltas' non-zero
  /// points) over the scene's parts, neutral first with 0, and then the scene's points (one
  /// more entry): a piece's share, to sum over the pieces. Zeros for no scene.
  static std::vector<double> MovedPoints(const MorphScene* scene, size_t numTargets);

  /// Whether the model `generation` (a caller's count of its models) is new to the budget.
  bool NeedsModel(uint64_t generation) const { return this->Generation != generation; }
  /// The model's moved points (MovedPoints, summed over the pieces).
  void SetModel(uint64_t generation, std::vector<double> movedPoints);

  /// The last execution's measurement: { 1 when there is one else 0, seconds, target
  /// points }; cleared by the next Decide or Skip.
  std::array<double, 3> GetMeasurement() const;

  /// This execution without budget: nothing is decided, the last measurement is dropped.
  void Skip();

  /// Reports `measured` (GetMeasurement, in parallel the slowest process's) when it is of
  /// the same model, remakes the controller when the model or the method changed, and
  /// decides from `requested` (the scene's weights, neutral first): the scene's optimizer
  /// settings get the chosen threshold (with a frame budget) and the target level of
  /// detail's bound. Returns the chosen threshold, -1 without a frame budget. Throws
  /// InputError as FrameBudgetController and ResolveWeights do.
  double Decide(MorphScene& scene, const std::vector<double>& requested, const Goals& goals,
    const std::array<double, 3>& measured);

  /// Keeps this execution's morph time for the next decision (nothing when this execution
  /// did not Decide).
  void Measure(const MorphScene& scene, double seconds);

private:
  FrameBudgetController Controller;
  ControllerSettings Settings;
  uint64_t Generation = 0;   ///< the model's; 0: none
  uint64_t ControllerOf = 0; ///< the model Controller was made for; 0: none
  std::vector<double> Moved; ///< per model target
  double ModelPoints = 0.0;
  bool Decided = false; ///< this execution
  bool HasMeasurement = false;
  double MeasuredSeconds = 0.0, MeasuredTargetPoints = 0.0;
  std::vector<double> Absolute;
};
} // namespace morphnode
