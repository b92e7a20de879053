// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkLiveLinkFaceReader
 * @brief   reads an ARKit capture (Live Link Face CSV) as a temporal weight source for
 *          vtkMorphNodeFilter, mapped onto a face's own target names
 *
 * A thin adapter over morphnode::ReadLiveLinkCsv and morphnode::MakeArkitRig
 * (docs/capture.md). The take's rows are the time steps; any time between them is
 * interpolated linearly, so it plays like vtkBehaviorTimeSource:
 *
 * @code
 * vtkNew<vtkLiveLinkFaceReader> capture;
 * capture->SetFileName("take.csv");
 * capture->SetFaceConnection(faceReader->GetOutputPort()); // names the columns
 * morph->SetWeightsConnection(capture->GetOutputPort(0));
 * morph->UpdateTimeStep(1.25); // the face at 1.25 s into the take
 * @endcode
 *
 * Outputs:
 * - port 0: a one-row vtkTable at the requested UPDATE_TIME_STEP (0 when none), one
 *   vtkDoubleArray column per channel; the information advertises TIME_STEPS (the rows'
 *   times, seconds from the first row) and TIME_RANGE.
 * - port 1: the whole take, one row per capture row, a `Time` column first (built only
 *   when port 1 itself is updated).
 *
 * Channels: with a face (the optional input port 0, whose field data `TargetNames` is read
 * as vtkMorphRigFilter does, or SetTargetNames()), the face's relative targets in its own
 * order, each the ARKit shape of its name in any spelling (`eyeBlink_L`, `eyeBlinkLeft`,
 * `EyeBlinkLeft`; both halves of browInnerUp and cheekPuff), then the angles. Without a
 * face: the ARKit shapes by Apple's names (`eyeBlinkLeft`: a face with Apple-named targets
 * needs no mapping), then the angles. Angles in degrees, as the behaviour channels:
 * HeadYaw, HeadPitch, HeadRoll, LeftEyeYaw, ..., RightEyeRoll, and EyeYaw, EyePitch (the
 * mean of both eyes).
 *
 * Names that map to nothing are reported, not fatal: GetUnmappedName() lists the file's
 * columns that are no ARKit shape or angle, and the shapes the take has that the face has
 * no target for (e.g. tongueOut on ICT-FaceKit); GetMappingReport() says it in one line.
 *
 * Bad input (no file, a malformed header or timecode, a row with missing cells or a value
 * that is not a number) is an error naming the line and the column; RequestData returns 0
 * and both outputs are empty. The file is read again after any change of the reader
 * (a setting, Modified()), not for each time step.
 *
 * @sa vtkMorphTrackSource vtkMorphNodeFilter vtkBehaviorTimeSource vtkMorphRigFilter
 * morphnode::ReadLiveLinkCsv
 */

#ifndef vtkLiveLinkFaceReader_h
#define vtkLiveLinkFaceReader_h

#include "vtkMorphNodeIOModule.h" // For export macro
#include "vtkMorphTrackSource.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkStringArray;

class VTKMORPHNODEIO_EXPORT vtkLiveLinkFaceReader : public vtkMorphTrackSource
{
public:
  static vtkLiveLinkFaceReader* New();
  vtkTypeMacro(vtkLiveLinkFaceReader, vtkMorphTrackSource);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The Live Link Face CSV file.
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /**
   * The rate the timecodes' frame field counts at, frames per second (a whole number in
   * [1, 1000]); default 60, the app's.
   */
  vtkSetClampMacro(TimecodeRate, int, 1, 1000);
  vtkGetMacro(TimecodeRate, int);
  ///@}

  ///@{
  /**
   * Degrees per unit of the file's angles: 57.2957... (radians, default) or 90 for angles
   * normalised to [-1, 1].
   */
  vtkSetMacro(PoseDegreesPerUnit, double);
  vtkGetMacro(PoseDegreesPerUnit, double);
  ///@}

  /**
   * Connect the face (a dataset with field data `TargetNames`, e.g. vtkMorphTargetReader's
   * output) to the optional input port 0.
   */
  void SetFaceConnection(vtkAlgorithmOutput* output);

  ///@{
  /**
   * The face's target names, neutral first (as in the field data `TargetNames`), used when
   * no face is connected. The array is copied; nullptr clears them.
   */
  void SetTargetNames(vtkStringArray* names);
  vtkStringArray* GetTargetNames();
  ///@}

  ///@{
  /**
   * After an execution: the take's rows and length, the channels of the outputs, the names
   * that map to nothing and a one-line report of the mapping.
   */
  vtkIdType GetNumberOfRows();
  double GetDuration();
  int GetNumberOfChannels();
  const char* GetChannelName(int index);
  int GetNumberOfUnmappedNames();
  const char* GetUnmappedName(int index);
  const char* GetMappingReport();
  ///@}

protected:
  vtkLiveLinkFaceReader();
  ~vtkLiveLinkFaceReader() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  int TimecodeRate = 60;
  double PoseDegreesPerUnit = 57.29577951308232;

private:
  vtkLiveLinkFaceReader(const vtkLiveLinkFaceReader&) = delete;
  void operator=(const vtkLiveLinkFaceReader&) = delete;

  bool EnsureRead();

  struct vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
