// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfSkinRead.h
/// @brief Internal to the gltf concept: reading skins while a scene is built (GltfSkin.cpp).

#include "TinyGltfConfig.h"
#include "gltf/GltfScene.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace morphnode
{
namespace gltfskin
{
/// Reads an accessor's values as floats, bounds-checked (the loader's reader).
using FloatReader = std::function<std::vector<float>(int accessor, const std::string& use)>;

/// The skins of the model: joints, skeleton and inverse bind matrices, each checked (indices
/// in range, joints unique, MAT4 FLOAT accessors inside their buffer views, matrices finite,
/// affine and invertible). Also checks every node's `skin` index. Throws InputError.
/// `decoded`: buffer views decoded by the loader (EXT_meshopt_compression), read instead of
/// their (empty) fallback buffers.
std::vector<GltfSkin> ReadSkins(const tinygltf::Model& model, const std::vector<GltfNode>& nodes,
  const std::string& source, const std::map<int, std::vector<unsigned char>>* decoded = nullptr);

/// The part's JOINTS_n / WEIGHTS_n, every set, checked and renormalized, into
/// part.Influences; part.Skin set. `pp` is the primitive's JSON pointer.
void ReadInfluences(const tinygltf::Model& model, const tinygltf::Primitive& primitive, int skin,
  const std::vector<GltfSkin>& skins, const std::string& pp, const FloatReader& read,
  const std::string& source, GltfPart& part);

/// Skins the part at rest (the scene's node transforms as stored), its points, normals and
/// every target's deltas (see skin/Skinning.h); sets TransformApplied. `what` names the
/// primitive in messages.
void SkinAtRest(GltfPart& part, const GltfScene& scene, const std::string& what);
} // namespace gltfskin
} // namespace morphnode
