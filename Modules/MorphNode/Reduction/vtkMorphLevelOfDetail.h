// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphLevelOfDetail
 * @brief   a face with morph targets at the level of detail the screen and the frame budget ask for
 *
 * The input is a triangle mesh in the glTF form vtkMorphTargetReader produces (the
 * neutral's points and triangles, `target<k>_position` deltas, field data `TargetNames`).
 * On its first execution (and whenever the input changes) the filter builds the ladder
 * (morphnode::BuildMorphLadder: the full mesh and its animation-aware reductions to 50, 25
 * and 10 % of the triangles, over one vertex buffer and one set of targets) and times each
 * level's blend. Every execution is then one frame of morphnode::ScalableMorph: the
 * controller chooses the level from the projected error in pixels (PixelsPerUnit,
 * PixelBound; FrameBudget breaking ties, never finer than FinestLevel) and the targets
 * (TargetPixelBound), the shown level's points are blended with the weights (relative,
 * glTF style: SetWeight) and geomorphed during a switch (no vertex moving more than
 * MaxGeomorphPixels per execution).
 *
 * The output is the shown level: its points (the ladder's numbering; point-data array
 * `OriginalPointId` gives each one's input point), its triangles, and the input's other
 * point arrays gathered the same way (the target arrays left out; normals are the
 * neutral's, not morphed). Field data: the input's, and `LevelOfDetail` (level, geomorph
 * target level or -1, alpha, active targets). Bad input (no triangles, polygons that are not
 * triangles, target arrays with gaps, non-manifold meshes OpenMesh cannot hold beyond a few
 * triangles) is reported with vtkErrorMacro and gives an empty output.
 *
 * vtkMorphNodeFilter has the target level of detail (PixelsPerUnit, TargetPixelBound) but
 * shows its parts' full meshes; this filter shows the mesh levels (docs/lod.md).
 *
 * @sa morphnode::ScalableMorph morphnode::BuildMorphLadder vtkMorphNodeFilter
 * vtkAnimationAwareDecimation
 */

#ifndef vtkMorphLevelOfDetail_h
#define vtkMorphLevelOfDetail_h

#include "vtkMorphNodeReductionModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // For std::unique_ptr

class VTKMORPHNODEREDUCTION_EXPORT vtkMorphLevelOfDetail : public vtkPolyDataAlgorithm
{
public:
  static vtkMorphLevelOfDetail* New();
  vtkTypeMacro(vtkMorphLevelOfDetail, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Relative (glTF) weight of target `target` (1 = the first target after the neutral).
   * Weights of targets the input does not have are ignored.
   */
  void SetWeight(int target, double weight);
  double GetWeight(int target) const;
  /// Every weight 0 (the neutral).
  void ResetWeights();
  ///@}

  ///@{
  /**
   * Pixels one model unit spans on screen at the avatar (0, the default: no screen; the
   * level then follows FrameBudget alone).
   */
  vtkSetClampMacro(PixelsPerUnit, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PixelsPerUnit, double);
  ///@}

  ///@{
  /**
   * Largest projected error of the shown level (default 1 px) and of the targets left out
   * (default 0.5 px; 0: all targets), in pixels.
   */
  vtkSetClampMacro(PixelBound, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PixelBound, double);
  vtkSetClampMacro(TargetPixelBound, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TargetPixelBound, double);
  ///@}

  ///@{
  /**
   * Milliseconds for the morph of an execution (0, the default: no budget).
   */
  vtkSetClampMacro(FrameBudget, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FrameBudget, double);
  ///@}

  ///@{
  /**
   * The finest level shown (0, the default: the full mesh).
   */
  vtkSetClampMacro(FinestLevel, int, 0, 3);
  vtkGetMacro(FinestLevel, int);
  ///@}

  ///@{
  /**
   * Largest jump of any vertex per execution during a geomorph, pixels (default 1).
   */
  vtkSetClampMacro(MaxGeomorphPixels, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxGeomorphPixels, double);
  ///@}

  /**
   * A device profile ("desktop", "laptop", "phone"): sets FrameBudget, FinestLevel,
   * PixelBound and TargetPixelBound to the profile's. An unknown name is an error and
   * changes nothing.
   */
  void SetDeviceProfile(const char* name);

  ///@{
  /**
   * The last execution's choice: the level shown (0: full; -1 before an execution), the
   * number of levels, the points shown and the targets blended.
   */
  int GetLevel() const;
  int GetNumberOfLevels() const;
  vtkIdType GetNumberOfLevelPoints() const;
  int GetActiveTargetCount() const;
  ///@}

protected:
  vtkMorphLevelOfDetail();
  ~vtkMorphLevelOfDetail() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double PixelsPerUnit = 0.0;
  double PixelBound = 1.0;
  double TargetPixelBound = 0.5;
  double FrameBudget = 0.0;
  int FinestLevel = 0;
  double MaxGeomorphPixels = 1.0;

private:
  vtkMorphLevelOfDetail(const vtkMorphLevelOfDetail&) = delete;
  void operator=(const vtkMorphLevelOfDetail&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
