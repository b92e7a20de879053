// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarNaming.h
/// @brief Before the behaviour and the pipeline are set up: the face's rig chosen from its
/// target names (capture/FaceRig.h) unless --rig, its viseme set unless --visemes, and how
/// its eyes turn (--gaze: eye bones or eyeLook* targets, never both), printed
/// (docs/avatars.md).

#include <string>

namespace morphnode
{
struct GltfScene;
}

namespace morphavatar
{
struct Avatar;
struct Options;

/// Reads the face once, chooses, prints the choice (unless --quiet) and records it in
/// a.Opt (Rig, Visemes, Gaze). False (with a message) when the face cannot be driven.
bool ChooseFaceSetup(Avatar& a);

/// The same choice for --serve, from the face's scene (no VTK): the rig from the target
/// names and a VRM's expressions unless --rig (the rig JSON, empty when none is needed),
/// the viseme set unless --visemes (oculus15 for a face with its own viseme_* targets,
/// else paper6); printed unless --quiet. InputError when no naming family is recognised.
std::string ChooseServeNaming(
  const morphnode::GltfScene& face, const std::string& faceFile, Options& o);
} // namespace morphavatar
