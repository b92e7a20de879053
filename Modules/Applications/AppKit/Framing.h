// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Framing.h
/// @brief What the camera frames of an avatar, like a conversation (docs/avatars.md): its
/// face (head and shoulders), its bust or its whole body, as a box for
/// HeadActors::SetUpView, with room above for the overlay.

#include <string>

namespace morphnode
{
namespace appkit
{
/// The box to frame for `framing` ("face", "bust", "body") of an avatar whose head (the
/// points its head joint and the joints below it move most, vtkMorphSkinFilter's
/// GetHeadBounds) has bounds `head`, and whose whole body has bounds `all`. SetUpView drops
/// the lowest 15 % of the box (neck, chest or the margin under the feet) and puts the top a
/// little under the frame's top, clear of the overlay in the top left corner.
void FramingBox(
  const double head[6], const double all[6], const std::string& framing, double box[6]);
} // namespace appkit
} // namespace morphnode
