// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphAvatarPipeline
 * @brief   the avatar's pipeline assembled in one place: face reader, rig, morph node,
 *          gaze, skin and the head pose, driven by any temporal weights source
 *
 * The chain every avatar program builds (MorphAvatar in batch, window and live mode, the
 * C++ and Python examples):
 *
 *   vtkMorphTargetReader (the whole scene) -> vtkMorphNodeFilter (RELATIVE weights from the
 *   weights connection [-> vtkMorphRigFilter]; with vtkMorphSkinFilter as its pose filter: a
 *   skinned avatar's head, neck and eye joints follow HeadYaw/Pitch/Roll and the gaze of the
 *   weights, posed in the morph node's own pass) -> vtkEyeGazeFilter (EyeYaw/EyePitch of
 *   the weights turn the eye parts that are not skinned) -> output
 *
 * plus the head pose of a head without head joints: HeadYaw/HeadPitch/HeadRoll of the
 * weights as one vtkTransform about the top of the neck (behavior/HeadPose.h), for the
 * actors of every part (GetHeadPose). The weights come from a temporal source's port:
 * vtkBehaviorTimeSource (a prepared behaviour), vtkLiveBehaviorSource (live commands),
 * vtkLiveLinkFaceReader (a capture take); or, with UseFaceAnimation, from the face file's
 * own glTF animation.
 *
 * @code
 * vtkNew<vtkMorphAvatarPipeline> avatar;
 * avatar->SetFileName("face.glb");
 * avatar->SetWeightsConnection(behavior->GetOutputPort(0));
 * avatar->UpdateTimeStep(1.25);           // the head at t = 1.25 s
 * actor->SetUserTransform(avatar->GetHeadPose());
 * @endcode
 *
 * The filters are reachable for their own settings (GetReader, GetMorph for the optimizer,
 * GetRig, GetGaze, GetSkin: the morph node's pose filter, with no input of its own, whose
 * settings and reports are those of the pose); their connections are this class's. It is a
 * helper that connects filters, not an algorithm: ParaView users connect the same filters
 * (each has a proxy), and the head pose there is the skin filter's (docs/paraview.md).
 *
 * @sa vtkMorphTargetReader vtkMorphNodeFilter vtkMorphRigFilter vtkEyeGazeFilter
 * vtkMorphSkinFilter vtkBehaviorTimeSource vtkLiveBehaviorSource
 */

#ifndef vtkMorphAvatarPipeline_h
#define vtkMorphAvatarPipeline_h

#include "vtkMorphNodeAvatarModule.h" // For export macro
#include "vtkNew.h"                   // For vtkNew
#include "vtkObject.h"
#include "vtkSmartPointer.h" // For vtkSmartPointer

#include <string> // For std::string

class vtkAlgorithm;
class vtkAlgorithmOutput;
class vtkDataObject;
class vtkEyeGazeFilter;
class vtkMorphNodeFilter;
class vtkMorphRigFilter;
class vtkMorphSkinFilter;
class vtkMorphTargetReader;
class vtkTable;
class vtkTransform;

class VTKMORPHNODEAVATAR_EXPORT vtkMorphAvatarPipeline : public vtkObject
{
public:
  static vtkMorphAvatarPipeline* New();
  vtkTypeMacro(vtkMorphAvatarPipeline, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The face (glTF/GLB or an OBJ set; the reader's file name).
  void SetFileName(const char* path);
  const char* GetFileName();
  ///@}

  ///@{
  /**
   * A rig (JSON) mapping the weights' channels onto the face's own targets; also the eye
   * rig of the gaze filter. Empty (default): the channels name the face's targets.
   */
  void SetRigFileName(const char* path);
  const char* GetRigFileName();
  ///@}

  ///@{
  /**
   * The weights: a one-row table at the requested time (a temporal source's port 0). It
   * drives the morph (through the rig), the eyes, the skin's pose and the head pose.
   * The pipeline holds the port's producer as long as it holds the port. (From Python,
   * keep the source in a variable: `SetWeightsConnection(vtkBehaviorTimeSource()
   * .GetOutputPort(0))` hands over a port whose temporary source is already gone, which
   * VTK 9.1's own SetInputConnection does not survive either.)
   */
  void SetWeightsConnection(vtkAlgorithmOutput* output);
  vtkAlgorithmOutput* GetWeightsConnection();
  ///@}

  ///@{
  /**
   * On (default): with a rig, the weights are its channels (a behaviour's, live or not) and
   * the rig maps them onto the face's targets. Off: the weights name the face's targets
   * already (a capture take mapped by vtkLiveLinkFaceReader); the rig then only names the
   * eye parts for the gaze.
   */
  void SetRigMapsWeights(bool maps);
  vtkGetMacro(RigMapsWeights, bool);
  vtkBooleanMacro(RigMapsWeights, bool);
  ///@}

  ///@{
  /**
   * Off (default): the morph's weights are the weights connection's. On: the face file's own
   * glTF animation drives the morph (the reader's port 1; choose it on GetReader()); its
   * weights carry no angles, so the eyes stay as the file has them, the head pose is the
   * identity, and a skinned avatar's pose comes from the weights connection (if any).
   */
  void SetUseFaceAnimation(bool use);
  vtkGetMacro(UseFaceAnimation, bool);
  vtkBooleanMacro(UseFaceAnimation, bool);
  ///@}

  ///@{
  /// The filters, for their own settings (not their connections).
  vtkMorphTargetReader* GetReader();
  vtkMorphRigFilter* GetRig();
  vtkMorphNodeFilter* GetMorph();
  vtkEyeGazeFilter* GetGaze();
  vtkMorphSkinFilter* GetSkin();
  ///@}

  ///@{
  /// The posed head (the reader's structure: a composite of parts, or one vtkPolyData).
  vtkAlgorithmOutput* GetOutputPort();
  vtkDataObject* GetOutputDataObject();
  ///@}

  /**
   * Brings the head to time t (seconds): weights, rig, blend, eyes, skin, then the head
   * pose. False when a filter failed (its error is reported).
   */
  bool UpdateTimeStep(double t);

  /**
   * The head pose of the last UpdateTimeStep: HeadYaw/HeadPitch/HeadRoll (degrees) of the
   * table that drives the morph, about GetHeadPivot; the identity for a skinned avatar that
   * turns its head by its joints. Shared by every part's actor (SetUserTransform).
   */
  vtkTransform* GetHeadPose();

  /// The point the head turns about: the top of the neck of the face as read (HeadPivot of
  /// its bounds, behavior/HeadPose.h). (0, 0, 0) before the face is read.
  void GetHeadPivot(double pivot[3]);

  /**
   * Sets `transform` from the HeadYaw, HeadPitch and HeadRoll of row 0 of `weights` (a
   * missing channel or table reads 0, a non-finite angle turns to 0) about `pivot`, in the
   * one convention of behavior/HeadPose.h.
   */
  static void SetHeadPoseFromWeights(
    vtkTransform* transform, vtkTable* weights, const double pivot[3]);

protected:
  vtkMorphAvatarPipeline();
  ~vtkMorphAvatarPipeline() override;

private:
  vtkMorphAvatarPipeline(const vtkMorphAvatarPipeline&) = delete;
  void operator=(const vtkMorphAvatarPipeline&) = delete;

  /// The connections of the current settings.
  void Connect();

  vtkNew<vtkMorphTargetReader> Reader;
  vtkNew<vtkMorphRigFilter> Rig;
  vtkNew<vtkMorphNodeFilter> Morph;
  vtkNew<vtkEyeGazeFilter> Gaze;
  vtkNew<vtkMorphSkinFilter> Skin;
  vtkNew<vtkTransform> HeadPose;
  vtkSmartPointer<vtkAlgorithmOutput> Weights;
  vtkSmartPointer<vtkAlgorithm> WeightsProducer; ///< kept alive while Weights is connected
  std::string RigFileName;
  bool UseFaceAnimation = false;
  bool RigMapsWeights = true;
  double Pivot[3] = { 0.0, 0.0, 0.0 };
  vtkMTimeType PivotTime = 0; ///< the reader output's MTime the pivot is of
};

#endif
