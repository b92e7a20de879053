// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfPerformanceExport.h
/// @brief A scene and a performance table (a row per frame: target weights, the
/// behaviour's head and eye angles) to the glTF performance GltfWriter.h writes: the
/// weights (optionally the optimizer's effective weights), the head pose and the eye turns
/// as rotations of the avatar's bones when it has them, else of nodes (docs/gltf.md,
/// "Export"; docs/avatars.md).
///
/// Bones (a skinned scene whose parts are in their nodes' frames): the skeleton's head,
/// neck and eye joints found by name (skin/AvatarBones.h) are turned per frame as
/// vtkMorphSkinFilter turns them (PoseAvatarBones: the head pose shared between neck and
/// head, the eyes by the eye rig's limits in the turned face frame), and each turned joint
/// gets a rotation track about its own origin, which the writer writes as a rotation
/// channel on the joint itself (the skeleton stays as its maker made it). A jaw joint
/// opens by the table's `jawOpen` when no part has a `jawOpen` target.
/// Nodes (unskinned heads, ICT): the head pose turns the whole scene about HeadPivot; the
/// eye nodes the eye rig finds (gaze/EyeRig.h's MakeEyeRig, as vtkEyeGazeFilter) turn about
/// their frames (NodeFrames, else the nodes' world transforms).
///
/// Nothing here depends on VTK.

#include "gaze/EyeRig.h"
#include "gltf/GltfWriter.h"
#include "skin/AvatarBones.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace morphnode
{
/// The performance as a table, a row per frame.
struct GltfPerformanceTable
{
  /// Seconds, strictly increasing.
  std::vector<double> Times;
  /// Column names and values (one value per time each). Columns named after a target of
  /// the scene are weights; `HeadYaw`, `HeadPitch`, `HeadRoll`, `EyeYaw` and `EyePitch` are
  /// angles (degrees, behavior/HeadPose.h's convention; no vergence, as vtkEyeGazeFilter's
  /// default); others are ignored.
  std::vector<std::string> Names;
  std::vector<std::vector<double>> Columns;

  /// The column of that name, or null.
  const std::vector<double>* Find(const std::string& name) const;
};

/// Where an eye node is when the nodes carry no transform (parts in world space).
struct GltfNodeFrame
{
  std::array<double, 3> Origin{ { 0, 0, 0 } };
  /// The node's world x, y and z axes, 3 values each.
  std::array<double, 9> Axes{ { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
};

struct GltfPerformanceSettings
{
  GltfInterpolation Interpolation = GltfInterpolation::Linear;
  /// The weights as the paper's optimizer decides them once per frame over the whole
  /// scene, in frame order (morph/MorphScene, Relative weights), instead of the table's.
  bool ApplyOptimizer = false;
  int OptimizerPreset = 3; ///< morph/OptimizerPresets.h
  double Threshold = 0.1;
  double MaxVertexError = 0.0;
  double Hysteresis = 0.0;
  /// Head pose and eye turns from the angle columns.
  bool HeadPose = true;
  bool EyeRotations = true;
  /// The pivot of a head turned as a whole (no head or neck bones): behavior/HeadPose.h's
  /// HeadPivot of the head's bounds.
  std::array<double, 3> HeadPivot{ { 0, 0, 0 } };
  /// The neck's share of the head pose when bones turn it (skin/AvatarBones.h).
  double NeckShare = 0.4;
  /// Eyes named (nodes or parts, as vtkEyeGazeFilter's EyeNames); empty: the avatar's eye
  /// bones when it has them, else the eye rig's default convention on nodes.
  std::vector<std::string> EyeNodeNames;
  EyeLimits Limits;
  /// The table's `jawOpen` column (0..1) turns the avatar's jaw joint by up to MaxJawAngle
  /// degrees when it has one and no part has a `jawOpen` target (skin/AvatarBones.h).
  bool JawByBone = true;
  double MaxJawAngle = 25.0;
  /// The avatar's own humanoid map (VRM humanBones: bone -> node name, gltf/GltfVrm.h),
  /// winning over the names' guess; and its look-at range maps for eye bones.
  std::map<std::string, std::string> Humanoid;
  EyeRangeMaps RangeMaps;
  /// One per scene node when the parts are in world space and the nodes carry no transform
  /// (the eye nodes' centres and axes); empty: from the nodes' world transforms.
  std::vector<GltfNodeFrame> NodeFrames;
  /// A T- or A-pose skinned avatar written with its arms relaxed, as vtkMorphSkinFilter's
  /// RelaxArms shows it (RelaxGltfArms): the upper arm joints' node rotations.
  bool RelaxArms = false;
  double ArmAngle = 12.0;
};

/// What was made, for reports.
struct GltfPerformanceReport
{
  size_t Frames = 0;
  size_t WeightColumns = 0;
  /// True when the head pose and gaze turn bones (joint rotation channels).
  bool Bones = false;
  /// The joints or nodes that turn (empty name: the whole scene).
  std::vector<std::string> Turned;
  /// The upper arm joints written relaxed (RelaxArms).
  std::vector<std::string> Relaxed;
};

/// Lowers the arms of a T- or A-pose skinned avatar in `scene`: the upper arm joints the
/// skeleton's names (or `humanoid`, VRM's map) give are turned as PoseAvatarBones' RelaxArms
/// turns them (skin/AvatarBones.h: ArmAngle degrees out from straight down) and their node
/// rotations (or matrices) and the nodes' world transforms set to that pose, so that every
/// reader shows the avatar at rest with its arms down. The points stay in bind space (the
/// skin places them). Returns the joints' names; none for a scene without a skinned part in
/// its nodes' frames, without both arm joints of a side, or arms already down.
std::vector<std::string> RelaxGltfArms(
  GltfScene& scene, double armAngle, const std::map<std::string, std::string>& humanoid = {});

/// The performance for `scene` from `table`. InputError for columns of the wrong length,
/// non-finite angles, times the writer refuses.
GltfPerformance MakeGltfPerformance(const GltfScene& scene, const GltfPerformanceTable& table,
  const GltfPerformanceSettings& settings, GltfPerformanceReport* report = nullptr);

/// The file in memory: the scene (its arms relaxed first when settings.RelaxArms) and, when
/// `table` has rows, its performance (MakeGltfPerformance then WriteGltfSceneToMemory).
/// Throws InputError.
std::vector<unsigned char> WriteGltfPerformanceToMemory(const GltfScene& scene,
  const GltfPerformanceTable* table, const GltfPerformanceSettings& settings,
  const GltfWriteOptions& options = {}, GltfPerformanceReport* report = nullptr);
} // namespace morphnode
