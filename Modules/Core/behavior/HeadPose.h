// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file HeadPose.h
/// @brief The one convention for turning the behaviour's head angles (channels HeadYaw,
/// HeadPitch, HeadRoll) into a rigid transform of the face. Every program that moves the
/// head uses it (the applications through AppKit's VTK transform).
///
/// Convention
/// - Angles are in degrees, as the behaviour channels carry them.
/// - The face's frame: +Y up, the face looks along +Z, so +X is the character's left.
/// - Angles are seen from the character: yaw > 0 turns the face to its left (towards +X),
///   pitch > 0 lifts the chin (looks up), roll > 0 tilts the crown to its left (+X).
/// - As rotations of the right-handed frame: yaw about +Y, pitch about -X, roll about -Z;
///   applied to a point in the order roll, then pitch, then yaw:
///   R = Ry(yaw) * Rx(-pitch) * Rz(-roll) (column vectors), the intrinsic yaw-pitch-roll
///   (Tait-Bryan Y-X'-Z'') order of a head on a neck.
/// - The rotation is about a pivot: p' = pivot + R (p - pivot).

#include <array>

namespace morphnode
{
/// The head's angles in degrees, seen from the character (see the file comment).
struct HeadAngles
{
  double Yaw = 0.0;
  double Pitch = 0.0;
  double Roll = 0.0;
};

/// The 4x4 transform of the convention above, row-major (element [4 * row + column],
/// translation in the last column; the layout of vtkMatrix4x4::DeepCopy(const double*)).
/// Angles must be finite; a non-finite angle is an InputError.
std::array<double, 16> HeadPoseMatrix(const HeadAngles& angles, const std::array<double, 3>& pivot);

/// The angles a live picture can always show: a non-finite angle becomes 0 and every angle
/// is wrapped into [-180, 180], so that one bad value upstream costs a frame's head turn,
/// never the frame (HeadPoseMatrix refuses non-finite angles).
HeadAngles FiniteHeadAngles(const HeadAngles& angles);

/// The pivot a head turns about, from the face's bounds {xmin, xmax, ymin, ymax, zmin,
/// zmax}: the top of the neck, centred in X and Z, a quarter of the height up from the
/// lowest point.
std::array<double, 3> HeadPivot(const double bounds[6]);
} // namespace morphnode
