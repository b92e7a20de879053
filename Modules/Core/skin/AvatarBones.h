// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarBones.h
/// @brief The bones of a head in a skeleton (head, neck, eyes, jaw) found by name, and
/// their turn by the behaviour's head pose and gaze (docs/avatars.md).
///
/// Names: compared without case, separators and the usual prefixes (`mixamorig:`,
/// `mixamorig_`, `CC_Base_`, `J_Bip_C_`, `J_Bip_`, `J_Adj_`, `Bip01 `, `DEF-`, `ORG-`), so
/// that Mixamo / Ready Player Me / Avaturn / MPFB (`Head`, `Neck`, `LeftEye`), VRM humanoid
/// (`head`, `neck`, `leftEye`, `jaw`), VRoid (`J_Bip_C_Head`, `J_Adj_L_FaceEye`),
/// Character Creator (`CC_Base_Head`, `CC_Base_L_Eye`, `CC_Base_JawRoot`), Rocketbox
/// (`Bip01 Head`, `Bip01 LEye`?) and Blender (`head`, `eye.L`) rigs are found. Eyes are the
/// joints the gaze concept's default convention calls eyes (gaze/EyeRig.h), below the head.
///
/// Convention (behavior/HeadPose.h): the face's frame at rest is +X left, +Y up, +Z forward
/// in world space (FaceFrame changes it). The head pose R = Ry(yaw) Rx(-pitch) Rz(-roll) is
/// shared between the neck (NeckShare of the angle) and the head (the rest), each turned
/// about its own pivot, so the head turns as a whole by R. Each eye turns about its own
/// pivot by G = Ry(yaw) Rx(-pitch) of its angles (gaze/EyeRotation.h's EyeAngles: vergence,
/// the eye rig's limits), in the face's frame as the head has turned it.

#include "gaze/EyeRig.h"
#include "skin/Skeleton.h"
#include "skin/SkinInfluences.h"
#include "skin/Skinning.h"

#include <glm/glm.hpp>

#include <map>
#include <string>
#include <vector>

namespace morphnode
{
struct AvatarBoneRoles
{
  int Head = -1;
  int Neck = -1;
  int LeftEye = -1;
  int RightEye = -1;
  int Jaw = -1;
  int LeftUpperArm = -1,
      LeftForeArm = -1; ///< Mixamo LeftArm/LeftForeArm, VRM leftUpperArm/leftLowerArm, ...
  int RightUpperArm = -1, RightForeArm = -1;
  /// Eyelid bones where a rig has them (CC_Base_L_UpperLid?, LeftUpperEyelid, upperlid.L,
  /// VRM has none): they follow the eyes' pitch (AvatarBonePose::LidFollow).
  int LeftUpperLid = -1, RightUpperLid = -1, LeftLowerLid = -1, RightLowerLid = -1;

  bool HasEyes() const { return this->LeftEye >= 0 || this->RightEye >= 0; }
  /// "Head, Neck, LeftEye, RightEye" as found, for reports.
  std::string Describe(const Skeleton& skeleton) const;
};

/// A joint name reduced for comparison: lower case, prefixes and separators removed.
std::string CanonicalBoneName(const std::string& name);

/// Finds the roles by name (see the file comment). Roles not found stay -1.
AvatarBoneRoles FindAvatarBones(const Skeleton& skeleton);

/// Whether `targetNames` hold a jawOpen target (any case, underscores ignored): such an
/// avatar opens its mouth by that target, so its jaw joint stays still (the skin filter's
/// JAW_AUTO and the glTF export decide by this one rule).
bool NamesJawOpenTarget(const std::vector<std::string>& targetNames);

/// The points of a skinned part whose strongest influence is `joint` or a joint below it in
/// the skeleton (the head's points for the head bone), in point order; empty for joint < 0.
std::vector<size_t> PointsUnderJoint(
  const Skeleton& skeleton, const SkinJoints& joints, const SkinInfluences& influences, int joint);
/// The same, with a humanoid map the avatar gives itself (VRM's humanBones: VRM bone name
/// -> node name, gltf/GltfVrm.h): its head, neck, leftEye, rightEye, jaw, leftUpperArm,
/// leftLowerArm, rightUpperArm and rightLowerArm win over the names' guess where the
/// skeleton has that node.
AvatarBoneRoles FindAvatarBones(
  const Skeleton& skeleton, const std::map<std::string, std::string>& humanoid);

/// VRM's look-at range maps for eye bones: an input angle up to the map's InputMax degrees
/// turns the eye linearly up to its OutputScale degrees (inner: towards the nose, outer:
/// away from it, down, up). When Enabled they replace the eye rig's limits.
struct EyeRangeMaps
{
  bool Enabled = false;
  double InnerMax = 90.0, InnerScale = 10.0;
  double OuterMax = 90.0, OuterScale = 10.0;
  double DownMax = 90.0, DownScale = 10.0;
  double UpMax = 90.0, UpScale = 10.0;
};

struct AvatarBonePose
{
  double HeadYaw = 0.0, HeadPitch = 0.0, HeadRoll = 0.0; ///< degrees (behavior/HeadPose.h)
  double EyeYaw = 0.0, EyePitch = 0.0;                   ///< degrees, relative to the head
  double Vergence = 0.0;                                 ///< degrees, >= 0
  double NeckShare = 0.4; ///< of the head's angle taken by the neck, in [0, 1]
  EyeLimits Limits;
  /// Columns: the face's left, up and forward directions in world space at rest.
  glm::dmat3 FaceFrame{ 1.0 };
  /// Arms of a T- or A-pose lowered: each upper arm turned (about its pivot) so that it
  /// hangs ArmAngle degrees out from straight down, in the plane of its rest direction and
  /// the down direction. Off: the arms as stored.
  bool RelaxArms = false;
  double ArmAngle = 12.0;
  /// The mouth opened by the jaw joint (when the roles have one): 0 closed, 1 open by
  /// MaxJawAngle degrees, the chin turned down about the jaw's pivot in the face frame as
  /// the head has turned it. For avatars with a jaw joint and no `jawOpen` target (who
  /// chooses: vtkMorphSkinFilter's TurnJaw, gltf/GltfPerformanceExport.h); 0 leaves it.
  double JawOpen = 0.0;
  double MaxJawAngle = 25.0;
  /// VRM look-at range maps (instead of Limits when enabled).
  EyeRangeMaps RangeMaps;
  /// Lid bones follow their eye's pitch by this share (upper lids; lower lids by half),
  /// about their own pivots, so that the lids open as the eyes look up and close as they
  /// look down, as ARKit's eyeLook* targets move them.
  double LidFollow = 0.6;
};

/// The rotation R of the convention for the head angles (degrees), in the face's frame.
glm::dquat HeadRotation(double yaw, double pitch, double roll);

/// Turns the head, neck and eye joints of `pose` (from its current local transforms,
/// normally rest) by `angles`. InputError for non-finite angles or a share outside [0, 1].
void PoseAvatarBones(
  SkeletonPose& pose, const AvatarBoneRoles& roles, const AvatarBonePose& angles);

/// True when the eye joints turn a whole skinned part: every point's largest weight is on
/// an eye joint or a joint below it (an eyeball; not the head, whose lids follow the head
/// joint). `skinJoints` maps the influences' joint indices to skeleton joints
/// (SkinJoints::Joints). Such parts must not also be turned by eyeLook* targets when the
/// eyes turn by bones. False for a part without points or an avatar without eye joints.
bool TurnedByEyeJoints(const SkinInfluences& influences, const std::vector<int>& skinJoints,
  const Skeleton& skeleton, const AvatarBoneRoles& roles);
} // namespace morphnode
