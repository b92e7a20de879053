// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file MorphMesh.h
/// @brief A mesh with named morph targets: target names (neutral first), the per-point
/// attributes they morph and, optionally, the triangles. The one mesh-with-targets type
/// of the core: the morph node, rigs, OBJ sets and the reduction all use it.

#include "morph/Distances.h"
#include "morph/MorphAttribute.h"

#include <cstdint>
#include <deque>
#include <string>
#include <variant>
#include <vector>

namespace morphnode
{
using AnyMorphAttribute = std::variant<MorphAttribute<float>, MorphAttribute<double>>;

class MorphMesh
{
public:
  /// Coverage at or below which a target's deltas are stored sparsely. Measured on the
  /// ICT face and synthetic meshes (see docs/benchmarks.md): sparse scatter costs about
  /// 3x a dense axpy per moved point, so it pays off below roughly a third of the points.
  static constexpr double DefaultSparseCoverage = 0.3;

  explicit MorphMesh(size_t numPoints = 0)
    : NumPoints(numPoints)
  {
  }

  size_t GetNumberOfPoints() const { return this->NumPoints; }
  /// Neutral included.
  size_t GetNumberOfTargets() const { return this->TargetNames.size(); }
  void SetTargetNames(std::vector<std::string> names) { this->TargetNames = std::move(names); }
  const std::vector<std::string>& GetTargetNames() const { return this->TargetNames; }
  /// -1 when no target has that name.
  int FindTarget(const std::string& name) const;

  /// The new attribute, to fill in (SetNeutral, then one Add...Target per non-neutral
  /// target). The reference stays valid when more attributes are added.
  template <typename T>
  MorphAttribute<T>& AddAttribute(const std::string& name, AttributeRole role, int components)
  {
    this->Attributes.emplace_back(
      std::in_place_type<MorphAttribute<T>>, name, role, components, this->NumPoints);
    return std::get<MorphAttribute<T>>(this->Attributes.back());
  }
  size_t GetNumberOfAttributes() const { return this->Attributes.size(); }
  const AnyMorphAttribute& GetAttribute(size_t i) const { return this->Attributes.at(i); }
  /// Index of the first Position attribute, -1 if none.
  int GetPositionAttribute() const;

  /// Throws InputError unless every attribute has one delta set per non-neutral target and
  /// the triangles (if any) are whole and reference existing points.
  void Validate() const;

  /// Distances of the Position attribute (all zero without one).
  TargetDistances ComputeDistances() const;
  std::vector<double> ComputePointDistances(size_t target) const;
  std::vector<double> ComputeAnimatedRegion() const;
  /// The points some target moves in some attribute (a delta not exactly zero), as sorted
  /// [first, last) pairs: outside them every blend equals the neutral whatever the weights
  /// (what a re-skin after the morph need not look at again).
  std::vector<size_t> MovedPointRanges() const;

  /// Optional topology: triangles as 3 point ids each (empty = points only; the morph
  /// node needs none, OBJ sets and the reduction do). Validate() checks the ids.
  void SetTriangles(std::vector<uint32_t> triangles) { this->Triangles = std::move(triangles); }
  const std::vector<uint32_t>& GetTriangles() const { return this->Triangles; }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
  bool HasTriangles() const { return !this->Triangles.empty(); }

  size_t GetMemorySize() const;

private:
  size_t NumPoints;
  std::vector<std::string> TargetNames;
  std::deque<AnyMorphAttribute> Attributes; // deque: AddAttribute's references stay valid
  std::vector<uint32_t> Triangles;
};

/// Default target names: "Neutral", "target0", "target1", ... (glTF's target<k> naming).
std::vector<std::string> DefaultTargetNames(size_t numTargets);
} // namespace morphnode
