// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfWriter.h
/// @brief A scene (GltfScene, the model LoadGltfScene reads) and a performance written
/// to glTF 2.0 (.glb, or .gltf with the buffer embedded) through tinygltf.
///
/// What is written (docs/gltf.md, "Export"):
/// - every part as a triangle primitive: POSITION (with min/max), NORMAL (normalized),
///   COLOR_0 (float RGBA, clamped to [0, 1]), indices (unsigned short below 65535 points,
///   else unsigned int), TEXCOORD_0/_1, its material; the parts of one node form one mesh,
///   named by the node;
/// - materials: the scene's own (GltfScene::Materials) whole, with textures, samplers,
///   texture coordinate sets, KHR_texture_transform, alpha mode and cutoff, double-sided,
///   unlit and emissive strength; the images they use in the buffer, PNG and JPEG as the
///   file held them (GltfImage::Encoded), WebP and images without bytes re-encoded as PNG.
///   A part without a scene material gets one from its name and base colour (alpha below
///   1 blends);
/// - skins, when the parts are in their nodes' frames (not TransformApplied): joints,
///   inverse bind matrices, every JOINTS_n/WEIGHTS_n set, the skin on the mesh nodes. A
///   rotation track on a joint about its own translation becomes a rotation channel on the
///   joint (turn times rest rotation) instead of inserted nodes;
/// - every target as POSITION (and NORMAL, when the part has normal deltas) deltas:
///   SPARSE (an accessor without bufferView, the moved points' indices and values) when
///   that takes fewer bytes than dense storage, so sparse targets stay sparse; a target
///   that moves nothing is an accessor of zeros without any data. The mesh's target names
///   go to `extras.targetNames` (the convention three.js, Blender and the loader use);
/// - the node tree with the nodes' names and transforms (TRS, or `matrix`). When the parts'
///   transforms were applied (GltfPart::TransformApplied, the loader's default, VTK's
///   world-space parts) the nodes are written with identity transforms, so that nothing is
///   transformed twice;
/// - one animation: a `weights` channel per node whose mesh has targets, each key holding
///   the track's weights mapped onto that mesh's targets by name (targets the track does
///   not name hold 0), and a `rotation` channel per rotation track, LINEAR (or STEP).
///   A rotation track turns the whole scene (Node empty: head pose) or one node (an eye)
///   about a pivot: the writer inserts a node `<name>Rotation` (translation = pivot,
///   the animated rotation) and below it `<name>Pivot` (translation = -pivot) above what
///   turns, so that p' = pivot + R (p - pivot) in the frame of the turned node's parent.
///   The rest pose (what a viewer shows without playing the animation) is the scene's
///   own: the inserted nodes do not turn, the meshes' `weights` are the parts' defaults.
///
/// Every input is checked first and a fault is an InputError naming it: counts that do
/// not match, non-finite values, times that do not increase (also after rounding to
/// float), names no mesh or node has, parts of one node with different targets.
///
/// Nothing here depends on VTK.

#include "gltf/GltfScene.h"

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace morphnode
{
/// A rotation over time of the whole scene or of one node, about a pivot.
struct GltfRotationTrack
{
  /// Empty: the whole scene (a node above every root, e.g. head pose). Else the name of
  /// the node to turn (exactly one node of the scene must have it), e.g. "EyeLeft".
  std::string Node;
  /// The point it turns about, in the frame of the node's parent (world space for the
  /// whole scene, and for every node when the parts are in world space).
  std::array<double, 3> Pivot{ { 0, 0, 0 } };
  /// One unit quaternion (x, y, z, w) per time of the animation; normalized on writing,
  /// signs made continuous (q and -q are the same rotation).
  std::vector<double> Rotations;
};

/// The performance: weights by target name and rotations, at the same times.
struct GltfPerformance
{
  std::string Name = "performance";
  /// Linear or Step (CubicSpline is not written).
  GltfInterpolation Interpolation = GltfInterpolation::Linear;
  /// Seconds: finite, >= 0, strictly increasing (also as floats).
  std::vector<double> Times;
  /// Target names, each one some mesh of the scene has; unique.
  std::vector<std::string> TargetNames;
  /// Times.size() * TargetNames.size() weights, time-major (glTF-style relative weights).
  std::vector<double> Weights;
  std::vector<GltfRotationTrack> Rotations;
  /// Per node: targets of its mesh whose weights stay 0 there (e.g. eyeLook* on eyeballs
  /// that the eye joints turn, while the same columns move the lids of the head).
  std::map<int, std::vector<std::string>> TargetsOffAtNode;
};

struct GltfWriteOptions
{
  /// True: GLB; false: glTF JSON with the buffer embedded as a data URI.
  bool Binary = true;
  /// asset.generator
  std::string Generator = "MorphNode";
  /// Sparse target deltas whose values all lie in [-1, 1] (model units) as normalized
  /// 16-bit integers (KHR_mesh_quantization, then used and required): half the bytes of
  /// float, a step of 1/32767 (30 micrometres for a head in metres). Dense and larger
  /// deltas stay float.
  bool QuantizeTargets = false;
};

/// The file in memory. `performance` may be null (no animation). Throws InputError.
std::vector<unsigned char> WriteGltfSceneToMemory(
  const GltfScene& scene, const GltfPerformance* performance, const GltfWriteOptions& options = {});

/// Writes a file: GLB unless the name ends in ".gltf" (options.Binary is set from the
/// name). Throws InputError for bad input or a file that cannot be written.
void WriteGltfScene(const std::string& fileName, const GltfScene& scene,
  const GltfPerformance* performance, GltfWriteOptions options = {});

/// The unit quaternion (x, y, z, w) of the rotation part of a 4x4 matrix given row-major
/// (element [4 * row + column], HeadPoseMatrix's layout). The 3x3 part must be a rotation.
std::array<double, 4> GltfQuaternionFromRowMajor(const std::array<double, 16>& m);
} // namespace morphnode
