// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file ObjSet.h
/// @brief Wavefront OBJ meshes and "OBJ sets": a neutral OBJ plus one OBJ per shape with
/// the same vertex order, the usual way scanned blend-shape faces (ICT-FaceKit, many
/// sculpting tools) are exchanged.
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

/// A neutral mesh and its shapes: absolute positions in the neutral's vertex order.
struct ObjSet
{
  ObjMesh Neutral;
  std::vector<std::string> ShapeNames;              ///< file stems
  std::vector<std::vector<float>> ShapePositions;   ///< absolute, 3 per vertex

  size_t GetNumberOfPoints() const { return this->Neutral.GetNumberOfPoints(); }
  size_t GetNumberOfShapes() const { return this->ShapeNames.size(); }
  /// -1 when no shape has that name.
  int FindShape(const std::string& name) const;
  /// shape - neutral, 3 per vertex (the relative, glTF-style form).
  std::vector<float> ComputeDeltas(size_t shape) const;
  /// A morph model with targets "Neutral" + ShapeNames and one float Position attribute
  /// (deltas stored sparsely where a shape moves few vertices).
  MorphMesh ToMorphModel(double sparseCoverage = MorphMesh::DefaultSparseCoverage) const;
};

/// Reads a neutral OBJ and shape OBJs; each shape is named after its file stem. Throws
/// InputError naming the file when a shape's vertex count differs from the neutral's, or
/// when two shapes share a stem.
ObjSet ReadObjSet(const std::string& neutralPath, const std::vector<std::string>& shapePaths);
/// Every `*.obj` of `directory` except the neutral is a shape, in file-name order.
ObjSet ReadObjSetDirectory(const std::string& directory, const std::string& neutralFileName);
} // namespace morphnode
