// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ScalableMorph.h
/// @brief The ladder at work: per frame, the FrameBudgetController chooses the level (on
/// screen and on time) and the target level of detail, and the chosen level's prefix of the
/// one vertex buffer is blended (geomorphed during a switch), timed, and the time reported
/// back to the controller. What an application (MorphAvatar, a browser client, the study)
/// calls once per frame for one mesh: a ScalableScene of one part.

#include "budget/DeviceProfile.h"
#include "budget/FrameBudgetController.h"
#include "lod/MorphLadder.h"
#include "lod/ScalableScene.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace morphnode
{
struct ScalableFrame
{
  ControllerDecision Decision;
  /// Points of the shown level: positions [0, 3 * NumberOfPoints) of GetPositions() are
  /// this frame's, in the ladder's numbering (OriginalPointIds).
  size_t NumberOfPoints = 0;
  /// Seconds the blend and geomorph took.
  double BlendSeconds = 0.0;
};

class ScalableMorph
{
public:
  /// The ladder (its Position attribute must be float) and one cost model per level
  /// (Calibrate). Throws InputError for a mismatch. Keeps the controller's settings.
  void SetLadder(std::shared_ptr<const MorphLadder> ladder, const std::vector<CostModel>& costs);
  /// Throws as FrameBudgetController::SetSettings.
  void SetSettings(const ControllerSettings& settings);
  const ControllerSettings& GetSettings() const { return this->Scene.GetSettings(); }
  /// A device profile's budget, finest level and pixel bounds on top of the settings.
  void SetProfile(const DeviceProfile& profile);

  /// One frame: absolute weights (neutral first) over the ladder's targets, and the pixels a
  /// model unit spans at the avatar (ScreenPixelsPerUnit; <= 0: no screen, time alone).
  /// Throws InputError without a ladder or for a wrong weight count.
  const ScalableFrame& Update(const std::vector<double>& absoluteWeights, double pixelsPerUnit);
  /// The shown level's positions (3 per point of the whole buffer; the shown prefix valid).
  const std::vector<float>& GetPositions() const;
  /// The shown level's index buffer.
  const std::vector<uint32_t>& GetTriangles() const;
  const MorphLadder* GetLadder() const;
  const FrameBudgetController& GetController() const { return this->Scene.GetController(); }

  /// Cost models of every level, timed here: blends of random active sets (0 to all
  /// targets) of the level's prefix, fitted by CostModel::Fit. Costs a few ms per level.
  static std::vector<CostModel> Calibrate(const MorphLadder& ladder, unsigned seed = 1);

private:
  ScalableScene Scene;
  ScalableFrame Frame;
};
} // namespace morphnode
