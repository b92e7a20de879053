// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file EyeRotation.h
/// @brief The rigid turn of an eye about its centre from gaze angles (docs/gaze.md).
///
/// Convention (the head's, behavior/HeadPose.h, without roll): in the eye's frame
/// (left, up, forward), the eye looking at (yaw, pitch) is the rest eye turned by
///   R = Ry(yaw) * Rx(-pitch)   (column vectors; yaw about up, pitch about -left),
/// so the rest direction (0, 0, 1) goes to (cos(pitch) sin(yaw), sin(pitch),
/// cos(pitch) cos(yaw)) (GazeDirection): yaw > 0 to the character's left, pitch > 0 up.
/// For an eye whose node frame is the head's (+X left, +Y up, +Z forward, the default
/// convention), R is exactly HeadPoseMatrix's rotation for the same yaw and pitch.
///
/// In world space the eye node's axes A (the reader's NodeAxes: the node's x, y and z axes)
/// and the eye's frame in the node B = [left up forward] give R_world = (A B) R (A B)^T,
/// and every point turns about the node's origin c: p' = c + R_world (p - c); normals
/// n' = R_world n.

#include "gaze/EyeRig.h"

#include <array>
#include <cstddef>

namespace morphnode
{
/// A rotation about a centre: p' = Origin + Rotation (p - Origin), Rotation row-major
/// (element [3 * row + column]).
struct RigidTurn
{
  std::array<double, 9> Rotation{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
  std::array<double, 3> Origin{ { 0, 0, 0 } };

  /// out[i] = Origin + Rotation (in[i] - Origin) for n points (3 values each); in and out
  /// may be the same array.
  void TurnPoints(const float* in, float* out, size_t n) const;
  void TurnPoints(const double* in, float* out, size_t n) const;
  void TurnPoints(const double* in, double* out, size_t n) const;
  void TurnPoints(const float* in, double* out, size_t n) const;
  /// out[i] = Rotation in[i] (normals, directions); in and out may be the same array.
  void TurnVectors(const float* in, float* out, size_t n) const;
  void TurnVectors(const double* in, double* out, size_t n) const;
};

/// The unit direction of gaze `angles` in the eye's frame (left, up, forward).
std::array<double, 3> GazeDirection(const GazeAngles& angles);

/// The angles one eye turns to: the gaze with half of `vergence` (degrees, >= 0: both eyes
/// turn inward, towards a near point) added inward (the left eye, at +X, turns to -yaw; the
/// right eye to +yaw; an eye of unknown side does not converge), then clamped to `limits`.
/// InputError for non-finite angles or a negative vergence.
GazeAngles EyeAngles(
  const GazeAngles& gaze, double vergence, EyeSide side, const EyeLimits& limits);

/// The world rotation of an eye turned by `angles` (not clamped here): `axes` are the eye
/// node's world x, y and z axes, 3 values each (the reader's NodeAxes; orthonormalized
/// here), `forward` and `up` the eye's rest and up directions in the node frame (EyeSpec).
/// InputError for non-finite values or degenerate axes or directions.
std::array<double, 9> EyeRotationMatrix(const GazeAngles& angles, const std::array<double, 9>& axes,
  const std::array<double, 3>& forward, const std::array<double, 3>& up);

/// The rigid turn of an eye about its world centre `origin` (the reader's NodeOrigin).
/// InputError for a non-finite origin (and as EyeRotationMatrix).
RigidTurn EyeTurn(const GazeAngles& angles, const std::array<double, 3>& origin,
  const std::array<double, 9>& axes, const EyeSpec& eye);
} // namespace morphnode
