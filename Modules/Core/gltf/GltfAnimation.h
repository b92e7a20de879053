// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfAnimation.h
/// @brief Plays a glTF animation of a GltfScene: the morph weights of every node (and by
/// target name, for a whole head) and every node's translation, rotation and scale at any
/// time, exactly as the glTF 2.0 specification defines the samplers (Appendix C,
/// "Animation Sampler Interpolation Modes"):
///
/// - keys are found with t_k <= t < t_k+1; before the first key the first value holds,
///   after the last key the last value (for CUBICSPLINE: the key's value, not a tangent);
/// - STEP: the value of key k;
/// - LINEAR: (1 - u) v_k + u v_k+1 with u = (t - t_k) / (t_k+1 - t_k); rotations are
///   spherically interpolated (slerp along the shorter arc) and stay unit quaternions;
/// - CUBICSPLINE: each key holds [in-tangents a_k, values v_k, out-tangents b_k], each
///   element as wide as the channel (3, 4, or the number of morph targets for weights);
///   the Hermite spline (2u^3 - 3u^2 + 1) v_k + (u^3 - 2u^2 + u) td b_k +
///   (-2u^3 + 3u^2) v_k+1 + (u^3 - u^2) td a_k+1 with td = t_k+1 - t_k; rotations are
///   normalized afterwards.
///
/// A node that no channel animates keeps its rest TRS (or its matrix); weights that no
/// channel animates are the node's `weights`, else its mesh's `weights`, else zeros, as
/// GltfPart::DefaultWeights.
///
/// Nothing here depends on VTK. The loader (LoadGltfScene) validated the animation data
/// (times finite, >= 0, non-decreasing; output counts; channel targets); GltfAnimationPlayer
/// checks what the loader does not (a channel animating the TRS of a node that gives a
/// `matrix`, which glTF forbids) and throws InputError naming the JSON pointer.
///
/// @code
/// const morphnode::GltfScene scene = morphnode::LoadGltfScene("talk.glb");
/// morphnode::GltfAnimationPlayer player(scene, 0);          // or FindGltfAnimation(scene, "Talk")
/// const morphnode::GltfSceneSample s = player.Sample(1.25); // seconds
/// s.Nodes[n].Weights; s.Nodes[n].Rotation; s.Nodes[n].World;
/// const morphnode::GltfNamedWeights w = GltfWeightsByTargetName(scene, s);
/// @endcode

#include "gltf/GltfScene.h"

#include <array>
#include <string>
#include <vector>

namespace morphnode
{
/// One node at one time.
struct GltfNodeSample
{
  std::array<double, 3> Translation{ { 0, 0, 0 } };
  std::array<double, 4> Rotation{ { 0, 0, 0, 1 } }; ///< x, y, z, w, unit length
  std::array<double, 3> Scale{ { 1, 1, 1 } };
  /// Morph weights of the node's mesh (one per target; empty when it has none).
  std::vector<double> Weights;
  bool TranslationAnimated = false;
  bool RotationAnimated = false;
  bool ScaleAnimated = false;
  bool WeightsAnimated = false;
  GltfMatrix Local = GltfIdentity(); ///< T * R * S (or the node's matrix when it has one)
  GltfMatrix World = GltfIdentity(); ///< parents' Local applied, root first
};

/// Every node of a scene at one time (indexed as GltfScene::Nodes).
struct GltfSceneSample
{
  double Time = 0;
  std::vector<GltfNodeSample> Nodes;
};

/// Morph weights by target name over the parts of a scene, in order of first appearance
/// (parts in scene order, each part's targets in order). A name that several parts carry
/// takes the value of its first part; `Disagreements` lists the names whose value differs
/// on another part at that time (empty for a head whose parts move together).
struct GltfNamedWeights
{
  std::vector<std::string> Names;
  std::vector<double> Values;
  std::vector<std::string> Disagreements;
};

/// Index of the animation with this name, -1 when none has it.
int FindGltfAnimation(const GltfScene& scene, const std::string& name);

/// Samples one sampler at time `t` (seconds) into `out` (`width` values: 3 for translation
/// and scale, 4 for rotation, the number of targets for weights). `rotation` selects slerp
/// for LINEAR and normalization for every mode. The sampler must hold width values per key
/// (three times that for CUBICSPLINE); throws InputError otherwise.
void SampleGltfSampler(
  const GltfAnimationSampler& sampler, int width, bool rotation, double t, double* out);

/// The rest pose: every node's TRS (or matrix) and default weights, nothing animated.
GltfSceneSample GltfRestPose(const GltfScene& scene);

/// Morph weights by target name, from the nodes' weights of a sample (see GltfNamedWeights).
GltfNamedWeights GltfWeightsByTargetName(const GltfScene& scene, const GltfSceneSample& sample);

/// One animation of a scene, checked once, sampled at any time.
class GltfAnimationPlayer
{
public:
  /// Throws InputError when `animation` is out of range or a channel animates the TRS of a
  /// node that has a matrix ("<source>: /animations/0/channels/2/target/node: ...").
  GltfAnimationPlayer(const GltfScene& scene, int animation, const std::string& source = "glTF");

  const std::string& GetName() const { return this->Name; }
  /// First and last key time over all channels (seconds).
  double GetStartTime() const { return this->Start; }
  double GetEndTime() const { return this->End; }
  /// Every key time of every channel, sorted, each once.
  const std::vector<double>& GetKeyTimes() const { return this->KeyTimes; }
  /// Nodes the animation moves (any path), sorted.
  const std::vector<int>& GetAnimatedNodes() const { return this->AnimatedNodes; }

  /// The scene at time `t` (seconds; held at the first/last key outside the range).
  GltfSceneSample Sample(double t) const;

private:
  const GltfScene* Scene;
  int Index;
  std::string Name;
  double Start = 0, End = 0;
  std::vector<double> KeyTimes;
  std::vector<int> AnimatedNodes;
};
} // namespace morphnode
