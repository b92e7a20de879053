// SPDX-License-Identifier: BSD-3-Clause
#include "gltf/GltfAnimation.h"

#include "base/Error.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

namespace morphnode
{
namespace
{
void Normalize4(double* q)
{
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (n > 0 && std::isfinite(n))
  {
    for (int k = 0; k < 4; ++k)
    {
      q[k] /= n;
    }
  }
  else
  {
    q[0] = q[1] = q[2] = 0;
    q[3] = 1;
  }
}

/// glTF 2.0, Appendix C: slerp along the shorter arc; plain lerp where the quaternions
/// (almost) coincide, where sin(angle) would lose every digit.
void Slerp(const double* a, const double* b, double u, double* out)
{
  double qa[4], qb[4];
  std::copy_n(a, 4, qa);
  std::copy_n(b, 4, qb);
  Normalize4(qa);
  Normalize4(qb);
  double dot = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
  const double s = dot < 0 ? -1.0 : 1.0;
  dot = std::min(1.0, std::abs(dot));
  const double angle = std::acos(dot);
  double wa = 1 - u, wb = u;
  if (angle > 1e-10)
  {
    const double sinAngle = std::sin(angle);
    wa = std::sin(angle * (1 - u)) / sinAngle;
    wb = std::sin(angle * u) / sinAngle;
  }
  for (int k = 0; k < 4; ++k)
  {
    out[k] = wa * qa[k] + s * wb * qb[k];
  }
  Normalize4(out);
}

const char* PathName(GltfAnimationPath path)
{
  switch (path)
  {
    case GltfAnimationPath::Translation:
      return "translation";
    case GltfAnimationPath::Rotation:
      return "rotation";
    case GltfAnimationPath::Scale:
      return "scale";
    default:
      return "weights";
  }
}

/// World transforms from Local, parents first (the loader checked the tree for cycles).
void ComputeWorld(const GltfScene& scene, GltfSceneSample& sample)
{
  const size_t count = scene.Nodes.size();
  std::vector<size_t> stack;
  for (size_t n = 0; n < count; ++n)
  {
    if (scene.Nodes[n].Parent < 0)
    {
      sample.Nodes[n].World = sample.Nodes[n].Local;
      stack.push_back(n);
    }
  }
  while (!stack.empty())
  {
    const size_t n = stack.back();
    stack.pop_back();
    for (int c : scene.Nodes[n].Children)
    {
      const size_t child = static_cast<size_t>(c);
      sample.Nodes[child].World = GltfMultiply(sample.Nodes[n].World, sample.Nodes[child].Local);
      stack.push_back(child);
    }
  }
}
} // namespace

int FindGltfAnimation(const GltfScene& scene, const std::string& name)
{
  for (size_t a = 0; a < scene.Animations.size(); ++a)
  {
    if (scene.Animations[a].Name == name)
    {
      return static_cast<int>(a);
    }
  }
  return -1;
}

void SampleGltfSampler(
  const GltfAnimationSampler& sampler, int width, bool rotation, double t, double* out)
{
  const size_t keys = sampler.Times.size();
  const bool cubic = sampler.Interpolation == GltfInterpolation::CubicSpline;
  const size_t w = static_cast<size_t>(std::max(width, 0));
  if (keys == 0 || w == 0 || sampler.Values.size() != keys * w * (cubic ? 3 : 1))
  {
    throw InputError("glTF animation sampler: " + std::to_string(sampler.Values.size()) +
      " output values for " + std::to_string(keys) + " keys of " + std::to_string(w) + " values" +
      (cubic ? " (CUBICSPLINE)" : ""));
  }
  // Element e of key k: for CUBICSPLINE, 0 in-tangent, 1 value, 2 out-tangent.
  auto at = [&](size_t k, size_t e)
  { return sampler.Values.data() + (cubic ? (3 * k + e) * w : k * w); };
  auto copy = [&](const float* v)
  {
    for (size_t i = 0; i < w; ++i)
    {
      out[i] = v[i];
    }
  };
  // The last key with t_k <= t; t before the first key holds the first value.
  const auto upper = std::upper_bound(sampler.Times.begin(), sampler.Times.end(), t,
    [](double value, float key) { return value < double(key); });
  if (upper == sampler.Times.begin())
  {
    copy(at(0, 1));
  }
  else if (upper == sampler.Times.end())
  {
    copy(at(keys - 1, 1));
  }
  else
  {
    const size_t k = static_cast<size_t>(upper - sampler.Times.begin()) - 1;
    const double t0 = sampler.Times[k], t1 = sampler.Times[k + 1]; // t0 <= t < t1
    const double td = t1 - t0;
    const double u = (t - t0) / td;
    switch (sampler.Interpolation)
    {
      case GltfInterpolation::Step:
        copy(at(k, 1));
        break;
      case GltfInterpolation::Linear:
        if (rotation && w == 4)
        {
          double a[4], b[4];
          const float* va = at(k, 1);
          const float* vb = at(k + 1, 1);
          for (int i = 0; i < 4; ++i)
          {
            a[i] = va[i];
            b[i] = vb[i];
          }
          Slerp(a, b, u, out);
          return;
        }
        else
        {
          const float* va = at(k, 1);
          const float* vb = at(k + 1, 1);
          for (size_t i = 0; i < w; ++i)
          {
            out[i] = (1 - u) * double(va[i]) + u * double(vb[i]);
          }
        }
        break;
      case GltfInterpolation::CubicSpline:
      {
        const double u2 = u * u, u3 = u2 * u;
        const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                     h11 = u3 - u2;
        const float* v0 = at(k, 1);
        const float* b0 = at(k, 2);
        const float* v1 = at(k + 1, 1);
        const float* a1 = at(k + 1, 0);
        for (size_t i = 0; i < w; ++i)
        {
          out[i] = h00 * v0[i] + h10 * td * b0[i] + h01 * v1[i] + h11 * td * a1[i];
        }
        break;
      }
    }
  }
  if (rotation && w == 4)
  {
    Normalize4(out);
  }
}

GltfSceneSample GltfRestPose(const GltfScene& scene)
{
  GltfSceneSample sample;
  sample.Nodes.resize(scene.Nodes.size());
  for (size_t n = 0; n < scene.Nodes.size(); ++n)
  {
    const GltfNode& node = scene.Nodes[n];
    GltfNodeSample& s = sample.Nodes[n];
    s.Translation = node.Translation;
    s.Rotation = node.Rotation;
    s.Scale = node.Scale;
    s.Local = node.Local;
    if (node.Mesh >= 0 && static_cast<size_t>(node.Mesh) < scene.Meshes.size())
    {
      const GltfMesh& mesh = scene.Meshes[static_cast<size_t>(node.Mesh)];
      s.Weights = !node.Weights.empty() ? node.Weights : mesh.Weights;
      s.Weights.resize(mesh.TargetNames.size(), 0.0);
    }
  }
  ComputeWorld(scene, sample);
  return sample;
}

GltfNamedWeights GltfWeightsByTargetName(const GltfScene& scene, const GltfSceneSample& sample)
{
  GltfNamedWeights out;
  std::unordered_map<std::string, size_t> index;
  std::set<std::string> disagreements;
  for (const GltfPart& part : scene.Parts)
  {
    if (part.Node < 0 || static_cast<size_t>(part.Node) >= sample.Nodes.size())
    {
      continue;
    }
    const std::vector<double>& weights = sample.Nodes[static_cast<size_t>(part.Node)].Weights;
    for (size_t k = 0; k < part.Targets.size() && k < weights.size(); ++k)
    {
      const std::string& name = part.Targets[k].Name;
      const auto found = index.find(name);
      if (found == index.end())
      {
        index.emplace(name, out.Names.size());
        out.Names.push_back(name);
        out.Values.push_back(weights[k]);
      }
      else if (out.Values[found->second] != weights[k] && disagreements.insert(name).second)
      {
        out.Disagreements.push_back(name);
      }
    }
  }
  return out;
}

GltfAnimationPlayer::GltfAnimationPlayer(
  const GltfScene& scene, int animation, const std::string& source)
  : Scene(&scene)
  , Index(animation)
{
  if (animation < 0 || static_cast<size_t>(animation) >= scene.Animations.size())
  {
    throw InputError(source + ": there is no animation " + std::to_string(animation) +
      " (the file has " + std::to_string(scene.Animations.size()) + ")");
  }
  const GltfAnimation& a = scene.Animations[static_cast<size_t>(animation)];
  this->Name = a.Name;
  std::set<double> times;
  std::set<int> nodes;
  bool first = true;
  for (size_t c = 0; c < a.Channels.size(); ++c)
  {
    const GltfAnimationChannel& channel = a.Channels[c];
    const std::string cp =
      "/animations/" + std::to_string(animation) + "/channels/" + std::to_string(c);
    if (channel.Sampler < 0 || static_cast<size_t>(channel.Sampler) >= a.Samplers.size() ||
      channel.Node < 0 || static_cast<size_t>(channel.Node) >= scene.Nodes.size())
    {
      throw InputError(source + ": " + cp + ": sampler or node out of range");
    }
    const GltfNode& node = scene.Nodes[static_cast<size_t>(channel.Node)];
    if (node.HasMatrix && channel.Path != GltfAnimationPath::Weights)
    {
      throw InputError(source + ": " + cp + "/target/node: node " + std::to_string(channel.Node) +
        " gives a matrix; glTF lets animations move only nodes given by translation, rotation and "
        "scale (" +
        PathName(channel.Path) + " animated here)");
    }
    const GltfAnimationSampler& sampler = a.Samplers[static_cast<size_t>(channel.Sampler)];
    const size_t per = static_cast<size_t>(std::max(channel.ValuesPerElement, 0)) *
      (sampler.Interpolation == GltfInterpolation::CubicSpline ? 3 : 1);
    if (sampler.Times.empty() || per == 0 || sampler.Values.size() != sampler.Times.size() * per)
    {
      throw InputError(source + ": " + cp + ": " + std::to_string(sampler.Values.size()) +
        " output values for " + std::to_string(sampler.Times.size()) + " keys of " +
        std::to_string(per) + " values");
    }
    for (float t : sampler.Times)
    {
      times.insert(double(t));
    }
    this->Start =
      first ? sampler.Times.front() : std::min(this->Start, double(sampler.Times.front()));
    this->End = first ? sampler.Times.back() : std::max(this->End, double(sampler.Times.back()));
    first = false;
    nodes.insert(channel.Node);
  }
  this->KeyTimes.assign(times.begin(), times.end());
  this->AnimatedNodes.assign(nodes.begin(), nodes.end());
}

GltfSceneSample GltfAnimationPlayer::Sample(double t) const
{
  const GltfScene& scene = *this->Scene;
  GltfSceneSample sample = GltfRestPose(scene);
  sample.Time = t;
  const GltfAnimation& a = scene.Animations[static_cast<size_t>(this->Index)];
  for (const GltfAnimationChannel& channel : a.Channels)
  {
    const GltfAnimationSampler& sampler = a.Samplers[static_cast<size_t>(channel.Sampler)];
    GltfNodeSample& node = sample.Nodes[static_cast<size_t>(channel.Node)];
    switch (channel.Path)
    {
      case GltfAnimationPath::Translation:
        SampleGltfSampler(sampler, 3, false, t, node.Translation.data());
        node.TranslationAnimated = true;
        break;
      case GltfAnimationPath::Rotation:
        SampleGltfSampler(sampler, 4, true, t, node.Rotation.data());
        node.RotationAnimated = true;
        break;
      case GltfAnimationPath::Scale:
        SampleGltfSampler(sampler, 3, false, t, node.Scale.data());
        node.ScaleAnimated = true;
        break;
      case GltfAnimationPath::Weights:
        node.Weights.resize(static_cast<size_t>(channel.ValuesPerElement));
        SampleGltfSampler(sampler, channel.ValuesPerElement, false, t, node.Weights.data());
        node.WeightsAnimated = true;
        break;
    }
  }
  for (size_t n = 0; n < sample.Nodes.size(); ++n)
  {
    GltfNodeSample& node = sample.Nodes[n];
    if (node.TranslationAnimated || node.RotationAnimated || node.ScaleAnimated)
    {
      node.Local = GltfComposeTrs(node.Translation, node.Rotation, node.Scale);
    }
  }
  ComputeWorld(scene, sample);
  return sample;
}
} // namespace morphnode
