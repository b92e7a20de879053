// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkAnimationAwareDecimation
 * @brief   reduces a face with morph targets, reducing its animated regions less
 *
 * The input is a triangle mesh in the glTF form vtkMorphTargetReader produces: the
 * neutral's points and triangles, point-data arrays `target<k>_position` (and
 * `target<k>_normal`) with relative deltas, field data `TargetNames`. The output is the
 * reduced mesh in the same form, ready for vtkMorphNodeFilter.
 *
 * The reduction is OpenMesh's Decimater with halfedge collapses (see
 * morphnode::ReduceAnimationAware): the reduced mesh's points are a subset of the input's,
 * and every point-data array (neutral normals, texture coordinates, every target's deltas)
 * is copied unchanged from the point each output point comes from, given by the point-data
 * array `OriginalPointId`. Collapses are ordered by the neutral's quadric error plus
 * AnimationWeight times an animation cost: the quadric error of every target pose and a
 * bound on how differently the merged points move, over all targets. With AnimationWeight
 * 0 this is plain quadric decimation (OpenMesh's ModQuadricT).
 *
 * The budget: NumberOfTriangles when set (> 0), else TargetReduction (the fraction of
 * triangles to remove, like vtkQuadricDecimation). Field data is passed; cell data, verts
 * and lines are not (the cells are new). The input is never modified. Bad input (no
 * triangles, polygons that are not triangles, a budget not below the mesh's size, target
 * arrays with gaps or of the wrong size, a TargetNames count that does not match,
 * non-manifold triangles) is reported with vtkErrorMacro and gives an empty output.
 *
 * @sa morphnode::ReduceAnimationAware vtkMorphNodeFilter vtkMorphTargetReader
 * vtkQuadricDecimation
 */

#ifndef vtkAnimationAwareDecimation_h
#define vtkAnimationAwareDecimation_h

#include "vtkMorphNodeReductionModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

class VTKMORPHNODEREDUCTION_EXPORT vtkAnimationAwareDecimation : public vtkPolyDataAlgorithm
{
public:
  static vtkAnimationAwareDecimation* New();
  vtkTypeMacro(vtkAnimationAwareDecimation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Fraction of the triangles to remove, in [0, 1). Default 0.5. Used when
   * NumberOfTriangles is 0.
   */
  vtkSetClampMacro(TargetReduction, double, 0.0, 1.0);
  vtkGetMacro(TargetReduction, double);
  ///@}

  ///@{
  /**
   * Triangles to keep; 0 (default) uses TargetReduction instead.
   */
  vtkSetClampMacro(NumberOfTriangles, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(NumberOfTriangles, vtkIdType);
  ///@}

  ///@{
  /**
   * Weight of the animation cost against the neutral's quadric error; 0 = plain quadric
   * decimation. Default 0.01, measured best on the ICT face (see docs/reduction.md): the
   * animation cost is about 100 times the quadric error of a face in metres.
   */
  vtkSetClampMacro(AnimationWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(AnimationWeight, double);
  ///@}

  ///@{
  /**
   * Include the quadrics of every target pose in the animation cost, so that the reduced
   * mesh approximates every target's shape. Default on.
   */
  vtkSetMacro(PoseQuadrics, bool);
  vtkGetMacro(PoseQuadrics, bool);
  vtkBooleanMacro(PoseQuadrics, bool);
  ///@}

  ///@{
  /**
   * Largest change of a face normal (degrees) a collapse may cause; 0 turns the check
   * off. Default 60.
   */
  vtkSetClampMacro(MaxNormalDeviation, double, 0.0, 180.0);
  vtkGetMacro(MaxNormalDeviation, double);
  ///@}

protected:
  vtkAnimationAwareDecimation();
  ~vtkAnimationAwareDecimation() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double TargetReduction = 0.5;
  vtkIdType NumberOfTriangles = 0;
  double AnimationWeight = 0.01;
  bool PoseQuadrics = true;
  double MaxNormalDeviation = 60.0;

private:
  vtkAnimationAwareDecimation(const vtkAnimationAwareDecimation&) = delete;
  void operator=(const vtkAnimationAwareDecimation&) = delete;
};

#endif
