// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ArkitNames.h
/// @brief The one table of the 52 ARKit blendshapes and their spellings, and the mapping of
/// ARKit weights onto a face's own targets through a rig (docs/capture.md).
///
/// Three spellings of the same shape are in use:
/// - Apple's (ARFaceAnchor.BlendShapeLocation raw values): camelCase, `eyeBlinkLeft`;
/// - Live Link Face's CSV columns: the same in PascalCase, `EyeBlinkLeft`;
/// - ICT-FaceKit's targets: `eyeBlink_L`, with browInnerUp and cheekPuff split into
///   `browInnerUp_L` / `browInnerUp_R` and `cheekPuff_L` / `cheekPuff_R`.
/// Names are matched without regard to case, so any of them finds its shape.

#include "rig/Rig.h"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace morphnode
{
/// The number of ARKit blendshapes (tongueOut included).
constexpr size_t ArkitShapeCount = 52;

/// Apple's names of the 52 shapes, in Live Link Face's column order (the order of its CSV
/// header and of Unreal's EARFaceBlendShape).
const std::vector<std::string>& ArkitShapeNames();

/// Live Link Face's column name of a shape: Apple's name with a capital first letter.
/// Throws std::out_of_range for an index >= ArkitShapeCount.
std::string ArkitLiveLinkName(size_t shape);

/// ICT-FaceKit's target names of a shape: one name, or two (`_L`, `_R`) for the shapes it
/// splits (browInnerUp, cheekPuff). tongueOut keeps Apple's name (ICT-FaceKit has no such
/// target). Throws std::out_of_range for an index >= ArkitShapeCount.
const std::vector<std::string>& ArkitIctNames(size_t shape);

/// The shape a name means in any of the three spellings, case-insensitive; -1 for a name
/// that is no ARKit shape. A split half (`browInnerUp_L`) finds its whole shape.
int FindArkitShape(std::string_view name);

/// The head and eye angle columns of Live Link Face, in its column order after the shapes.
const std::vector<std::string>& LiveLinkPoseNames();

/// How the 52 shapes land on one face's targets.
struct ArkitFaceMapping
{
  /// Per shape (ArkitShapeNames order): indices into the face's target names it drives.
  std::vector<std::vector<size_t>> Targets;
  /// Shapes that drive nothing on this face (e.g. tongueOut on ICT-FaceKit).
  std::vector<std::string> UnmappedShapes;
  /// Face targets that no ARKit shape drives.
  std::vector<std::string> UnmappedTargets;

  /// One line for users: "N of 52 ARKit shapes drive M of K targets; no target for: ...;
  /// no shape for: ...".
  std::string Report() const;
};

/// Matches each of the face's target names (relative targets, no neutral) with the shape it
/// spells (FindArkitShape).
ArkitFaceMapping MapArkitShapes(const std::vector<std::string>& faceTargets);

/// A rig whose shapes are the 52 ARKit shapes (Apple's names), each driving the face
/// targets MapArkitShapes finds with coefficient 1, bound to `faceTargets`: Expand turns a
/// frame of ARKit weights into the face's weights (a split shape drives both halves).
/// `mapping` (optional) receives the mapping and its report.
Rig MakeArkitRig(const std::vector<std::string>& faceTargets, ArkitFaceMapping* mapping = nullptr);
} // namespace morphnode
