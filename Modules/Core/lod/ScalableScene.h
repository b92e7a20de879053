// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ScalableScene.h
/// @brief Every part of an avatar (head, eyes, teeth, body; skinned or not) on its own
/// ladder, under ONE FrameBudgetController: one decision per frame for the whole avatar.
///
/// Parts switch together. Scene level l shows every part at its own level min(l, its
/// coarsest): a part too small to reduce (a one-level ladder) stays whole. The controller
/// sees the scene as one mesh whose level l has
///  - the parts' points added (its cost: the parts' moved points added, timed as a whole by
///    Calibrate and by every frame's measured blend),
///  - the LARGEST of the parts' level errors (LadderLevel::Error99) as its error: the level
///    is chosen on screen by the part whose error projects to the most pixels, so no part
///    shows more than the pixel bound (all parts share the avatar's model space and so its
///    pixels per unit),
///  - the scene's targets: the parts' target names matched by name as the morph node's
///    MorphScene matches them (CombineTargetDistances: the neutral first, then each new name
///    as it is met, part by part), so one weight drives a viseme on every part that has it;
///    each target's largest displacement and geomorph reach the largest over the parts, its
///    moved points and distances summed.
/// Why together rather than each part by its own error: one frame budget, one level and one
/// geomorph to reason about (the same hysteresis, no part popping while another stays), and
/// a part that could go coarser alone (an eye far from every fold) saves little next to the
/// head that sets the level. docs/lod.md has the choice.
///
/// Every part keeps ONE vertex buffer (its ladder's) and its own positions buffer; the shown
/// level is the prefix [0, NumberOfPoints(part)) of it with the level's index buffer
/// (GetTriangles). A skinned part's influences are its ladder's (MorphLadder::Influences),
/// the same prefix skins it.

#include "budget/DeviceProfile.h"
#include "budget/FrameBudgetController.h"
#include "lod/MorphLadder.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
struct SceneFrame
{
  ControllerDecision Decision;
  /// Per part: its shown level and points (the prefix of its positions that is this frame's).
  std::vector<int> PartLevels;
  std::vector<size_t> PartPoints;
  /// Points of every part's shown level, added.
  size_t NumberOfPoints = 0;
  /// Seconds the blend and geomorph of every part took.
  double BlendSeconds = 0.0;
};

class ScalableScene
{
public:
  using Ladders = std::vector<std::shared_ptr<const MorphLadder>>;

  /// The parts (each ladder's Position attribute float) and one cost model per scene level
  /// (Calibrate). Throws InputError for no parts, a null ladder, positions that are not
  /// float, a name twice in one part, or a cost count that is not the scene's level count.
  /// Keeps the settings.
  void SetParts(Ladders parts, const std::vector<CostModel>& costs);
  /// Throws as FrameBudgetController::SetSettings.
  void SetSettings(const ControllerSettings& settings);
  const ControllerSettings& GetSettings() const { return this->Settings; }
  /// A device profile's budget, finest level and pixel bounds on top of the settings.
  void SetProfile(const DeviceProfile& profile);

  size_t GetNumberOfParts() const { return this->Parts.size(); }
  /// The most levels of any part.
  size_t GetNumberOfLevels() const { return this->Levels; }
  /// The scene's targets (neutral first): what Update's weights are over.
  const std::vector<std::string>& GetTargetNames() const { return this->TargetNames; }
  /// Part target k (neutral 0) -> scene target.
  const std::vector<size_t>& GetTargetMap(size_t part) const { return this->TargetMaps.at(part); }
  /// The level part `part` shows at scene level `level`: min(level, its coarsest).
  int GetPartLevel(size_t part, int level) const;
  /// The scene's level `level` as the controller sees it (see the file's comment).
  LevelOfDetail GetSceneLevel(size_t level, const CostModel& cost) const;

  /// One frame: absolute weights (neutral first) over GetTargetNames(), and the pixels a
  /// model unit spans at the avatar (ScreenPixelsPerUnit; <= 0: time alone). Throws
  /// InputError without parts or for a wrong weight count.
  const SceneFrame& Update(const std::vector<double>& absoluteWeights, double pixelsPerUnit);
  const SceneFrame& GetFrame() const { return this->Frame; }
  /// Part `part`'s positions (3 per point of its whole buffer, its shown prefix valid).
  const std::vector<float>& GetPositions(size_t part) const { return this->Positions.at(part); }
  /// Whether the last frame blended part `part` again (false: its positions and every
  /// attribute at the shown level are the frame before's: same level, same weights, no
  /// geomorph then or now).
  bool IsPartChanged(size_t part) const { return this->Shown.at(part).Changed; }
  /// Part `part`'s shown index buffer.
  const std::vector<uint32_t>& GetTriangles(size_t part) const;
  /// The weights part `part` blended with in the last frame: its own targets' scene
  /// weights, neutral first (the weight of scene targets it lacks on its neutral). Empty
  /// before a frame.
  const std::vector<double>& GetPartWeights(size_t part) const
  {
    return this->PartWeights.at(part);
  }
  /// Any other attribute of a part (an index into its ladder's Mesh attributes: normals,
  /// texture coordinates, colours) as the last frame shows it: blended over the shown
  /// prefix with GetPartWeights and geomorphed as the positions were (normals renormalized
  /// after). `out` holds components values per point of the part's whole buffer; the shown
  /// prefix is written. Throws InputError before a frame, for an index out of range or an
  /// attribute whose values are not of type T.
  template <typename T>
  void BlendAttribute(size_t part, size_t attribute, T* out) const;
  const MorphLadder& GetLadder(size_t part) const { return *this->Parts.at(part); }
  const FrameBudgetController& GetController() const { return this->Controller; }

  /// Cost models of every scene level, timed here: blends of random active sets of the
  /// scene's targets over every part's level prefix, fitted by CostModel::Fit. A few ms per
  /// level. Throws as SetParts.
  static std::vector<CostModel> Calibrate(const Ladders& parts, unsigned seed = 1);

private:
  void Layout(Ladders parts);
  void Rebuild();
  /// Blends every part at scene level `level` with scene weights `w` (and the geomorph).
  void Blend(const std::vector<double>& w, int level, int morphTowards, double alpha);

  Ladders Parts;
  size_t Levels = 0;
  std::vector<std::string> TargetNames;
  std::vector<std::vector<size_t>> TargetMaps;
  std::vector<std::vector<size_t>> Unmapped; ///< per part: the scene targets it lacks
  std::vector<CostModel> Costs;
  ControllerSettings Settings;
  FrameBudgetController Controller;
  std::vector<std::vector<float>> Positions;
  std::vector<std::vector<double>> PartWeights; ///< per part, the last frame's
  std::vector<double> Scratch;
  /// Per part, what its positions show: a part shown as in the last frame is not blended
  /// again (off while calibrating).
  struct ShownState
  {
    bool Valid = false;
    int Level = -1;
    bool Morphed = false;
    bool Changed = true;
  };
  std::vector<ShownState> Shown;
  bool SkipUnchanged = true;
  SceneFrame Frame;
};

extern template void ScalableScene::BlendAttribute(size_t, size_t, float*) const;
extern template void ScalableScene::BlendAttribute(size_t, size_t, double*) const;
} // namespace morphnode
