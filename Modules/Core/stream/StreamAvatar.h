// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file StreamAvatar.h
/// @brief The avatar prepared once for streaming (shared, read-only, by every session):
/// which of the face's targets the behaviour can drive (the stream's targets; the others
/// are left out of the file and of the frames), the behaviour's channels mapped onto them
/// (by name, or through a rig), the rotation nodes (head, eyes) and the file a remote face
/// loads: the face with only the driven targets, sparse deltas, and a node above the head
/// and above each eye whose rotation the frames set (gltf/GltfWriter.h).
///
///   morphnode::GltfScene face = morphnode::LoadGltfScene("default_head.glb");
///   morphnode::stream::StreamAvatar avatar(face, live.GetChannelNames(), rig /* or null */);
///   avatar.GetFile();                          // the GLB for the page
///   avatar.Map(channels, targetWeights, quats); // one frame's weights and rotations
///
/// Nothing here depends on VTK.

#include "gaze/EyeRig.h"
#include "gltf/GltfScene.h"
#include "morph/MorphScene.h"
#include "rig/Rig.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace morphnode
{
struct DeviceProfile;
namespace stream
{
/// How the avatar file is prepared for a device (DeviceAvatarOptions from a profile).
struct StreamAvatarOptions
{
  /// The file's sparse target deltas as normalized 16-bit integers (KHR_mesh_quantization,
  /// GltfWriteOptions::QuantizeTargets), which three.js reads; MorphNode's own loader does
  /// not take that extension yet, so tools that read the file back ask for floats.
  bool QuantizeDeltas = true;
  /// Driven targets whose largest point motion (at weight 1) stays below this many pixels
  /// when the face is FacePixels high are left out (the device would not show them). 0:
  /// every driven target is kept.
  double TargetPixelBound = 0.0;
  /// The face's height on the device's screen, pixels (the page frames the face to the
  /// view's height).
  double FacePixels = 800.0;
  /// The mesh's level of detail: 0 the full mesh; l >= 1 the level-of-detail ladder's level
  /// l (lod/MorphLadder.h, its default triangle fractions), for every part of at least
  /// MinReducedTriangles triangles, when this build has the reduction
  /// (MORPHNODE_ENABLE_REDUCTION; else the full mesh: GetLevel() says which).
  int Level = 0;
  size_t MinReducedTriangles = 500;
};

/// The options of a device profile (budget/DeviceProfile.h: desktop, laptop, phone): its
/// TargetPixelBound and FinestLevel, the face `facePixels` high.
StreamAvatarOptions DeviceAvatarOptions(const DeviceProfile& profile, double facePixels = 800.0);

class StreamAvatar
{
public:
  /// `face`: a scene as LoadGltfScene reads it (transforms applied). `channels`: the
  /// behaviour's channel names (LiveBehavior::GetChannelNames). `rig`: null to drive
  /// targets named like channels, else a rig whose shapes are named like channels (it is
  /// copied and bound to the face's targets). InputError when no target can be driven,
  /// more than MaxTargets can, or the rig does not fit the face. `quantizeDeltas`: the
  /// file's sparse target deltas as normalized 16-bit integers (KHR_mesh_quantization,
  /// GltfWriteOptions::QuantizeTargets), which three.js reads; MorphNode's own loader does
  /// not take that extension yet, so tools that read the file back ask for floats.
  StreamAvatar(const GltfScene& face, const std::vector<std::string>& channels,
    const Rig* rig = nullptr, bool quantizeDeltas = true);
  /// The same, prepared as `options` ask (e.g. for a device).
  StreamAvatar(const GltfScene& face, const std::vector<std::string>& channels, const Rig* rig,
    const StreamAvatarOptions& options);

  /// The level of detail of the file's mesh (0: full; options.Level when it was reduced).
  int GetLevel() const { return this->Level; }
  /// Triangles of the file's mesh, all parts.
  size_t GetNumberOfTriangles() const { return this->Triangles; }
  /// The reduced level's error (99th percentile of the points' largest distance over the
  /// poses, the largest over the reduced parts; model units); 0 at level 0.
  double GetLevelError() const { return this->LevelError; }
  /// Driven targets left out by the pixel bound, in the face's order.
  const std::vector<std::string>& GetPrunedTargets() const { return this->Pruned; }

  /// The stream's targets: those the channels can drive, in the face's order.
  const std::vector<std::string>& GetTargetNames() const { return this->Targets; }
  /// The face's target count (driven or not).
  size_t GetNumberOfFaceTargets() const { return this->FaceTargets; }
  /// The rotation nodes a frame sets, as named in GetFile(): HeadRotation first, then one
  /// per eye (e.g. EyeLeftRotation).
  const std::vector<std::string>& GetRotationNames() const { return this->RotationNames; }
  /// The avatar file (GLB) for remote faces.
  const std::vector<unsigned char>& GetFile() const { return this->File; }
  /// The model the optimizer decides on (the face reduced to the stream's targets; its
  /// target k + 1 is the stream's target k). Sessions copy it (each has its history).
  const MorphScene& GetModel() const { return *this->Model; }

  /// One frame: the behaviour's channel values (GetChannelNames order) -> the stream's
  /// target weights (GetTargetNames order, clamped to [0, 1]) and one unit quaternion
  /// (x, y, z, w) per rotation node. `scratch` is the caller's (one per session: Map is
  /// const and may run on several threads at once). No allocation once sizes are known.
  void Map(const double* channels, std::vector<double>& targetWeights,
    std::vector<std::array<double, 4>>& rotations, std::vector<double>& scratch) const;

private:
  std::vector<std::string> Targets;
  std::vector<std::string> Pruned;
  int Level = 0;
  size_t Triangles = 0;
  double LevelError = 0.0;
  size_t FaceTargets = 0;
  size_t NumberOfChannels = 0;
  std::vector<std::string> RotationNames;
  std::vector<unsigned char> File;
  std::shared_ptr<MorphScene> Model;
  /// Without a rig: channel -> stream target (-1: none).
  std::vector<int> ChannelTarget;
  /// With a rig: channel -> rig shape (-1: none), and rig bound target -> stream target.
  std::unique_ptr<Rig> BoundRig;
  std::vector<int> ChannelShape;
  std::vector<int> RigTargetToStream;
  int HeadYaw = -1, HeadPitch = -1, HeadRoll = -1, EyeYaw = -1, EyePitch = -1;
  struct Eye
  {
    EyeSpec Spec;
    std::array<double, 9> Axes;
  };
  std::vector<Eye> Eyes;
  EyeLimits Limits;
};
} // namespace stream
} // namespace morphnode
