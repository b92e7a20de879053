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

/// The inverse of GltfSkinPart: a skinned part shown at the joints' `nodeWorlds` in world
/// space (TransformApplied, as the loader and vtkMorphTargetReader give it) back in its
/// bind space, so that skinning it again at `nodeWorlds` gives the same points, normals and
/// deltas: p = B^-1 p', normals by B's transpose (renormalized, their deltas scaled alike),
/// deltas by the inverse of B's linear part, B the point's blended joint matrix. Clears
/// TransformApplied. InputError for a part that is not skinned or not transformed, or a
/// point whose blended matrix is singular.
void GltfUnskinPart(GltfPart& part, const GltfScene& scene,
  const std::vector<GltfMatrix>& nodeWorlds, const std::string& what);

/// Scene nodes (names, parents, children, local transforms; every node in the scene) from a
/// skeleton, joint i = node i: a local matrix that is translation * rotation * positive
/// scale becomes TRS (so that joints can be turned by rotation channels), any other stays
/// a matrix. The skeleton is validated.
std::vector<GltfNode> GltfNodesFromSkeleton(Skeleton skeleton);

/// glm <-> the loader's column-major matrix.
glm::dmat4 GltfToGlm(const GltfMatrix& m);
GltfMatrix GltfFromGlm(const glm::dmat4& m);
} // namespace morphnode
