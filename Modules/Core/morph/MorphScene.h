// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MorphScene.h
/// @brief Several meshes morphed as one model: the parts of a glTF scene (a head's skin,
/// teeth, tongue, lashes, eyes), or the pieces of one mesh on several processes. Targets
/// are matched by name, weights are set once, and the optimizer decides once for the whole
/// model, so that parts never disagree.
///
/// Each part is a MorphMesh with its own targets (a subset of the scene's, in any order;
/// a part may have none, like an eye). The scene's targets are the neutral and then every
/// name any part has, in order of first appearance. A weight reaches every part that has a
/// target of that name; parts without it are not moved by it.
///
/// What the optimizer decides by is the model's, not a part's: dist_morph of a target is
/// summed over all parts, its largest displacement M_i is the largest over all parts, and
/// dist_norm divides by the largest summed dist_morph. With one part, everything equals
/// MorphNode on that part, bit for bit. Pieces of a model on several processes exchange
/// their NamedTargetDistances (CombineTargetDistances) and hand the whole model's to
/// SetModel, so that every process decides the same.
///
/// @code
/// morphnode::MorphScene scene;
/// scene.SetParts({ skin, teeth, eyeLeft });            // std::shared_ptr<const MorphMesh>
/// scene.SetWeightMode(morphnode::WeightMode::Relative);
/// scene.SetOptimizerPreset(morphnode::OptimizerPreset::Adjusted, 0.2, 0.0);
/// std::vector<double> w(scene.GetNumberOfTargets(), 0.0);
/// w[scene.FindTarget("jawOpen")] = 0.7;
/// scene.SetWeights(w);
/// scene.Blend(0, { skinPoints.data(), skinNormals.data() }, 0, skin->GetNumberOfPoints());
/// @endcode

#include "morph/Distances.h"
#include "morph/MorphMesh.h"
#include "morph/MorphNode.h"
#include "morph/WeightDecision.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
/// A piece's (or a whole model's) distance figures by target name: what pieces exchange to
/// decide as one model.
struct NamedTargetDistances
{
  std::vector<std::string> Names;      ///< neutral first
  std::vector<double> DistMorph;       ///< one per name, 0 for the neutral
  std::vector<double> MaxDisplacement; ///< one per name, 0 for the neutral
};

/// The figures of a model from those of its pieces, in the pieces' order: the names in
/// order of first appearance (the first piece's neutral name first; every piece's first
/// entry is its neutral), dist_morph summed and the largest displacement the largest.
/// Throws InputError when a piece has no names, its vectors' lengths differ from its
/// names', a name appears twice in one piece, or a target is named like the neutral.
NamedTargetDistances CombineTargetDistances(const std::vector<NamedTargetDistances>& pieces);

/// DistMorph and MaxDisplacement as given, DistNorm = DistMorph / max DistMorph over the
/// targets (all 0 when nothing moves), as ComputeTargetDistances computes it.
TargetDistances MakeTargetDistances(const NamedTargetDistances& model);

/// Points a blend task covers at least: below that, handing work to another thread costs
/// more than it saves (a 1024-point range of positions and normals blends in about 1 us).
constexpr size_t MinPointsPerBlendTask = 2048;

/// How a scene's blend is cut into tasks for threads (MorphScene::PlanBlend): the point
/// ranges of the parts to blend, one after the other, and the tasks, each a run of about
/// `grain` points over one or more consecutive ranges (small parts share a task).
struct BlendPlan
{
  struct Range
  {
    size_t Part;       ///< scene part
    size_t Begin, End; ///< its points [Begin, End)
  };
  std::vector<Range> Ranges;
  std::vector<size_t> Tasks; ///< first range of each task, then Ranges.size()
  /// Too little work (or one thread) to share: run the tasks one after the other.
  bool Serial = true;

  size_t GetNumberOfTasks() const { return this->Tasks.empty() ? 0 : this->Tasks.size() - 1; }
};

class MorphScene : public WeightDecision
{
public:
  /// The parts, shared and never modified (at least one). Each is validated, and its
  /// distances computed, as MorphNode::SetMesh does. `excludedFromSums`, when not empty,
  /// holds one vector per part: empty, or one flag per point, non-zero for a point that
  /// must not count in dist_morph because another part or piece holds it too (VTK's
  /// duplicate ghost points). The model becomes the parts' own (SetModel with
  /// GetPartsDistances()); the hysteresis history and the last result are cleared.
  /// Throws InputError for no parts, a null part, a part that fails validation, two
  /// targets of one part with the same name, a target named like the neutral, or flags
  /// of the wrong count.
  void SetParts(std::vector<std::shared_ptr<const MorphMesh>> parts,
    const std::vector<std::vector<uint8_t>>& excludedFromSums = {});
  size_t GetNumberOfParts() const { return this->Parts.size(); }
  const MorphMesh& GetPart(size_t part) const;

  /// The parts' figures combined (CombineTargetDistances over the parts in order).
  const NamedTargetDistances& GetPartsDistances() const { return this->PartsDistances; }

  /// The model the optimizer decides for: its targets (neutral first; every part's target
  /// names must be among them, others are allowed: targets only other pieces have) and
  /// their figures. For pieces on several processes: combine every piece's
  /// GetPartsDistances() in the same order on every process and pass the result. Clears
  /// the hysteresis history and the last result. Throws InputError when a part's target
  /// is missing, a name appears twice, or the vectors' lengths differ from the names'.
  void SetModel(const NamedTargetDistances& model);

  ///@{
  /// The scene's targets, neutral first.
  size_t GetNumberOfTargets() const { return this->Names.size(); }
  const std::vector<std::string>& GetTargetNames() const { return this->Names; }
  /// -1 when no target has that name.
  int FindTarget(const std::string& name) const;
  /// Scene target of each target of a part (index 0, the part's neutral, maps to 0).
  const std::vector<size_t>& GetPartTargets(size_t part) const;
  ///@}

  /// Targets that never move part `part`: their scene weights count as 0 for this part
  /// only (e.g. eyeLook* targets on eyeballs that their joints turn, while the same weights
  /// still move the lids of the head). Replaces the part's earlier list; names the part
  /// lacks are ignored. Kept until SetParts; takes effect with the next SetWeights.
  void SetPartTargetsOff(size_t part, const std::vector<std::string>& names);

  /// Targets off by part name, for every part at once (SetPartTargetsOff): `off` maps a
  /// part name to the targets that never move that part; `partNames` names the scene's
  /// parts, in order. A part takes the entry of its own name, else the entry of its name up
  /// to the last '/' (the partitions "Name/0", "Name/1" of a mesh "Name"); a part with
  /// neither has no targets off. Returns whether any part has an entry. Throws InputError
  /// when `partNames` does not name every part.
  bool SetTargetsOffByPartName(const std::vector<std::string>& partNames,
    const std::map<std::string, std::vector<std::string>>& off);

  // The weight mode, the optimizer's settings or preset, the target distances of the model
  // (MakeTargetDistances), the effective weights (one per scene target), the error bound
  // over all parts and the active target count: the WeightDecision base, as in MorphNode.

  ///@{
  /// Requested weights, one per scene target (neutral first), to the effective weights:
  /// the mode's rule, then the optimizer, once for the whole model. Every part then
  /// blends its own targets with their scene weights. Throws InputError (and clears the
  /// last result) as MorphNode::SetWeights does.
  const std::vector<double>& SetWeights(const double* requested, size_t count);
  const std::vector<double>& SetWeights(const std::vector<double>& requested)
  {
    return this->SetWeights(requested.data(), requested.size());
  }
  ///@}

  /// The weights part `part` blends with: its own targets' scene weights, neutral first
  /// (the neutral's weight makes them sum to 1: weights of targets the part lacks move
  /// nothing of it). Empty before SetWeights.
  const std::vector<double>& GetPartWeights(size_t part) const;
  /// Whether a part's blend differs from its neutral: some target of it has a non-zero
  /// weight. (False for parts without targets.)
  bool IsPartMoved(size_t part) const;

  /// The core node of a part: its mesh and effective weights (its own optimizer is off:
  /// the scene decides), for CheckOutputs, Blend and BlendAttribute.
  const MorphNode& GetPartNode(size_t part) const;
  /// Blends points [begin, end) of part `part` (MorphNode::Blend): disjoint ranges, of one
  /// part or of different parts, may be blended by different threads at once.
  void Blend(
    size_t part, const std::vector<AttributeOutput>& outputs, size_t begin, size_t end) const
  {
    this->GetPartNode(part).Blend(outputs, begin, end);
  }

  /// Plans the blend of the scene parts `parts` (each once) on `threads` threads: a few
  /// tasks per thread, enough to even out a busy core, few enough that handing them out
  /// costs little next to blending them; none smaller than MinPointsPerBlendTask points.
  /// Serial (one task) when there is one thread or less than two tasks' worth of points.
  void PlanBlend(const std::vector<size_t>& parts, int threads, BlendPlan& plan) const;
  /// Blends task `task` of `plan`; `outputs[p]` is where scene part p's attributes go
  /// (CheckOutputs'd by the caller). Different tasks may run on different threads at once.
  void BlendTask(const BlendPlan& plan, size_t task,
    const std::vector<const std::vector<AttributeOutput>*>& outputs) const;

private:
  void ClearResult();
  void CheckPart(size_t part) const;

  struct PartState
  {
    std::shared_ptr<const MorphMesh> Mesh;
    MorphNode Node;              // Relative mode, no optimizer: blends what the scene decided
    std::vector<size_t> Targets; // scene target of each of the part's targets
    std::vector<double> Weights; // requested of Node (neutral ignored in Relative mode)
    std::vector<char> Off;       // per target of the part: its weight is 0 here (SetPartTargetsOff)
    bool Moved = false;
  };
  std::vector<std::unique_ptr<PartState>> Parts;
  NamedTargetDistances PartsDistances;
  std::vector<std::string> Names;
};
} // namespace morphnode
