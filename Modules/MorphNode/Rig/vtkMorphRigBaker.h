// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphRigBaker
 * @brief   replaces a face's morph targets by a rig's semantic shapes
 *          (morphnode::Rig::BakeModel), e.g. the paper's 13 targets on an ARKit face
 *
 * Input: one vtkPointSet with relative targets, as vtkMorphTargetReader produces it:
 * point arrays `target<k>_position` (and `target<k>_normal` with active normals) and field
 * data `TargetNames` (neutral first) naming the targets the rig refers to.
 *
 * Output: the same face (structure, cells, other arrays shared) whose relative targets are
 * the rig's shapes: `target<k>_position` = sum over the shape's terms of coefficient times
 * the face target's position delta (likewise `target<k>_normal` when the input has normal
 * deltas), arrays of the input's target-array type, and `TargetNames` = `Neutral` followed
 * by the shape names. The input's own target arrays are not passed on. vtkMorphNodeFilter
 * then runs the shape set directly (weight 1 on a baked shape equals the rig's expansion
 * at weight 1 as long as no coefficient leaves [0, 1]; baking does not clamp).
 *
 * Shapes: SetShapeNames() (an explicit list, wins when non-empty), else SetShapeSet()
 * (a set of the rig, e.g. "paper" = Berner's Table 1 order), else all the rig's shapes.
 *
 * The rig file is read when first needed and again only when the file name changes or the
 * filter is modified. Errors (unreadable rig, unknown set or shape, a rig naming a target
 * the face lacks, no relative targets) are reported with vtkErrorMacro and give an empty
 * output. The input is never modified.
 *
 * @sa morphnode::Rig vtkMorphRigFilter vtkMorphTargetReader vtkMorphNodeFilter
 */

#ifndef vtkMorphRigBaker_h
#define vtkMorphRigBaker_h

#include "vtkMorphNodeRigModule.h" // For export macro
#include "vtkPointSetAlgorithm.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkStringArray;

class VTKMORPHNODERIG_EXPORT vtkMorphRigBaker : public vtkPointSetAlgorithm
{
public:
  static vtkMorphRigBaker* New();
  vtkTypeMacro(vtkMorphRigBaker, vtkPointSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The rig file (JSON, format in docs/rigs.md), e.g. Data/rigs/arkit.json.
   */
  /// Setting the current value does not modify the filter.
  virtual void SetRigFileName(const char* value);
  vtkGetCharFromStdStringMacro(RigFileName);
  ///@}

  ///@{
  /**
   * A named set of the rig's shapes to bake (e.g. "paper"); empty (default) = all shapes.
   * Ignored when ShapeNames is non-empty.
   */
  /// Setting the current value does not modify the filter.
  virtual void SetShapeSet(const char* value);
  vtkGetCharFromStdStringMacro(ShapeSet);
  ///@}

  ///@{
  /**
   * An explicit list of shapes to bake, in target order (copied; nullptr or an empty
   * array clears it).
   */
  void SetShapeNames(vtkStringArray* names);
  vtkStringArray* GetShapeNames();
  ///@}

  ///@{
  /**
   * Targets moving at most this fraction of the points are stored sparsely while baking
   * (no effect on the result). Default morphnode::MorphMesh::DefaultSparseCoverage.
   */
  vtkSetClampMacro(SparseCoverage, double, 0.0, 1.0);
  vtkGetMacro(SparseCoverage, double);
  ///@}

protected:
  vtkMorphRigBaker();
  ~vtkMorphRigBaker() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string RigFileName;
  std::string ShapeSet;
  double SparseCoverage;

private:
  vtkMorphRigBaker(const vtkMorphRigBaker&) = delete;
  void operator=(const vtkMorphRigBaker&) = delete;

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
