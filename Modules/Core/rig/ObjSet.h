// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ObjSet.h
/// @brief Wavefront OBJ meshes and "OBJ sets": a neutral OBJ plus one OBJ per shape with
/// the same vertex order, the usual way scanned blend-shape faces (ICT-FaceKit, many
/// sculpting tools) are exchanged. An OBJ set is read into a MorphMesh.
///
/// Supported statements: `v x y z [w]` (extra colour components are ignored), `vt u [v [w]]`,
/// `vn x y z`, `f` with corners `v`, `v/vt`, `v//vn`, `v/vt/vn` (1-based or negative
/// relative indices), polygons fan-triangulated from their first corner. Comments (`#`)
/// and grouping/material/smoothing statements (o g s usemtl mtllib) are skipped, as are
/// the other statements of the format (l p vp curves), which a face does not use.
/// Malformed lines throw InputError with the file name and line number.

#include "morph/MorphMesh.h"

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace morphnode
{
/// One OBJ file. Indices are 0-based.
struct ObjMesh
{
  std::vector<float> Positions; ///< 3 per vertex
  std::vector<float> TexCoords; ///< 2 per `vt` (u, v; w dropped)
  std::vector<float> Normals;   ///< 3 per `vn`
  /// Position indices, 3 per triangle, polygons fan-triangulated.
  std::vector<uint32_t> Triangles;
  /// Per triangle corner (parallel to Triangles): `vt` / `vn` index, -1 when the corner
  /// has none.
  std::vector<int32_t> CornerTexCoords;
  std::vector<int32_t> CornerNormals;
  /// Polygons as written in the file (before triangulation).
  size_t NumberOfPolygons = 0;

  size_t GetNumberOfPoints() const { return this->Positions.size() / 3; }
  size_t GetNumberOfTriangles() const { return this->Triangles.size() / 3; }
};

/// Parses OBJ text; `sourceName` (usually the file name) prefixes error messages.
ObjMesh ParseObj(std::istream& in, const std::string& sourceName);
/// Reads an OBJ file. Throws InputError when it cannot be opened or is malformed.
ObjMesh ReadObj(const std::string& path);

/// Reads an OBJ set: a neutral OBJ and shape OBJs with the neutral's vertex order, into a
/// mesh with targets "Neutral" followed by the shapes' file stems, one float Position
/// attribute "Position" (each shape stored as shape - neutral; sparsely where a shape moves
/// at most `sparseCoverage` of the vertices) and the neutral's triangles. Throws InputError
/// naming the file when a shape's vertex count differs from the neutral's, or when two
/// shapes share a stem.
MorphMesh ReadObjSet(const std::string& neutralPath, const std::vector<std::string>& shapePaths,
  double sparseCoverage = MorphMesh::DefaultSparseCoverage);
/// Every `*.obj` of `directory` except the neutral is a shape, in file-name order.
MorphMesh ReadObjSetDirectory(const std::string& directory, const std::string& neutralFileName,
  double sparseCoverage = MorphMesh::DefaultSparseCoverage);
} // namespace morphnode
