// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file TransferGeometry.h
/// @brief The triangle-mesh geometry the transfer needs: closest points on a mesh (a grid of
/// triangles), vertex normals, edges, boundary loops, connected components, and the
/// manifold check. Nothing here depends on VTK.

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace morphnode
{
/// Points and triangles (3 point ids each), double precision.
struct TransferSurface
{
  std::vector<glm::dvec3> Points;
  std::vector<uint32_t> Triangles;
  size_t GetNumberOfPoints() const { return this->Points.size(); }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
};

/// The closest point of triangle (a, b, c) to p, with its barycentric coordinates.
glm::dvec3 ClosestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
  const glm::dvec3& c, glm::dvec3& barycentric);

/// A hit of a closest-point query.
struct SurfaceHit
{
  int Triangle = -1; ///< -1: nothing within the search radius (or allowed by the filter)
  glm::dvec3 Point{ 0.0 };
  glm::dvec3 Barycentric{ 0.0 };
  double Distance = 0.0;
};

/// Exact closest points on a triangle mesh through a uniform grid of triangles (each
/// triangle in every cell its bounding box touches), searched ring by ring until no closer
/// cell remains. Written here because the core is VTK-free (vtkCellLocator is not) and the
/// library that has such a tree in Debian (CGAL's AABB tree) is GPL.
class TriangleGrid
{
public:
  explicit TriangleGrid(const TransferSurface& surface);
  /// The closest point within maxDistance whose triangle `allowed` accepts (null: all).
  SurfaceHit Closest(const glm::dvec3& p, double maxDistance,
    const std::function<bool(uint32_t)>& allowed = nullptr) const;

private:
  const TransferSurface& Surface;
  glm::dvec3 Origin{ 0.0 };
  double CellSize = 1.0;
  int Dims[3] = { 1, 1, 1 };
  std::vector<uint32_t> CellStart; ///< CSR: triangles of cell c at [CellStart[c], CellStart[c+1])
  std::vector<uint32_t> CellTriangles;
  std::vector<glm::dvec4> Spheres; ///< per triangle: centre and radius
};

/// Area-weighted vertex normals (unit; zero for a point without triangles).
std::vector<glm::dvec3> ComputeVertexNormals(const TransferSurface& surface);
/// Unit normal of every triangle (zero for a degenerate one).
std::vector<glm::dvec3> ComputeTriangleNormals(const TransferSurface& surface);
/// Mean edge length.
double MeanEdgeLength(const TransferSurface& surface);

/// Unique undirected edges (a < b) and, per edge, how many triangles use it.
struct SurfaceEdges
{
  std::vector<std::pair<uint32_t, uint32_t>> Edges;
  std::vector<uint32_t> TriangleCount;
};
SurfaceEdges ComputeEdges(const TransferSurface& surface);

/// Throws InputError (naming `what`) when the surface is empty, has ids out of range,
/// non-finite points, or edges shared by more than two triangles.
void CheckSurface(const TransferSurface& surface, const std::string& what);

/// Closed boundary loops (point ids in order) of a surface; open chains at non-manifold
/// vertices are dropped.
std::vector<std::vector<uint32_t>> ComputeBoundaryLoops(const TransferSurface& surface);
/// True for points on a boundary edge.
std::vector<bool> ComputeBoundaryPoints(const TransferSurface& surface);

/// Connected component of every point (through triangles); returns the count.
int ComputeComponents(const TransferSurface& surface, std::vector<int>& component);

/// Point adjacency (CSR): neighbours of i at [offsets[i], offsets[i+1]).
void ComputeAdjacency(const TransferSurface& surface, std::vector<uint32_t>& offsets,
  std::vector<uint32_t>& neighbours);
} // namespace morphnode
