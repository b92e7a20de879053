// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file GltfMorphMesh.h
/// @brief A part of a glTF scene as the core's morphable mesh. Header-only, so that the
/// loader itself (MorphNode::Gltf) needs no more than MorphNode::Base: link MorphNode::Morph
/// too when you include this.

#include "gltf/GltfScene.h"
#include "morph/MorphMesh.h"

#include <string>
#include <vector>

namespace morphnode
{
/// The part's points ("Position") and normals ("Normals", when it has them) with their
/// targets' deltas, the target names (neutral first, as MorphMesh names them) and the
/// triangles. Targets are stored sparsely where they move at most `sparseCoverage` of the
/// points. COLOR_0 is not morphed and stays with the part.
inline MorphMesh GltfPartToMorphMesh(
  const GltfPart& part, double sparseCoverage = MorphMesh::DefaultSparseCoverage)
{
  const size_t n = part.GetNumberOfPoints();
  MorphMesh mesh(n);
  std::vector<std::string> names{ "Neutral" };
  for (const auto& target : part.Targets)
  {
    names.push_back(target.Name);
  }
  mesh.SetTargetNames(std::move(names));
  auto& positions = mesh.AddAttribute<float>("Position", AttributeRole::Position, 3);
  positions.SetNeutral(part.Positions.data());
  for (const auto& target : part.Targets)
  {
    positions.AddRelativeTarget(target.PositionDeltas.data(), sparseCoverage);
  }
  if (!part.Normals.empty())
  {
    auto& normals = mesh.AddAttribute<float>("Normals", AttributeRole::Normal, 3);
    normals.SetNeutral(part.Normals.data());
    const std::vector<float> none(3 * n, 0.0f);
    for (const auto& target : part.Targets)
    {
      normals.AddRelativeTarget(
        target.NormalDeltas.empty() ? none.data() : target.NormalDeltas.data(), sparseCoverage);
    }
  }
  mesh.SetTriangles(part.Triangles);
  mesh.Validate();
  return mesh;
}
} // namespace morphnode
