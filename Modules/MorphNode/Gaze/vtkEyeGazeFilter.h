// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkEyeGazeFilter
 * @brief   turns a head's eyes rigidly about their centres by gaze angles
 *
 * Input (port 0): a whole head as vtkMorphTargetReader or vtkMorphNodeFilter give it (a
 * vtkPartitionedDataSetCollection or any vtkCompositeDataSet of vtkPointSet leaves), or
 * one vtkPointSet. Output: the input's type and structure. Every eye part's points and
 * normals (point and cell data's active normals) are turned rigidly about the eye's centre;
 * every other part is passed on untouched, sharing its data with the input. The input is
 * never modified.
 *
 * Which parts are eyes (morphnode::EyeRig, docs/gaze.md): the parts named by AddEyeName (a
 * node name, every part of that node, or a part name), else those of a rig file's "eyes"
 * section (RigFileName), else the default convention: a node whose name contains "eye"
 * (case-insensitive: EyeLeft, eye_L, LeftEye, ...) but not lash, brow, lid, socket, ... .
 * A part's names come from its field data `NodeName` and `PartName` (the reader's), or
 * from its block's NAME. An eye turns about its field data `NodeOrigin` (the node's origin
 * in world space, the eyeball's centre) in the frame of `NodeAxes` (the node's x, y, z
 * axes); a part without them is taken to be in its node's own frame (origin 0, identity
 * axes), as the reader's one-mesh output is.
 *
 * Gaze: EyeYaw and EyePitch in degrees, the behaviour's convention (behavior/HeadPose.h):
 * yaw > 0 turns the eyes to the character's left (+X of a face looking along +Z), pitch > 0
 * up. Each eye's rest direction (EyeForward, default +Z of its node) turns to
 * (cos p sin y, sin p, cos p cos y) in its (left, up, forward) frame. Vergence (degrees,
 * default 0) turns both eyes inward by half of it each (the side from the eye's name:
 * Left/Right, _L/_R, ...). The angles are clamped to the anatomical limits MaxEyeYaw
 * (default 40), MaxEyeUp (25) and MaxEyeDown (35). Every eye part gets field data
 * `EyeGaze` (the yaw and pitch it was turned by) and `EyeSide` ("left", "right", "unknown").
 *
 * With a vtkTable on the optional port 1 (SetGazeConnection, e.g. a vtkBehaviorTimeSource's
 * port 0), the angles are that table's `EyeYaw` and `EyePitch` columns (first row) instead
 * of the properties, and its time steps are the output's: the gaze follows the behaviour's
 * saccades, looks and idle fixations at the requested time. The lids follow through the
 * same behaviour's LookUp/LookDown/LookLeft/LookRight channels (a rig's gaze shapes, e.g.
 * Data/rigs/arkit.json's, into eyeLook* targets, through vtkMorphRigFilter).
 *
 * Skinned parts (a glTF skin, vtkMorphSkinArrays.h) are passed on untouched: their eyes
 * turn with their eye joints in vtkMorphSkinFilter (a skinned mesh's node origin is not the
 * eye's centre).
 *
 * Head pose is not this filter's: it turns the whole head (behavior/HeadPose.h, e.g. an
 * actor's user transform), and the eyes' angles are relative to the head.
 *
 * Errors (vtkErrorMacro, RequestData returns 0, empty output): a non-finite angle, limits
 * outside (0, 90], an eye with a NodeOrigin or NodeAxes that is not finite or of the wrong
 * size, degenerate directions, a rig file that does not read, a gaze table without the
 * columns or rows.
 *
 * @sa vtkMorphTrackFilter vtkMorphTargetReader vtkMorphNodeFilter vtkBehaviorTimeSource
 * morphnode::EyeRig
 */

#ifndef vtkEyeGazeFilter_h
#define vtkEyeGazeFilter_h

#include "vtkMorphNodeGazeModule.h" // For export macro
#include "vtkMorphTrackFilter.h"

#include <memory> // For std::unique_ptr

class VTKMORPHNODEGAZE_EXPORT vtkEyeGazeFilter : public vtkMorphTrackFilter
{
public:
  static vtkEyeGazeFilter* New();
  vtkTypeMacro(vtkEyeGazeFilter, vtkMorphTrackFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The gaze in degrees, relative to the head: yaw > 0 to the character's left, pitch > 0
   * up (default 0, 0: the eyes at rest). Ignored while a gaze table is connected.
   */
  vtkSetMacro(EyeYaw, double);
  vtkGetMacro(EyeYaw, double);
  vtkSetMacro(EyePitch, double);
  vtkGetMacro(EyePitch, double);
  ///@}

  ///@{
  /**
   * Vergence in degrees (>= 0, default 0): each eye turns inward by half of it (a near
   * target). Eyes whose side the name does not tell do not converge.
   */
  vtkSetClampMacro(Vergence, double, 0.0, 90.0);
  vtkGetMacro(Vergence, double);
  ///@}

  ///@{
  /**
   * Anatomical limits in degrees, each in (0, 90]: |yaw| <= MaxEyeYaw (default 40),
   * -MaxEyeDown (35) <= pitch <= MaxEyeUp (25). A rig file's "eyes" limits replace them.
   */
  vtkSetMacro(MaxEyeYaw, double);
  vtkGetMacro(MaxEyeYaw, double);
  vtkSetMacro(MaxEyeUp, double);
  vtkGetMacro(MaxEyeUp, double);
  vtkSetMacro(MaxEyeDown, double);
  vtkGetMacro(MaxEyeDown, double);
  ///@}

  ///@{
  /**
   * The eyes' rest (forward) and up directions in their node's frame (default +Z, +Y, the
   * glTF convention of a face looking along +Z). A rig file's "eyes" directions replace them.
   */
  vtkSetVector3Macro(EyeForward, double);
  vtkGetVector3Macro(EyeForward, double);
  vtkSetVector3Macro(EyeUp, double);
  vtkGetVector3Macro(EyeUp, double);
  ///@}

  ///@{
  /**
   * Eye parts by name: node names (every part of the node) or part names, exact. None
   * (default): the rig file's eyes, else the default convention.
   */
  void AddEyeName(const char* name);
  void RemoveAllEyeNames();
  int GetNumberOfEyeNames();
  const char* GetEyeName(int i);
  ///@}

  ///@{
  /**
   * A rig file (docs/rigs.md) whose "eyes" section names the eyes, their directions and
   * limits; nullptr or "" (default): none. A rig without that section changes nothing.
   */
  vtkSetStringMacro(RigFileName);
  vtkGetStringMacro(RigFileName);
  ///@}

  /**
   * Connect a gaze table (a vtkTable with EyeYaw and EyePitch columns, e.g.
   * vtkBehaviorTimeSource's port 0) to port 1.
   */
  void SetGazeConnection(vtkAlgorithmOutput* output);

  /**
   * The number of eye parts the last execution turned (0 before).
   */
  vtkGetMacro(NumberOfEyeParts, int);

  ///@{
  /**
   * The gaze the last execution used, before the limits and vergence (the properties, or
   * the gaze table's values).
   */
  vtkGetMacro(LastEyeYaw, double);
  vtkGetMacro(LastEyePitch, double);
  ///@}

protected:
  vtkEyeGazeFilter();
  ~vtkEyeGazeFilter() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double EyeYaw = 0.0;
  double EyePitch = 0.0;
  double Vergence = 0.0;
  double MaxEyeYaw = 40.0;
  double MaxEyeUp = 25.0;
  double MaxEyeDown = 35.0;
  double EyeForward[3] = { 0.0, 0.0, 1.0 };
  double EyeUp[3] = { 0.0, 1.0, 0.0 };
  char* RigFileName = nullptr;
  int NumberOfEyeParts = 0;
  double LastEyeYaw = 0.0;
  double LastEyePitch = 0.0;

private:
  vtkEyeGazeFilter(const vtkEyeGazeFilter&) = delete;
  void operator=(const vtkEyeGazeFilter&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
