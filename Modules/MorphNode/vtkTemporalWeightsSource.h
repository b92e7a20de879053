// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkTemporalWeightsSource
 * @brief   the protocol MorphNode's temporal weights sources share: the weights at the
 *          requested time on port 0, the whole track on port 1
 *
 * An abstract vtkTableAlgorithm. Its subclasses (vtkBehaviorTimeSource, vtkLiveLinkFaceReader,
 * vtkLiveBehaviorSource) give on output port 0 a one-row vtkTable of weights, one column per
 * channel, at the requested UPDATE_TIME_STEP (GetRequestedTime: 0 when none is requested),
 * and may give on port 1 the whole track (one row per frame, a `Time` column first) for
 * plots, CSV and the glTF writer. Port 0 feeds vtkMorphNodeFilter's weights port (or
 * vtkMorphRigFilter, vtkEyeGazeFilter's gaze, vtkMorphSkinFilter's pose:
 * vtkMorphAvatarPipeline connects them all).
 *
 * The shared pipeline logic: a request on port 0 (a time step) marks port 1 as not generated
 * (DATA_NOT_GENERATED), so a track is built only when port 1 itself is updated
 * (IsTrackRequested in RequestData). A subclass with one output port (an endless source has
 * no track) has no port 1 to spare.
 *
 * @sa vtkBehaviorTimeSource vtkLiveLinkFaceReader vtkLiveBehaviorSource vtkMorphAvatarPipeline
 */

#ifndef vtkTemporalWeightsSource_h
#define vtkTemporalWeightsSource_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkTableAlgorithm.h"

class VTKMORPHNODE_EXPORT vtkTemporalWeightsSource : public vtkTableAlgorithm
{
public:
  vtkTypeMacro(vtkTemporalWeightsSource, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkTemporalWeightsSource() = default;
  ~vtkTemporalWeightsSource() override = default;

  /// Marks the track (port 1) as not generated when only port 0 is asked for.
  vtkTypeBool ProcessRequest(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// The UPDATE_TIME_STEP of an output's information, 0 when none is requested.
  static double GetRequestedTime(vtkInformation* outInfo);
  /// In RequestData: whether port 1 (the track) is to be built in this execution.
  bool IsTrackRequested(vtkInformationVector* outputVector);

private:
  vtkTemporalWeightsSource(const vtkTemporalWeightsSource&) = delete;
  void operator=(const vtkTemporalWeightsSource&) = delete;
};

#endif
