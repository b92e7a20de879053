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
 *   RequestData);
 * - the track's first row read by column name (ReadTrackRow) and the head's parts moved
 *   the VTK way (MoveParts), so that a subclass's RequestData only moves a part.
 *
 * Subclasses implement RequestData and may name the track port after what it holds
 * (SetGazeConnection, SetPoseConnection). A subclass that only adds field data to the parts
 * it moves, or gives them points and arrays of its own, may also move them in place inside
 * another filter's pass (MoveInPlace: vtkMorphSkinFilter within vtkMorphNodeFilter's, see
 * vtkMorphNodeFilter::SetPoseFilter): one pass of VTK's executive instead of two.
 *
 * @sa vtkEyeGazeFilter vtkMorphSkinFilter vtkMorphTrackSource
 */

#ifndef vtkMorphTrackFilter_h
#define vtkMorphTrackFilter_h

#include "vtkMorphNodeModule.h" // For export macro
#include "vtkPassInputTypeAlgorithm.h"
#include "vtkSmartPointer.h" // For vtkSmartPointer

#include <functional>       // For std::function
#include <initializer_list> // For std::initializer_list
#include <memory>           // For std::unique_ptr
#include <string>           // For std::string

class vtkPointSet;

class vtkMorphCompositeLeaves;

class VTKMORPHNODE_EXPORT vtkMorphTrackFilter : public vtkPassInputTypeAlgorithm
{
public:
  vtkTypeMacro(vtkMorphTrackFilter, vtkPassInputTypeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The track (port 1): a one-row vtkTable at the requested time.
   */
  void SetTrackConnection(vtkAlgorithmOutput* output);

  /**
   * Moves the parts of `data` in place, inside another filter's pass: the fused form of
   * this filter (vtkMorphNodeFilter::SetPoseFilter). `data` is that filter's own output: its
   * leaves take new field data, and new points and point arrays in place of theirs (never
   * written into). `track` is the information vector of the table this filter would read
   * on its port 1 (null: none). Reports as an execution would. Returns false, with
   * vtkErrorMacro, when it cannot; this class has no fused form and always returns false.
   */
  virtual bool MoveInPlace(vtkInformationVector* track, vtkDataObject* data);

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

  /// A column of the track and where its value goes.
  struct TrackColumn
  {
    const char* Name;
    double* Value;
  };

  /**
   * The track's first row (`trackVector`: port 1's input information): every numeric
   * column of `columns` the table has sets its value. Returns false without a track.
   * Throws morphnode::InputError for a table without rows, or (`requireAll`) without one
   * of the columns; `table` names it in the message ("the gaze table").
   */
  static bool ReadTrackRow(vtkInformationVector* trackVector,
    std::initializer_list<TrackColumn> columns, const char* table, bool requireAll);

  /**
   * Moves a part: the leaf, its block name ("" without one) and its description for
   * messages ("part 'Name'", "part 3", "the input"); returns the moved data set, or null
   * to keep the leaf as it is. The mover holds what it returns at least until MoveParts
   * returns (the output then holds it): handing data sets over by smart pointers cost the
   * garbage collector's check of each, three times a leaf and frame.
   */
  using MovePart = std::function<vtkPointSet*(
    vtkPointSet* part, const std::string& name, const std::string& description)>;

  /**
   * The head's parts moved, the VTK way: a composite output takes the input's structure
   * (shallow: names, assembly, leaves shared) and each vtkPointSet leaf is replaced by what
   * `move` returns for it; a single data set's output is released first (so that its last
   * arrays can be written in place) and takes the moved data set or the input. Returns the
   * number of parts moved. Throws morphnode::InputError for an input that is neither,
   * naming what could not be done (`what`, e.g. "turn eyes in").
   */
  int MoveParts(
    vtkDataObject* input, vtkDataObject* output, const MovePart& move, const char* what);

  /**
   * MoveParts' walk over the parts, for MoveInPlace: `move` changes each vtkPointSet leaf of
   * `data` (a composite or one point set) in place; what it returns is not placed anywhere
   * (it must be the leaf or null). Returns the number of parts moved; throws as MoveParts.
   */
  static int MovePartsInPlace(vtkDataObject* data, const MovePart& move, const char* what);

private:
  /// A composite output's structure, kept across executions (MoveParts).
  std::unique_ptr<vtkMorphCompositeLeaves> Leaves;

  vtkMorphTrackFilter(const vtkMorphTrackFilter&) = delete;
  void operator=(const vtkMorphTrackFilter&) = delete;
};

#endif
