// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphTrackSource
 * @brief   abstract superclass of the temporal weight sources: one frame on port 0, the
 *          whole track on port 1
 *
 * The protocol vtkBehaviorTimeSource, vtkLiveLinkFaceReader and vtkLiveBehaviorSource share
 * (an endless source such as the live behaviour sets one output port: it has no track):
 * - port 0: a one-row vtkTable at the requested UPDATE_TIME_STEP (RequestedTime, 0 when
 *   none), its DATA_TIME_STEP set; the information advertises TIME_STEPS and TIME_RANGE
 *   (SetTimeInformation);
 * - port 1: the whole track, one row per time step; built only when port 1 itself is
 *   asked for: a request from port 0 marks port 1 DATA_NOT_GENERATED (ProcessRequest), so
 *   that playing frames never pays for the track (IsTrackWanted).
 *
 * Subclasses implement RequestInformation (calling ClearTimeInformation first, then
 * SetTimeInformation) and RequestData.
 *
 * @sa vtkBehaviorTimeSource vtkLiveLinkFaceReader vtkLiveBehaviorSource vtkMorphTrackFilter
 */

#ifndef vtkMorphTrackSource_h
#define vtkMorphTrackSource_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkTableAlgorithm.h"

class VTKMORPHNODE_EXPORT vtkMorphTrackSource : public vtkTableAlgorithm
{
public:
  vtkTypeMacro(vtkMorphTrackSource, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkMorphTrackSource();
  ~vtkMorphTrackSource() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// Marks the track (port 1) as not generated when only port 0 is asked for.
  vtkTypeBool ProcessRequest(
    vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// Removes TIME_STEPS and TIME_RANGE from both outputs.
  static void ClearTimeInformation(vtkInformationVector* outputVector);
  /// Advertises `numberOfSteps` time steps (none when 0) and the range [0, end] on port 0.
  static void SetTimeInformation(
    vtkInformationVector* outputVector, const double* steps, int numberOfSteps, double end);
  /// The UPDATE_TIME_STEP asked of port 0, 0 when none.
  static double RequestedTime(vtkInformationVector* outputVector);
  /// False when only port 0 was asked for (port 1 is then left as it is).
  static bool IsTrackWanted(vtkInformationVector* outputVector);

private:
  vtkMorphTrackSource(const vtkMorphTrackSource&) = delete;
  void operator=(const vtkMorphTrackSource&) = delete;
};

#endif
