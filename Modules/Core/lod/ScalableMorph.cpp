// SPDX-License-Identifier: BSD-3-Clause
#include "lod/ScalableMorph.h"

#include "base/Error.h"

#include <utility>

namespace morphnode
{
void ScalableMorph::SetLadder(
  std::shared_ptr<const MorphLadder> ladder, const std::vector<CostModel>& costs)
{
  if (!ladder || ladder->Levels.empty())
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  this->Scene.SetParts({ std::move(ladder) }, costs);
}

void ScalableMorph::SetSettings(const ControllerSettings& settings)
{
  this->Scene.SetSettings(settings);
}

void ScalableMorph::SetProfile(const DeviceProfile& profile)
{
  this->Scene.SetProfile(profile);
}

const std::vector<uint32_t>& ScalableMorph::GetTriangles() const
{
  if (this->Scene.GetNumberOfParts() == 0)
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  return this->Scene.GetTriangles(0);
}

const std::vector<float>& ScalableMorph::GetPositions() const
{
  static const std::vector<float> none;
  return this->Scene.GetNumberOfParts() ? this->Scene.GetPositions(0) : none;
}

const MorphLadder* ScalableMorph::GetLadder() const
{
  return this->Scene.GetNumberOfParts() ? &this->Scene.GetLadder(0) : nullptr;
}

const ScalableFrame& ScalableMorph::Update(const std::vector<double>& weights, double pixelsPerUnit)
{
  if (this->Scene.GetNumberOfParts() == 0)
  {
    throw InputError("ScalableMorph: no ladder.");
  }
  const SceneFrame& scene = this->Scene.Update(weights, pixelsPerUnit);
  this->Frame.Decision = scene.Decision;
  this->Frame.NumberOfPoints = scene.NumberOfPoints;
  this->Frame.BlendSeconds = scene.BlendSeconds;
  return this->Frame;
}

std::vector<CostModel> ScalableMorph::Calibrate(const MorphLadder& ladder, unsigned seed)
{
  // A non-owning pointer: the scene lives only for the calibration.
  return ScalableScene::Calibrate(
    { std::shared_ptr<const MorphLadder>(&ladder, [](const MorphLadder*) {}) }, seed);
}
} // namespace morphnode
