// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file EyeRig.h
/// @brief Which parts of a head are eyes, where they look at rest and how far they turn:
/// the eye rig (docs/gaze.md).
///
/// An eye is a part (or every part of a node) whose vertices turn rigidly about the node's
/// origin, the eyeball's centre. A rig file may name the eyes (its "eyes" section,
/// docs/rigs.md); without one the default convention recognizes common node names.
///
/// Conventions (those of behavior/HeadPose.h): the head's frame is +Y up, the face looks
/// along +Z, +X is the character's left; yaw > 0 turns the eye to the character's left,
/// pitch > 0 up; angles in degrees.

#include <array>
#include <string>
#include <vector>

namespace morphnode
{
/// Eye angles in degrees, seen from the character (yaw > 0: to its left, pitch > 0: up).
struct GazeAngles
{
  double Yaw = 0.0;
  double Pitch = 0.0;
};

/// How far an eye turns from its rest direction, in degrees (all in (0, 90]).
/// Defaults: the oculomotor range used by avatars, inside the human one (docs/gaze.md):
/// +-40 horizontally, 25 up, 35 down.
struct EyeLimits
{
  double MaxYaw = 40.0;  ///< |yaw| at most this
  double MaxUp = 25.0;   ///< pitch at most this
  double MaxDown = 35.0; ///< -pitch at most this

  /// Throws InputError (naming `what`) unless every limit is finite and in (0, 90].
  void Validate(const std::string& what = "eye limits") const;
  /// The angles clamped into the limits: yaw to [-MaxYaw, MaxYaw], pitch to
  /// [-MaxDown, MaxUp]. InputError for a non-finite angle.
  GazeAngles Clamp(const GazeAngles& angles) const;
};

/// The character's side of an eye (+X is the character's left).
enum class EyeSide
{
  Unknown,
  Left,
  Right
};

/// "left", "right" or "unknown".
const char* EyeSideName(EyeSide side);

/// One eye of a rig.
struct EyeSpec
{
  /// A node name (every part of the node) or a part name ("EyeLeft/M_IrisLeft"); exact,
  /// case-sensitive as glTF names are. Empty for an eye found by the default convention.
  std::string Name;
  EyeSide Side = EyeSide::Unknown;
  /// The rest (forward) direction and the up direction in the eye node's own frame; the
  /// rotation's frame is left = up x forward, up, forward (orthonormalized: up is made
  /// perpendicular to forward).
  std::array<double, 3> Forward{ { 0.0, 0.0, 1.0 } };
  std::array<double, 3> Up{ { 0.0, 1.0, 0.0 } };
};

class EyeRig
{
public:
  /// The default convention (no eyes named, forward +Z, up +Y, default limits).
  EyeRig() = default;

  /// Names an eye explicitly; from then on only named eyes are eyes (the default
  /// convention is off). InputError for an empty or repeated name or a bad direction.
  void AddEye(const EyeSpec& eye);
  const std::vector<EyeSpec>& GetEyes() const { return this->Eyes; }
  /// True while no eye is named: eyes are found by MatchesDefaultConvention.
  bool UsesDefaultConvention() const { return this->Eyes.empty(); }

  /// The rest and up directions of the eyes the default convention finds (node frame).
  /// InputError for a zero, non-finite or parallel pair.
  void SetDefaultDirections(const std::array<double, 3>& forward, const std::array<double, 3>& up);
  const std::array<double, 3>& GetDefaultForward() const { return this->DefaultForward; }
  const std::array<double, 3>& GetDefaultUp() const { return this->DefaultUp; }

  /// The limits of every eye. Validated.
  void SetLimits(const EyeLimits& limits);
  const EyeLimits& GetLimits() const { return this->Limits; }

  /// The eye a part belongs to: its node name (may be empty) and part name. Named eyes
  /// match the node name or the part name, or the part name's node prefix ("EyeLeft" for
  /// "EyeLeft/M_Iris"); under the default convention the node name (or, when empty, the
  /// part name's node prefix) must satisfy MatchesDefaultConvention, and the side comes
  /// from SideFromName. Returns false when the part is not an eye.
  bool FindEye(const std::string& nodeName, const std::string& partName, EyeSpec& eye) const;

  /// The default convention: a node name containing "eye" (case-insensitive: EyeLeft,
  /// eye_L, LeftEye, mixamorig:LeftEye, lEye, Eye.R, ...) that is not an eye's neighbour:
  /// none of lash, brow, lid, socket, lacrimal, tear, blend, occlusion, shadow, bag, liner,
  /// highlight, wet. ICT-FaceKit's EyeLeft/EyeRight and the default head's match.
  static bool MatchesDefaultConvention(const std::string& nodeName);

  /// The side a name tells: "left"/"right" anywhere (case-insensitive), else an L/R token
  /// at either end (eye_L, eye.R, L_eye, lEye, EyeL); Unknown otherwise.
  static EyeSide SideFromName(const std::string& name);

private:
  std::vector<EyeSpec> Eyes;
  std::array<double, 3> DefaultForward{ { 0.0, 0.0, 1.0 } };
  std::array<double, 3> DefaultUp{ { 0.0, 1.0, 0.0 } };
  EyeLimits Limits;
};

/// The eye rig of a set-up: the eyes named in `names` (node or part names, each side from
/// its name, SideFromName) or, with no names, the default convention; every eye looking
/// along `forward` with `up` at rest (node frame), turning within `limits`. The one place
/// where vtkEyeGazeFilter and the glTF export (gltf/GltfPerformanceExport.h) set up the
/// same eyes. InputError as AddEye, SetDefaultDirections and SetLimits.
EyeRig MakeEyeRig(const std::vector<std::string>& names,
  const std::array<double, 3>& forward = { { 0.0, 0.0, 1.0 } },
  const std::array<double, 3>& up = { { 0.0, 1.0, 0.0 } }, const EyeLimits& limits = EyeLimits());
} // namespace morphnode
