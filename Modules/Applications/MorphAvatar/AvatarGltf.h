// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file AvatarGltf.h
/// @brief MorphAvatar --gltf: the whole performance as a glTF animation (docs/gltf.md).

namespace morphavatar
{
struct Avatar;

/// Writes the avatar's head with its morph targets and the whole behaviour (every frame at
/// the frame rate, through the rig when there is one) to Opt.Gltf with vtkMorphGltfWriter:
/// the weights as the optimizer decides them (Opt.GltfOptimized, with the avatar's method,
/// threshold, error bound and hysteresis) or as the behaviour gives them, head pose and
/// eye turns; and the sound as the same name with `.wav`. False with a message on stderr.
bool ExportGltf(Avatar& avatar);
} // namespace morphavatar
