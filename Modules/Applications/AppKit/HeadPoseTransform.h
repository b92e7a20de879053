// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file HeadPoseTransform.h
/// @brief The behaviour's head angles on a VTK transform, in the one convention of
/// behavior/HeadPose.h (degrees, seen from the character, roll then pitch then yaw, about
/// the top of the neck).

#include "behavior/HeadPose.h"

#include <array>

class vtkTable;
class vtkTransform;

namespace morphnode
{
namespace appkit
{
/// The channels HeadYaw, HeadPitch and HeadRoll of row 0 of a behaviour weight table (a
/// channel that is missing, or a null table, reads 0).
HeadAngles ReadHeadAngles(vtkTable* weights);

/// Sets `transform` to HeadPoseMatrix(FiniteHeadAngles(angles), pivot): a non-finite angle
/// turns the head to 0 in that frame instead of failing it.
void SetHeadPose(vtkTransform* transform, const HeadAngles& angles, const std::array<double, 3>& pivot);
} // namespace appkit
} // namespace morphnode
