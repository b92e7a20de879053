// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MorphNode.h
/// @brief The morph node without VTK: Java3D's Morph and glTF's morph targets with the
/// paper's weight optimizer, on a mesh with named targets.
///
/// One object holds what a morph node does between "here are the weights" and "here are
/// the blended values": the weight mode (morph/Weights.h), the optimizer's settings or a
/// preset (morph/WeightOptimizer.h, morph/OptimizerPresets.h), the effective weights, the
/// optimizer's error bound, the number of active targets, and the blend of a point range
/// with those weights. The VTK filter (vtkMorphNodeFilter) and the benchmarks drive it; it
/// never touches VTK.
///
/// @code
/// morphnode::MorphNode node(mesh);                    // std::shared_ptr<const MorphMesh>
/// node.SetWeightMode(morphnode::WeightMode::Strict);  // Java3D: weights sum to 1
/// node.SetOptimizerPreset(morphnode::OptimizerPreset::Adjusted, 0.2, 0.0);
/// node.SetWeights({ 0.6, 0.3, 0.1 });                 // neutral first
/// std::vector<float> points(3 * mesh->GetNumberOfPoints()), normals(points.size());
/// node.Blend({ points.data(), normals.data() }, 0, mesh->GetNumberOfPoints());
/// @endcode

#include "morph/Distances.h"
#include "morph/MorphMesh.h"
#include "morph/WeightDecision.h"

#include <cstddef>
#include <memory>
#include <variant>
#include <vector>

namespace morphnode
{
/// Where one attribute's blended values go: GetNumberOfPoints() * components values of the
/// attribute's own value type (float or double), point-major.
using AttributeOutput = std::variant<float*, double*>;

/// The decision (weight mode, optimizer, effective weights, error bound, active targets) is
/// the WeightDecision base, shared with MorphScene.
class MorphNode : public WeightDecision
{
public:
  MorphNode() = default;
  /// As SetMesh(mesh).
  explicit MorphNode(std::shared_ptr<const MorphMesh> mesh);

  /// The mesh to morph, shared and never modified. Validates it (InputError), computes
  /// the target distances the optimizer needs (once per mesh), forgets which targets were
  /// active (hysteresis) and clears the last result. nullptr detaches the mesh.
  void SetMesh(std::shared_ptr<const MorphMesh> mesh);
  const MorphMesh* GetMesh() const { return this->Mesh.get(); }
  /// Targets of the mesh, neutral included; 0 without a mesh.
  size_t GetNumberOfTargets() const;

  ///@{
  /// Requested weights (one per target, neutral first) to the effective weights the blend
  /// uses: the weight mode's rule, then the optimizer. Throws InputError without a mesh,
  /// for a weight count other than GetNumberOfTargets(), and for what the mode rejects
  /// (NaN or infinite weights, a Strict sum off 1, ...); the last result is then cleared.
  /// Allocates nothing per call once the node has seen its mesh's weight count (with the
  /// optimizer off).
  const std::vector<double>& SetWeights(const double* requested, size_t count);
  const std::vector<double>& SetWeights(const std::vector<double>& requested)
  {
    return this->SetWeights(requested.data(), requested.size());
  }
  ///@}

  /// Throws InputError unless `outputs` has one non-null output per attribute of the mesh,
  /// each of its attribute's value type, and effective weights exist.
  void CheckOutputs(const std::vector<AttributeOutput>& outputs) const;

  /// Blends points [begin, end) of every attribute with the effective weights into
  /// `outputs` (CheckOutputs), writing only that range: disjoint ranges may be blended by
  /// different threads at the same time. `end` is clamped to the number of points.
  void Blend(const std::vector<AttributeOutput>& outputs, size_t begin, size_t end) const;

  /// One attribute's points [begin, end); T must be the attribute's value type
  /// (InputError otherwise, or without effective weights).
  template <typename T>
  void BlendAttribute(size_t attribute, T* out, size_t begin, size_t end) const;

private:
  std::shared_ptr<const MorphMesh> Mesh;
};

extern template void MorphNode::BlendAttribute<float>(size_t, float*, size_t, size_t) const;
extern template void MorphNode::BlendAttribute<double>(size_t, double*, size_t, size_t) const;
} // namespace morphnode
