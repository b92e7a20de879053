// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfPose.h
/// @brief A glTF scene as a viewer shows it at one time: an animation's sample (or the rest
/// pose), every part posed by it (morph weights blended, skins posed at their joints, parts
/// moved by their nodes), and what a reader of a scene asks besides: the time steps to
/// advertise, the union of the parts' target names, one mesh's part chosen by name or
/// index. vtkMorphTargetReader converts what these return; nothing here depends on VTK.

#include "gltf/GltfAnimation.h"
#include "gltf/GltfScene.h"

#include <optional>
#include <string>
#include <vector>

namespace morphnode
{
/// How to pose a scene.
struct GltfPoseOptions
{
  /// The animation sampled; -1: the rest pose (nothing is applied then).
  int Animation = -1;
  /// The time sampled (seconds); none: the animation's start.
  std::optional<double> Time;
  /// Move parts by their nodes' sampled transforms and pose skins at their joints' (the
  /// parts must be in their nodes' frames: loaded without ApplyTransforms).
  bool ApplyTransforms = false;
  /// Blend the sampled morph weights into the parts' points and normals.
  bool ApplyWeights = false;
  /// Prefixes error messages (the file name).
  std::string Source = "glTF";
};

/// A scene's nodes at one time.
struct GltfPose
{
  GltfPoseOptions Options;
  /// The time sampled (0 for the rest pose).
  double Time = 0.0;
  GltfSceneSample Sample;
  /// The nodes the animation moves (empty for the rest pose).
  std::vector<int> AnimatedNodes;
  /// Every node's world and local transform: sampled with ApplyTransforms, else the scene's.
  std::vector<GltfMatrix> Worlds;
  std::vector<GltfMatrix> Locals;
};

/// Samples the scene. Throws InputError for an animation out of range or a time that is
/// not finite.
GltfPose PoseGltfScene(const GltfScene& scene, const GltfPoseOptions& options);

/// A copy of one part of the scene as posed: weights blended (ApplyWeights), then skinned at
/// its joints or moved by its node (ApplyTransforms).
GltfPart PoseGltfPart(const GltfScene& scene, const GltfPose& pose, const GltfPart& part);

/// Blends morph weights into a part's points and normals: base + sum w_k delta_k, normals
/// renormalized, as a glTF viewer shows the morphed mesh. Weights beyond the part's targets
/// are ignored.
void GltfBlendPart(GltfPart& part, const std::vector<double>& weights);

/// The time steps to advertise for an animation: its key times, or with `rate` > 0 a
/// regular grid at `rate` per second over the keys' range, the end included (at most a
/// million steps).
std::vector<double> GltfTimeSteps(const GltfAnimationPlayer& player, double rate);

/// The parts' target names (the neutral not included) in order of first appearance: parts
/// in scene order, each part's targets in order.
std::vector<std::string> GltfTargetNames(const GltfScene& scene);

/// The part of one mesh and primitive: the mesh by name (when `meshName` is not empty) or
/// index (negative: 0), the primitive by index (negative: 0). Throws InputError naming the
/// meshes there are, or the range, or a mesh that is on no node of the scene.
const GltfPart& FindGltfPart(const GltfScene& scene, const std::string& meshName, int meshIndex,
  int primitive, const std::string& source);
} // namespace morphnode
