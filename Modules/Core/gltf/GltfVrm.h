// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfVrm.h
/// @brief What a VRM avatar says of itself in its glTF extensions (docs/avatars.md): its
/// expressions bound to morph targets, its humanoid bones and how it looks at things.
///
/// - VRM 1.0 (`extensions.VRMC_vrm`): `expressions.preset` / `expressions.custom`, each
///   with `morphTargetBinds` ({node, index, weight 0..1}); `humanoid.humanBones`
///   ({"head": {"node": i}, ...}); `lookAt` (`type` "bone" or "expression",
///   `offsetFromHeadBone`, `rangeMapHorizontalInner/Outer`, `rangeMapVerticalDown/Up` with
///   `inputMaxValue` and `outputScale`).
/// - VRM 0.x (`extensions.VRM`): `blendShapeMaster.blendShapeGroups` ({name, presetName,
///   binds: {mesh, index, weight 0..100}}); `humanoid.humanBones` ([{bone, node}]);
///   `firstPerson.lookAtTypeName` ("Bone" or "BlendShape") with `lookAtHorizontalInner/
///   Outer`, `lookAtVerticalDown/Up` ({xRange, yRange}: input degrees, output degrees or
///   weight) and `firstPersonBoneOffset`.
/// Expression names come out as VRM 1.0's presets (0.x's `a i u e o joy sorrow fun
/// blink_l blink_r lookup ...` become `aa ih ou ee oh happy sad relaxed blinkLeft
/// blinkRight lookUp ...`), custom ones as named. Binds name targets by the mesh's
/// `extras.targetNames` (else `target<k>`, as the loader names them).
///
/// Only the JSON is read (no buffer is decoded): cheap beside the scene's loading. A bind
/// or bone that points outside the file is an InputError naming it.

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace morphnode
{
struct GltfVrmExpression
{
  std::string Name;
  bool Preset = true;
  bool Binary = false;
  /// (target name, weight in [0, 1]) per bind.
  std::vector<std::pair<std::string, double>> Binds;
};

/// A VRM range map: an input angle up to InputMax degrees maps linearly to OutputScale
/// (degrees for a bone look-at, a weight for an expression look-at).
struct GltfVrmRangeMap
{
  double InputMax = 90.0;
  double OutputScale = 10.0;
  /// The output for an input angle (degrees, its magnitude; clamped at InputMax).
  double Map(double degrees) const;
};

struct GltfVrm
{
  /// 0: not a VRM file; 1: VRM 0.x; 2: VRM 1.0.
  int Version = 0;
  std::vector<GltfVrmExpression> Expressions;
  /// Humanoid bones by VRM name (head, neck, leftEye, rightEye, jaw, ...): node index.
  std::map<std::string, int> HumanBones;
  /// Names of the nodes, so that HumanBones can be matched to a skeleton by name.
  std::map<std::string, std::string> HumanBoneNodeNames;
  /// "bone" or "expression" (0.x's Bone / BlendShape); empty when the file says nothing.
  std::string LookAtType;
  GltfVrmRangeMap HorizontalInner, HorizontalOuter, VerticalDown, VerticalUp;
  std::array<double, 3> LookAtOffset{ { 0, 0, 0 } };

  bool IsVrm() const { return this->Version > 0; }
  /// "VRM 1.0: 18 expressions, 5 humanoid bones, look-at by bone" for reports.
  std::string Describe() const;
};

/// From the glTF JSON text. InputError for a VRM extension that points outside the file.
GltfVrm ReadGltfVrmFromJson(const std::string& json, const std::string& what);

/// From a GLB or glTF JSON in memory (the JSON chunk only). InputError as above, or for
/// bytes that are not glTF.
GltfVrm ReadGltfVrmFromMemory(const void* data, size_t size, const std::string& what);

/// From a .glb, .gltf or .vrm file (the JSON chunk only). InputError as above, or for a file
/// that is not glTF.
GltfVrm ReadGltfVrm(const std::string& fileName);
} // namespace morphnode
