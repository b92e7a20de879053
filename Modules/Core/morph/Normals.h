// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Normals.h
/// @brief Vertex normals of triangle meshes, for faces and morph targets that come without.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace morphnode
{
/// Area-weighted vertex normals (unit length; zero for vertices on no triangle).
/// `positions`: numPoints * 3; `triangles`: numTriangles * 3 point ids.
/// Throws InputError for a point id out of range.
std::vector<float> ComputeVertexNormals(
  const float* positions, size_t numPoints, const uint32_t* triangles, size_t numTriangles);

/// Normal deltas of a relative target: normals(base + delta) - normals(base), the form
/// glTF stores; `baseNormals` from ComputeVertexNormals of the base.
std::vector<float> ComputeNormalDeltas(const float* basePositions, const float* positionDeltas,
  const std::vector<float>& baseNormals, size_t numPoints, const uint32_t* triangles,
  size_t numTriangles);
} // namespace morphnode
