// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarNaming.h
/// @brief Before the behaviour and the pipeline are set up: the face's rig chosen from its
/// target names (capture/FaceRig.h) unless --rig, its viseme set unless --visemes, and how
/// its eyes turn (--gaze: eye bones or eyeLook* targets, never both), printed
/// (docs/avatars.md).

namespace morphavatar
{
struct Avatar;

/// Reads the face once, chooses, prints the choice (unless --quiet) and records it in
/// a.Opt (Rig, Visemes, Gaze). False (with a message) when the face cannot be driven.
bool ChooseFaceSetup(Avatar& a);
} // namespace morphavatar
