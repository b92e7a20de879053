// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfPerformanceExport.h"

#include "base/Error.h"
#include "base/Text.h"
#include "gaze/EyeRotation.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfSkin.h"
#include "morph/MorphScene.h"
#include "morph/OptimizerPresets.h"
#include "skin/AvatarBones.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <set>

namespace morphnode
{
const std::vector<double>* GltfPerformanceTable::Find(const std::string& name) const
{
  for (size_t c = 0; c < this->Names.size() && c < this->Columns.size(); ++c)
  {
    if (this->Names[c] == name)
    {
      return &this->Columns[c];
    }
  }
  return nullptr;
}

namespace
{
/// (x, y, z, w) of a rotation matrix given row-major in a 4x4 (GltfQuaternionFromRowMajor).
std::array<double, 4> Quaternion(const std::array<double, 9>& r)
{
  const std::array<double, 16> m{ { r[0], r[1], r[2], 0, r[3], r[4], r[5], 0, r[6], r[7], r[8], 0,
    0, 0, 0, 1 } };
  return GltfQuaternionFromRowMajor(m);
}

/// The weights of the table's target columns, optionally through the optimizer.
void Weights(const GltfScene& scene, const GltfPerformanceTable& table,
  const GltfPerformanceSettings& s, GltfPerformance& p)
{
  std::set<std::string> targets;
  for (const auto& part : scene.Parts)
  {
    for (const auto& t : part.Targets)
    {
      targets.insert(t.Name);
    }
  }
  const size_t frames = p.Times.size();
  std::vector<const std::vector<double>*> columns;
  for (size_t c = 0; c < table.Names.size(); ++c)
  {
    if (targets.count(table.Names[c]) &&
      std::find(p.TargetNames.begin(), p.TargetNames.end(), table.Names[c]) == p.TargetNames.end())
    {
      p.TargetNames.push_back(table.Names[c]);
      columns.push_back(&table.Columns[c]);
    }
  }
  p.Weights.resize(frames * columns.size());
  for (size_t f = 0; f < frames; ++f)
  {
    for (size_t c = 0; c < columns.size(); ++c)
    {
      p.Weights[f * columns.size() + c] = (*columns[c])[f];
    }
  }
  if (!s.ApplyOptimizer || columns.empty())
  {
    return;
  }
  std::vector<std::shared_ptr<const MorphMesh>> meshes;
  for (const auto& part : scene.Parts)
  {
    GltfPart positions = part;
    positions.Normals.clear(); // the optimizer decides on positions
    meshes.push_back(std::make_shared<MorphMesh>(GltfPartToMorphMesh(positions)));
  }
  MorphScene model;
  model.SetParts(meshes);
  OptimizerSettings settings = MakeOptimizerSettings(
    static_cast<OptimizerPreset>(s.OptimizerPreset), s.Threshold, s.MaxVertexError);
  settings.Hysteresis = s.Hysteresis;
  model.SetOptimizerSettings(settings);
  model.SetWeightMode(WeightMode::Relative);
  std::vector<int> index(columns.size());
  for (size_t c = 0; c < index.size(); ++c)
  {
    index[c] = model.FindTarget(p.TargetNames[c]);
  }
  std::vector<double> requested(model.GetNumberOfTargets(), 0.0);
  for (size_t f = 0; f < frames; ++f)
  {
    std::fill(requested.begin(), requested.end(), 0.0);
    for (size_t c = 0; c < index.size(); ++c)
    {
      requested[static_cast<size_t>(index[c])] = p.Weights[f * index.size() + c];
    }
    const std::vector<double>& effective = model.SetWeights(requested);
    for (size_t c = 0; c < index.size(); ++c)
    {
      p.Weights[f * index.size() + c] = effective[static_cast<size_t>(index[c])];
    }
  }
}

/// The joint's local rotation (x, y, z, w) in a posed local matrix (scale divided out).
glm::dquat LocalRotation(const glm::dmat4& local)
{
  glm::dmat3 r(local);
  for (int c = 0; c < 3; ++c)
  {
    r[c] = glm::normalize(r[c]);
  }
  return glm::normalize(glm::quat_cast(r));
}
} // namespace

GltfPerformance MakeGltfPerformance(const GltfScene& scene, const GltfPerformanceTable& table,
  const GltfPerformanceSettings& s, GltfPerformanceReport* report)
{
  GltfPerformance p;
  p.Interpolation = s.Interpolation;
  p.Times = table.Times;
  const size_t frames = p.Times.size();
  if (table.Names.size() != table.Columns.size())
  {
    throw InputError("the performance table has " + std::to_string(table.Names.size()) +
      " names and " + std::to_string(table.Columns.size()) + " columns");
  }
  for (size_t c = 0; c < table.Columns.size(); ++c)
  {
    if (table.Columns[c].size() != frames)
    {
      throw InputError("the performance's column '" + table.Names[c] + "' has " +
        std::to_string(table.Columns[c].size()) + " values for " + std::to_string(frames) +
        " times");
    }
  }
  Weights(scene, table, s, p);

  auto column = [&](const char* name) { return table.Find(name); };
  auto at = [](const std::vector<double>* c, size_t f) { return c ? (*c)[f] : 0.0; };
  const std::vector<double>* headYaw = s.HeadPose ? column("HeadYaw") : nullptr;
  const std::vector<double>* headPitch = s.HeadPose ? column("HeadPitch") : nullptr;
  const std::vector<double>* headRoll = s.HeadPose ? column("HeadRoll") : nullptr;
  const std::vector<double>* eyeYaw = s.EyeRotations ? column("EyeYaw") : nullptr;
  const std::vector<double>* eyePitch = s.EyeRotations ? column("EyePitch") : nullptr;
  const bool head = headYaw || headPitch || headRoll;
  const bool eyes = eyeYaw || eyePitch;
  // The jaw joint opens the mouth only where no jawOpen target does (as vtkMorphSkinFilter's
  // JAW_AUTO): the table's jawOpen column is then not a weight of any mesh.
  std::vector<std::string> targetNames;
  for (const auto& part : scene.Parts)
  {
    for (const auto& t : part.Targets)
    {
      targetNames.push_back(t.Name);
    }
  }
  const bool jawTarget = NamesJawOpenTarget(targetNames);
  const std::vector<double>* jawOpen = s.JawByBone && !jawTarget ? column("jawOpen") : nullptr;
  GltfPerformanceReport r;
  r.Frames = frames;
  r.WeightColumns = p.TargetNames.size();

  // The avatar's bones, when its parts are skinned in their nodes' frames.
  const bool skinned = std::any_of(scene.Parts.begin(), scene.Parts.end(),
    [](const GltfPart& part) { return part.Skin >= 0 && !part.TransformApplied; });
  const EyeRig rig =
    MakeEyeRig(s.EyeNodeNames, { { 0.0, 0.0, 1.0 } }, { { 0.0, 1.0, 0.0 } }, s.Limits);
  bool headByBones = false;
  bool eyesByBones = false;
  if (skinned && (head || eyes || jawOpen))
  {
    const Skeleton skeleton = GltfSkeleton(scene);
    AvatarBoneRoles roles = FindAvatarBones(skeleton, s.Humanoid);
    headByBones = head && (roles.Head >= 0 || roles.Neck >= 0);
    eyesByBones = eyes && roles.HasEyes() && s.EyeNodeNames.empty();
    if (!jawOpen)
    {
      roles.Jaw = -1;
    }
    std::vector<int> joints;
    if (roles.Jaw >= 0)
    {
      joints.push_back(roles.Jaw);
    }
    if (headByBones)
    {
      for (int j : { roles.Neck, roles.Head })
      {
        if (j >= 0)
        {
          joints.push_back(j);
        }
      }
    }
    if (eyesByBones)
    {
      for (int j : { roles.LeftEye, roles.RightEye, roles.LeftUpperLid, roles.RightUpperLid,
             roles.LeftLowerLid, roles.RightLowerLid })
      {
        if (j >= 0)
        {
          joints.push_back(j);
        }
      }
    }
    if (eyesByBones)
    {
      // The eye joints turn the eyeballs: their eyeLook* targets stay at 0 there (the same
      // weights still move the lids of the head), as vtkMorphNodeFilter::SetTargetOffInPart
      // on screen.
      for (const GltfPart& part : scene.Parts)
      {
        if (part.Skin < 0 || part.Node < 0 ||
          !TurnedByEyeJoints(
            part.Influences, GltfSkinJoints(scene, part.Skin).Joints, skeleton, roles))
        {
          continue;
        }
        std::vector<std::string>& off = p.TargetsOffAtNode[part.Node];
        for (const auto& t : part.Targets)
        {
          if (text::ToLower(t.Name).rfind("eyelook", 0) == 0 &&
            std::find(off.begin(), off.end(), t.Name) == off.end())
          {
            off.push_back(t.Name);
          }
        }
      }
    }
    std::vector<GltfRotationTrack> tracks(joints.size());
    for (size_t k = 0; k < joints.size(); ++k)
    {
      const GltfNode& node = scene.Nodes[static_cast<size_t>(joints[k])];
      tracks[k].Node = node.Name;
      tracks[k].Pivot = node.Translation;
      tracks[k].Rotations.reserve(4 * frames);
    }
    SkeletonPose pose(skeleton);
    for (size_t f = 0; f < frames; ++f)
    {
      AvatarBonePose angles;
      if (headByBones)
      {
        angles.HeadYaw = at(headYaw, f);
        angles.HeadPitch = at(headPitch, f);
        angles.HeadRoll = at(headRoll, f);
      }
      if (eyesByBones)
      {
        angles.EyeYaw = at(eyeYaw, f);
        angles.EyePitch = at(eyePitch, f);
      }
      angles.NeckShare = s.NeckShare;
      angles.Limits = rig.GetLimits();
      angles.JawOpen = at(jawOpen, f);
      angles.MaxJawAngle = s.MaxJawAngle;
      angles.RangeMaps = s.RangeMaps;
      pose.Reset();
      PoseAvatarBones(pose, roles, angles);
      for (size_t k = 0; k < joints.size(); ++k)
      {
        const GltfNode& node = scene.Nodes[static_cast<size_t>(joints[k])];
        const glm::dquat rest(
          node.Rotation[3], node.Rotation[0], node.Rotation[1], node.Rotation[2]);
        // The writer's channel holds turn * rest rotation (GltfWriter.h): the turn is the
        // posed local rotation times the rest rotation's inverse.
        const glm::dquat turn =
          LocalRotation(pose.GetLocals()[static_cast<size_t>(joints[k])]) * glm::conjugate(rest);
        tracks[k].Rotations.insert(tracks[k].Rotations.end(), { turn.x, turn.y, turn.z, turn.w });
      }
    }
    for (auto& track : tracks)
    {
      r.Turned.push_back(track.Node);
      p.Rotations.push_back(std::move(track));
    }
    r.Bones = !tracks.empty();
  }

  // The head as a whole, about its pivot.
  if (head && !headByBones)
  {
    GltfRotationTrack track;
    track.Pivot = s.HeadPivot;
    for (size_t f = 0; f < frames; ++f)
    {
      const glm::dquat q = HeadRotation(at(headYaw, f), at(headPitch, f), at(headRoll, f));
      track.Rotations.insert(track.Rotations.end(), { q.x, q.y, q.z, q.w });
    }
    r.Turned.emplace_back();
    p.Rotations.push_back(std::move(track));
  }

  // Eye nodes (unskinned parts) as vtkEyeGazeFilter finds and turns them.
  if (eyes && !eyesByBones)
  {
    std::set<int> done;
    for (const auto& part : scene.Parts)
    {
      if (part.Skin >= 0 || part.Node < 0 || static_cast<size_t>(part.Node) >= scene.Nodes.size() ||
        done.count(part.Node))
      {
        continue; // a skinned part turns with its joints, never by its node
      }
      const GltfNode& node = scene.Nodes[static_cast<size_t>(part.Node)];
      EyeSpec eye;
      const bool unique =
        std::count_if(scene.Nodes.begin(), scene.Nodes.end(),
          [&node](const GltfNode& other) { return other.Name == node.Name; }) == 1;
      if (!unique || !rig.FindEye(node.Name, part.Name, eye))
      {
        continue;
      }
      done.insert(part.Node);
      GltfNodeFrame frame;
      if (s.NodeFrames.size() == scene.Nodes.size())
      {
        frame = s.NodeFrames[static_cast<size_t>(part.Node)];
      }
      else
      {
        const GltfMatrix& w = node.World;
        frame.Origin = { { w[12], w[13], w[14] } };
        frame.Axes = { { w[0], w[1], w[2], w[4], w[5], w[6], w[8], w[9], w[10] } };
      }
      GltfRotationTrack track;
      track.Node = node.Name;
      track.Pivot = frame.Origin;
      for (size_t f = 0; f < frames; ++f)
      {
        GazeAngles gaze;
        gaze.Yaw = at(eyeYaw, f);
        gaze.Pitch = at(eyePitch, f);
        const GazeAngles turned = EyeAngles(gaze, 0.0, eye.Side, rig.GetLimits());
        const auto q = Quaternion(EyeRotationMatrix(turned, frame.Axes, eye.Forward, eye.Up));
        track.Rotations.insert(track.Rotations.end(), q.begin(), q.end());
      }
      r.Turned.push_back(node.Name);
      p.Rotations.push_back(std::move(track));
    }
  }
  if (report)
  {
    *report = r;
  }
  return p;
}

std::vector<std::string> RelaxGltfArms(
  GltfScene& scene, double armAngle, const std::map<std::string, std::string>& humanoid)
{
  const bool skinned = std::any_of(scene.Parts.begin(), scene.Parts.end(),
    [](const GltfPart& part) { return part.Skin >= 0 && !part.TransformApplied; });
  if (!skinned || scene.Nodes.empty())
  {
    return {};
  }
  const Skeleton skeleton = GltfSkeleton(scene);
  const AvatarBoneRoles roles = FindAvatarBones(skeleton, humanoid);
  SkeletonPose pose(skeleton);
  AvatarBonePose relaxed;
  relaxed.RelaxArms = true;
  relaxed.ArmAngle = armAngle;
  PoseAvatarBones(pose, roles, relaxed);
  const std::vector<glm::dmat4> rest = skeleton.RestLocals();
  std::vector<std::string> names;
  for (int j : { roles.LeftUpperArm, roles.RightUpperArm })
  {
    const size_t n = static_cast<size_t>(j);
    if (j < 0 || n >= scene.Nodes.size() || pose.GetLocals()[n] == rest[n])
    {
      continue;
    }
    GltfNode& node = scene.Nodes[n];
    const glm::dmat4& local = pose.GetLocals()[n];
    if (node.HasMatrix)
    {
      node.Local = GltfFromGlm(local);
    }
    else
    {
      // The joint turns about its own origin: its translation and scale stay.
      const glm::dquat q = LocalRotation(local);
      node.Rotation = { { q.x, q.y, q.z, q.w } };
      node.Local = GltfComposeTrs(node.Translation, node.Rotation, node.Scale);
    }
    names.push_back(node.Name);
  }
  // The world transforms again, parents first.
  std::vector<char> done(scene.Nodes.size(), 0);
  std::function<void(size_t)> world = [&](size_t n)
  {
    if (done[n])
    {
      return;
    }
    done[n] = 1; // a cycle (refused when the scene was read) ends here
    GltfNode& node = scene.Nodes[n];
    const int parent = node.Parent;
    if (parent >= 0 && static_cast<size_t>(parent) < scene.Nodes.size())
    {
      world(static_cast<size_t>(parent));
      node.World = GltfMultiply(scene.Nodes[static_cast<size_t>(parent)].World, node.Local);
    }
    else
    {
      node.World = node.Local;
    }
  };
  for (size_t n = 0; n < scene.Nodes.size() && !names.empty(); ++n)
  {
    world(n);
  }
  return names;
}

std::vector<unsigned char> WriteGltfPerformanceToMemory(const GltfScene& scene,
  const GltfPerformanceTable* table, const GltfPerformanceSettings& settings,
  const GltfWriteOptions& options, GltfPerformanceReport* report)
{
  const GltfScene* written = &scene;
  GltfScene relaxed;
  std::vector<std::string> relaxedArms;
  if (settings.RelaxArms)
  {
    relaxed = scene;
    relaxedArms = RelaxGltfArms(relaxed, settings.ArmAngle, settings.Humanoid);
    written = &relaxed;
  }
  if (table && !table->Times.empty())
  {
    const GltfPerformance p = MakeGltfPerformance(*written, *table, settings, report);
    if (report)
    {
      report->Relaxed = relaxedArms;
    }
    return WriteGltfSceneToMemory(*written, &p, options);
  }
  if (report)
  {
    *report = GltfPerformanceReport();
    report->Relaxed = relaxedArms;
  }
  return WriteGltfSceneToMemory(*written, nullptr, options);
}
} // namespace morphnode
