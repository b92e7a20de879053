// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfPose.h"

#include "base/Error.h"
#include "gltf/GltfSkin.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

namespace morphnode
{
GltfPose PoseGltfScene(const GltfScene& scene, const GltfPoseOptions& options)
{
  GltfPose pose;
  pose.Options = options;
  if (options.Animation >= 0)
  {
    const GltfAnimationPlayer player(scene, options.Animation, options.Source);
    pose.Time = options.Time ? *options.Time : player.GetStartTime();
    if (!std::isfinite(pose.Time))
    {
      throw InputError("the time requested is not a finite number");
    }
    pose.Sample = player.Sample(pose.Time);
    pose.AnimatedNodes = player.GetAnimatedNodes();
  }
  else
  {
    pose.Options.ApplyTransforms = pose.Options.ApplyWeights = false;
    pose.Sample = GltfRestPose(scene);
  }
  for (size_t n = 0; n < scene.Nodes.size(); ++n)
  {
    const bool sampled = pose.Options.ApplyTransforms && n < pose.Sample.Nodes.size();
    pose.Worlds.push_back(sampled ? pose.Sample.Nodes[n].World : scene.Nodes[n].World);
    pose.Locals.push_back(sampled ? pose.Sample.Nodes[n].Local : scene.Nodes[n].Local);
  }
  return pose;
}

GltfPart PoseGltfPart(const GltfScene& scene, const GltfPose& pose, const GltfPart& part)
{
  const GltfNodeSample& node = pose.Sample.Nodes.at(static_cast<size_t>(part.Node));
  GltfPart posed = part;
  if (pose.Options.ApplyWeights)
  {
    GltfBlendPart(posed, node.Weights);
  }
  if (pose.Options.ApplyTransforms && posed.Skin >= 0)
  {
    GltfSkinPart(posed, scene, pose.Worlds, pose.Options.Source);
  }
  else if (pose.Options.ApplyTransforms)
  {
    GltfTransformPart(posed, node.World);
    posed.World = node.World;
  }
  return posed;
}

void GltfBlendPart(GltfPart& part, const std::vector<double>& weights)
{
  const size_t n = part.GetNumberOfPoints();
  std::vector<double> p(part.Positions.begin(), part.Positions.end());
  std::vector<double> normals(part.Normals.begin(), part.Normals.end());
  for (size_t k = 0; k < part.Targets.size() && k < weights.size(); ++k)
  {
    const double w = weights[k];
    if (w == 0.0)
    {
      continue;
    }
    const auto& target = part.Targets[k];
    for (size_t i = 0; i < 3 * n; ++i)
    {
      p[i] += w * double(target.PositionDeltas[i]);
    }
    if (!normals.empty() && !target.NormalDeltas.empty())
    {
      for (size_t i = 0; i < 3 * n; ++i)
      {
        normals[i] += w * double(target.NormalDeltas[i]);
      }
    }
  }
  std::copy(p.begin(), p.end(), part.Positions.begin());
  for (size_t i = 0; i < n && !normals.empty(); ++i)
  {
    const double* v = &normals[3 * i];
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (size_t c = 0; c < 3; ++c)
    {
      part.Normals[3 * i + c] = static_cast<float>(length > 0 ? v[c] / length : v[c]);
    }
  }
}

std::vector<double> GltfTimeSteps(const GltfAnimationPlayer& player, double rate)
{
  if (rate <= 0.0)
  {
    return player.GetKeyTimes();
  }
  std::vector<double> steps;
  const double start = player.GetStartTime(), end = player.GetEndTime();
  const double count = std::floor((end - start) * rate + 1e-9);
  for (double i = 0; i <= count && steps.size() < 1000000; ++i)
  {
    steps.push_back(start + i / rate);
  }
  if (steps.empty() || steps.back() < end - 1e-12)
  {
    steps.push_back(end);
  }
  return steps;
}

std::vector<std::string> GltfTargetNames(const GltfScene& scene)
{
  std::vector<std::string> names;
  std::unordered_set<std::string> seen;
  for (const GltfPart& part : scene.Parts)
  {
    for (const GltfTarget& target : part.Targets)
    {
      if (seen.insert(target.Name).second)
      {
        names.push_back(target.Name);
      }
    }
  }
  return names;
}

const GltfPart& FindGltfPart(const GltfScene& scene, const std::string& meshName,
  int meshIndexWanted, int primitiveWanted, const std::string& source)
{
  std::vector<std::string> meshNames;
  for (size_t m = 0; m < scene.Meshes.size(); ++m)
  {
    meshNames.push_back(GltfMeshName(scene, m));
  }
  size_t meshIndex = static_cast<size_t>(std::max(meshIndexWanted, 0));
  if (!meshName.empty())
  {
    auto it = std::find(meshNames.begin(), meshNames.end(), meshName);
    if (it == meshNames.end())
    {
      std::ostringstream msg;
      msg << "'" << source << "' has no mesh named '" << meshName << "'; meshes:";
      for (const auto& n : meshNames)
      {
        msg << " " << n;
      }
      throw InputError(msg.str());
    }
    meshIndex = static_cast<size_t>(it - meshNames.begin());
  }
  if (meshIndex >= meshNames.size())
  {
    std::ostringstream msg;
    msg << "mesh index " << meshIndex << " out of range: '" << source << "' has "
        << meshNames.size() << " meshes";
    throw InputError(msg.str());
  }
  const int primitive = std::max(primitiveWanted, 0);
  if (static_cast<size_t>(primitive) >= scene.Meshes[meshIndex].NumberOfPrimitives)
  {
    std::ostringstream msg;
    msg << "primitive " << primitive << " out of range: mesh '" << meshNames[meshIndex] << "' has "
        << scene.Meshes[meshIndex].NumberOfPrimitives;
    throw InputError(msg.str());
  }
  for (const GltfPart& part : scene.Parts)
  {
    if (part.Mesh == static_cast<int>(meshIndex) && part.Primitive == primitive)
    {
      return part;
    }
  }
  throw InputError(
    "mesh '" + meshNames[meshIndex] + "' of '" + source + "' is on no node of the scene");
}
} // namespace morphnode
