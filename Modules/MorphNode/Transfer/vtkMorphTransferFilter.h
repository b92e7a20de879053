// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphTransferFilter
 * @brief   gives a mesh without morph targets the targets of a source face
 *
 * Input port 0: the target, a vtkPolyData of polygons (any topology, scale and pose;
 * polygons are fan-triangulated; its own target arrays, if any, are replaced). Input port 1
 * (SetSourceConnection): the source face in the form vtkMorphTargetReader produces (one
 * vtkPolyData of triangles with `target<k>_position` and field data `TargetNames`), whose
 * targets must include jawOpen, eyeBlink_L and eyeBlink_R (they find the mouth and lids).
 *
 * The output is the target's points and polygons (as triangles) with the source's targets
 * on them: point data `target<k>_position` (float relative deltas), field data
 * `TargetNames` (neutral first), and the point arrays `TransferConfidence` (float, 0..1:
 * how close and alike the registered source is) and `TransferSide` (signed char: +1/-1
 * upper/lower lip, +2/-2 and +3/-3 the lids, 0 elsewhere), ready for vtkMorphNodeFilter.
 *
 * The work is morphnode::TransferTargets (docs/transfer.md): similarity alignment
 * (landmarks from LandmarkFileName, else automatic), non-rigid ICP, deformation transfer,
 * seam-aware resampling. Bad input (no triangles, a non-manifold mesh, a source that is
 * not a face, a closed mouth, a residual above MaxResidual) is reported with vtkErrorMacro
 * and gives an empty output. The inputs are never modified.
 *
 * @sa morphnode::TransferTargets vtkMorphTargetReader vtkMorphNodeFilter
 */
#ifndef vtkMorphTransferFilter_h
#define vtkMorphTransferFilter_h

#include "vtkMorphNodeTransferModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for the landmark file name

class VTKMORPHNODETRANSFER_EXPORT vtkMorphTransferFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkMorphTransferFilter* New();
  vtkTypeMacro(vtkMorphTransferFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The source face (input port 1).
   */
  void SetSourceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSourceData(vtkDataObject* data) { this->SetInputData(1, data); }

  enum Methods
  {
    NEAREST_VERTEX = 0,
    BARYCENTRIC = 1,
    DEFORMATION_TRANSFER = 2
  };
  ///@{
  /**
   * How the deltas reach the target's points: 0 the nearest registered-source vertex's,
   * 1 interpolated at the closest point, 2 (default) deformation transfer, interpolated.
   */
  vtkSetClampMacro(Method, int, NEAREST_VERTEX, DEFORMATION_TRANSFER);
  vtkGetMacro(Method, int);
  ///@}

  ///@{
  /**
   * The largest accepted registration residual (95th percentile of the distances of the
   * source's animated region to the target) in eye distances. Default 0.1.
   */
  vtkSetClampMacro(MaxResidual, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxResidual, double);
  ///@}

  ///@{
  /**
   * Refuse a target whose lips are not cut apart (default on).
   */
  vtkSetMacro(RequireMouthOpening, bool);
  vtkGetMacro(RequireMouthOpening, bool);
  vtkBooleanMacro(RequireMouthOpening, bool);
  ///@}

  ///@{
  /**
   * Landmarks on the target, one "name x y z" per line (morphnode::ParseTransferLandmarks);
   * empty (default): automatic alignment.
   */
  void SetLandmarkFileName(const std::string& name);
  std::string GetLandmarkFileName() const { return this->LandmarkFileName; }
  ///@}

  /**
   * After an update: the registration residual (95th percentile, target units) and the
   * similarity's scale.
   */
  vtkGetMacro(ResidualP95, double);
  vtkGetMacro(Scale, double);

protected:
  vtkMorphTransferFilter();
  ~vtkMorphTransferFilter() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Method = DEFORMATION_TRANSFER;
  double MaxResidual = 0.1;
  bool RequireMouthOpening = true;
  std::string LandmarkFileName;
  double ResidualP95 = 0.0;
  double Scale = 1.0;

private:
  vtkMorphTransferFilter(const vtkMorphTransferFilter&) = delete;
  void operator=(const vtkMorphTransferFilter&) = delete;
};

#endif
