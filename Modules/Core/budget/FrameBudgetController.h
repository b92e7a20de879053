// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file FrameBudgetController.h
/// @brief Scalable avatars: per frame, the level of detail and the optimizer threshold
/// that keep the morph stage within a frame-time budget with the least error.
///
/// Each level (the full face and its reductions, finest first, each nested in the previous
/// one) has a measured cost model
///
///     seconds = Fixed + PerTargetPoint * sum over active targets of the points they move
///
/// (the morph blends only active targets, and each over the points it moves; with dense
/// targets that is "active targets x points"), calibrated by timing real blends
/// (CostModel::Fit), and a geometric error (e.g. its RMS surface distance over a weight
/// track, from the reduction study). For every level and candidate threshold the
/// controller runs the paper's optimizer (adjusted threshold, remaining redistribution,
/// hysteresis) on the frame's weights, predicts time and error,
///
///     error = level error + optimizer bound (sum |w'_i - w_i| M_i, see WeightOptimizer)
///
/// and picks the least error among the candidates within the budget (the cheapest when none
/// is), keeping the previous frame's threshold while it is nearly as good
/// (ThresholdHysteresis). The threshold may change every frame; the level only with hysteresis: at
/// once to the next coarser level when the current one cannot meet the budget at any threshold;
/// otherwise to a neighbour level only when its error (within the budget, for a finer one
/// within (1 - LevelHysteresis) of it) is below (1 - LevelHysteresis) times the current
/// one's for MinFramesPerLevel frames in a row. Levels change one step at a time.
///
/// No popping: a switch is a geomorph over GeomorphFrames frames (Hoppe 1997). The finer
/// of the two levels is displayed while every point slides between its own position and
/// that of the coarser level's point it collapses into (both blended by the same
/// weights, so the morph animates on during the transition); at the coarse end the fine
/// mesh has exactly the coarse mesh's shape and the topology switches invisibly. See
/// morphnode::Geomorph. During a transition the finer level's cost is paid; the controller
/// then raises its threshold to stay within budget where it can.
///
/// Measured costs: the given cost models are priors. After each frame, report what the
/// frame really cost (ReportMeasuredSeconds, e.g. the timed morph stage); the displayed
/// level's model is then refitted to its last MeasurementWindow measurements with a
/// robust fit (CostModel::FitMedian), so the decisions follow the machine as it runs now
/// (other load, clock changes, a model calibrated elsewhere), and a frame preempted once
/// does not move it.

#include "morph/Distances.h"
#include "morph/WeightOptimizer.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace morphnode
{
/// seconds = Fixed + PerTargetPoint * (moved points summed over active targets).
struct CostModel
{
  double Fixed = 0.0;
  double PerTargetPoint = 0.0;

  double Predict(double targetPoints) const
  {
    return this->Fixed + this->PerTargetPoint * targetPoints;
  }
  /// Least-squares fit to measurements; both clamped to >= 0.
  /// Throws InputError for fewer than two samples or mismatched sizes.
  static CostModel Fit(const std::vector<double>& targetPoints, const std::vector<double>& seconds);
  /// Robust fit (Theil-Sen): the slope is the median of the slopes between every two
  /// measurements whose target points differ by more than a tenth of the largest,
  /// `flatSlope` when there are none; Fixed is the
  /// median of seconds - slope * targetPoints. Outliers (a preempted frame) up to nearly
  /// half of the samples do not move it. Both clamped to >= 0.
  /// Throws InputError for no samples or mismatched sizes.
  static CostModel FitMedian(
    const std::vector<double>& targetPoints, const std::vector<double>& seconds, double flatSlope);
};

/// Device classes and the morph stage's share of a frame: a rule of thumb to start from
/// when no budget is measured.
enum class DeviceClass
{
  Desktop, ///< 2 ms of a 60 Hz frame
  Laptop,  ///< 1 ms
  Mobile,  ///< 0.4 ms
  Embedded ///< 0.15 ms
};
double DeviceFrameBudget(DeviceClass device);
const char* DeviceClassName(DeviceClass device);

struct LevelOfDetail
{
  std::string Name;
  size_t NumberOfPoints = 0;
  /// Points each target moves at this level (neutral first, entry 0 unused).
  std::vector<double> MovedPoints;
  /// Distances of the level's targets (for the optimizer's adjusted threshold and bound).
  TargetDistances Distances;
  /// The level's own geometric error in model units (0 for the full face).
  double GeometricError = 0.0;
  CostModel Cost;
  /// Level point -> point of the next coarser level it collapses into (in this level's
  /// ids), for the geomorph; empty for the coarsest level.
  std::vector<uint32_t> RepresentativeInThisLevel;
  /// Coarser level point -> this level's point (the coarser level's OriginalPointIds when it
  /// was reduced from this one); empty for the coarsest level.
  std::vector<uint32_t> CoarserToThis;
  /// Bound on how far a point of this level moves during a whole geomorph towards the next
  /// coarser level: GeomorphReach[0] + sum_k |w_k| GeomorphReach[k] under absolute weights w
  /// (MorphLadder's LadderLevel::GeomorphReach); empty: unknown (MaxGeomorphPixels has no
  /// effect on this level's transitions).
  std::vector<double> GeomorphReach;
};

struct ControllerSettings
{
  double FrameBudget = 0.001; ///< seconds for the morph stage
  std::vector<double> Thresholds = { 0.0, 0.05, 0.1, 0.2, 0.3, 0.5 };
  Redistribution Strategy = Redistribution::Remaining;
  bool AdjustThreshold = true;
  double OptimizerHysteresis = 0.2;
  /// The previous frame's threshold stays while it fits the budget, unless one with less
  /// error fits in (1 - ThresholdHysteresis) of it or costs no more (when nothing fits:
  /// while it is as cheap as the cheapest), so the setting does not change on every frame.
  double ThresholdHysteresis = 0.15;
  /// Applied by every candidate on top of its threshold (WeightOptimizer's budget and
  /// error bound); 0: off.
  int MaxActiveTargets = 0;
  double MaxVertexError = 0.0;
  /// A neighbour level must beat the current one's error by this fraction (a finer one
  /// must also fit in (1 - LevelHysteresis) * budget)...
  double LevelHysteresis = 0.15;
  /// ... for this many frames in a row.
  int MinFramesPerLevel = 20;
  int GeomorphFrames = 8;
  /// On screen, no vertex may jump more than this many pixels in one frame of a geomorph:
  /// a transition then takes more than GeomorphFrames frames where the points slide far
  /// (the bound from GeomorphReach and the frame's weights), at most MaxGeomorphFrames.
  /// 0: always GeomorphFrames.
  double MaxGeomorphPixels = 0.0;
  int MaxGeomorphFrames = 120;
  /// Measurements per level that ReportMeasuredSeconds refits its cost model to (the
  /// latest ones); 0 keeps the given models.
  int MeasurementWindow = 32;
  /// Measured costs scatter around the fit (other threads, caches, the clock). A level
  /// measured plans for this quantile of its frames: its predictions add that quantile of
  /// its measurements' residuals (>= 0) to the fit, so that about this share of frames fits
  /// the budget rather than half. In [0.5, 1).
  double MeasuredQuantile = 0.9;

  /// Chosen on screen (Update with pixelsPerUnit > 0; both bounds 0: off). The level is the
  /// coarsest whose GeometricError projects to at most PixelBound pixels (a coarser level
  /// than the current one only within (1 - LevelHysteresis) of it, so a level does not
  /// flicker at the edge), never finer than FinestLevel; the frame budget then breaks the
  /// tie between "as fine as the screen needs" and "as cheap as the budget needs" by
  /// coarsening as without a screen. Levels change one step at a time, with geomorphs.
  double PixelBound = 0.0;
  /// Target level of detail (Seo and Magnenat-Thalmann): every candidate's optimizer gets
  /// MaxVertexError = TargetPixelBound / pixelsPerUnit (the smaller with MaxVertexError), so
  /// targets whose weighted reach projects below it are left out, with the optimizer's
  /// guarantee (no vertex moves farther than that) and its hysteresis (no popping visemes).
  double TargetPixelBound = 0.0;
  /// The finest level shown (a device profile's largest level); clamped to the levels.
  int FinestLevel = 0;
};

struct ControllerDecision
{
  int Level = 0;               ///< the level whose topology is displayed
  double Threshold = 0.0;      ///< optimizer threshold used at that level
  std::vector<double> Weights; ///< effective absolute weights (neutral first)
  int ActiveTargets = 0;
  double TargetPoints = 0.0; ///< points moved, summed over the active targets
  double PredictedSeconds = 0.0;
  double PredictedError = 0.0; ///< level error + optimizer bound
  bool WithinBudget = true;
  /// Geomorph in progress: display Level's mesh morphed by Alpha towards Level + 1
  /// (Alpha 0 = Level's own shape, 1 = Level + 1's shape). -1 when none.
  int MorphTowards = -1;
  double Alpha = 0.0;
  /// Chosen on screen: the displayed level's geometric error in pixels (0 without a
  /// screen), and the level the screen asked for (-1 without a screen).
  double LevelPixelError = 0.0;
  int ScreenLevel = -1;
  /// The target level of detail's error bound this frame, model units (0: none).
  double TargetErrorBound = 0.0;
};

class FrameBudgetController
{
public:
  /// Throws InputError for a budget <= 0, no thresholds, a threshold outside [0, 1],
  /// or hysteresis outside [0, 1).
  void SetSettings(const ControllerSettings& settings);
  const ControllerSettings& GetSettings() const { return this->Settings; }

  /// Finest first. Throws InputError when the target count differs from the first level's
  /// or a level is not coarser than the previous one. Resets the controller.
  void AddLevel(const LevelOfDetail& level);
  size_t GetNumberOfLevels() const { return this->Levels.size(); }
  const LevelOfDetail& GetLevel(size_t i) const { return this->Levels.at(i); }

  /// Starts again at `level` with no transition and no history.
  void Reset(int level = 0);

  /// Decides one frame from absolute weights (neutral first, summing to 1).
  /// Throws InputError when there is no level or the weight count is wrong.
  ControllerDecision Update(const std::vector<double>& absoluteWeights);
  /// The same, chosen on screen: `pixelsPerUnit` is how many pixels one model unit spans at
  /// the avatar (ScreenPixelsPerUnit); <= 0 decides as without a screen.
  /// Throws InputError for a non-finite pixelsPerUnit.
  ControllerDecision Update(const std::vector<double>& absoluteWeights, double pixelsPerUnit);

  int GetCurrentLevel() const { return this->Current; }
  size_t GetNumberOfSwitches() const { return this->Switches; }

  /// What the frame the last Update decided really cost, in seconds: a measurement of its
  /// displayed level at its target points; that level's cost model is refitted to its last
  /// MeasurementWindow measurements (FitMedian; the slope kept while all lie at one target
  /// point count; frames over 3x slower than predicted left out while they are fewer than
  /// a third). Does nothing with MeasurementWindow 0. Throws InputError for a negative
  /// or non-finite value, or when no frame was decided since the levels were set.
  void ReportMeasuredSeconds(double seconds);
  /// The same for a frame that ended up moving `targetPoints` (its active targets' moved
  /// points) rather than the decided ones, e.g. when the caller's own optimizer decided.
  void ReportMeasuredSeconds(double seconds, double targetPoints);
  /// The cost model a level predicts with: its given one until it is measured.
  const CostModel& GetCostModel(size_t level) const { return this->Models.at(level); }
  /// Seconds a measured level's predictions add to its cost model for the scatter of its
  /// measurements (MeasuredQuantile); 0 until measured.
  double GetCostMargin(size_t level) const { return this->Margins.at(level); }
  /// Measurements kept for a level.
  size_t GetNumberOfMeasurements(size_t level) const { return this->Samples.at(level).size(); }

private:
  struct Candidate
  {
    double Threshold = 0.0;
    std::vector<double> Weights;
    int Active = 0;
    double TargetPoints = 0.0;
    double Seconds = 0.0;
    double Error = 0.0;
  };
  /// Best candidate of a level: least error within `budget`, else the cheapest.
  Candidate Evaluate(size_t level, const std::vector<double>& weights, double budget);
  /// Gives every optimizer the frame's error bound (the settings' MaxVertexError and the
  /// target level of detail's); keeps their histories.
  void SetOptimizerBound(double maxVertexError);

  ControllerSettings Settings;
  std::vector<LevelOfDetail> Levels;
  /// One optimizer per level and threshold, so each keeps its own hysteresis history.
  std::vector<std::vector<WeightOptimizer>> Optimizers;
  /// Per level: the model predictions use and its measurements (target points, seconds),
  /// oldest first.
  std::vector<CostModel> Models;
  std::vector<double> Margins;
  std::vector<int> Chosen;     ///< per level: the threshold index chosen last frame, -1: none
  std::vector<bool> Evaluated; ///< per level: evaluated last frame (current level +- 1)
  std::vector<std::vector<std::pair<double, double>>> Samples;
  int LastLevel = -1; ///< displayed by the last Update, -1: none since the levels were set
  double LastTargetPoints = 0.0;
  int Current = 0;
  int Streak = 0;             ///< consecutive frames preferring StreakDirection
  int StreakDirection = 0;    ///< +1 coarser, -1 finer, 0 stay
  int MorphFrom = -1;         ///< transition: the level we come from
  double MorphProgress = 0.0; ///< of the transition, in [0, 1]
  size_t Switches = 0;
  double OptimizerBound = 0.0; ///< MaxVertexError the optimizers have now
};

/// Pixels one model unit spans at `distance` from a perspective camera with a vertical
/// field of view `fovYDegrees` and a viewport `viewportHeight` pixels high:
/// viewportHeight / (2 distance tan(fov / 2)). Throws InputError for a distance, field of
/// view (in (0, 180)) or height that is not positive and finite.
double ScreenPixelsPerUnit(double viewportHeight, double fovYDegrees, double distance);

/// Points each target moves (non-zero delta), neutral first with 0: a level's MovedPoints.
std::vector<double> MovedPointsPerTarget(const std::vector<std::vector<float>>& positionDeltas);
} // namespace morphnode
