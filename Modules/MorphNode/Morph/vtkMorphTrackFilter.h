// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphTrackFilter
 * @brief   abstract superclass of the filters that move a head by a track: the head on
 *          port 0, an optional one-row vtkTable on port 1 whose time steps are the output's
 *
 * The protocol vtkEyeGazeFilter and vtkMorphSkinFilter share:
 * - port 0: a vtkPointSet or a vtkCompositeDataSet of them (a whole head); the output has
 *   the input's type (vtkPassInputTypeAlgorithm);
 * - port 1 (optional): a vtkTable, one row at the requested time, e.g. a
 *   vtkBehaviorTimeSource's or vtkLiveLinkFaceReader's port 0 (SetTrackConnection);
 * - RequestInformation: the track's TIME_STEPS and TIME_RANGE win over the head's (the
 *   executive copies port 0's only), so that the head animates with the track;
 * - the output carries DATA_TIME_STEP, the time requested (StampTime, for subclasses'
 *   RequestData).
 *
 * Subclasses implement RequestData and may name the track port after what it holds
 * (SetGazeConnection, SetPoseConnection).
 *
 * @sa vtkEyeGazeFilter vtkMorphSkinFilter vtkMorphTrackSource
 */

#ifndef vtkMorphTrackFilter_h
#define vtkMorphTrackFilter_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkPassInputTypeAlgorithm.h"

class VTKMORPHNODE_EXPORT vtkMorphTrackFilter : public vtkPassInputTypeAlgorithm
{
public:
  vtkTypeMacro(vtkMorphTrackFilter, vtkPassInputTypeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The track (port 1): a one-row vtkTable at the requested time.
   */
  void SetTrackConnection(vtkAlgorithmOutput* output);

protected:
  vtkMorphTrackFilter();
  ~vtkMorphTrackFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  /**
   * Sets the output's DATA_TIME_STEP to the UPDATE_TIME_STEP requested, when there is one.
   */
  static void StampTime(vtkDataObject* output, vtkInformationVector* outputVector);

private:
  vtkMorphTrackFilter(const vtkMorphTrackFilter&) = delete;
  void operator=(const vtkMorphTrackFilter&) = delete;
};

#endif
