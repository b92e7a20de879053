// SPDX-License-Identifier: BSD-3-Clause
#include "stream/StreamAvatar.h"

#include "base/Error.h"
#include "behavior/HeadPose.h"
#include "budget/DeviceProfile.h"
#include "gaze/EyeRotation.h"
#include "gltf/GltfMorphMesh.h"
#include "gltf/GltfWriter.h"
#include "stream/StreamProtocol.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#ifdef MORPHNODE_HAVE_LOD
#include "lod/MorphLadder.h"
#endif

namespace morphnode
{
namespace stream
{
namespace
{
int Find(const std::vector<std::string>& names, const std::string& name)
{
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

std::array<double, 4> ToQuaternion(const std::array<double, 9>& r)
{
  const std::array<double, 16> m{ { r[0], r[1], r[2], 0, r[3], r[4], r[5], 0, r[6], r[7], r[8], 0,
    0, 0, 0, 1 } };
  return GltfQuaternionFromRowMajor(m);
}

#ifdef MORPHNODE_HAVE_LOD
/// The part at the ladder's level `level`: the points that level keeps (every attribute and
/// delta as they are: collapses keep a subset of the points) and its triangles. The
/// ladder's shared numbering puts a level's points first, so its triangle ids index them
/// directly. `error`: the level's Error99.
GltfPart ReducePart(const GltfPart& part, int level, double& error)
{
  LadderSettings settings;
  settings.TriangleFractions.resize(
    std::min(settings.TriangleFractions.size(), static_cast<size_t>(level)));
  const MorphLadder ladder = BuildMorphLadder(GltfPartToMorphMesh(part), settings);
  const LadderLevel& l = ladder.Levels.back();
  error = l.Error99;
  GltfPart out = part;
  const size_t n = l.NumberOfPoints;
  const auto copy = [&](const std::vector<float>& from, std::vector<float>& to, size_t width)
  {
    if (from.empty())
    {
      return;
    }
    to.assign(n * width, 0.0f);
    for (size_t i = 0; i < n; ++i)
    {
      const size_t o = ladder.OriginalPointIds[i];
      std::copy(from.begin() + static_cast<std::ptrdiff_t>(o * width),
        from.begin() + static_cast<std::ptrdiff_t>((o + 1) * width),
        to.begin() + static_cast<std::ptrdiff_t>(i * width));
    }
  };
  copy(part.Positions, out.Positions, 3);
  copy(part.Normals, out.Normals, 3);
  copy(part.Colors, out.Colors, 4);
  copy(part.TexCoords0, out.TexCoords0, 2);
  copy(part.TexCoords1, out.TexCoords1, 2);
  for (size_t t = 0; t < part.Targets.size(); ++t)
  {
    copy(part.Targets[t].PositionDeltas, out.Targets[t].PositionDeltas, 3);
    copy(part.Targets[t].NormalDeltas, out.Targets[t].NormalDeltas, 3);
  }
  if (!part.Influences.Empty())
  {
    const size_t per = part.Influences.PerPoint;
    out.Influences.Joints.assign(n * per, 0);
    out.Influences.Weights.assign(n * per, 0.0f);
    for (size_t i = 0; i < n; ++i)
    {
      const size_t o = ladder.OriginalPointIds[i];
      for (size_t k = 0; k < per; ++k)
      {
        out.Influences.Joints[i * per + k] = part.Influences.Joints[o * per + k];
        out.Influences.Weights[i * per + k] = part.Influences.Weights[o * per + k];
      }
    }
  }
  out.Triangles = l.Triangles;
  return out;
}
#endif
} // namespace

StreamAvatarOptions DeviceAvatarOptions(const DeviceProfile& profile, double facePixels)
{
  StreamAvatarOptions o;
  o.TargetPixelBound = profile.TargetPixelBound;
  o.FacePixels = facePixels;
  o.Level = profile.FinestLevel;
  return o;
}

StreamAvatar::StreamAvatar(const GltfScene& face, const std::vector<std::string>& channels,
  const Rig* rig, bool quantizeDeltas)
  : StreamAvatar(face, channels, rig,
      [quantizeDeltas]
      {
        StreamAvatarOptions o;
        o.QuantizeDeltas = quantizeDeltas;
        return o;
      }())
{
}

StreamAvatar::StreamAvatar(const GltfScene& face, const std::vector<std::string>& channels,
  const Rig* rig, const StreamAvatarOptions& options)
  : NumberOfChannels(channels.size())
{
  if (!(options.TargetPixelBound >= 0.0 && std::isfinite(options.TargetPixelBound)) ||
    !(options.FacePixels > 0.0 && std::isfinite(options.FacePixels)) || options.Level < 0 ||
    options.Level > 8)
  {
    throw InputError(
      "stream avatar options: a pixel bound >= 0, a face height > 0 pixels and a level in [0, 8]");
  }
  // The face's targets, in order of first appearance over the parts.
  std::vector<std::string> faceTargets;
  for (const GltfPart& part : face.Parts)
  {
    for (const GltfTarget& t : part.Targets)
    {
      if (Find(faceTargets, t.Name) < 0)
      {
        faceTargets.push_back(t.Name);
      }
    }
  }
  this->FaceTargets = faceTargets.size();

  // What the channels drive.
  std::set<std::string> driven;
  if (rig)
  {
    this->BoundRig = std::make_unique<Rig>(*rig);
    this->BoundRig->Bind(faceTargets); // InputError when the rig names a target the face lacks
    this->ChannelShape.assign(channels.size(), -1);
    for (size_t c = 0; c < channels.size(); ++c)
    {
      const int shape = this->BoundRig->FindShape(channels[c]);
      this->ChannelShape[c] = shape;
      if (shape >= 0)
      {
        for (const RigTerm& term : this->BoundRig->GetShapeTerms(static_cast<size_t>(shape)))
        {
          if (term.Coefficient != 0.0)
          {
            driven.insert(term.Target);
          }
        }
      }
    }
  }
  else
  {
    for (const std::string& channel : channels)
    {
      if (Find(faceTargets, channel) >= 0)
      {
        driven.insert(channel);
      }
    }
  }
  if (options.TargetPixelBound > 0.0)
  {
    // The device's pixel bound: a target whose largest point motion stays below it on a
    // face FacePixels high is not worth its bytes there.
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    std::map<std::string, double> motion;
    for (const GltfPart& part : face.Parts)
    {
      for (size_t p = 0; p + 2 < part.Positions.size(); p += 3)
      {
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = std::min(lo[k], static_cast<double>(part.Positions[p + k]));
          hi[k] = std::max(hi[k], static_cast<double>(part.Positions[p + k]));
        }
      }
      for (const GltfTarget& t : part.Targets)
      {
        double& m = motion[t.Name];
        for (size_t p = 0; p + 2 < t.PositionDeltas.size(); p += 3)
        {
          const double dx = t.PositionDeltas[p], dy = t.PositionDeltas[p + 1],
                       dz = t.PositionDeltas[p + 2];
          m = std::max(m, std::sqrt(dx * dx + dy * dy + dz * dz));
        }
      }
    }
    const double height = hi[1] - lo[1];
    const double pixelsPerUnit = height > 0.0 ? options.FacePixels / height : 0.0;
    for (const std::string& name : faceTargets)
    {
      if (driven.count(name) && motion[name] * pixelsPerUnit < options.TargetPixelBound)
      {
        driven.erase(name);
        this->Pruned.push_back(name);
      }
    }
  }
  for (const std::string& name : faceTargets)
  {
    if (driven.count(name))
    {
      this->Targets.push_back(name);
    }
  }
  if (this->Targets.empty())
  {
    throw InputError("the behaviour drives none of the face's " +
      std::to_string(faceTargets.size()) +
      " targets: name them like the behaviour's channels, or give a rig");
  }
  if (this->Targets.size() > MaxTargets)
  {
    throw InputError("the behaviour drives " + std::to_string(this->Targets.size()) +
      " targets; a stream carries at most " + std::to_string(MaxTargets));
  }
  if (this->BoundRig)
  {
    const auto& bound = this->BoundRig->GetBoundTargetNames();
    this->RigTargetToStream.resize(bound.size());
    for (size_t t = 0; t < bound.size(); ++t)
    {
      this->RigTargetToStream[t] = Find(this->Targets, bound[t]);
    }
  }
  else
  {
    this->ChannelTarget.resize(channels.size());
    for (size_t c = 0; c < channels.size(); ++c)
    {
      this->ChannelTarget[c] = Find(this->Targets, channels[c]);
    }
  }
  this->HeadYaw = Find(channels, "HeadYaw");
  this->HeadPitch = Find(channels, "HeadPitch");
  this->HeadRoll = Find(channels, "HeadRoll");
  this->EyeYaw = Find(channels, "EyeYaw");
  this->EyePitch = Find(channels, "EyePitch");

  // The reduced face: only the driven targets (and their default weights).
  GltfScene reduced = face;
  reduced.Animations.clear();
  double bounds[6] = { std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max(), -std::numeric_limits<double>::max() };
  for (GltfPart& part : reduced.Parts)
  {
    std::vector<GltfTarget> kept;
    std::vector<double> weights;
    for (size_t t = 0; t < part.Targets.size(); ++t)
    {
      if (driven.count(part.Targets[t].Name))
      {
        kept.push_back(std::move(part.Targets[t]));
        weights.push_back(t < part.DefaultWeights.size() ? part.DefaultWeights[t] : 0.0);
      }
    }
    part.Targets = std::move(kept);
    part.DefaultWeights = std::move(weights);
    for (size_t p = 0; p < part.Positions.size(); p += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        bounds[2 * k] = std::min(bounds[2 * k], static_cast<double>(part.Positions[p + k]));
        bounds[2 * k + 1] = std::max(bounds[2 * k + 1], static_cast<double>(part.Positions[p + k]));
      }
    }
  }
  for (GltfMesh& mesh : reduced.Meshes)
  {
    std::vector<std::string> names;
    std::vector<double> weights;
    for (size_t t = 0; t < mesh.TargetNames.size(); ++t)
    {
      if (driven.count(mesh.TargetNames[t]))
      {
        names.push_back(mesh.TargetNames[t]);
        weights.push_back(t < mesh.Weights.size() ? mesh.Weights[t] : 0.0);
      }
    }
    mesh.TargetNames = std::move(names);
    mesh.Weights = std::move(weights);
  }
  if (reduced.Parts.empty())
  {
    throw InputError("the face has no parts");
  }
#ifdef MORPHNODE_HAVE_LOD
  if (options.Level > 0)
  {
    // The device's level of detail, on the parts big enough to reduce.
    for (GltfPart& part : reduced.Parts)
    {
      if (part.Triangles.size() / 3 >= options.MinReducedTriangles)
      {
        double error = 0.0;
        part = ReducePart(part, options.Level, error);
        this->LevelError = std::max(this->LevelError, error);
        this->Level = options.Level;
      }
    }
  }
#endif
  for (const GltfPart& part : reduced.Parts)
  {
    this->Triangles += part.Triangles.size() / 3;
  }

  // The optimizer's model: the reduced parts.
  std::vector<std::shared_ptr<const MorphMesh>> meshes;
  for (const GltfPart& part : reduced.Parts)
  {
    meshes.push_back(std::make_shared<MorphMesh>(GltfPartToMorphMesh(part)));
  }
  this->Model = std::make_shared<MorphScene>();
  this->Model->SetParts(meshes);
  this->Model->SetWeightMode(WeightMode::Relative);

  // Rotation nodes: the head about its pivot, each eye (one per node) about its centre.
  GltfPerformance rest;
  rest.Name = "rest";
  rest.Times = { 0.0 };
  GltfRotationTrack head;
  head.Pivot = HeadPivot(bounds);
  head.Rotations = { 0, 0, 0, 1 };
  rest.Rotations.push_back(head);
  this->RotationNames.push_back("HeadRotation");
  const EyeRig eyes = (rig && rig->HasEyes()) ? rig->GetEyes() : EyeRig();
  this->Limits = eyes.GetLimits();
  std::set<int> eyeNodes;
  for (const GltfPart& part : reduced.Parts)
  {
    const std::string nodeName =
      part.Node >= 0 && static_cast<size_t>(part.Node) < reduced.Nodes.size()
      ? reduced.Nodes[part.Node].Name
      : "";
    EyeSpec spec;
    if (nodeName.empty() || eyeNodes.count(part.Node) || !eyes.FindEye(nodeName, part.Name, spec) ||
      this->RotationNames.size() >= MaxRotations)
    {
      continue;
    }
    // The writer finds a node by name: it must be unique.
    if (std::count_if(reduced.Nodes.begin(), reduced.Nodes.end(),
          [&](const GltfNode& n) { return n.Name == nodeName; }) != 1)
    {
      continue;
    }
    eyeNodes.insert(part.Node);
    const GltfMatrix& m = part.World; // column-major
    std::array<double, 9> axes{};
    for (int c = 0; c < 3; ++c)
    {
      const double length =
        std::sqrt(m[4 * c] * m[4 * c] + m[4 * c + 1] * m[4 * c + 1] + m[4 * c + 2] * m[4 * c + 2]);
      for (int r = 0; r < 3; ++r)
      {
        axes[3 * c + r] = length > 0.0 ? m[4 * c + r] / length : (r == c ? 1.0 : 0.0);
      }
    }
    GltfRotationTrack track;
    track.Node = nodeName;
    track.Pivot = { m[12], m[13], m[14] };
    track.Rotations = { 0, 0, 0, 1 };
    rest.Rotations.push_back(track);
    this->RotationNames.push_back(nodeName + "Rotation");
    this->Eyes.push_back({ spec, axes });
  }
  GltfWriteOptions write;
  write.Binary = true;
  write.QuantizeTargets =
    options.QuantizeDeltas; // sparse deltas as normalized shorts (KHR_mesh_quantization)
  this->File = WriteGltfSceneToMemory(reduced, &rest, write);
}

void StreamAvatar::Map(const double* channels, std::vector<double>& targetWeights,
  std::vector<std::array<double, 4>>& rotations, std::vector<double>& scratch) const
{
  targetWeights.assign(this->Targets.size(), 0.0);
  if (this->BoundRig)
  {
    const size_t shapes = this->BoundRig->GetNumberOfShapes();
    const size_t bound = this->BoundRig->GetNumberOfBoundTargets();
    scratch.assign(shapes + bound, 0.0);
    for (size_t c = 0; c < this->ChannelShape.size(); ++c)
    {
      if (this->ChannelShape[c] >= 0 && std::isfinite(channels[c]))
      {
        scratch[static_cast<size_t>(this->ChannelShape[c])] = channels[c];
      }
    }
    this->BoundRig->Expand(scratch.data(), scratch.data() + shapes);
    for (size_t t = 0; t < bound; ++t)
    {
      const int s = this->RigTargetToStream[t];
      if (s >= 0)
      {
        targetWeights[static_cast<size_t>(s)] = scratch[shapes + t];
      }
    }
  }
  else
  {
    for (size_t c = 0; c < this->ChannelTarget.size(); ++c)
    {
      const int s = this->ChannelTarget[c];
      if (s >= 0)
      {
        targetWeights[static_cast<size_t>(s)] =
          std::isfinite(channels[c]) ? std::clamp(channels[c], 0.0, 1.0) : 0.0;
      }
    }
  }
  auto channel = [channels](int c)
  { return c >= 0 && std::isfinite(channels[c]) ? channels[c] : 0.0; };
  rotations.resize(this->RotationNames.size());
  HeadAngles head;
  head.Yaw = channel(this->HeadYaw);
  head.Pitch = channel(this->HeadPitch);
  head.Roll = channel(this->HeadRoll);
  rotations[0] = GltfQuaternionFromRowMajor(HeadPoseMatrix(head, { { 0, 0, 0 } }));
  GazeAngles gaze;
  gaze.Yaw = channel(this->EyeYaw);
  gaze.Pitch = channel(this->EyePitch);
  for (size_t e = 0; e < this->Eyes.size(); ++e)
  {
    const Eye& eye = this->Eyes[e];
    const GazeAngles turned = EyeAngles(gaze, 0.0, eye.Spec.Side, this->Limits);
    rotations[e + 1] =
      ToQuaternion(EyeRotationMatrix(turned, eye.Axes, eye.Spec.Forward, eye.Spec.Up));
  }
}
} // namespace stream
} // namespace morphnode
