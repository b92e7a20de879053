// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file FaceRig.h
/// @brief A rig chosen from a face's own target names, whatever naming its maker used
/// (docs/avatars.md): the behaviour's shapes (the paper's, the Meta/Oculus and German
/// visemes, the behaviour's brows, smiles and looks, as Data/rigs/arkit.json defines them)
/// onto the face's targets.
///
/// Naming families recognised:
/// - the paper's own shapes (A, E, O, S, F, L, EyesClosed, BrowsUp, ...): no rig needed;
/// - ARKit in any spelling capture/ArkitNames.h knows (eyeBlinkLeft, EyeBlinkLeft,
///   eyeBlink_L): the ARKit rig's terms are translated onto the face's spelling;
/// - Oculus / Meta visemes as Ready Player Me, Avaturn and TalkingHead name them
///   (viseme_sil, viseme_PP, ..., viseme_aa, viseme_E, viseme_I, viseme_O, viseme_U);
/// - VRoid Studio's `Fcl_*` shape keys (Fcl_MTH_A, Fcl_EYE_Close, Fcl_BRW_Angry, ...);
/// - VRM expression names on targets: 1.0's presets (aa, ih, ou, ee, oh, blink, happy,
///   angry, sad, surprised) and 0.x's (A, I, U, E, O, Blink, Joy, Angry, Sorrow);
/// - VRM expressions the file defines (VRMC_vrm / VRM 0.x blend shape groups, bound to
///   targets of any name), given as FaceExpression.
/// A shape the face has a target for by name drives that target (its own); otherwise,
/// where the face has the ARKit shapes, it is synthesized from them (e.g. a viseme from
/// jawOpen, mouthFunnel, ...); otherwise it is missing. Nothing is dropped silently: the
/// choice lists all three.

#include "rig/Rig.h"

#include <string>
#include <utility>
#include <vector>

namespace morphnode
{
struct FaceRigChoice
{
  /// The families found, with counts, e.g. "ARKit (52 of 52 shapes), Oculus visemes (15)".
  std::string Families;
  /// True when the face's targets are the behaviour's shapes themselves (the paper's
  /// naming): no rig is needed.
  bool NeedsRig = true;
  /// True when the face has its own Oculus visemes (then the Meta viseme set fits best).
  bool HasOwnVisemes = false;
  /// Shapes driving the face's own targets of that name, shapes synthesized from ARKit
  /// shapes, and shapes nothing drives.
  std::vector<std::string> Own, Synthesized, Missing;
  /// The rig as rig JSON (docs/rigs.md), bound to nothing yet; empty when !NeedsRig.
  std::string RigJson;

  /// Lines for users: the families, then what drives which shapes.
  std::string Report() const;
};

/// An expression a file defines over its targets (VRM: gltf/GltfVrm.h's expressions), by
/// name (VRM 1.0's preset names: aa ih ou ee oh blink happy angry sad relaxed surprised
/// lookUp lookDown lookLeft lookRight, or custom names) and its binds (target, weight).
struct FaceExpression
{
  std::string Name;
  std::vector<std::pair<std::string, double>> Binds;
};

/// Chooses the rig for a face whose relative targets are `faceTargets` (no neutral), from
/// the shipped ARKit rig `arkitRig` (Data/rigs/arkit.json: its shapes and their ARKit terms).
/// InputError when no family is recognised (nothing would move the face).
FaceRigChoice ChooseFaceRig(const std::vector<std::string>& faceTargets, const Rig& arkitRig);

/// The same with the file's own expressions (a VRM's): a shape whose own name is an
/// expression drives that expression's binds (e.g. O -> the `oh` expression -> its targets
/// with their weights), before a target of that name and before synthesis. The family
/// is reported as "VRM expressions (n, from the file)".
FaceRigChoice ChooseFaceRig(const std::vector<std::string>& faceTargets, const Rig& arkitRig,
  const std::vector<FaceExpression>& expressions);
} // namespace morphnode
