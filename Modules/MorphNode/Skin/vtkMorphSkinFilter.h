// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMorphSkinFilter
 * @brief   moves the bones of a skinned avatar (head and neck by the head pose, eyes by the
 *          gaze, arms relaxed) and re-skins its morphed parts
 *
 * Input (port 0): a head or a whole avatar as vtkMorphTargetReader or vtkMorphNodeFilter
 * give it (a vtkPartitionedDataSetCollection or any vtkCompositeDataSet of vtkPointSet
 * leaves), or one vtkPointSet. Skinned parts carry the skin convention (SkinJoints,
 * SkinWeights, the skeleton; see docs/avatars.md): they are shown in their rest pose, and
 * morphed there by vtkMorphNodeFilter. This filter poses the skeleton and re-skins every
 * skinned part exactly (morph first, then skin: morphnode::RestSkin); parts that are not
 * skinned, and points whose joints did not move, pass through untouched (shared with the
 * input). The input is never modified.
 *
 * The bones (morphnode::FindAvatarBones, any of the usual namings: Mixamo / Ready Player
 * Me / Avaturn / MPFB, VRM, VRoid, Character Creator, Rocketbox, Blender):
 * - the head pose HeadYaw, HeadPitch, HeadRoll (degrees, behavior/HeadPose.h) turns the
 *   neck (NeckShare of it, default 0.4) and the head (the rest), each about its own pivot;
 * - the gaze EyeYaw, EyePitch (degrees, relative to the head; Vergence) turns each eye
 *   joint about its own pivot from its rest orientation, within MaxEyeYaw, MaxEyeUp,
 *   MaxEyeDown (TurnEyes, default on; off when the eyes are driven by eyeLook* targets);
 * - RelaxArms (default off) lowers the arms of a T- or A-pose to ArmAngle (12) degrees
 *   from straight down;
 * - JawOpen (0..1) turns the jaw joint chin-down by JawOpen * MaxJawAngle (25) degrees
 *   about its pivot. TurnJaw chooses: JAW_AUTO (default) turns it only when the avatar has
 *   a jaw joint and no `jawOpen` target (any ARKit spelling) on any part, so that a mouth
 *   opened by its target is never opened twice; JAW_ON, JAW_OFF. GetJawByBone() reports
 *   the choice of the last execution.
 * With a vtkTable on the optional port 1 (SetPoseConnection, e.g. vtkBehaviorTimeSource's
 * port 0), its columns HeadYaw, HeadPitch, HeadRoll, EyeYaw, EyePitch and jawOpen (those
 * present, first row) replace the properties, and its time steps are the output's.
 *
 * With SkinPoints off the filter poses only: skinned parts keep their points and carry the
 * pose's per-joint transforms (`SkinJointDeltas`) for a renderer that skins per vertex
 * (vtkMorphSkinMapper).
 *
 * Every re-skinned or posed part gets field data `SkinPose` (HeadYaw, HeadPitch, HeadRoll, EyeYaw,
 * EyePitch and JawOpen as used; JawOpen 0 when the jaw joint stays). GetBones() reports the bones
 * found.
 *
 * In the morph node's pass (vtkMorphNodeFilter::SetPoseFilter, MoveInPlace) the filter poses
 * the morph node's output itself, as it would pose its own: the same parts, arrays and
 * reports, without a second pass of VTK's executive over the avatar (what a frame skinned on
 * the GPU costs the CPU falls by about that pass; docs/benchmarks.md).
 *
 * Errors (vtkErrorMacro, RequestData returns 0, empty output): non-finite angles, a damaged
 * skin convention (sizes, joint indices, singular or non-finite matrices).
 *
 * @sa vtkMorphTrackFilter vtkMorphTargetReader vtkMorphNodeFilter vtkEyeGazeFilter
 * morphnode::RestSkin vtkMorphSkinMapper
 */

#ifndef vtkMorphSkinFilter_h
#define vtkMorphSkinFilter_h

#include "vtkMorphNodeSkinModule.h" // For export macro
#include "vtkMorphTrackFilter.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string
#include <vector> // For std::vector

class VTKMORPHNODESKIN_EXPORT vtkMorphSkinFilter : public vtkMorphTrackFilter
{
public:
  static vtkMorphSkinFilter* New();
  vtkTypeMacro(vtkMorphSkinFilter, vtkMorphTrackFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The head pose in degrees (behavior/HeadPose.h; default 0). Ignored for the columns a
   * pose table gives.
   */
  vtkSetMacro(HeadYaw, double);
  vtkGetMacro(HeadYaw, double);
  vtkSetMacro(HeadPitch, double);
  vtkGetMacro(HeadPitch, double);
  vtkSetMacro(HeadRoll, double);
  vtkGetMacro(HeadRoll, double);
  ///@}

  ///@{
  /**
   * The gaze in degrees, relative to the head (yaw > 0 to the character's left, pitch > 0
   * up), and the vergence (>= 0).
   */
  vtkSetMacro(EyeYaw, double);
  vtkGetMacro(EyeYaw, double);
  vtkSetMacro(EyePitch, double);
  vtkGetMacro(EyePitch, double);
  vtkSetClampMacro(Vergence, double, 0.0, 90.0);
  vtkGetMacro(Vergence, double);
  ///@}

  ///@{
  /**
   * The eye limits in degrees, each in (0, 90] (defaults 40, 25, 35 as vtkEyeGazeFilter).
   */
  vtkSetClampMacro(MaxEyeYaw, double, 0.1, 90.0);
  vtkGetMacro(MaxEyeYaw, double);
  vtkSetClampMacro(MaxEyeUp, double, 0.1, 90.0);
  vtkGetMacro(MaxEyeUp, double);
  vtkSetClampMacro(MaxEyeDown, double, 0.1, 90.0);
  vtkGetMacro(MaxEyeDown, double);
  ///@}

  ///@{
  /** The neck's share of the head turn, in [0, 1] (default 0.4). */
  vtkSetClampMacro(NeckShare, double, 0.0, 1.0);
  vtkGetMacro(NeckShare, double);
  ///@}

  ///@{
  /** Turn the head and neck joints (default on) and the eye joints (default on). */
  vtkSetMacro(TurnHead, bool);
  vtkGetMacro(TurnHead, bool);
  vtkBooleanMacro(TurnHead, bool);
  vtkSetMacro(TurnEyes, bool);
  vtkGetMacro(TurnEyes, bool);
  vtkBooleanMacro(TurnEyes, bool);
  ///@}

  ///@{
  /** Lower T- or A-pose arms to ArmAngle degrees from straight down (default off, 12). */
  vtkSetMacro(RelaxArms, bool);
  vtkGetMacro(RelaxArms, bool);
  vtkBooleanMacro(RelaxArms, bool);
  vtkSetClampMacro(ArmAngle, double, 0.0, 90.0);
  vtkGetMacro(ArmAngle, double);
  ///@}

  enum JawModes
  {
    JAW_AUTO = 0,
    JAW_OFF = 1,
    JAW_ON = 2
  };

  ///@{
  /**
   * The jaw: how far open (0..1, default 0), its largest turn (degrees, default 25) and
   * who decides whether the jaw joint turns (default JAW_AUTO: a jaw joint and no jawOpen
   * target).
   */
  vtkSetClampMacro(JawOpen, double, 0.0, 1.0);
  vtkGetMacro(JawOpen, double);
  vtkSetClampMacro(MaxJawAngle, double, 0.0, 60.0);
  vtkGetMacro(MaxJawAngle, double);
  vtkSetClampMacro(TurnJaw, int, JAW_AUTO, JAW_ON);
  vtkGetMacro(TurnJaw, int);
  /** True when the last execution turned (or would turn) the jaw joint. */
  vtkGetMacro(JawByBone, bool);
  ///@}

  /**
   * Connect a pose table (HeadYaw, HeadPitch, HeadRoll, EyeYaw, EyePitch columns, e.g.
   * vtkBehaviorTimeSource's port 0) to port 1.
   */
  void SetPoseConnection(vtkAlgorithmOutput* output);

  ///@{
  /**
   * Move the points (default on): every skinned part re-skinned here. Off ("pose only"):
   * the skeleton is posed exactly as with it on (every report the same), but the points
   * stay: each skinned part whose points' joints share one rest matrix and that has one
   * set of four influences passes through (shallow: points, normals and arrays shared with
   * the input) with field data `SkinJointDeltas` (vtkMorphSkinArrays.h): the per-joint
   * transforms a renderer blends per vertex (vtkMorphSkinMapper). Other skinned parts are
   * re-skinned here as with it on (GetCPUSkinnedPart). For drawing only: writers and
   * filters that read points want them on.
   */
  vtkSetMacro(SkinPoints, bool);
  vtkGetMacro(SkinPoints, bool);
  vtkBooleanMacro(SkinPoints, bool);
  ///@}

  /** Skinned parts the last execution passed posed only, with SkinJointDeltas (0 before). */
  vtkGetMacro(NumberOfPosedOnlyParts, int);

  ///@{
  /**
   * With SkinPoints off: the skinned parts the last execution re-skinned here all the same
   * (a point's joints with different rest matrices, or more than four influences), by name.
   */
  int GetNumberOfCPUSkinnedParts() { return static_cast<int>(this->CPUSkinnedParts.size()); }
  const char* GetCPUSkinnedPart(int i);
  ///@}

  /** Skinned parts the last execution re-skinned or passed (0 before). */
  vtkGetMacro(NumberOfSkinnedParts, int);

  /// Points re-skinned by the last execution. Each frame re-skins only the points whose
  /// morphed input changed or that have a joint whose matrix changed since the previous
  /// frame; the others keep the previous frame's output, written in place (when nothing
  /// downstream holds the previous output's arrays; else new arrays, all re-skinned).
  vtkGetMacro(NumberOfReskinnedPoints, vtkIdType);

  /**
   * The bones the last execution found, e.g. "head 'Head', neck 'Neck', left eye 'LeftEye',
   * ..." ("" before, or without a skinned part).
   */
  const char* GetBones() { return this->Bones.c_str(); }

  /** True when the last execution found an eye joint, a head joint. */
  vtkGetMacro(HasEyeBones, bool);
  vtkGetMacro(HasHeadBones, bool);

  ///@{
  /**
   * The parts the eye joints turn (every point's largest weight on an eye joint or a joint
   * below it: the eyeballs, not the lids of the head), by part name, found by the last
   * execution. With the eyes turned by bones their eyeLook* targets must not turn them
   * again: vtkMorphNodeFilter::SetTargetOffInPart on these parts (MorphAvatar does).
   */
  int GetNumberOfEyeParts() { return static_cast<int>(this->EyeParts.size()); }
  const char* GetEyePart(int i);
  ///@}

  /**
   * The bounds of the head at rest as the last execution found it: every point of a skinned
   * part whose largest weight is on the head joint or a joint below it (eyes, jaw, ...).
   * False (bounds untouched) without a head joint. For framing a face.
   */
  bool GetHeadBounds(double bounds[6]);

  /**
   * Poses the parts of `data` (the morph node's output, inside its pass) in place: skinned
   * parts take SkinPose and, posed only, SkinJointDeltas in their field data, or re-skinned
   * points and normals of this filter's (never written into the leaf's). The pose table is
   * `track` (null: the properties alone). Returns false with vtkErrorMacro on the errors of
   * RequestData.
   */
  bool MoveInPlace(vtkInformationVector* track, vtkDataObject* data) override;

protected:
  vtkMorphSkinFilter();
  ~vtkMorphSkinFilter() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  /// Resets what GetBones, GetEyePart, GetHeadBounds, ... report, before an execution.
  void ClearReports();
  /// One execution: the reports cleared, the pose read from `track` (the table of port 1, or
  /// the morph node's), every part of `input` posed into `output` (MoveParts) or, `inPlace`,
  /// in `input` itself (MovePartsInPlace). False, with vtkErrorMacro and no part counted, on
  /// the errors RequestData reports.
  bool PoseParts(
    vtkInformationVector* track, vtkDataObject* input, vtkDataObject* output, bool inPlace);

  double HeadYaw = 0.0;
  double HeadPitch = 0.0;
  double HeadRoll = 0.0;
  double EyeYaw = 0.0;
  double EyePitch = 0.0;
  double Vergence = 0.0;
  double MaxEyeYaw = 40.0;
  double MaxEyeUp = 25.0;
  double MaxEyeDown = 35.0;
  double NeckShare = 0.4;
  bool TurnHead = true;
  bool TurnEyes = true;
  bool RelaxArms = false;
  double ArmAngle = 12.0;
  double JawOpen = 0.0;
  double MaxJawAngle = 25.0;
  int TurnJaw = JAW_AUTO;
  bool JawByBone = false;
  bool SkinPoints = true;
  int NumberOfSkinnedParts = 0;
  int NumberOfPosedOnlyParts = 0;
  std::vector<std::string> CPUSkinnedParts;
  vtkIdType NumberOfReskinnedPoints = 0;
  bool HasEyeBones = false;
  std::vector<std::string> EyeParts;
  bool HasHeadBones = false;
  double HeadBounds[6] = { 0, -1, 0, -1, 0, -1 };
  std::string Bones;

private:
  vtkMorphSkinFilter(const vtkMorphSkinFilter&) = delete;
  void operator=(const vtkMorphSkinFilter&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
