// SPDX-License-Identifier: BSD-3-Clause
#include "transfer/TransferScene.h"

#include "base/Error.h"

#include <algorithm>

namespace morphnode
{
TransferSource MakeTransferSource(const GltfScene& scene)
{
  TransferSource source;
  for (const auto& part : scene.Parts)
    for (const auto& t : part.Targets)
      if (std::find(source.TargetNames.begin(), source.TargetNames.end(), t.Name) ==
        source.TargetNames.end())
        source.TargetNames.push_back(t.Name);
  if (source.TargetNames.empty())
    throw InputError("source: no part of the scene has morph targets");
  source.Deltas.resize(source.TargetNames.size());
  for (const auto& part : scene.Parts)
  {
    if (part.Targets.empty())
      continue;
    const uint32_t base = uint32_t(source.Surface.Points.size());
    const size_t n = part.GetNumberOfPoints();
    for (size_t i = 0; i < n; ++i)
      source.Surface.Points.emplace_back(
        part.Positions[3 * i], part.Positions[3 * i + 1], part.Positions[3 * i + 2]);
    for (uint32_t v : part.Triangles)
      source.Surface.Triangles.push_back(base + v);
    for (size_t k = 0; k < source.TargetNames.size(); ++k)
    {
      auto& d = source.Deltas[k];
      d.resize(source.Surface.Points.size(), glm::dvec3(0.0));
      for (const auto& t : part.Targets)
        if (t.Name == source.TargetNames[k])
          for (size_t i = 0; i < n; ++i)
            d[base + i] = { t.PositionDeltas[3 * i], t.PositionDeltas[3 * i + 1],
              t.PositionDeltas[3 * i + 2] };
    }
  }
  return source;
}

TransferSurface MergeParts(const GltfScene& target, std::vector<size_t>& partOffsets)
{
  TransferSurface s;
  partOffsets.clear();
  for (const auto& part : target.Parts)
  {
    partOffsets.push_back(s.Points.size());
    const uint32_t base = uint32_t(s.Points.size());
    for (size_t i = 0; i < part.GetNumberOfPoints(); ++i)
      s.Points.emplace_back(
        part.Positions[3 * i], part.Positions[3 * i + 1], part.Positions[3 * i + 2]);
    for (uint32_t v : part.Triangles)
      s.Triangles.push_back(base + v);
  }
  partOffsets.push_back(s.Points.size());
  return s;
}

TransferResult TransferOntoScene(
  const TransferSource& source, GltfScene& target, const TransferOptions& options)
{
  std::vector<size_t> offsets;
  const TransferSurface surface = MergeParts(target, offsets);
  TransferResult result = TransferTargets(source, surface, options);
  for (size_t p = 0; p < target.Parts.size(); ++p)
  {
    GltfPart& part = target.Parts[p];
    part.Targets.clear();
    for (size_t k = 0; k < result.TargetNames.size(); ++k)
    {
      GltfTarget t;
      t.Name = result.TargetNames[k];
      t.PositionDeltas.assign(result.Deltas[k].begin() + long(3 * offsets[p]),
        result.Deltas[k].begin() + long(3 * offsets[p + 1]));
      part.Targets.push_back(std::move(t));
    }
    part.DefaultWeights.assign(result.TargetNames.size(), 0.0);
  }
  for (auto& node : target.Nodes)
    node.Weights.clear();
  for (auto& mesh : target.Meshes)
  {
    mesh.TargetNames = result.TargetNames;
    mesh.Weights.assign(result.TargetNames.size(), 0.0);
  }
  return result;
}
} // namespace morphnode
