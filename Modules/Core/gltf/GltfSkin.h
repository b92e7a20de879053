// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfSkin.h
/// @brief The skins of a glTF scene as the skin concept's skeleton and joints
/// (docs/avatars.md). The loader (GltfScene.h) reads the skins (GltfScene::Skins, every
/// part's GltfPart::Skin and Influences) and, with ApplyTransforms, skins each part at rest;
/// these functions hand them to skin/Skinning.h to pose them again.

#include "gltf/GltfScene.h"
#include "skin/Skeleton.h"
#include "skin/Skinning.h"

namespace morphnode
{
/// Every node of the scene as a joint, joint i = node i (names, parents, rest TRS or matrix),
/// validated.
Skeleton GltfSkeleton(const GltfScene& scene);

/// Skin `skin` of the scene (joint node indices and inverse bind matrices).
SkinJoints GltfSkinJoints(const GltfScene& scene, int skin);

/// glm <-> the loader's column-major matrix.
glm::dmat4 GltfToGlm(const GltfMatrix& m);
} // namespace morphnode
