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

/// Skins a skinned part read in bind space (GltfLoadOptions::ApplyTransforms off) with the
/// joints at `nodeWorlds` (one world transform per node of the scene, e.g. an animation's
/// sample), its normals and target deltas with it (morph then skin: see skin/Skinning.h);
/// sets TransformApplied. The part's own node transform is ignored, as glTF requires.
/// InputError for a part that is not skinned or already transformed, or points beyond float.
void GltfSkinPart(GltfPart& part, const GltfScene& scene, const std::vector<GltfMatrix>& nodeWorlds,
  const std::string& what);

/// glm <-> the loader's column-major matrix.
glm::dmat4 GltfToGlm(const GltfMatrix& m);
} // namespace morphnode
